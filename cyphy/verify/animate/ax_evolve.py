"""The axiomatic dialect's ``[Λ x` = e, …]``: an explicit ODE whose frame is its primed
variables; every other variable it reads keeps its value during the evolution (it enters
the system as a state of rate 0, so a call's new set-point is read at the next Evolve).

Also what the axiomatic main action says of the values it leaves open until its first
re-establishing assignment (``Range_range := Range_distance``), and the rate the animator
chooses for a world input (``cSpec rates (True)_e (True)_e``: any value)."""

from __future__ import annotations

from typing import Any, Callable

from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.evolve import OdeSystem
from cyphy.verify.animate.terms import Unsupported, evaluate


def _reads(node: Any) -> set[str]:
    return {str(n.children[0]) for n in node.iter_subtrees() if n.data == "state"}


def explicit(odes: Any, state: dict[str, Any], constant: Callable[[str], Any], t: Any,
             where: Any) -> OdeSystem:
    """The ODE of ``odes`` from the current ``state`` (None: not given a value yet)."""
    import sympy  # lazy: the rates are compiled with SymPy

    rhs = {str(o.children[0]): o.children[1] for o in odes.children}
    read = set().union(*(_reads(e) for e in rhs.values())) if rhs else set()
    running = {x for x in rhs if state.get(x) is not None}
    unset_read = sorted(x for x in read if state.get(x) is None
                        and any(x in _reads(rhs[y]) for y in running))
    if unset_read:
        raise AnimateError("E-ANIMATE-OPEN", f"{where.name} reads {unset_read[0]}, which no "
                           "action has given a value", path=where.path, line=where.line,
                           status=1, hint="a world input is given with --input NAME=EXPR")
    differential = [x for x in state if state[x] is not None and (x in rhs or x in read)]
    ys = [sympy.Symbol(x) for x in differential]
    symbols = dict(zip(differential, ys))

    def value(x: str) -> Any:
        return symbols[x]

    def name(x: str) -> Any:
        try:
            return constant(x)
        except KeyError:
            raise AnimateError("E-ANIMATE-CONST", f"{where.name} reads the constant {x}, "
                               "which has no value", path=where.path, line=where.line,
                               hint=f"give it with --const {x}=VALUE", status=1) from None

    try:
        exprs = [evaluate(rhs[x], value, _no_rate, name) if x in rhs else 0
                 for x in differential]
    except Unsupported as err:
        raise AnimateError("E-ANIMATE-UNSUPPORTED", f"{where.name}: animate does not run "
                           f"{err}", path=where.path, line=where.line, status=2) from None
    rates = sympy.lambdify((t, ys), [sympy.sympify(e) for e in exprs], modules="math",
                           cse=True)
    undetermined = sorted(x for x in rhs if x not in running)
    return OdeSystem(differential, lambda tt, y: rates(tt, y), {}, undetermined,
                     dict(symbols), t, ys)


def _no_rate(x: str) -> Any:
    raise Unsupported(f"the rate of {x} on an equation's right")


def ties(definitions: list[Any]) -> dict[str, Any]:
    """Each variable an assignment of the p-model's actions re-establishes from the state
    (an algebraic output from its definition): variable → that expression."""
    out: dict[str, Any] = {}
    for definition in definitions:
        for node in definition.tree.iter_subtrees():
            if node.data not in ("assign", "assign_one"):
                continue
            names = [str(c) for c in node.children if not hasattr(c, "data")]
            exprs = [c for c in node.children if hasattr(c, "data")]
            for x, e in zip(names, exprs):
                if _reads(e):
                    out.setdefault(x, e)
    return out


def input_rate(expr: Any, t_sym: Any, t: float, state: dict[str, Any],
               system: OdeSystem, now: list[float]) -> float:
    """d/dt of a world input's ``--input`` expression now: its partial in t and, through
    the chain rule, Evolve's rates of the states it reads (exact for one linear in t)."""
    import sympy  # lazy: as above
    rates = dict(zip(system.states, system.rates(t, now)))
    total = sympy.diff(expr, t_sym)
    for s in expr.free_symbols - {t_sym}:
        if str(s) not in rates:
            raise AnimateError("E-ANIMATE-OPEN", f"the input reads {s}, whose rate Evolve "
                               "does not give", status=1)
        total += sympy.diff(expr, s) * rates[str(s)]
    subs = {sympy.Symbol(k): v for k, v in state.items() if v is not None}
    subs[t_sym] = t
    return float(sympy.sympify(total).subs(subs))
