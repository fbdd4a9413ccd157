"""Two independent simulations of a Flow* scenario, for the tests (SciPy).

``interpret`` runs an exported model file from one initial point with the package's
simulator (:mod:`cyphy.verify.flowstar.simulate`: flows by their ODE text, invariants as terminal
events, then the first jump in file order whose guard holds, its resets applied
simultaneously). ``simulate_direct`` runs the same scenario from the elaborated model's
reduced equations and the scenario's controller without any of the exporter's rendering:
cycle by cycle, events evaluated as the mapping's predicates, transitions in the scenario's
order, actuator inputs set by the calls of the state entered.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy
from scipy.integrate import solve_ivp

from cyphy import expr as ex
from cyphy.translate.to_sympy import to_sympy
from cyphy.verify.flowstar.simulate import Automaton
from cyphy.verify.flowstar.syntax import FlowModel

RTOL, ATOL = 1e-11, 1e-12


def _sym(name: str) -> Any:
    return sympy.Symbol(name, real=True)


def _expr(e: ex.Expr, params: dict[str, float]) -> Any:
    names = {n.text: _sym(n.text) for n in e.walk() if isinstance(n, ex.Name)}
    value = to_sympy(e, symbols=names)
    return value.xreplace({_sym(k): sympy.Float(v) for k, v in params.items()})


def interpret(text: str, point: dict[str, float], samples: np.ndarray) -> dict[str, np.ndarray]:
    """Values of every state variable at the sample times (the automaton's global time),
    from ``point`` (the middle of the model's initial box where it says nothing), by the
    package's simulator of model files."""
    automaton = Automaton(text)
    model: FlowModel = automaton.model
    start = {v: (float(lo) + float(hi)) / 2 for v, (lo, hi) in model.init.items()}
    start.update(point)  # variables the model leaves out of init start at 0 (spec §4.7)
    return automaton.sample({v: start.get(v, 0.0) for v in model.variables}, samples)


def simulate_direct(problem: Any, point: dict[str, float], samples: np.ndarray
                    ) -> dict[str, np.ndarray]:
    """The scenario run straight from the reduced equations (``problem`` is the exporter's
    :class:`~cyphy.verify.flowstar.problem.Problem`: its ODEs, call effects and event predicates in
    SymPy), one cycle at a time."""
    s = problem.scenario
    states, inputs = problem.states, problem.inputs
    t = _sym("t")
    syms = [_sym(v) for v in states] + [_sym(u) for u in inputs] + [t]
    rhs = sympy.lambdify(syms, [problem.rhs[x] for x in states], "numpy")
    events = {name: sympy.lambdify(syms, pred, "numpy") for name, pred in problem.events.items()}
    controller = s.initial
    u = {name: float(point.get(name, 0.0)) for name in inputs}
    u.update({k: float(v) for k, v in problem.effects[controller].items()})
    x = np.array([point[v] for v in states], dtype=float)
    out = {v: np.full(len(samples), np.nan) for v in states}
    period, k = s.period, 0
    while k * period < s.horizon - 1e-12:
        start, end = k * period, min((k + 1) * period, s.horizon)
        args = [u[n] for n in inputs]
        sol = solve_ivp(lambda tt, y: np.asarray(rhs(*y, *args, tt), dtype=float),
                        (start, end), x, method="DOP853", rtol=RTOL, atol=ATOL,
                        dense_output=True)
        inside = (samples >= start) & (samples <= end)
        for i, v in enumerate(states):
            out[v][inside] = sol.sol(samples[inside])[i]
        x, k = sol.y[:, -1], k + 1
        values = [*x, *[u[n] for n in inputs], end]
        for tr in s.transitions:
            if tr.source != controller:
                continue
            occurs = bool(events[tr.event](*values))
            if occurs != tr.negated:
                controller = tr.target
                break
        u.update({name: float(v) for name, v in problem.effects[controller].items()})
    return out
