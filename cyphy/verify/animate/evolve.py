"""``Evolve``'s equations as an explicit ODE: the rates of the differential states and the
values of the algebraic ones, solved from the conjunction the theory states.

A differential state is a variable whose rate (``$x\\<acute>``) Evolve names and that a discrete
action has given a value (Init, a call's assignment): the theory fixes where it starts. Every
other name of the equations is solved for: the algebraic state (sensor readings, joint outputs,
the rates of the others), the existential locals, the rates themselves. Solving is causal
first (an equation with one unknown left gives it), then SymPy's ``solve`` on what is left;
a variable no equation determines (a world input not given with ``--input``, a joint force
the equations leave open) stays undetermined, which is an error only when a rate needs it."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.terms import Unsupported, evaluate, op_name

RATE = "d__"  # prefix of a rate's symbol (no theory name starts with it: names start A-Za-z)


@dataclass
class OdeSystem:
    """The ODE one Evolve denotes under the current differential states."""

    states: list[str]
    rates: Callable[[float, Any], Any]
    algebraic: dict[str, Callable[[float, Any], float]]
    undetermined: list[str]
    symbols: dict[str, Any] = field(default_factory=dict)  # name → its closed expression
    t: Any = None
    y: list[Any] = field(default_factory=list)

    def expression(self, name: str) -> Any:
        """The closed expression (over t and the differential states) of a state, or None."""
        return self.symbols.get(name)


def _equations(tree: Any, state: Callable[[str], Any], rate: Callable[[str], Any],
               name: Callable[[str], Any]) -> list[Any]:
    eqs = []
    for conjunct in tree.children:
        if getattr(conjunct, "data", None) == "binder":
            continue
        node = conjunct.children[0] if conjunct.data == "lifted" else conjunct
        if node.data != "binop" or op_name(node.children[1]) != "=":
            raise Unsupported("a conjunct of Evolve that is not an equation")
        lhs = evaluate(node.children[0], state, rate, name)
        rhs = evaluate(node.children[2], state, rate, name)
        eqs.append(lhs - rhs)
    return eqs


def _solve_one(eq: Any, u: Any) -> list[Any]:
    """The solutions of ``eq = 0`` for ``u``: directly when linear (most are), else SymPy's."""
    import sympy  # lazy: as below
    coefficient = sympy.diff(eq, u)
    if u not in coefficient.free_symbols:
        if coefficient == 0:
            return []
        return [-eq.xreplace({u: 0}) / coefficient]
    return list(sympy.solve(eq, u, rational=False))


def _solve_causal(eqs: list[Any], unknowns: set[Any]) -> tuple[dict[Any, Any], list[Any]]:
    """Solve equations with one unknown left, substituting, until none is left; then
    SymPy's solve on the rest (a coupled block), keeping the closed answers."""
    import sympy  # lazy: Evolve is solved when the first cycle evolves
    solved: dict[Any, Any] = {}
    pending = [sympy.sympify(e) for e in eqs]
    progress = True
    while progress:
        progress = False
        rest = []
        for eq in pending:
            eq = eq.xreplace(solved) if solved else eq
            free = eq.free_symbols & unknowns
            if not free:
                continue
            if len(free) == 1:
                (u,) = free
                answers = _solve_one(eq, u)
                if len(answers) == 1:
                    solved = {k: v.xreplace({u: answers[0]}) for k, v in solved.items()}
                    solved[u] = answers[0]
                    unknowns = unknowns - {u}
                    progress = True
                    continue
            rest.append(eq)
        pending = rest
        if not progress and pending and len(pending) <= 60:
            left = sorted(set().union(*(e.free_symbols for e in pending)) & unknowns, key=str)
            answers = sympy.solve(pending, left, dict=True, rational=False)
            if len(answers) == 1:
                closed = {u: v for u, v in answers[0].items()
                          if not (v.free_symbols & unknowns)}
                if closed:
                    solved.update(closed)
                    unknowns = unknowns - set(closed)
                    solved = {k: v.xreplace(closed) for k, v in solved.items()}
                    pending = [e.xreplace(closed) for e in pending]
                    progress = True
    return solved, pending


