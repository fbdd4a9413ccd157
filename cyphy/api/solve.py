"""``solve``: a p-model's equations reduced to explicit ODEs (SymPy), and the closed form."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from cyphy.deep import deep
from cyphy.diagnostics import Report, did_you_mean
from cyphy.pipeline.elaborate import ElaborateOptions, ElaborateResult, elaborate

if TYPE_CHECKING:
    from cyphy.model.elements import ElaboratedModel


class UsageError(ValueError):
    """An option that names nothing in the model (``solve --element Nope::X``): the caller's
    mistake, not the model's, so not a diagnostic; the CLI exits with status 2."""


def unknown_elements(model: "ElaboratedModel", elements: Sequence[str]) -> str | None:
    """Why some of ``elements`` (qualified names) name no element with equations of
    ``model``, or None when each names one (or contains some)."""
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
    gravity: tuple[float, float, float] | None = None  # default −9.81 m/s² along z
    default_inertial: str | None = None  # see ElaborateOptions
    floating_base: bool = False  # the root bodies free (six coordinates each), not fixed


@dataclass
class SolveResult:
    elaboration: ElaborateResult
    system: Any = None  # cyphy.semantics.dynamics.equations.System
    reduced: Any = None  # cyphy.semantics.dynamics.reduce.Reduced
    closed_form: dict[str, Any] | None = None

    @property
    def report(self) -> Report:
        return self.elaboration.report


@deep
def solve(paths: Sequence[str | Path], options: SolveOptions = SolveOptions()) -> SolveResult:
    """Assemble the model's equations (optionally with one mapping call), reduce them to
    explicit ODEs with SymPy and, where SymPy finds one, give the closed form."""
    # lazy: NumPy, SymPy: `cyphy check` must not pay for it
    from cyphy.semantics.dynamics.closed_form import closed_form
    from cyphy.semantics.dynamics.obstacles import report_obstacles
    from cyphy.semantics.dynamics.reduce import reduce_system
    from cyphy.semantics.dynamics.equations import AssemblyError, assemble, mapping_operation

    elaborated = elaborate(paths, ElaborateOptions(
        options.model, options.consts, options.search_paths,
        default_inertial=options.default_inertial))
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
        result.system = assemble(model, list(options.elements) or None, mapping, call, params,
                                 options.gravity, definitions=True,
                                 floating_base=options.floating_base)
    except AssemblyError as err:
        # lazy: NumPy: `cyphy check` must not pay for it
        from cyphy.semantics.dynamics.equations import ASSEMBLY

        report.report(getattr(err, "code", ASSEMBLY), err.message, err.span, err.hint)
        return result
    result.reduced = reduce_system(result.system)
    report_obstacles(result.reduced, report)
    free = [p for p in result.reduced.parameters if result.system.parameters.get(p) is None]
    if options.closed_form and not free and result.reduced.states \
            and not result.reduced.obstacles and not result.reduced.definitions:
        inputs = {f"der_{n}": 0 for n in result.system.inputs}
        result.closed_form = closed_form(result.reduced, inputs)
    return result
