"""What is known of ``D``'s state along one path of a cycle written out
(:mod:`cyphy.semantics.circus.dmodel_cycle`), so that a transition whose guard cannot hold
there is not written, and one whose guard must hold ends the choice.

Why: the cycle is unrolled symbolically, node after node, until ``exec``. A machine that
resets a clock when it enters a state and leaves it when ``since(C) >= T`` passes through
that state again only in a later cycle: in this one the clock reads 0, and the guard is
false. Unrolled without that knowledge, the path ``Fast → Slow → Fast → …`` never ends and
``D`` was refused ("a loop of transitions without exec"), although the interpreter, and
simulate, run the machine one state per cycle.

A fact is the value of one field of ``D``'s state (``<D>_x``, ``<D>_C``, ``<D>_e``) that
holds at that point of the path in every run: a clock reset in this cycle (the clocks
advance only at the start of ``<D>Step``), a variable assigned a value that folds to a
constant, the machine's initial values in ``<D>Start`` (it runs after ``<D>Init`` and
``<D>Read``, which sets only the events), an event tested by the guard just taken
(``$e`` or ``not $e`` as a conjunct), or not by an earlier guard that was a single test.
Arithmetic is exact (rationals): the theory's numbers are reals, not floats.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Union

from cyphy import expr as ex

Value = Union[Fraction, bool]

_ARITHMETIC = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b}
_COMPARISONS = {"==": lambda a, b: a == b, "!=": lambda a, b: a != b,
                "<": lambda a, b: a < b, "<=": lambda a, b: a <= b,
                ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


class Facts:
    """The fields of ``D``'s state known along one path (immutable: each change is a copy,
    so that the paths of a choice do not share what they learn)."""

    def __init__(self, known: dict[str, Value] | None = None) -> None:
        self.known: dict[str, Value] = dict(known or {})

    def value(self, e: ex.Expr) -> Value | None:
        """``e``'s value where every field it reads is known (None where one is not, or
        the expression is not plain arithmetic, comparison and logic)."""
        if isinstance(e, ex.Num):
            try:
                return Fraction(e.text)
            except (ValueError, ZeroDivisionError):
                return None
        if isinstance(e, ex.Bool):
            return e.value
        if isinstance(e, ex.Name):
            return self.known.get(e.text)
        if isinstance(e, ex.UnaryOp):
            inner = self.value(e.operand)
            if e.op == "not" and isinstance(inner, bool):
                return not inner
            if e.op == "-" and isinstance(inner, Fraction):
                return -inner
            return None
        if isinstance(e, ex.BinOp):
            return self._binary(e)
        return None

    def _binary(self, e: ex.BinOp) -> Value | None:
        left, right = self.value(e.left), self.value(e.right)
        if e.op in ("/\\", "\\/", "=>", "<=>"):
            return _connective(e.op, left, right)
        if left is None or right is None or isinstance(left, bool) != isinstance(right, bool):
            return None
        if e.op in _COMPARISONS and (e.op in ("==", "!=") or not isinstance(left, bool)):
            return _COMPARISONS[e.op](left, right)
        if isinstance(left, bool):
            return None
        if e.op in _ARITHMETIC:
            return _ARITHMETIC[e.op](left, right)
        if e.op == "/" and right != 0:
            return left / right
        return None

    def assigned(self, field: str, value: ex.Expr) -> Facts:
        """After ``field := value``: known when ``value`` folds, else forgotten."""
        folded = self.value(value)
        out = Facts(self.known)
        if folded is None:
            out.known.pop(field, None)
        else:
            out.known[field] = folded
        return out

    def after(self, fields: tuple[str, ...], values: tuple[ex.Expr, ...]) -> Facts:
        """After ``(f1, …) := (v1, …)``: one field as :meth:`assigned` says; several at once
        (a vector's entries, which may read each other) forgotten."""
        if len(fields) == 1:
            return self.assigned(fields[0], values[0])
        return self.forgotten(fields)

    def forgotten(self, fields: tuple[str, ...]) -> Facts:
        out = Facts(self.known)
        for f in fields:
            out.known.pop(f, None)
        return out

    def taken(self, guard: ex.Expr) -> Facts:
        """After a guard held: each conjunct that tests one field (``f == b``, ``not (f ==
        b)``, ``b`` a Boolean) tells its value."""
        out = Facts(self.known)
        for part in ex.conjuncts(guard):
            test = _test(part)
            if test is not None:
                out.known[test[0]] = test[1]
        return out

    def refused(self, guard: ex.Expr) -> Facts:
        """After a guard did not hold: when it is a single test of one field, the opposite
        value."""
        test = _test(guard)
        if test is None:
            return self
        out = Facts(self.known)
        out.known[test[0]] = not test[1]
        return out


def _test(e: ex.Expr) -> tuple[str, bool] | None:
    """``(field, value)`` when ``e`` holds exactly when the Boolean field has that value."""
    negated = isinstance(e, ex.UnaryOp) and e.op == "not"
    inner = e.operand if negated else e
    if isinstance(inner, ex.BinOp) and inner.op == "==" and isinstance(inner.left, ex.Name) \
            and isinstance(inner.right, ex.Bool):
        return inner.left.text, inner.right.value != negated
    return None


def _connective(op: str, left: Value | None, right: Value | None) -> Value | None:
    """A connective where one side may be unknown: ``false /\\ ?`` is false, and so on."""
    if (left is not None and not isinstance(left, bool)) or \
            (right is not None and not isinstance(right, bool)):
        return None
    if op == "/\\":
        return False if False in (left, right) else (True if left and right else None)
    if op == "\\/":
        return True if True in (left, right) else (False if left is False and right is False
                                                   else None)
    if op == "=>":
        return True if left is False or right is True else (
            False if left is True and right is False else None)
    return None if left is None or right is None else left == right
