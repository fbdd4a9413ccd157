"""``simulate``: a p-model's equations integrated with SciPy, alone or under a scenario."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from cyphy import codes
from cyphy.deep import deep
from cyphy.diagnostics import Report, Span
from cyphy.model.machines import select_machines
from cyphy.pipeline.check import CheckResult
from cyphy.pipeline.elaborate import ElaborateOptions, ElaborateResult, elaborate
from cyphy.verify.flowstar.controller import CallEffects, ScenarioController
from cyphy.verify.flowstar.scenario import SCENARIO, load_scenario


@dataclass(frozen=True)
class SimulateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    simulation: Any = None  # cyphy.backends.simulate.SimulationOptions (defaults when None)
    numeric: bool = False  # the kinematic tree alone, articulated-body algorithm
    scenario: str | None = None  # a Flow* scenario whose controller and environment run
    gravity: tuple[float, float, float] | None = None  # default −9.81 m/s² along z
    controller: Any = None  # with a scenario: a Controller run instead of its [controller]
    machine: str | None = None  # with a scenario without [controller]: the d-model machine
    default_inertial: str | None = None  # see ElaborateOptions (wins over the scenario's)
    floating_base: bool = False  # the root bodies free (six coordinates each), not fixed


@dataclass
class SimulateResult:
    elaboration: ElaborateResult
    trajectory: Any = None  # cyphy.backends.simulate.Trajectory
    numeric: bool = False  # whether the numeric (tree-only) path ran
    #: the d-model's machines that control the p-model but did not run (no scenario)
    idle_machines: tuple[str, ...] = ()

    @property
    def report(self) -> Report:
        return self.elaboration.report


@deep
def simulate(paths: Sequence[str | Path], options: SimulateOptions = SimulateOptions()
             ) -> SimulateResult:
    """Integrate the model's explicit ODEs (``cyphy solve``'s, the equations of motion as
    named definitions, for trees of any size) with SciPy, or, with ``numeric``, the
    kinematic tree alone with the numeric articulated-body algorithm. With a ``scenario``
    (TOML, as for ``gen --flowstar``), its ``[controller]`` runs at the d-model cycle, its
    environment drives the sensor inputs and its ``[init]`` intervals start at their
    midpoints. A
    ``controller`` (:class:`cyphy.backends.simulate.Controller`, e.g. a state-machine
    interpreter) replaces the ``[controller]`` table; its calls must be among those the
    table's states issue, whose effects the scenario's problem solves. A scenario without
    ``[controller]`` runs the d-model's state machine (``machine`` names it when there are
    several), as ``reach`` does: its interpreter is the controller, one cycle per
    ``cycle × tscale`` seconds, and the mapping's operations give its calls' effects."""
    # lazy: NumPy, SciPy: `cyphy check` must not pay for it
    from cyphy.backends import simulate as sim
    from cyphy.semantics.dynamics import spatial
    from cyphy.semantics.dynamics import tree as dynamics
    from cyphy.semantics.dynamics.equations import ASSEMBLY, AssemblyError

    if options.scenario is not None:
        return _simulate_scenario(paths, options)
    elaborated = elaborate(paths, ElaborateOptions(
        options.model, options.consts, options.search_paths,
        default_inertial=options.default_inertial))
    result = SimulateResult(elaborated)
    model = elaborated.model
    if model is None:
        return result
    report = elaborated.report
    settings = options.simulation or sim.SimulationOptions()
    if not options.numeric:  # (the tree alone says so itself)
        result.idle_machines = _idle_machines(elaborated.check, model.name)
    try:
        numeric = options.numeric
        gravity = options.gravity or dynamics.STANDARD_GRAVITY
        several = options.floating_base or any(
            dynamics.DOF.get(dynamics.joint_kind(j), 1) > 1 for j in model.joints)
        tree = None
        if numeric or several:  # ZYX Euler angles must not start at their singularity
            tree = dynamics.kinematic_tree(model, gravity, options.floating_base)
            spatial.euler_singularity(tree, [float(settings.init.get(name, 0.0))
                                              for name in tree.coordinates("theta")])
            if numeric:
                result.numeric = True
                result.trajectory = sim.simulate_tree(tree, settings)
                return result
        # lazy: NumPy, SymPy: `cyphy check` must not pay for it
        from cyphy.semantics.dynamics.obstacles import report_obstacles
        from cyphy.semantics.dynamics.reduce import reduce_system
        from cyphy.semantics.dynamics.equations import assemble

        reduced = reduce_system(assemble(model, gravity=options.gravity, definitions=True,
                                         floating_base=options.floating_base))
        if reduced.obstacles:
            report_obstacles(reduced, report)
            return result
        if several:
            settings = dataclasses.replace(settings, pitches=sim.euler_pitches(tree))
        elif reduced.definitions:  # the tree's accelerations: Pinocchio evaluates them
            tree = dynamics.kinematic_tree(model, gravity, options.floating_base)
        result.trajectory = sim.simulate_reduced(reduced, settings,
                                                 tree=tree if reduced.definitions else None)
    except AssemblyError as err:
        report.report(getattr(err, "code", ASSEMBLY), err.message, err.span, err.hint)
    except sim.SimulationError as err:
        hint = err.hint
        if err.message.startswith("constants without a value"):
            qualified = sorted({f"{e.definition.split('::')[-1]}::{p.name}"
                                for e in [*model.joints, *model.sensors, *model.actuators]
                                if e.device is not None and e.definition
                                for p in e.device.ports if p.mangled in err.message}
                               & set(model.missing))
            if qualified:
                hint = "give them values: " + " ".join(f"--const {n}=VALUE" for n in qualified)
        span = getattr(model.pmodel, "span", None) or Span.unknown(str(paths[0]))
        if isinstance(err, sim.OptionError):
            report.report(codes.OPTION, err.message, Span.unknown("<command line>"), hint)
        else:
            report.report(sim.SIMULATE, err.message, span, hint)
    return result


def _idle_machines(check: CheckResult, pmodel: str) -> tuple[str, ...]:
    """The d-model's machines that control ``pmodel`` (as a scenario would choose them):
    without a scenario they do not run, since a cycle needs the scenario's ``tscale`` and
    initial values; the command says so rather than leave the run's flat inputs unexplained."""
    machines, _ = select_machines(list(check.workspace.user_files()), check.resolution, pmodel,
                                  None)
    return tuple(m.name for m in machines)


