"""The library entry points behind the CLI: values in, results with diagnostics out.

Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from cyphy import collector, progress
from cyphy.diagnostics import Report
from cyphy.lang.placement import check_placement
from cyphy.lang.resolve import Resolution, check_scopes
from cyphy.lang.workspace import Workspace, load_workspace

if TYPE_CHECKING:  # the model needs NumPy and SciPy: `cyphy check` must not import them
    from cyphy.model.elements import ElaboratedModel


@dataclass(frozen=True)
class CheckOptions:
    syntax_only: bool = False
    search_paths: tuple[str, ...] = ()
    wellformedness: bool = True
    consts: dict[str, object] = field(default_factory=dict)
    neighbours_as_targets: bool = False  # check the files the given ones use, too
    value_checks: bool = True  # V1-V5 (geometry, inertia, meshes): what simulators need
    consistency: bool = False  # also C1-C5 on the platform mappings (imports Z3)
    z3_timeout_ms: int | None = None  # per Z3 query; None: the checks' default


@dataclass
class CheckResult:
    workspace: Workspace
    report: Report
    resolution: Resolution | None = None
    sources: dict[str, str] = field(default_factory=dict)


def check(paths: Sequence[str | Path], options: CheckOptions = CheckOptions()) -> CheckResult:
    """Parse the files (or folders) and, unless ``syntax_only``, resolve names and check the
    scope conditions. Diagnostics of library files are never reported."""
    with collector.paused():  # the syntax tree and the resolution tables all stay alive
        result = _front_end(paths, options)
    if options.consistency and result.resolution is not None:
        _check_consistency(result.workspace, result.resolution, result.report, options)
    return result


def _front_end(paths: Sequence[str | Path], options: CheckOptions) -> CheckResult:
    ws, report = load_workspace(paths, options.search_paths)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    if options.neighbours_as_targets:
        ws.targets = _with_dependencies(ws)
    check_placement(ws.user_files(), report)
    progress.stage("resolving names")
    result.resolution = check_scopes(ws, report)
    if options.wellformedness:
        from cyphy.wellformed import RULES, WFContext, check_wellformed

        only = None if options.value_checks else {i for i in RULES if not i.startswith("V")}
        check_wellformed(WFContext(ws, result.resolution, report, dict(options.consts)), only)
    return result


def _check_consistency(ws: Workspace, resolution: Resolution, report: Report,
                       options: CheckOptions) -> None:
    from cyphy.semantics.consistency import DEFAULT_TIMEOUT_MS, check_consistency

    check_consistency(ws, resolution, report, options.consts,
                      options.z3_timeout_ms or DEFAULT_TIMEOUT_MS)


@dataclass
class Generated:
    """What a generator produced: files by relative path, in writing order. ``files`` is
    empty when the model has errors (the report says which), so nothing gets written."""

    report: Report
    sources: dict[str, str] = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)


def _with_dependencies(ws: Workspace) -> list[str]:
    """The given files and every (non-library) file they use, transitively: what a
    generator translates with them, so what must be resolved and checked with them. Files
    that merely sit in the same folder (another robot's p-model) are left out."""
    item_file = {id(item): f.path for f in ws.files.values() for item in f.items}
    library = {f.path for pkg in ws.packages.values() if pkg.builtin for f in pkg.files}
    targets = list(ws.targets)
    while True:
        ws.targets = targets
        resolution = check_scopes(ws, Report())
        used = {item_file[id(d)] for d in resolution.targets.values() if id(d) in item_file}
        new = sorted(used - set(targets) - library)
        if not new:
            return targets
        targets = targets + new


@dataclass(frozen=True)
class ElaborateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    despite_value_errors: bool = False  # `cyphy show`: elaborate a model with V1-V5/E-EVAL


@dataclass
class ElaborateResult:
    check: CheckResult
    model: "ElaboratedModel | None"

    @property
    def report(self) -> Report:
        return self.check.report


def elaborate(paths: Sequence[str | Path], options: ElaborateOptions = ElaborateOptions()
              ) -> ElaborateResult:
    """Check the files, then elaborate one p-model. The model is None when the files have
    errors (generation must not run on them) or no p-model can be chosen."""
    from cyphy.model.elaborate import elaborate as run

    checked = check(paths, CheckOptions(search_paths=options.search_paths))
    if checked.resolution is None or (checked.report.has_errors and not (
            options.despite_value_errors
            and all(_value_error(d) for d in checked.report.errors))):
        return ElaborateResult(checked, None)
    model = run(checked.workspace, checked.resolution, checked.report, options.model,
                options.consts)  # type: ignore[arg-type]
    return ElaborateResult(checked, model)


def _value_error(d: Any) -> bool:
    """Whether an error concerns only values (``V1``-``V5``, ``E-EVAL``): the model can
    still be elaborated and shown, with the error reported; generators refuse it."""
    import re

    return d.code.id == "E-EVAL" or re.fullmatch(r"V\d+", d.code.id) is not None


class UsageError(ValueError):
    """An option that names nothing in the model (``solve --element Nope::X``): the caller's
    mistake, not the model's, so not a diagnostic; the CLI exits with status 2."""


def unknown_elements(model: "ElaboratedModel", elements: Sequence[str]) -> str | None:
    """Why some of ``elements`` (qualified names) name no element with equations of
    ``model``, or None when each names one (or contains some)."""
    from cyphy.diagnostics import did_you_mean

    names = {e.name for e in [*model.joints, *model.unconnected, *model.sensors,
                              *model.actuators]}
    for q in elements:
        if not any(n == q or n.startswith(q + "::") for n in names):
            return (f"'{q}' names no element of {model.name}; "
                    + (did_you_mean(q, names) or f"qualified names start with "
                       f"{model.name}::"))
    return None


@dataclass(frozen=True)
class SolveOptions:
    model: str | None = None
    elements: tuple[str, ...] = ()
    mapping_call: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    closed_form: bool = True


@dataclass
class SolveResult:
    elaboration: ElaborateResult
    system: Any = None  # cyphy.semantics.equations.System
    reduced: Any = None  # cyphy.backends.reduce.Reduced
    closed_form: dict[str, Any] | None = None

    @property
    def report(self) -> Report:
        return self.elaboration.report


def solve(paths: Sequence[str | Path], options: SolveOptions = SolveOptions()) -> SolveResult:
    """Assemble the model's equations (optionally with one mapping call), reduce them to
    explicit ODEs with SymPy and, where SymPy finds one, give the closed form."""
    from cyphy.backends.reduce import closed_form, reduce_system, report_obstacles
    from cyphy.semantics.equations import AssemblyError, assemble, mapping_operation

    elaborated = elaborate(paths, ElaborateOptions(options.model, options.consts,
                                                   options.search_paths))
    result = SolveResult(elaborated)
    model = elaborated.model
    if model is None:
        return result
    report = elaborated.report
    unknown = unknown_elements(model, options.elements)
    if unknown:
        raise UsageError(unknown)
    try:
        mapping, call, params = (None, None, ())
        if options.mapping_call is not None:
            mapping, call, params = mapping_operation(
                elaborated.check.workspace, elaborated.check.resolution, model,
                options.mapping_call)
        result.system = assemble(model, list(options.elements) or None, mapping, call, params)
    except AssemblyError as err:
        from cyphy.semantics.equations import ASSEMBLY

        report.report(ASSEMBLY, err.message, err.span, err.hint)
        return result
    result.reduced = reduce_system(result.system)
    report_obstacles(result.reduced, report)
    free = [p for p in result.reduced.parameters if result.system.parameters.get(p) is None]
    if options.closed_form and not free and result.reduced.states \
            and not result.reduced.obstacles:
        inputs = {f"der_{n}": 0 for n in result.system.inputs}
        result.closed_form = closed_form(result.reduced, inputs)
    return result


@dataclass(frozen=True)
class SemanticsGenOptions:
    """Options of the generators built on the CyPhyCircus semantics (``--cyphycircus``,
    ``--latex``, ``--isabelle``)."""

    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of the whole system (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pdf: bool = False  # --latex: also typeset with pdflatex
    namesets: bool = False  # --isabelle: keep interleaved updates with a name-set partition
    dialect: str = "utp"  # --isabelle: "utp" (utp-main 2020) or "axiomatic" (Ax_CyPhyCircus)
    elements: tuple[str, ...] = ()  # --isabelle axiomatic: the elements Evolve's ODE covers


def semantics(paths: Sequence[str | Path], options: SemanticsGenOptions = SemanticsGenOptions()
              ) -> tuple[CheckResult, Any]:
    """Check the files (and the files they use) and apply the paper's rules to the chosen
    platform mapping: ``(check result, Semantics or None)``."""
    from cyphy.semantics.build import SemanticsOptions, build_semantics

    # The value checks concern geometry and inertia, which the semantics does not use.
    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts),
                                        neighbours_as_targets=True, value_checks=False))
    if checked.report.has_errors or checked.resolution is None:
        return checked, None
    built = build_semantics(checked.workspace, checked.resolution, checked.report,
                            SemanticsOptions(options.mapping, options.system_name,
                                             options.tscale, dict(options.consts)))
    return checked, built


