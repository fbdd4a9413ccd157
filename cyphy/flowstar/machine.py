"""The d-model's state machine as the scenario's controller (a scenario without
``[controller]``): the machine is chosen (the one the mapped module's controller runs, or
``machine = NAME`` / ``--machine NAME``), compiled under RoboSim's cycle semantics
(:mod:`cyphy.semantics.machine_automaton`), and written into the scenario's ``initial``,
``states`` (mode → calls) and ``transitions`` (guards: conjunctions of event literals), the
structure a ``[controller]`` table gives, so the export treats both alike."""

from __future__ import annotations

from typing import Any

from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.flowstar.scenario import Scenario, Transition
from cyphy.lang import ast


def machine_controller(check: Any, pmodel: str, scenario: Scenario, report: Report) -> bool:
    """Fill the scenario's controller from the d-model's machine; False (with diagnostics)
    when there is none to choose, or it cannot be compiled."""
    from cyphy.flowstar.export import EXPORT
    from cyphy.lang.scopes import Scopes
    from cyphy.model.machines import global_constants, machines_of
    from cyphy.semantics.machine import MachineError, MachineInterpreter
    from cyphy.semantics.machine_automaton import compile_machine

    files = list(check.workspace.user_files())
    machines = machines_of(files, check.resolution)
    running = _run_by_mapped_module(files, check.resolution, pmodel)
    span = scenario.span("machine") if scenario.machine else Span(scenario.path, 1, 1, 1, 2)
    if scenario.machine is not None:
        chosen = [m for m in machines if m.name == scenario.machine]
        if not chosen:
            report.report(EXPORT, f"no state machine '{scenario.machine}' among the files",
                          span, did_you_mean(scenario.machine, [m.name for m in machines])
                          or "machines: " + (", ".join(m.name for m in machines) or "(none)"))
            return False
    else:
        chosen = [m for m in machines if id(m.decl) in running] or machines
        if len(chosen) != 1:
            names = ", ".join(m.name for m in chosen)
            report.report(EXPORT, "the scenario has no [controller], and " + (
                f"the d-model has several state machines ({names})" if chosen else
                "the files have no state machine to use instead"), span,
                "name one with --machine NAME (or machine = \"NAME\" in the scenario)"
                if chosen else "add the d-model's files, or a [controller] table")
            return False
    machine = chosen[0]
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


def _run_by_mapped_module(files: list[ast.SourceFile], resolution: Any, pmodel: str
                          ) -> set[int]:
    """Ids of the machines that the controllers of the module mapped onto ``pmodel`` run."""
    out: set[int] = set()
    for f in files:
        for mapping in f.items:
            if not (isinstance(mapping, ast.PlatformMapping) and mapping.pmodel[-1] == pmodel):
                continue
            module = resolution.get(mapping)
            if not isinstance(module, ast.Module):
                continue
            controllers = [c for c in module.members if isinstance(c, ast.Controller)]
            controllers += [resolution.get(r) for r in module.members
                            if isinstance(r, ast.NodeRef) and r.kind == "cref"]
            for c in controllers:
                if not isinstance(c, ast.Controller):
                    continue
                out.update(id(m) for m in c.machines)
                out.update(id(resolution.get(r)) for r in c.machine_refs)
    return out
