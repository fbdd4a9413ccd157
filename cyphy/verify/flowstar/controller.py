"""A scenario's ``[controller]`` table as a sampled controller object, for ``cyphy simulate
--scenario`` (issue 16), with the timing ``cyphy gen --flowstar`` gives it: the initial state's
calls act from time 0; at the end of every cycle the input events are sampled, the first
transition (in file order) out of the current state whose ``when`` holds is taken, and the
calls of the state entered act until the next cycle.

The object has the interface of :class:`cyphy.backends.simulate.Controller`
(``cycle(events) -> calls``), which a RoboSim state-machine interpreter can share.
"""

from __future__ import annotations

from typing import Any, Mapping

from cyphy.verify.flowstar.scenario import Scenario

Calls = tuple[tuple[str, tuple[float, ...]], ...]


def parse_calls(texts: tuple[str, ...], consts: Mapping[str, Any]) -> Calls:
    """``("drive(10)", "stop()")`` → ``(("drive", (10.0,)), ("stop", ()))``; arguments may
    name the scenario's ``[consts]``. Raises ``ValueError`` for an argument without a value."""
    import sympy  # lazy: SymPy (0.5-1 s); `simulate --numeric` loads this module, parses no call

    from cyphy.translate.to_sympy import to_sympy  # lazy: SymPy, as above
    # lazy: the assembly of equations, which `simulate --numeric` does not need either
    from cyphy.semantics.dynamics.equations import parse_call

    values = {sympy.Symbol(n, real=True): v for n, v in consts.items()
              if isinstance(v, (int, float)) and not isinstance(v, bool)}
    out = []
    for text in texts:
        call = parse_call(text)
        args = []
        for a in call.args:
            value = sympy.sympify(to_sympy(a)).xreplace(values)
            if not value.is_number:
                raise ValueError(f"the call {text} has an argument without a value: {value}")
            args.append(float(value))
        out.append((call.func.text, tuple(args)))  # type: ignore[attr-defined]
    return tuple(out)


class ScenarioController:
    """The ``[controller]`` table: its states, calls and transitions."""

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.state = scenario.initial
        self.calls = {name: parse_calls(calls, scenario.consts)
                      for name, calls in scenario.states.items()}
        self._started = False

    def cycle(self, events: Mapping[str, object]) -> Calls:
        """The calls of this cycle; the first cycle (time 0) only performs the initial
        state's calls, later ones first take the transition whose ``when`` holds."""
        if self._started:
            for t in self.scenario.transitions:
                if t.source != self.state:
                    continue
                present = events.get(t.event) is not None
                if present != t.negated:
                    self.state = t.target
                    break
        self._started = True
        return self.calls[self.state]


class CallEffects:
    """What a controller's calls do to the actuator inputs, applied in order: each call's
    solved mapping equations (``Problem.call_effects``: the calls the scenario's states
    issue) and, for a state machine, each operation's equations solved for any arguments
    (``Problem.operation_effects``), so that a machine whose cycles compute their
    arguments runs too."""

    def __init__(self, call_effects: Mapping[str, Mapping[str, Any]],
                 consts: Mapping[str, Any],
                 operations: Mapping[str, tuple[tuple[Any, ...], Mapping[str, Any]]]
                 | None = None) -> None:
        self.table = {parse_calls((text,), consts)[0]: {u: float(v) for u, v in values.items()}
                      for text, values in call_effects.items()}
        self.operations = dict(operations or {})

    def __call__(self, calls: Calls) -> dict[str, float]:
        out: dict[str, float] = {}
        for call in calls:
            key = (call[0], tuple(float(a) for a in call[1]))
            if key in self.table:
                out.update(self.table[key])
            elif key[0] in self.operations and \
                    len(self.operations[key[0]][0]) == len(key[1]):
                params, values = self.operations[key[0]]
                bound = dict(zip(params, key[1]))
                out.update({u: float(v.xreplace(bound)) for u, v in values.items()})
            else:
                known = ", ".join([f"{op}({', '.join(f'{a:g}' for a in args)})"
                                   for op, args in sorted(self.table)] +
                                  [f"{op}(…)" for op in sorted(self.operations)])
                raise ValueError(f"the call {call[0]}{call[1]} has no effect the mapping "
                                 f"determines (solved: {known})")
        return out