def generate_cyphycircus(paths: Sequence[str | Path], target: str,
                         options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """``target`` ``"text"``: ``<N>.cpc`` (Unicode, reads like the paper's Figure 18);
    ``"latex"``: ``<N>.tex`` with ``cyphycircus.sty`` (and ``<N>.pdf`` with ``pdf``). Both
    with the names table ``<N>.names.json``."""
    import json

    checked, built = semantics(paths, options)
    result = Generated(checked.report, checked.sources)
    if built is None or checked.report.has_errors:
        return result
    stem = built.program.system.name
    if target == "text":
        from cyphy.backends.circus_text import program_to_text

        result.files[f"{stem}.cpc"] = program_to_text(built.program)
    else:
        from cyphy.backends.circus_latex import STYLE, program_to_latex

        document = program_to_latex(built.program)
        result.files[f"{stem}.tex"] = document
        result.files["cyphycircus.sty"] = STYLE
        if options.pdf:
            from cyphy.backends.pdf import PdfError, typeset

            try:
                result.files[f"{stem}.pdf"] = typeset(document, {"cyphycircus.sty": STYLE})
            except PdfError as err:
                from cyphy.semantics.build import NO_PDF

                checked.report.report(NO_PDF, str(err), built.mapping.span, err.hint)
                result.files.clear()
                return result
    table = dict(built.names.items())
    result.files[f"{stem}.names.json"] = json.dumps(table, indent=2, sort_keys=True) + "\n"
    return result


@dataclass(frozen=True)
class SdfGenOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pose: tuple[float, float, float, float, float, float] = (0.0,) * 6
    short_names: bool = False
    target: str = "gazebo"  # or "coppeliasim"
    gazebo_model: bool = False  # files model.sdf and model.config instead of <Model>.sdf
    split_trees: bool = False  # a <world> with one <model> per tree of links


def generate_sdf(paths: Sequence[str | Path], options: SdfGenOptions = SdfGenOptions()
                 ) -> Generated:
    """SDF 1.6 for one p-model (``cyphy gen --sdf``): ``<Model>.sdf`` and the name table
    ``<Model>.names.json``, or, for a Gazebo model folder, ``model.sdf``, ``model.config``
    and the table. No files when the model has errors or constants without values."""
    from cyphy.backends.sdf_xml import model_config, names_json, to_xml
    from cyphy.model.elaborate import choose_pmodel, elaborate_pmodel, require_constants
    from cyphy.semantics.sdf import SdfOptions, translate, unvalued

    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts)))
    generated = Generated(checked.report, checked.sources)
    if checked.report.has_errors or checked.resolution is None:
        return generated
    chosen = choose_pmodel(checked.workspace, options.model, checked.report)
    if chosen is None:
        return generated
    model = elaborate_pmodel(checked.workspace, checked.resolution, checked.report, *chosen,
                             options.consts)  # type: ignore[arg-type]
    if unvalued(model):  # only constants that SDF needs must have values
        needed = {n: spans for n, spans in model.missing.items()
                  if not _device_constant(model, n)} or model.missing
        model.missing = needed
        require_constants(model, checked.report, "SDF generation")
    if checked.report.has_errors:
        return generated
    document = translate(model, checked.workspace, checked.report,
                         SdfOptions(options.pose, options.short_names, options.target,
                                    options.split_trees))
    text = to_xml(document.root)
    if options.gazebo_model:
        generated.files = {"model.sdf": text, "model.config": model_config(model.name),
                           f"{model.name}.names.json": names_json(document.names)}
    else:
        generated.files = {f"{model.name}.sdf": text,
                           f"{model.name}.names.json": names_json(document.names)}
    return generated


