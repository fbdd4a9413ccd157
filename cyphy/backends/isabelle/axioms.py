"""The axioms a theory states about its constants, shown satisfiable with Z3 before writing.

A theory axiomatises ``cycle`` and ``tscale`` with their constraints (``cycle > 0``,
``tscale > 0``, the d-model's cycle restriction, a fixed ``tscale``). Inconsistent axioms
make every lemma of the theory provable, silently; so the theory is written only when Z3
finds a model of them (``cycle`` ranges over the naturals, ``tscale`` over the reals; any
other name in them is one more unknown). Axioms Z3 cannot read, or cannot decide, count as
not shown satisfiable: nothing is written for them either. Most axioms are satisfied by
the numbers they are written with (``cycle = 1``): values found among those show them
satisfiable without importing Z3.
"""

from __future__ import annotations

from typing import Any

from cyphy import codes
from cyphy import expr as ex
from cyphy.backends.isabelle.witness import satisfied
from cyphy.lang.notation import to_notation
from cyphy.semantics.circus import ast as c

INCONSISTENT_AXIOMS = codes.code("E-ISABELLE-AXIOMS", codes.E,
                                 "the axioms on the theory's constants are not satisfiable")


def unsatisfiable_axioms(axdef: c.AxDef, timeout_ms: int = 5000) -> str | None:
    """None when Z3 finds values for the constants that satisfy every axiom of ``axdef``;
    otherwise why the axioms cannot be written (unsatisfiable, or not shown satisfiable).
    Values that satisfy them found among the numbers they are written with show it without
    Z3 (:mod:`cyphy.backends.isabelle.witness`)."""
    if satisfied(axdef):
        return None
    # lazy: Z3 takes about 0.1 s to import; only the axioms' satisfiability check needs it
    import z3

    from cyphy.translate.to_z3 import UnsupportedNode, to_z3  # lazy: imports Z3 (see above)

    kinds = {b.name: b.type for b in axdef.constants}
    made: dict[str, Any] = {}

    def symbol(name: str, node: ex.Expr) -> Any:
        if name not in made:
            t = kinds.get(name, c.REAL)
            made[name] = z3.Int(name) if t in (c.NAT, c.INT) else z3.Real(name)
        return made[name]

    solver = z3.Solver()
    solver.set("timeout", timeout_ms)
    text = " ∧ ".join(to_notation(w) for w in axdef.where)
    try:
        for w in axdef.where:
            solver.add(to_z3(w, symbol))
    except (UnsupportedNode, ValueError, ArithmeticError) as err:
        return f"the axioms {text} cannot be checked with Z3 ({err})"
    for name, t in kinds.items():
        if t == c.NAT and name in made:
            solver.add(made[name] >= 0)
    verdict = solver.check()
    if verdict == z3.sat:
        return None
    if verdict == z3.unsat:
        return f"the axioms {text} have no model: every lemma of the theory would follow"
    return f"Z3 could not show the axioms {text} satisfiable ({solver.reason_unknown()})"
