"""The hybrid automaton of a p-model under a scenario, as data: the reduced ODEs, the
actuator inputs the controller's calls set, the events and the unsafe set, in SymPy.

:mod:`cyphy.verify.flowstar.build` makes a :class:`Problem` from the model and the scenario;
:mod:`cyphy.verify.flowstar.export` writes it as Flow* text, and the checker, the invariant
search and the simulator read it. It lives apart from both so that readers of a problem need
neither the elaboration nor the printer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import sympy

from cyphy.verify.flowstar.constraints import dnf
from cyphy.verify.flowstar.scenario import Scenario


TIMER, CLOCK = "timer", "t"


@dataclass
class Problem:
    """Everything the automaton is made of, in SymPy (plain real symbols by name)."""

    name: str  # the p-model
    scenario: Scenario
    states: list[str]  # the reduced ODEs' states (environment-driven inputs included)
    rhs: dict[str, Any]  # state → f(states, actuator inputs, t)
    inputs: list[str]  # actuator inputs set by calls
    outputs: dict[str, Any]  # algebraic variables as functions of the states and inputs
    effects: dict[str, dict[str, Any]]  # controller state → actuator input → value
    events: dict[str, Any]  # event name → predicate over the states and inputs
    unsafe: Any  # the unsafe set's conjunction
    qualified: dict[str, str] = field(default_factory=dict)  # mangled → qualified name
    call_effects: dict[str, dict[str, Any]] = field(default_factory=dict)  # call → input → value
    # The d-model's state machine when it is the controller (a MachineInterpreter), and the
    # effect of each operation it may call, for any arguments: operation → (parameter
    # symbols, actuator input → value in them), from the mapping's equations.
    machine: Any = None
    operation_effects: dict[str, tuple[tuple[Any, ...], dict[str, Any]]] = \
        field(default_factory=dict)
    # A typed input event's value when it occurs (a machine run by its interpreter, not
    # compiled): event → the mapping's parameter as a function of the states and inputs.
    event_values: dict[str, Any] = field(default_factory=dict)
    # The events a machine's first cycle reads (kept once the initial set has decided it:
    # :func:`cyphy.verify.flowstar.first_cycle.settle`), for the verdict's account.
    first_events: tuple[str, ...] = ()

    @property
    def mode_inputs(self) -> list[str]:
        """Inputs every controller state sets: constants of each mode."""
        return [u for u in self.inputs if all(u in e for e in self.effects.values())]

    @property
    def held_inputs(self) -> list[str]:
        """Inputs some state leaves alone: state variables with derivative 0."""
        return [u for u in self.inputs if u not in self.mode_inputs]

    def disjuncts(self) -> list["Problem"]:
        """One problem per disjunct of the unsafe set (Flow* checks one conjunction per
        run): the system is safe when it avoids every one."""
        variables = {symbol(n) for n in [*self.states, *self.inputs, TIMER, CLOCK]}
        conjunctions = dnf(self.unsafe, variables)
        if len(conjunctions) <= 1:
            return [self]
        return [replace(self, unsafe=sympy.And(*[a.relation() for a in c]))
                for c in conjunctions]

    @property
    def final_states(self) -> set[str]:
        """Controller states no transition leaves. Their cycles change nothing: the calls
        re-set the same inputs, and only the timer is reset. Such a mode flows to the
        horizon without the timer's invariant and jumps: every jump costs Flow* precision
        (the enclosure grows at each), so this is what lets a stopped robot be proved at
        rest. Not done when the unsafe set reads the timer, whose values it changes."""
        if symbol(TIMER) in self.unsafe.free_symbols:
            return set()
        leaving = {t.source for t in self.scenario.transitions if t.target != t.source}
        return {state for state in self.effects if state not in leaving}

    @property
    def max_jumps(self) -> int:
        required = self.required_jumps
        given = self.scenario.settings.max_jumps
        return required if given is None else given

    @property
    def required_jumps(self) -> int:
        """One jump per cycle over the horizon, and one more (spec §5); one more again for
        the jump at time 0 out of the start mode of an undecided first cycle
        (:mod:`cyphy.verify.flowstar.first_cycle`)."""
        return math.ceil(self.scenario.horizon / self.scenario.period - 1e-9) + 1 + \
            (1 if self.scenario.first else 0)


def symbol(name: str) -> Any:
    return sympy.Symbol(name, real=True)



def mode_values(p: Problem, mode: str) -> dict[Any, Any]:
    """The actuator inputs that are constants of ``mode``, as a substitution."""
    return {symbol(u): p.effects[mode][u] for u in p.mode_inputs}


def initial_interval(p: Problem, name: str) -> tuple[Any, Any]:
    """The initial interval of a state or held input: the scenario's, else (a held input)
    the value the initial state's calls give it."""
    s = p.scenario
    for n, v in s.init.items():
        if n == name or p.qualified.get(name) in (n, f"{p.name}::{n}"):
            return v
    # _check_init saw that the initial state (or, for a first cycle that reads the events,
    # every state it may end in) sets every other held input: the value before it is then
    # never read, and the first such state's is given
    setters = [t.target for t in s.first] or [s.initial]
    initial = next((p.effects[m] for m in setters if name in p.effects[m]), p.effects[s.initial])
    return initial[name], initial[name]