def _simulate_scenario(paths: Sequence[str | Path], options: SimulateOptions
                       ) -> SimulateResult:
    """The scenario's problem as ``gen --flowstar`` builds it (reduced ODEs with the
    environment, the effects of each state's calls, the events' predicates), integrated
    cycle by cycle under the ``[controller]`` table, or the d-model's state machine run by
    its interpreter (:mod:`cyphy.semantics.machines.cycle`) when the scenario has none."""
    # lazy: NumPy, SciPy, SymPy: `cyphy check` must not pay for it
    from cyphy.backends import simulate as sim
    from cyphy.semantics.machines.cycle import MACHINE, MachineError
    from cyphy.verify.flowstar.build import build_problem
    from cyphy.verify.flowstar.problem import CLOCK, TIMER, symbol

    report = Report()
    empty = ElaborateResult(CheckResult(None, report), None)  # type: ignore[arg-type]
    scenario = load_scenario(options.scenario, report,  # type: ignore[arg-type]
                             needs_unsafe=False)
    if scenario is None:
        return SimulateResult(empty)
    if options.model is not None:
        scenario.model = options.model
    if options.machine is not None:
        if scenario.states:
            report.report(SCENARIO, f"--machine {options.machine}: the scenario has a "
                          "[controller], which is the controller", scenario.span("controller"),
                          "remove the [controller] table to use the machine")
            empty.check.sources[scenario.path] = scenario.text
            return SimulateResult(empty)
        scenario.machine = options.machine
    scenario.consts.update(options.consts)
    if options.default_inertial is not None:
        scenario.default_inertial = options.default_inertial
    problem, sources = build_problem(paths, scenario, report, options.search_paths,
                                     sampled=True)
    empty.check.sources.update(sources)
    if problem is None:
        return SimulateResult(empty)
    settings = options.simulation or sim.SimulationOptions(t_end=scenario.horizon)
    init = {n: (lo + hi) / 2 for n, (lo, hi) in scenario.init.items()}
    init = {n: v for n, v in init.items() if n in problem.states}
    init.update(settings.init)
    settings = dataclasses.replace(settings, init=init)
    result = SimulateResult(empty)
    try:
        controller = options.controller or problem.machine or ScenarioController(scenario)
        effects = CallEffects(problem.call_effects, scenario.consts, problem.operation_effects)

        def events(t: float, values: dict[str, float]) -> dict[str, object]:
            """Each input event at the cycle's instant: ``None`` when its predicate is
            false, else ``True`` or, typed, its value (``Problem.event_values``)."""
            import sympy

            subs = {sympy.Symbol(n, real=True): v for n, v in values.items()}
            subs.update({symbol(CLOCK): t, symbol(TIMER): 0.0})  # a cycle's start
            out: dict[str, object] = {}
            for name, pred in problem.events.items():
                value = problem.event_values.get(name)
                if not bool(pred.xreplace(subs)):
                    out[name] = None
                elif value is None:
                    out[name] = True
                else:
                    number = complex(value.xreplace(subs))
                    if number.imag or not math.isfinite(number.real):
                        raise ValueError(f"the input event {name} occurs at t = {t:g} with "
                                         f"the value {value.xreplace(subs)}, not a finite "
                                         "real number")
                    out[name] = number.real
            return out

        reduced = dataclasses.make_dataclass("Problem", ["states", "rhs", "inputs", "outputs"])(
            problem.states, problem.rhs, problem.inputs, problem.outputs)
        result.trajectory = sim.simulate_reduced(
            reduced, settings, controller, effects, scenario.period, events,
            getattr(controller, "observable", frozenset()))
    except sim.OptionError as err:
        report.report(codes.OPTION, err.message, Span.unknown("<command line>"), err.hint)
    except MachineError as err:  # the machine's cycle at run time (a division by zero, …)
        name = getattr(getattr(problem.machine, "machine", None), "name", None)
        report.report(MACHINE, f"state machine {name}: {err.message}" if name else
                      err.message, err.span, err.hint)
    except (sim.SimulationError, ValueError) as err:
        report.report(sim.SIMULATE, getattr(err, "message", str(err)),
                      scenario.span("controller"), getattr(err, "hint", ""))
    return result
