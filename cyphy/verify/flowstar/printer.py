"""Expressions in Flow* 2.1.0 syntax: the shared expression AST printed with Flow*'s lexical
rules; SymPy results (the reduced ODEs) are brought into that AST first by
:func:`cyphy.translate.to_sympy.to_expr`.

Flow*'s traps (``../shared/spec/flowstar.md`` §4.1, §4.5) are handled here once: a binary
minus always has spaces around it (``x -1`` would read as ``x`` followed by the number
``-1``), numbers never use a capital ``E`` or an exponent ``+`` without a decimal point,
``^`` only takes a non-negative integer literal, and division and functions are refused in
polynomial right-hand sides (``poly ode`` has neither).
"""

from __future__ import annotations

import math
import re
from typing import Any

from cyphy import expr as ex
from cyphy.translate.to_sympy import NotAnExpression, to_expr

#: Words Flow* 2.1.0 reserves: none of them may name a variable (spec §4.1).
RESERVED = frozenset(
    "mode init in end setting order min max interval octagon grid plot tm time modes jumps "
    "inv guard reset start output unsafe exp sin cos log sqrt cutoff precision gnuplot matlab "
    "par uncertain step true false visualize".split())
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*\Z")
#: The functions of ``nonpoly ode`` (spec §4.5); Flow* has no other.
FUNCTIONS = ("exp", "sin", "cos", "log", "sqrt")
_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "^": 4}
_UNARY = 3


class NotExpressible(Exception):
    """An expression Flow* cannot take where it is used; the message says what and why."""


def valid_name(name: str) -> bool:
    return bool(_IDENTIFIER.match(name)) and name not in RESERVED


def number(value: Any) -> str:
    """A finite real as a Flow* number token (never negative: the sign is the caller's).

    Integers print as written; other values as the shortest decimal that reads back as the
    same double, with an exponent only when Python chooses one, and then always with a
    decimal point and a sign (``1.0e-05``), the one spelling Flow*'s lexer always accepts."""
    if isinstance(value, int) or (hasattr(value, "is_Integer") and value.is_Integer):
        return str(abs(int(value)))
    f = abs(float(value))
    if not math.isfinite(f):
        raise NotExpressible(f"{value} is not a finite number")
    if f.is_integer() and f < 1e15:
        return str(int(f))
    text = repr(f)
    if "e" in text:
        mantissa, exponent = text.split("e")
        if "." not in mantissa:
            mantissa += ".0"
        text = f"{mantissa}e{int(exponent):+03d}"
    return text


class FlowstarPrinter:
    """``_print_<Node>`` per node class of :mod:`cyphy.expr`, SymPy-printer style.

    ``polynomial=True`` (the default) is the syntax of ``poly ode`` right-hand sides,
    constraints and resets; ``False`` is ``nonpoly ode``'s, which adds ``/`` and
    ``exp sin cos log sqrt``."""

    def __init__(self, polynomial: bool = True) -> None:
        self.polynomial = polynomial

    def doprint(self, e: ex.Expr) -> str:
        return self._print(e)

    def _print(self, e: ex.Expr) -> str:
        method = getattr(self, "_print_" + type(e).__name__, None)
        if method is None:
            raise NotExpressible(f"Flow* has no counterpart for {type(e).__name__}")
        return method(e)

    def _print_Num(self, e: ex.Num) -> str:
        try:
            return number(int(e.text) if e.is_integer else float(e.text))
        except ValueError:
            raise NotExpressible(f"'{e.text}' is not a number") from None

    def _print_Name(self, e: ex.Name) -> str:
        if not valid_name(e.text):
            raise NotExpressible(f"'{e.text}' cannot name a Flow* variable (a reserved word, "
                                 "or a character Flow* names do not allow)")
        return e.text

    def _print_UnaryOp(self, e: ex.UnaryOp) -> str:
        if e.op != "-":
            raise NotExpressible(f"Flow* has no operator '{e.op}' in expressions")
        return "-" + self._wrap(e.operand, _PRECEDENCE["*"])  # -2*x is -(2*x)

    def _print_BinOp(self, e: ex.BinOp) -> str:
        op = e.op
        if op not in _PRECEDENCE:
            raise NotExpressible(f"Flow* has no operator '{op}' in expressions")
        if op == "/" and self.polynomial:
            raise NotExpressible("'poly ode' right-hand sides and constraints have no "
                                 "division")
        if op == "^":
            exponent = e.right
            if not (isinstance(exponent, ex.Num) and exponent.is_integer):
                raise NotExpressible("Flow* casts every exponent to an integer: only "
                                     "non-negative integer powers are kept")
            return f"{self._wrap(e.left, _PRECEDENCE['^'] + 1)}^{exponent.text}"
        prec = _PRECEDENCE[op]
        left = self._wrap(e.left, prec)
        right = self._wrap(e.right, prec, right=op in "-/")
        if op in "*/":
            return f"{left}{op}{right}"
        return f"{left} {op} {right}"  # spaces around '-': `x -1` is a syntax error

    def _print_Call(self, e: ex.Call) -> str:
        name = e.func.text if isinstance(e.func, ex.Name) else ""
        if self.polynomial or name not in FUNCTIONS or len(e.args) != 1:
            where = "'poly ode' right-hand sides and constraints" if self.polynomial else \
                "Flow*"
            raise NotExpressible(f"{where} cannot apply '{name or '?'}' (Flow* knows only "
                                 "exp, sin, cos, log and sqrt, in 'nonpoly ode')")
        return f"{name}({self._print(e.args[0])})"

    def _wrap(self, e: ex.Expr, prec: int, right: bool = False) -> str:
        text = self._print(e)
        inner = _PRECEDENCE.get(e.op, 0) if isinstance(e, ex.BinOp) else (
            _UNARY if isinstance(e, ex.UnaryOp) else 99)
        if inner < prec or (right and inner == prec):
            return f"({text})"
        return text


# --------------------------------------------------------------------------- from SymPy


def flowstar_text(e: Any, polynomial: bool = True) -> str:
    """A SymPy expression (the reducer's output) in Flow* syntax: brought into the shared
    AST with rationals as decimals (``poly ode`` has no division), then printed."""
    try:
        tree = to_expr(e, decimals=True)
    except NotAnExpression:
        raise NotExpressible(f"Flow* has no counterpart for {e}") from None
    return FlowstarPrinter(polynomial).doprint(tree)
