"""The shared expression AST as Z3 terms (the consistency checks of platform mappings).

Z3 is imported by this module, so only ``cyphy check --consistency`` imports it. Arithmetic
is real: literals become exact rationals (``0.025025`` is 1001/40000), ``/`` is real division
even between integer-typed variables, and powers with small natural exponents become products
(which Z3's nonlinear real arithmetic handles). Functions Z3 has no theory for (``sin``,
``sqrt``, user functions) become uninterpreted functions and are listed in
``uninterpreted``: a satisfiable answer that relies on them may not hold for the real
function, an unsatisfiable one does. Z3's division is total (``x/0`` is some number), the
notation's is not: every divisor that is not a literal is listed in ``divisors`` so that the
caller can require it to be non-zero. What a name denotes is the caller's business: the
printer asks its ``symbol`` callback.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, Callable

import z3

from cyphy import expr as ex
from cyphy.lang.notation import to_notation
from cyphy.model.evaluate import UNIT_FACTORS

MAX_EXPANDED_POWER = 8
"""``x^n`` with a natural ``n`` up to this is written as a product; beyond it Z3's ``**``."""

_COMPARISONS: dict[str, Callable[[Any, Any], Any]] = {
    "==": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
}
_CONNECTIVES: dict[str, Callable[[Any, Any], Any]] = {
    "/\\": z3.And, "\\/": z3.Or, "=>": z3.Implies, "<=>": lambda a, b: a == b,
}


class UnsupportedNode(Exception):
    """An expression Z3 has no counterpart for here (vectors, sequences, integrals…)."""

    def __init__(self, node: ex.Expr, why: str = "") -> None:
        super().__init__(why or f"Z3 has no counterpart for {type(node).__name__}")
        self.node = node


def rational(text: str | float | int) -> Any:
    """An exact Z3 real for a literal or an evaluated value (``0.06`` is 3/50, not the
    binary double nearest to it)."""
    if isinstance(text, bool):
        raise TypeError("a boolean is not a number")
    value = Fraction(repr(text)) if isinstance(text, float) else Fraction(text)
    return z3.Q(value.numerator, value.denominator)


def _real(a: Any) -> Any:
    return z3.ToReal(a) if z3.is_int(a) else a


