"""The CyPhyCircus semantics of a platform mapping, and the generators built on it: text,
LaTeX (``--cyphycircus``, ``--latex``) and the Isabelle session (``--isabelle``)."""

from __future__ import annotations

import json
from dataclasses import field, replace
from pathlib import Path
from typing import Any, Sequence

from cyphy.deep import deep
from cyphy.diagnostics import Report
from cyphy.pipeline.check import CheckOptions, CheckResult, check
from cyphy.pipeline.generated import Generated
from cyphy.records import record


@record(frozen=True, slots=False)
class SemanticsGenOptions:
    """Options of the generators built on the CyPhyCircus semantics (``--cyphycircus``,
    ``--latex``, ``--isabelle``)."""

    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of the whole system (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pdf: bool = False  # --latex: also typeset with pdflatex
    dialect: str = "utp"  # --isabelle: "utp" (utp-main 2020) or "axiomatic" (Ax_CyPhyCircus)
    elements: tuple[str, ...] = ()  # --isabelle axiomatic: the elements Evolve's ODE covers
    default_inertial: str | None = None  # see ElaborateOptions
    machine: str | None = None  # the d-model's state machine D is written from (default: as simulate)
    scenario: str | None = None  # a simulate/reach scenario: its [init] starts Init (see semantics)


@deep
def semantics(paths: Sequence[str | Path], options: SemanticsGenOptions = SemanticsGenOptions()
              ) -> tuple[CheckResult, Any]:
    """Check the files (and the files they use) and apply the paper's rules to the chosen
    platform mapping: ``(check result, Semantics or None)``. With a ``scenario`` (the TOML
    file ``simulate`` and ``reach`` read), ``Init`` starts the state at its ``[init]``
    values, and its ``[consts]``, ``tscale``, ``machine``, ``model``, ``default_inertial``
    (and, for the axiomatic dialect, ``elements``) apply where the options give none; an
    ``[init]`` name that is no state of the generated theory is a warning."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.semantics.circus.build import SemanticsOptions, build_semantics

    scenario = None
    if options.scenario is not None:
        # lazy: the scenario reader (TOML) only with a scenario
        from cyphy.verify.flowstar.scenario import load_scenario

        loaded = Report()
        scenario = load_scenario(options.scenario, loaded, needs_unsafe=False)
        if scenario is None:  # the diagnostics quote the file's lines when it can be read
            sources: dict[str, str] = {}
            try:
                sources[options.scenario] = Path(options.scenario).read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                pass
            return CheckResult(None, loaded, sources=sources), None  # type: ignore[arg-type]
        options = _with_scenario(options, scenario)
    # With the value checks (V1-V6): Evolve holds the equations of motion, built from the
    # masses, inertias and axes; a theory of a robot with a negative mass is not the robot's.
    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts),
                                        neighbours_as_targets=True,
                                        find_in_folder="mapping"))
    if scenario is not None:
        checked.sources[scenario.path] = scenario.text
    if checked.report.has_errors or checked.resolution is None:
        return checked, None
    built = build_semantics(checked.workspace, checked.resolution, checked.report,
                            SemanticsOptions(options.mapping, options.system_name,
                                             options.tscale, dict(options.consts),
                                             options.default_inertial, options.machine,
                                             scenario.init if scenario else None))
    if built is not None:
        built.scenario = scenario  # its [init] names the theory's Init must start (checked
        # by each generator on its own Init: the dialects hold different states)
    return checked, built


def _with_scenario(options: SemanticsGenOptions, scenario: Any) -> SemanticsGenOptions:
    """The options with the scenario's settings where the options give none (the command
    line wins, as in ``simulate``: ``--const`` over ``[consts]``)."""
    elements = options.elements
    if options.dialect == "axiomatic" and not elements:
        elements = scenario.elements
    return replace(options, consts={**scenario.consts, **options.consts},
                   tscale=options.tscale if options.tscale is not None else scenario.tscale,
                   machine=options.machine or scenario.machine,
                   mapping=options.mapping or scenario.model,
                   default_inertial=options.default_inertial or scenario.default_inertial,
                   elements=elements)


def _report_unassigned(report: Report, scenario: Any, actions: Sequence[Any]) -> None:
    """``W-SCENARIO-INIT`` for the scenario's ``[init]`` names that the theory's ``Init``
    does not start (they are locals of this output, or name nothing)."""
    from cyphy.semantics.circus.build import UNASSIGNED_INIT, started_by_init

    started = started_by_init(actions)
    for name in sorted(set(scenario.init) - started):
        report.report(UNASSIGNED_INIT, f"the scenario's initial value of '{name}' is not "
                      "assigned: it is no state of this theory's p-model process",
                      scenario.span("init", name),
                      "only the p-model process's state can start at a value: the text and "
                      "LaTeX keep the paper's ∃ PLocal (an ODE's state is quantified afresh in "
                      "each Evolve), the Isabelle dialects hold it as state under their own "
                      "names (a running integral of e is <Device>_e_int in the utp dialect, "
                      "the reduction's <Device>_int<n> in the axiomatic one; names.tsv lists "
                      "them)")


@deep
def generate_cyphycircus(paths: Sequence[str | Path], target: str,
                         options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """``target`` ``"text"``: ``<N>.cpc`` (Unicode, reads like the paper's Figure 18);
    ``"latex"``: ``<N>.tex`` with ``cyphycircus.sty`` (and ``<N>.pdf`` with ``pdf``). Both
    with the names table ``<N>.names.json``."""
    checked, built = semantics(paths, options)
    result = Generated(checked.report, checked.sources)
    if built is None or checked.report.has_errors:
        return result
    if built.scenario is not None:  # the text and LaTeX keep the paper's ∃ PLocal
        _report_unassigned(checked.report, built.scenario, built.program.pmodel.actions)
    stem = built.program.system.name
    if target == "text":
        # lazy: each printer only for its own target (--isabelle needs neither)
        from cyphy.backends.circus.text import program_to_text

        result.files[f"{stem}.cpc"] = program_to_text(built.program)
    else:
        # lazy: each printer only for its own target (--isabelle needs neither)
        from cyphy.backends.circus.latex import STYLE, program_to_latex

        document = program_to_latex(built.program)
        result.files[f"{stem}.tex"] = document
        result.files["cyphycircus.sty"] = STYLE
        if options.pdf:
            # lazy: the typesetter (subprocess, pdflatex) only with --pdf
            from cyphy.backends.circus.pdf import PdfError, typeset

            try:
                result.files[f"{stem}.pdf"] = typeset(document, {"cyphycircus.sty": STYLE})
            except PdfError as err:
                # lazy: NumPy: `cyphy check` must not pay for it
                from cyphy.semantics.circus.build import NO_PDF

                checked.report.report(NO_PDF, str(err), built.mapping.span, err.hint)
                result.files.clear()
                return result
    table = dict(built.names.items())
    result.files[f"{stem}.names.json"] = json.dumps(table, indent=2, sort_keys=True) + "\n"
    return result


@deep
def generate_isabelle(paths: Sequence[str | Path],
                      options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """The Isabelle session of one platform mapping: ``ROOT``, the prelude, the theory, a
    README and the names table. Files are empty when the model has errors."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.isabelle.session import session_files

    checked, built = semantics(paths, options)
    generated = Generated(checked.report, dict(checked.sources))
    if built is None or checked.report.has_errors:
        return generated
    found = session_files(built, options, checked.report)
    if found is not None:
        generated.files, init = found
        if built.scenario is not None:
            _report_unassigned(checked.report, built.scenario, [init])
    return generated
