"""The d-model's state machine as the scenario's controller (a scenario without
``[controller]``): the machine is chosen (the one the mapped module's controller runs, or
``machine = NAME`` / ``--machine NAME``), compiled under RoboSim's cycle semantics
(:mod:`cyphy.semantics.machine_automaton`), and written into the scenario's ``initial``,
``states`` (mode → calls) and ``transitions`` (guards: conjunctions of event literals), the
structure a ``[controller]`` table gives, so the export treats both alike."""

from __future__ import annotations

from typing import Any

from cyphy.diagnostics import Report, Span
from cyphy.flowstar.scenario import Scenario, Transition


def machine_controller(check: Any, pmodel: str, scenario: Scenario, report: Report) -> bool:
    """Fill the scenario's controller from the d-model's machine; False (with diagnostics)
    when there is none to choose, or it cannot be compiled."""
    from cyphy.flowstar.export import EXPORT
    from cyphy.lang.scopes import Scopes
    from cyphy.model.machines import global_constants, select_machine
    from cyphy.semantics.machine import MachineError, MachineInterpreter
    from cyphy.semantics.machine_automaton import compile_machine

    files = list(check.workspace.user_files())
    span = scenario.span("machine") if scenario.machine else Span(scenario.path, 1, 1, 1, 2)
    machine, problem = select_machine(files, check.resolution, pmodel, scenario.machine)
    if machine is None:
        message, hint = problem
        report.report(EXPORT, message if scenario.machine else
                      f"the scenario has no [controller], and {message}", span, hint)
        return False
    consts = {n: v for n, v in scenario.consts.items() if "::" not in n and
              isinstance(v, (int, float)) and not isinstance(v, bool)}
    try:
        interpreter = MachineInterpreter(
            machine, {**global_constants(machine, Scopes(check.workspace)), **consts})
        automaton = compile_machine(interpreter)
    except MachineError as err:
        report.report(EXPORT, f"state machine {machine.name}: {err.message}", err.span,
                      err.hint)
        return False
    scenario.initial = automaton.initial
    scenario.states = {mode.name: tuple(_call_text(n, args) for n, args in mode.calls)
                       for mode in automaton.modes}
    scenario.transitions = [
        Transition(e.source, e.target, e.guard[0][0] if e.guard else "",
                   e.guard[0][1] if e.guard else False, machine.decl.span, e.guard[1:])
        for e in automaton.edges]
    return True


def _call_text(name: str, args: tuple[float, ...]) -> str:
    return f"{name}({', '.join(repr(float(a)) for a in args)})"