def build(tree: Any, differential: list[str], fields: set[str], inputs: dict[str, Any],
          constant: Callable[[str], Any], t: Any) -> OdeSystem:
    """The ODE of the ``exists`` tree under these differential states; ``inputs`` maps a
    world input to its SymPy expression over ``t`` and the states; ``constant`` gives a
    constant's value or raises KeyError for one without."""
    import sympy  # lazy: as above
    binders = {str(b.children[0]) for b in tree.children if getattr(b, "data", "") == "binder"}
    ys = [sympy.Symbol(x) for x in differential]
    diff = set(differential)
    sym: dict[str, Any] = {}
    open_constants: set[Any] = set()

    def state(x: str) -> Any:
        if x in inputs:
            return inputs[x]
        if x not in fields:
            raise Unsupported(f"the name {x}, which is not a state variable")
        return sym.setdefault(x, sympy.Symbol(x))

    def rate(x: str) -> Any:
        return sym.setdefault(RATE + x, sympy.Symbol(RATE + x))

    def name(x: str) -> Any:
        if x in binders:
            return sym.setdefault("b__" + x, sympy.Symbol("b__" + x))
        try:
            return constant(x)
        except KeyError:
            s = sympy.Symbol(x)
            open_constants.add(s)
            return s

    eqs = _equations(tree, state, rate, name)
    known = set(ys) | {t}
    unknowns = set(sym.values()) - known
    solved, _left = _solve_causal(eqs, unknowns)
    # an algebraic state whose rate an equation reads (Kd * e'): differentiate its equations
    loose_rates = [s for k, s in sym.items() if k.startswith(RATE) and k[len(RATE):] not in diff
                   and s not in solved and any(s in e.free_symbols for e in eqs)]
    if loose_rates:
        # only equations over the state alone (no existential, no open constant: their
        # rates are unknown too) that name a variable whose rate is read
        loose = {sym[str(r)[len(RATE):]] for r in loose_rates if str(r)[len(RATE):] in sym}
        local = {s for k, s in sym.items() if k.startswith("b__")} | open_constants
        extra = []
        for e in eqs:
            names = e.free_symbols
            if names & loose and not names & local and not any(
                    str(s).startswith(RATE) for s in names):
                dt = sympy.diff(e, t)
                for s in list(names):
                    if str(s) in fields:
                        dt += sympy.diff(e, s) * rate(str(s))
                extra.append(dt)
        unknowns = set(sym.values()) - known
        solved, _left = _solve_causal(eqs + extra, unknowns)
    closed: dict[str, Any] = {}
    for key, s in sym.items():
        value = s if s in known else solved.get(s)
        if value is not None and not (value.free_symbols - known):
            closed[key] = value
    for x in inputs:
        closed[x] = inputs[x]
    for x, y in zip(differential, ys):
        closed[x] = y
    missing_rates = [x for x in differential if RATE + x not in closed]
    if missing_rates:
        raise _undetermined(missing_rates, sym, solved, known, diff, open_constants, fields)
    rate_exprs = [closed[RATE + x] for x in differential]
    rates = sympy.lambdify((t, ys), rate_exprs, modules="math", cse=True)
    algebraic = {k: sympy.lambdify((t, ys), v, modules="math")
                 for k, v in sorted(closed.items())
                 if not k.startswith((RATE, "b__")) and k not in diff}
    undetermined = sorted(k for k in sym if k not in closed and not k.startswith((RATE, "b__"))
                          and k not in diff)
    return OdeSystem(list(differential), lambda tt, y: rates(tt, y), algebraic, undetermined,
                     {k: v for k, v in closed.items() if not k.startswith("b__")}, t, ys)


def _undetermined(missing: list[str], sym: dict[str, Any], solved: dict[Any, Any],
                  known: set[Any], diff: set[str], open_constants: set[Any],
                  fields: set[str]) -> AnimateError:
    """Why some rates are open: the unsolved names they reach."""
    causes: set[str] = set()
    for x in missing:
        expr = solved.get(sym.get(RATE + x))
        if expr is not None:
            causes |= {str(s) for s in expr.free_symbols - known}
    never_set = sorted(c for c in causes | {k for k in sym if k in fields}
                       if c in fields and c not in diff and (RATE + c) in sym)
    consts = sorted(str(s) for s in open_constants if str(s) in causes)
    parts = [f"Evolve does not determine the rate of {', '.join(missing)}"]
    if never_set:
        parts.append(f"{', '.join(never_set)} evolve but nothing assigns them before Evolve "
                     "(Init leaves them open)")
    if consts:
        parts.append(f"the constants {', '.join(consts)} have no value")
    others = sorted(c for c in causes if c not in never_set and c not in consts
                    and not c.startswith((RATE, "b__")))
    if others:
        parts.append(f"it depends on {', '.join(others)}, which no equation determines")
    return AnimateError("E-ANIMATE-EVOLVE", "; ".join(parts), status=1,
                        hint="give open constants with --const NAME=VALUE and world inputs "
                        "with --input NAME=EXPR")