def _device_constant(model: "ElaboratedModel", name: str) -> bool:
    """Whether a missing constant (``IR::a``) is a constant of a device's definition: the
    equations need it, SDF only if an annotation uses it."""
    definition, _, const = name.rpartition("::")
    return any(e.definition == definition and e.device is not None
               and e.device.port(const) is not None
               for e in [*model.joints, *model.sensors, *model.actuators])


def generate_isabelle(paths: Sequence[str | Path],
                      options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """The Isabelle session of one platform mapping: ``ROOT``, the prelude, the theory, a
    README and the names table. Files are empty when the model has errors. Interleavings
    that discard state updates are reported as warnings (W-INTERLEAVE)."""
    from cyphy.backends.isabelle_theory import (LOSSY_INTERLEAVING, UNTRANSLATABLE,
                                                IsabelleError, IsabelleOptions,
                                                generate_session)

    checked, built = semantics(paths, options)
    generated = Generated(checked.report, dict(checked.sources))
    report = checked.report
    if built is None or report.has_errors:
        return generated
    span = built.mapping.span
    try:
        if options.dialect == "axiomatic":
            session = _axiomatic_session(built, options, report)
            if session is None:
                return generated
        else:
            session = generate_session(built.program, built.names,
                                       IsabelleOptions(options.namesets),
                                       options.system_name)
    except IsabelleError as err:
        report.report(UNTRANSLATABLE, str(err), span,
                      "this construct cannot be written in Isabelle/UTP yet; the text and "
                      "LaTeX printers (--cyphycircus, --latex) show it")
        return generated
    for found in session.lossy:
        if session.namesets_applied and found.partition:
            continue
        branches = " ||| ".join(found.branches)
        updated = ", ".join(sorted(found.updated))
        if not options.namesets:
            hint = ("this follows the paper; --isabelle-namesets writes the interleaving with "
                    "a name-set partition where the branches update disjoint variables")
        else:
            hint = ("--isabelle-namesets cannot help here: no name-set partition exists, "
                    f"the branches all may update {', '.join(sorted(found.overlap))}")
        report.report(LOSSY_INTERLEAVING,
                      f"{found.action} ≙ {branches} interleaves with empty name sets: the "
                      f"updates of {updated} are discarded when it ends", span, hint)
    generated.files = session.files
    return generated


def _axiomatic_session(built: Any, options: SemanticsGenOptions, report: Report) -> Any:
    """The Ax_CyPhyCircus session, with Evolve reduced to explicit ODEs (SymPy); None when
    the equations cannot be reduced (E-ISABELLE-ODE reported)."""
    from cyphy.backends.isabelle_ax_theory import generate_ax_session
    from cyphy.backends.isabelle_theory import IsabelleOptions
    from cyphy.semantics import circus as c
    from cyphy.semantics.namesets import action_nodes

    pm = built.program.pmodel
    evolutions = [n for d in pm.actions for n in action_nodes(d.body)
                  if isinstance(n, c.Evolution)]
    odes = None
    if evolutions:
        from cyphy.backends.evolve_odes import explicit_odes

        odes = explicit_odes(built.model, evolutions[0], {f.name for f in pm.state.fields},
                             options.elements, report, built.mapping.span)
        if odes is None:
            return None
    return generate_ax_session(built.program, built.names, odes,
                               IsabelleOptions(options.namesets), options.system_name,
                               options.elements)
