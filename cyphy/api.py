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
    ws, report = load_workspace(paths, options.search_paths)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    check_placement(ws.user_files(), report)
    result.resolution = check_scopes(ws, report)
    if options.wellformedness:
        from cyphy.wellformed import WFContext, check_wellformed

        check_wellformed(WFContext(ws, result.resolution, report, dict(options.consts)))
    if options.consistency:
        _check_consistency(ws, result.resolution, report, options)
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
