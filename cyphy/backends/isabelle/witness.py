"""Values that satisfy a theory's axioms, found by trying a few, in exact arithmetic.

The axioms of most theories are ``cycle > 0``, ``tscale > 0`` and a cycle restriction such as
``cycle = 1``: values that satisfy them are among the numbers they are written with. Found,
such values show the axioms satisfiable exactly as Z3's model would
(:func:`cyphy.backends.isabelle.axioms.unsatisfiable_axioms`), without importing Z3 (0.03 s,
a tenth of a warm ``gen --isabelle``). Not found, nothing is concluded: Z3 decides.

Only what has the same meaning here and in Z3's translation (:mod:`cyphy.translate.to_z3`)
is evaluated: numbers (exact rationals, ``0.06`` is 3/50), names, ``-``, ``not``, ``+ - * /``,
comparisons (not chained) and the connectives; anything else, or a division by zero, is not
evaluated. A ``nat`` takes non-negative integers, an ``int`` integers, anything else a
rational.
"""

from __future__ import annotations

import itertools
from fractions import Fraction
from typing import Callable

from cyphy import expr as ex
from cyphy.semantics.circus import ast as c

#: The most assignments tried before leaving the question to Z3.
MAX_TRIES = 256

_COMPARE: dict[str, Callable[[Fraction, Fraction], bool]] = {
    "==": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
}
_CONNECT: dict[str, Callable[[bool, bool], bool]] = {
    "/\\": lambda a, b: a and b, "\\/": lambda a, b: a or b, "=>": lambda a, b: not a or b,
    "<=>": lambda a, b: a == b,
}
_ARITHMETIC: dict[str, Callable[[Fraction, Fraction], Fraction]] = {
    "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
}


class _NotEvaluated(Exception):
    """The axiom holds something not evaluated here, or divides by zero."""


def satisfied(axdef: c.AxDef) -> bool:
    """Whether some assignment of the numbers the axioms are written with (and 0, 1, and
    one more than each) to their names satisfies every axiom."""
    try:
        names = sorted({n for w in axdef.where for n in _names(w)})
        literals = {Fraction(0), Fraction(1)}
        for w in axdef.where:
            for node in w.walk():
                if isinstance(node, ex.Num):
                    literals.add(Fraction(node.text))
    except (_NotEvaluated, ValueError, ZeroDivisionError):
        return False
    literals |= {v + 1 for v in literals}
    kinds = {b.name: b.type for b in axdef.constants}
    choices = [sorted(v for v in literals if _fits(v, kinds.get(n, c.REAL))) for n in names]
    tried = 0
    for values in itertools.product(*choices):
        tried += 1
        if tried > MAX_TRIES:
            return False
        env = dict(zip(names, values))
        try:
            if all(_truth(w, env) for w in axdef.where):
                return True
        except (_NotEvaluated, ZeroDivisionError):
            continue
    return False


def _fits(value: Fraction, kind: c.Type) -> bool:
    if kind == c.NAT:
        return value.denominator == 1 and value >= 0
    if kind == c.INT:
        return value.denominator == 1
    return True


def _names(e: ex.Expr) -> set[str]:
    """The names the axiom reads; ``_NotEvaluated`` when it holds a node not evaluated."""
    out: set[str] = set()
    for node in e.walk():
        if isinstance(node, ex.Name):
            out.add(node.text)
        elif not isinstance(node, (ex.Num, ex.Bool, ex.UnaryOp, ex.BinOp)):
            raise _NotEvaluated
    return out


def _truth(e: ex.Expr, env: dict[str, Fraction]) -> bool:
    if isinstance(e, ex.Bool):
        return bool(e.value)
    if isinstance(e, ex.UnaryOp) and e.op == "not":
        return not _truth(e.operand, env)
    if isinstance(e, ex.BinOp) and e.op in _CONNECT:
        return _CONNECT[e.op](_truth(e.left, env), _truth(e.right, env))
    if isinstance(e, ex.BinOp) and e.op in _COMPARE:
        if isinstance(e.left, ex.BinOp) and e.left.op in _COMPARE:
            raise _NotEvaluated  # a chain (a == b < c): Z3's translation decides
        return _COMPARE[e.op](_value(e.left, env), _value(e.right, env))
    raise _NotEvaluated


def _value(e: ex.Expr, env: dict[str, Fraction]) -> Fraction:
    if isinstance(e, ex.Num):
        return Fraction(e.text)
    if isinstance(e, ex.Name):
        return env[e.text]
    if isinstance(e, ex.UnaryOp) and e.op == "-":
        return -_value(e.operand, env)
    if isinstance(e, ex.BinOp) and e.op in _ARITHMETIC:
        return _ARITHMETIC[e.op](_value(e.left, env), _value(e.right, env))
    if isinstance(e, ex.BinOp) and e.op == "/":
        return _value(e.left, env) / _value(e.right, env)  # ZeroDivisionError: not this one
    raise _NotEvaluated
