"""The d-model's state machine as the scenario's controller (a scenario without
``[controller]``): the machine is chosen (the one the mapped module's controller runs, or
``machine = NAME`` / ``--machine NAME``), compiled under RoboSim's cycle semantics
(:mod:`cyphy.semantics.machines.automaton`), and written into the scenario's ``initial``,
``states`` (mode → calls) and ``transitions`` (guards: conjunctions of event literals), the
structure a ``[controller]`` table gives, so the export treats both alike. The interpreter
itself is returned too: ``cyphy simulate`` runs it, cycle by cycle, as the sampled controller.
The operation definitions the machine calls run inside it; its output events that the
mapping maps act like calls, the others are observable only (``interpreter.observable``).
A machine that reads typed input events has no automaton (it knows events as present or
absent): ``reach`` refuses it, ``simulate`` runs its interpreter alone
(:mod:`cyphy.verify.flowstar.typed_events`)."""

from __future__ import annotations

import tomllib
from typing import TYPE_CHECKING, Any

from cyphy.diagnostics import Report, Span
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import select_machines
from cyphy.semantics.machines.cycle import MachineError
from cyphy.semantics.machines.interpreters import interpreter_for, machine_constants
from cyphy.semantics.machines.parallel import ModuleInterpreter, compile_module
from cyphy.verify.flowstar.scenario import EXPORT, Scenario, Transition

if TYPE_CHECKING:
    from cyphy.semantics.machines.cycle import MachineInterpreter


def machine_controller(check: Any, pmodel: str, scenario: Scenario, report: Report,
                       sampled: bool = False
                       ) -> "MachineInterpreter | ModuleInterpreter | None":
    """Fill the scenario's controller from the d-model's machine and return the machine's
    interpreter (reset to its start); None (with diagnostics) when there is none to choose,
    or it cannot be compiled.

    A machine that reads typed input events is not compiled: the automaton knows an event
    as present or absent, not the value ``$e?x`` binds. With ``sampled`` (``simulate``,
    whose controller is the interpreter itself) the interpreter is returned and the
    scenario's controller is left empty (the caller then takes the events the machines read
    and every operation they may call from the machines); without it (``reach``,
    ``gen --flowstar``) the machine is refused. So is, for ``sampled``, a machine the
    automaton cannot hold (a first cycle that reads the inputs, too many configurations):
    the interpreter runs it."""
    files = list(check.workspace.user_files())
    span = scenario.span("machine") if scenario.machine else Span(scenario.path, 1, 1, 1, 2)
    machines, problem = select_machines(files, check.resolution, pmodel, scenario.machine)
    if not machines:
        message, hint = problem
        report.report(EXPORT, message if scenario.machine else
                      f"the scenario has no [controller], and {message}", span, hint)
        return None
    consts = machine_constants(scenario.consts)
    machine = machines[0]
    try:
        interpreters = []
        for machine in machines:
            interpreters.append(interpreter_for(machine, files, check.resolution,
                                                Scopes(check.workspace), consts, pmodel))
        typed = typed_events(interpreters)
        if typed and not sampled:
            names = ", ".join(typed)
            machine = next(i.machine for i in interpreters if typed_events([i]))
            raise MachineError(
                f"the typed input event{'s' if len(typed) > 1 else ''} {names} cannot be "
                "written for Flow*: its automaton models an event as present or absent, not "
                "the value the machine reads", machine.decl.span,
                "`cyphy simulate` runs this machine with the events' values (its interpreter "
                "is the controller); for reach, make the events untyped")
        automaton = None if typed else _compiled(interpreters, sampled)
        # the module's machines run together, every cycle (one machine: itself)
        interpreter = interpreters[0] if len(interpreters) == 1 else \
            ModuleInterpreter(interpreters)
    except MachineError as err:
        # the compilation of a module reports at the machine it cannot compile
        name = next((m.name for m in machines if m.decl.span == err.span), machine.name)
        report.report(EXPORT, f"state machine {name}: {err.message}", err.span, err.hint)
        return None
    if not _same_cycle(interpreter, scenario, report):
        return None
    if automaton is None:  # sampled: the interpreter alone is the controller
        interpreter.reset()
        return interpreter
    scenario.initial = automaton.initial
    scenario.states = {mode.name: tuple(_call_text(n, args) for n, args in mode.calls)
                       for mode in automaton.modes}
    scenario.transitions = [_transition(e, machine.decl.span) for e in automaton.edges]
    # a first cycle that reads the events: where it ends, per combination (the export
    # decides which combinations the initial set allows: cyphy.verify.flowstar.first_cycle)
    scenario.first = [_transition(e, machine.decl.span) for e in automaton.first]
    interpreter.reset()  # the compilation explored its configurations
    return interpreter


def _transition(e: Any, span: Span) -> Transition:
    """An edge of the automaton as a scenario's transition (its guard's first literal
    as ``event``, the rest as ``conjuncts``)."""
    return Transition(e.source, e.target, e.guard[0][0] if e.guard else "",
                      e.guard[0][1] if e.guard else False, span, e.guard[1:])


def _compiled(interpreters: "list[MachineInterpreter]", sampled: bool) -> Any:
    """The module's automaton; for ``sampled``, None (the interpreter runs the machines)
    when they cannot be compiled, which a run of the interpreter does not need. Without
    ``sampled`` (``reach``, ``gen --flowstar``) a first cycle that reads the input events is
    compiled too (``Automaton.first``); ``simulate``'s interpreter runs such a machine
    itself."""
    # lazy: NumPy, as the rest of this module imports the machines' semantics
    from cyphy.semantics.machines.cycle import MachineError

    try:
        return compile_module(interpreters, first_cycle=not sampled)
    except MachineError:
        if not sampled:
            raise
        return None


def _same_cycle(interpreter: "MachineInterpreter", scenario: Scenario, report: Report
                ) -> bool:
    """The controller runs every ``cycle × tscale`` seconds with the machine's own cycle
    (``cycleDef cycle == k``): a scenario without ``cycle`` takes it; one that gives another
    is reported, as is a cycle that is not a whole number of time units."""
    period = interpreter.period
    name = interpreter.machine.name
    if period != int(period):
        report.report(EXPORT, f"the cycle of {name} is {period:g} time units; the scenario's "
                      "cycle must be a whole number of them", interpreter.machine.decl.span,
                      "give the machine a whole cycle (cycleDef cycle == 1) and scale time "
                      "with the scenario's tscale")
        return False
    if "cycle" not in tomllib.loads(scenario.text):
        scenario.cycle = int(period)
    elif scenario.cycle != int(period):
        report.report(EXPORT, f"cycle = {scenario.cycle}, but {name} runs every "
                      f"{int(period)} time unit{'s' if period != 1 else ''} "
                      f"(cycleDef cycle == {int(period)})", scenario.span("cycle"),
                      f"remove 'cycle' (the machine's is used) or write cycle = {int(period)}")
        return False
    return True


def _call_text(name: str, args: tuple[float, ...]) -> str:
    return f"{name}({', '.join(repr(float(a)) for a in args)})"


def typed_events(interpreters: "list[MachineInterpreter]") -> list[str]:
    """The typed input events of the input contexts of the machines (and of the operation
    definitions they call), in the order first declared."""
    out: dict[str, None] = {}
    for i in interpreters:
        for m in [i.machine, *i.operations.values()]:
            out.update((e, None) for e, d in m.platform.input_events.items()
                       if d.type is not None and e not in i.machine.unconnected)
    return list(out)
