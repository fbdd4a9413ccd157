"""Predicates as Flow* constraints: disjunctions of conjunctions of ``P <= c``, ``P >= c`` and
``P = c`` with ``P`` a polynomial (spec §4.6).

Flow* has no ``<``, ``>``, ``!=`` nor disjunction. A strict comparison becomes its closure
(``<`` → ``<=``): the guard then also holds on its boundary, where Flow* explores both
branches, which over-approximates and so stays sound for safety. ``!=`` has the whole space as
closure and becomes *true*. A disjunction becomes one jump per disjunct. A rational
comparison ``n/d >= 0`` is rewritten ``n*d >= 0``, the same set wherever ``d`` is not 0 (where
the predicate is undefined anyway).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy

from cyphy.verify.flowstar.printer import NotExpressible, flowstar_text

_FLIP = {"<=": ">=", ">=": "<=", "=": "="}


@dataclass(frozen=True)
class Atom:
    """``poly REL 0``, ``rel`` one of ``<=``, ``>=``, ``=``."""

    poly: Any
    rel: str

    def text(self) -> str:
        """Flow* syntax: the constant moved to the right (``timer = 0.1``), the leading
        coefficient's sign kept by flipping the relation when the left side would start
        with a minus."""
        poly = sympy.expand(self.poly)
        const = poly.as_coeff_Add()[0]
        lhs = poly - const
        rel = self.rel
        rhs = -const
        if lhs.as_ordered_terms()[0].as_coeff_Mul()[0].is_negative:
            lhs, rhs, rel = -lhs, -rhs, _FLIP[rel]
        return f"{flowstar_text(lhs)} {rel} {_signed(rhs)}"

    def relation(self) -> Any:
        """The atom as a SymPy relation again."""
        return {"<=": sympy.Le, ">=": sympy.Ge, "=": sympy.Eq}[self.rel](self.poly, 0)

    def holds(self, values: dict[Any, float], tol: float = 1e-9) -> bool:
        v = float(self.poly.xreplace(values))
        return {"<=": v <= tol, ">=": v >= -tol, "=": abs(v) <= tol}[self.rel]


def _signed(value: Any) -> str:
    text = flowstar_text(sympy.Abs(value))
    return f"-{text}" if value < 0 else text  # a leading '-' is part of the number token


Conjunction = tuple[Atom, ...]


def dnf(pred: Any, variables: set[Any]) -> list[Conjunction]:
    """``pred`` (a SymPy boolean over ``variables``) as a list of conjunctions; ``[]`` is
    *false*, ``[()]`` is *true*. Raises :class:`NotExpressible` for what has no polynomial
    form."""
    return _simplify(_dnf(pred, False, variables))


def _dnf(p: Any, negate: bool, variables: set[Any]) -> list[Conjunction]:
    if p is sympy.true or p is sympy.false:
        return [()] if (p is sympy.true) != negate else []
    if isinstance(p, sympy.Not):
        return _dnf(p.args[0], not negate, variables)
    if isinstance(p, (sympy.And, sympy.Or)):
        is_and = isinstance(p, sympy.And) != negate
        parts = [_dnf(a, negate, variables) for a in p.args]
        if is_and:
            out: list[Conjunction] = [()]
            for part in parts:
                out = _and(out, part)
            return out
        return [c for part in parts for c in part]
    if isinstance(p, sympy.Rel):
        return _relation(p, negate, variables)
    raise NotExpressible(f"'{p}' is not a comparison Flow* can check")


def _and(a: list[Conjunction], b: list[Conjunction]) -> list[Conjunction]:
    return [x + y for x in a for y in b]


def _relation(p: Any, negate: bool, variables: set[Any]) -> list[Conjunction]:
    op = {sympy.StrictLessThan: "<", sympy.LessThan: "<=", sympy.StrictGreaterThan: ">",
          sympy.GreaterThan: ">=", sympy.Equality: "==", sympy.Unequality: "!="}[type(p)]
    if negate:
        op = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "==": "!=", "!=": "=="}[op]
    if op == "!=":
        return [()]  # its closure is everything
    diff = sympy.together(sympy.expand(p.lhs - p.rhs))
    numer, denom = sympy.fraction(diff)
    if denom.free_symbols & variables:
        poly = sympy.expand(numer * denom) if op != "==" else sympy.expand(numer)
    else:
        denom = sympy.nsimplify(denom) if not denom.is_number else denom
        poly = sympy.expand(numer / denom)
    if not poly.free_symbols:
        value = float(poly)
        holds = {"<": value <= 0, "<=": value <= 0, ">": value >= 0, ">=": value >= 0,
                 "==": value == 0}[op]
        return [()] if holds else []
    if not poly.is_polynomial(*sorted(variables, key=str)) or \
            poly.free_symbols - variables:
        extra = poly.free_symbols - variables
        why = f"it depends on {', '.join(sorted(map(str, extra)))}, which is not a state" \
            if extra else "it is not polynomial in the state variables"
        raise NotExpressible(f"'{p}' has no Flow* constraint form: {why}")
    rel = {"<": "<=", "<=": "<=", ">": ">=", ">=": ">=", "==": "="}[op]
    return [(Atom(poly, rel),)]


def _simplify(conjunctions: list[Conjunction]) -> list[Conjunction]:
    """Duplicates removed, in a deterministic order of first appearance."""
    out: list[Conjunction] = []
    for c in conjunctions:
        unique = tuple(dict.fromkeys(c))
        if unique not in out:
            out.append(unique)
    return out
