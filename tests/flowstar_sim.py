"""Two independent simulations of a Flow* scenario, for the tests (SciPy).

``interpret`` reads an exported model file with our Flow* grammar and runs the hybrid
automaton it describes from one initial point: flows by their ODE text, invariants as
terminal events, then the first jump (in file order) whose guard holds, its resets applied
simultaneously. ``simulate_direct`` runs the same scenario from the elaborated model's
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
from cyphy.backends.sympy import to_sympy
from cyphy.flowstar.syntax import FlowModel, parse_model

RTOL, ATOL = 1e-11, 1e-12


def _sym(name: str) -> Any:
    return sympy.Symbol(name, real=True)


def _expr(e: ex.Expr, params: dict[str, float]) -> Any:
    names = {n.text: _sym(n.text) for n in e.walk() if isinstance(n, ex.Name)}
    value = to_sympy(e, symbols=names)
    return value.xreplace({_sym(k): sympy.Float(v) for k, v in params.items()})


def interpret(text: str, point: dict[str, float], samples: np.ndarray) -> dict[str, np.ndarray]:
    """Values of every state variable at the sample times (the automaton's global time),
    from ``point`` (the middle of the model's initial box where it says nothing)."""
    model: FlowModel = parse_model(text)
    params = {k: float(v) for k, v in model.params.items()}
    variables = model.variables
    syms = [_sym(v) for v in variables]
    horizon = float(model.settings["time"])
    max_jumps = int(model.settings["max jumps"])

    def bound(b: str) -> float:
        return params[b] if b in params else float(b)

    flows, invariants = {}, {}
    for name, mode in model.modes.items():
        exprs = [_expr(mode.flow[v], params) if v in mode.flow else sympy.Integer(0)
                 for v in variables]
        flows[name] = sympy.lambdify(syms, exprs, "numpy")
        invariants[name] = [(sympy.lambdify(syms, _expr(c.lhs, params)), c.rel,
                             bound(c.bounds[0])) for c in mode.invariant]
    jumps = []
    for j in model.jumps:
        guard = [(sympy.lambdify(syms, _expr(c.lhs, params)), c.rel, bound(c.bounds[0]))
                 for c in j.guard]
        resets = {v: sympy.lambdify(syms, _expr(r, params)) for v, r in j.resets.items()}
        jumps.append((j.source, j.target, guard, resets))

    def holds(cons: list, x: np.ndarray) -> bool:
        for f, rel, b in cons:
            v = float(f(*x)) - b
            tol = 1e-9 * max(1.0, abs(b))
            if (rel == "<=" and v > tol) or (rel == ">=" and v < -tol) or \
                    (rel == "=" and abs(v) > tol):
                return False
        return True

    mode = model.initial_mode
    start = {v: (float(lo) + float(hi)) / 2 for v, (lo, hi) in model.init.items()}
    start.update(point)  # variables the model leaves out of init start at 0 (spec §4.7)
    x = np.array([start.get(v, 0.0) for v in variables], dtype=float)
    now, count = 0.0, 0
    out = {v: np.full(len(samples), np.nan) for v in variables}
    while now < horizon - 1e-12:
        events = []
        for f, rel, b in invariants[mode]:
            if rel != "<=":
                raise NotImplementedError("only upper-bound invariants are interpreted")
            ev = (lambda t, y, f=f, b=b: float(f(*y)) - b)
            ev.terminal, ev.direction = True, 1
            events.append(ev)
        flow = flows[mode]
        sol = solve_ivp(lambda t, y: np.asarray(flow(*y), dtype=float), (now, horizon), x,
                        method="DOP853", rtol=RTOL, atol=ATOL, events=events,
                        dense_output=True)
        end = sol.t[-1]
        inside = (samples >= now) & (samples <= end)
        for k, v in enumerate(variables):
            out[v][inside] = sol.sol(samples[inside])[k]
        now, x = end, sol.y[:, -1]
        if now >= horizon - 1e-12:
            break
        taken = next(((t, r) for s, t, g, r in jumps if s == mode and holds(g, x)), None)
        if taken is None or count >= max_jumps:
            break
        target, resets = taken
        new = x.copy()
        for v, f in resets.items():
            new[variables.index(v)] = float(f(*x))
        x, mode, count = new, target, count + 1
    return out


def simulate_direct(problem: Any, point: dict[str, float], samples: np.ndarray
                    ) -> dict[str, np.ndarray]:
    """The scenario run straight from the reduced equations (``problem`` is the exporter's
    :class:`~cyphy.flowstar.export.Problem`: its ODEs, call effects and event predicates in
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
