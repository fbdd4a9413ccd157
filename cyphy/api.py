"""The library entry points behind the CLI: values in, results with diagnostics out.

Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

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
    neighbours_as_targets: bool = False  # check the files beside a given file too


@dataclass
class CheckResult:
    workspace: Workspace
    report: Report
    resolution: Resolution | None = None
    sources: dict[str, str] = field(default_factory=dict)


def check(paths: Sequence[str | Path], options: CheckOptions = CheckOptions()) -> CheckResult:
    """Parse the files (or folders) and, unless ``syntax_only``, resolve names and check the
    scope conditions. Diagnostics of library files are never reported."""
    ws, report = load_workspace(paths, options.search_paths,
                                neighbours_as_targets=options.neighbours_as_targets)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    check_placement(ws.user_files(), report)
    result.resolution = check_scopes(ws, report)
    if options.wellformedness:
        from cyphy.wellformed import WFContext, check_wellformed

        check_wellformed(WFContext(ws, result.resolution, report, dict(options.consts)))
    return result


@dataclass
class Generated:
    """What a generator produced: files by relative path, in writing order. ``files`` is
    empty when the model has errors (the report says which), so nothing gets written."""

    report: Report
    sources: dict[str, str] = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)


@dataclass(frozen=True)
class ElaborateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()


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
    if checked.report.has_errors or checked.resolution is None:
        return ElaborateResult(checked, None)
    model = run(checked.workspace, checked.resolution, checked.report, options.model,
                options.consts)  # type: ignore[arg-type]
    return ElaborateResult(checked, model)


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
class IsabelleGenOptions:
    """``cyphy gen --isabelle``: which mapping, the semantics' parameters, the name sets."""

    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of the whole system (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    namesets: bool = False  # keep interleaved updates with a name-set partition


def generate_isabelle(paths: Sequence[str | Path],
                      options: IsabelleGenOptions = IsabelleGenOptions()) -> Generated:
    """The Isabelle session of one platform mapping: ``ROOT``, the prelude, the theory, a
    README and the names table. Files are empty when the model has errors. Interleavings
    that discard state updates are reported as warnings (W-INTERLEAVE)."""
    from cyphy.backends.isabelle_theory import (LOSSY_INTERLEAVING, UNTRANSLATABLE,
                                                IsabelleError, IsabelleOptions,
                                                generate_session)
    from cyphy.semantics.build import SemanticsOptions, build_semantics

    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts),
                                        neighbours_as_targets=True))
    generated = Generated(checked.report, dict(checked.sources))
    report = checked.report
    if report.has_errors or checked.resolution is None:
        return generated
    semantics = build_semantics(checked.workspace, checked.resolution, report,
                                SemanticsOptions(options.mapping, options.system_name,
                                                 options.tscale, dict(options.consts)))
    if semantics is None or report.has_errors:
        return generated
    span = semantics.mapping.span
    try:
        session = generate_session(semantics.program, semantics.names,
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