class Z3Printer:
    """``_print_<Node>`` per node class, found along the MRO (as SymPy's printers)."""

    def __init__(self, symbol: Callable[[str, ex.Expr], Any]) -> None:
        self.symbol = symbol  # (name as written, the node) → a Z3 term
        self.uninterpreted: set[str] = set()
        self.divisors: list[Any] = []
        self._functions: dict[tuple[str, int], Any] = {}

    def doprint(self, e: ex.Expr) -> Any:
        return self._print(e)

    def defined(self, e: ex.Expr) -> Any:
        """``e`` where it is defined: its divisors non-zero (a boolean ``e`` only)."""
        start = len(self.divisors)
        term = self._print(e)
        guards = [d != 0 for d in self.divisors[start:]]
        return z3.And(*guards, term) if guards else term

    def _print(self, e: ex.Expr) -> Any:
        for cls in type(e).__mro__:
            method = getattr(self, "_print_" + cls.__name__, None)
            if method is not None:
                return method(e)
        raise UnsupportedNode(e)

    def _print_Num(self, e: ex.Num) -> Any:
        return rational(e.text)

    def _print_Quantity(self, e: ex.Quantity) -> Any:
        factor = UNIT_FACTORS.get(e.unit)
        if factor is None:
            raise UnsupportedNode(e, f"unknown unit '{e.unit}'")
        return _real(self._print(e.value)) * rational(factor)

    def _print_Bool(self, e: ex.Bool) -> Any:
        return z3.BoolVal(e.value)

    def _print_Name(self, e: ex.Name) -> Any:
        return self.symbol(e.text, e)

    def _print_Member(self, e: ex.Member) -> Any:
        """A field of a record-typed value (``su.shoulderAngle``): a variable of its own."""
        path = ex.path_of(e)
        if path is None:
            raise UnsupportedNode(e, f"field access on an expression: {to_notation(e)}")
        return self.symbol(".".join(path), e)

    def _print_UnaryOp(self, e: ex.UnaryOp) -> Any:
        operand = self._print(e.operand)
        return z3.Not(operand) if e.op == "not" else -operand

    def _print_BinOp(self, e: ex.BinOp) -> Any:
        if e.op in _COMPARISONS and isinstance(e.left, ex.BinOp) and \
                e.left.op in _COMPARISONS:  # a chain: a == b < c is a == b /\ b < c
            return z3.And(self._print(e.left),
                          _COMPARISONS[e.op](self._print(e.left.right), self._print(e.right)))
        a, b = self._print(e.left), self._print(e.right)
        if e.op in _COMPARISONS:
            return _COMPARISONS[e.op](a, b)
        if e.op in _CONNECTIVES:
            return _CONNECTIVES[e.op](a, b)
        if e.op == "+":
            return a + b
        if e.op == "-":
            return a - b
        if e.op == "*":
            return a * b
        if e.op == "/":
            if not z3.is_rational_value(b):
                self.divisors.append(_real(b))
            return _real(a) / _real(b)
        if e.op == "%":
            if z3.is_int(a) and z3.is_int(b):
                return a % b
            raise UnsupportedNode(e, "a remainder of real numbers")
        return self._power(e, a)  # ^ and `cat`, which RoboTool's models misuse as a power

    def _power(self, e: ex.BinOp, base: Any) -> Any:
        if isinstance(e.right, ex.Num) and e.right.is_integer and \
                int(e.right.text) <= MAX_EXPANDED_POWER:
            n = int(e.right.text)
            out = rational(1)
            for _ in range(n):
                out = out * base
            return out
        return _real(base) ** _real(self._print(e.right))

    def _print_IfExpr(self, e: ex.IfExpr) -> Any:
        return z3.If(self._print(e.cond), self._print(e.then), self._print(e.orelse))

    def _print_Call(self, e: ex.Call) -> Any:
        if not isinstance(e.func, ex.Name):
            raise UnsupportedNode(e, f"a call of an expression: {to_notation(e)}")
        name = e.func.text
        args = [self._print(a) for a in e.args]
        if name == "abs" and len(args) == 1:
            return z3.If(args[0] >= 0, args[0], -args[0])
        if name == "sgn" and len(args) == 1:
            return z3.If(args[0] > 0, rational(1), z3.If(args[0] < 0, rational(-1), rational(0)))
        if name in ("min", "max") and len(args) == 2:
            a, b = args
            return z3.If(a <= b, a, b) if name == "min" else z3.If(a >= b, a, b)
        if any(not z3.is_arith(a) for a in args):
            raise UnsupportedNode(e, f"{name} applied to a non-number")
        key = (name, len(args))
        if key not in self._functions:
            self._functions[key] = z3.Function(name, *([z3.RealSort()] * (len(args) + 1)))
        self.uninterpreted.add(name)
        return self._functions[key](*[_real(a) for a in args])

    def _print_Derivative(self, e: ex.Derivative) -> Any:
        """At one instant the derivative is one more unknown: ``derivative(x)`` is ``x'``."""
        if not isinstance(e.operand, ex.Name):
            raise UnsupportedNode(e, f"the derivative of an expression: {to_notation(e)}")
        return self.symbol(e.operand.text + "'", e)


def to_z3(e: ex.Expr, symbol: Callable[[str, ex.Expr], Any]) -> Any:
    return Z3Printer(symbol).doprint(e)


def value_text(v: Any) -> str:
    """A model value as a reader wants it: ``3``, ``0.5``, ``1/3 (≈ 0.333333)``, ``true``."""
    if z3.is_true(v) or z3.is_false(v):
        return "true" if z3.is_true(v) else "false"
    if z3.is_int_value(v):
        return str(v.as_long())
    if z3.is_rational_value(v):
        value = Fraction(v.numerator_as_long(), v.denominator_as_long())
        exact = f"{float(value):.12g}"
        if Fraction(exact) == value:
            return exact
        return f"{value} (≈ {float(value):.6g})"
    if z3.is_algebraic_value(v):
        return "≈ " + v.approx(6).as_decimal(6).rstrip("?")
    return str(v)
