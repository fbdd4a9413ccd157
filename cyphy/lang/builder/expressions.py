"""The rules of expressions, and operator precedence applied to a flat row of operands and
operators (Pratt parsing, a loop: generated files nest thousands deep)."""

from __future__ import annotations

from typing import Any

from lark import Token

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang.builder.base import QN, BuilderBase, Tagged, name_of, text_of, unescape
from cyphy.lang.grammar import TOKEN_TYPES
from cyphy.lang.reductions import Pos


class ExpressionRules(BuilderBase):
    """Methods of the expression rules."""

    # ----- expressions
    def binop(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    sum_op = cmp_op = binop

    def prefix(self, pos: Pos, c: list[Token]) -> Tagged:
        return Tagged("prefix", text_of(c[0]), self._tok_span(c[0]))

    def unit(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("unit", c, self._span(pos))

    def power_group(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("power_group", c[-1], self._span(pos))

    def expr(self, pos: Pos, c: list[Any]) -> ex.Expr:
        """Apply operator precedence to a flat row of operands and operators (Pratt)."""
        if len(c) == 1 and not isinstance(c[0], (str, Tagged)):
            return c[0]  # one operand, the commonest row (what Pratt would return)
        items: list[tuple[str, Any]] = []
        for child in c:
            if isinstance(child, str):
                items.append(("op", child))
            elif isinstance(child, Tagged) and child.tag == "power_group":
                items.append(("op", "^"))
                items.append(("term", child.value))
            elif isinstance(child, Tagged) and child.tag == "unit":
                for part in child.value:
                    if isinstance(part, Tagged):
                        items.append(("prefix", part))
                    else:
                        items.append(("term", part))
            else:
                items.append(("term", child))
        return _Pratt(items, self.path).parse()

    sum = expr

    def call(self, pos: Pos, c: list[Any]) -> ex.Expr:
        func, args = c[0], tuple(a for a in c[1:] if a is not None)
        span = self._span(pos)
        if isinstance(func, ex.Name) and func.parts == ("derivative",) and len(args) == 1:
            return ex.Derivative(args[0], span=span)
        if isinstance(func, ex.Name) and func.parts == ("integral",) and len(args) in (1, 3):
            lower, upper = (args[1], args[2]) if len(args) == 3 else (None, None)
            return ex.Integral(args[0], lower, upper, span=span)
        return ex.Call(func, args, span=span)

    def index_expr(self, pos: Pos, c: list[Any]) -> ex.Index:
        return ex.Index(c[0], tuple(c[1:]), span=self._span(pos))

    def member(self, pos: Pos, c: list[Any]) -> ex.Member:
        return ex.Member(c[0], name_of(c[1]), span=self._span(pos))

    def number(self, pos: Pos, c: list[Token]) -> ex.Num:
        return ex.Num(text_of(c[0]), span=self._span(pos))

    def quantity(self, pos: Pos, c: list[Any]) -> ex.Quantity:
        value, unit = c
        span = self._span(pos)
        if isinstance(value, TOKEN_TYPES):
            value = ex.Num(text_of(value), span=self._tok_span(value))
        return ex.Quantity(value, text_of(unit), span=span)

    def platform_ref(self, pos: Pos, c: list[Any]) -> ex.PlatformRef:
        return ex.PlatformRef(c[0].parts, name_of(c[1]) if c[1] is not None else None,
                              span=self._span(pos))

    def string(self, pos: Pos, c: list[Token]) -> ex.Str:
        return ex.Str(unescape(str(c[0])), span=self._span(pos))

    def true_lit(self, pos: Pos, c: list[Any]) -> ex.Bool:
        return ex.Bool(True, span=self._span(pos))

    def false_lit(self, pos: Pos, c: list[Any]) -> ex.Bool:
        return ex.Bool(False, span=self._span(pos))

    def name_ref(self, pos: Pos, c: list[QN]) -> ex.Name:
        return ex.Name(c[0].parts, span=self._span(pos))

    def field_value(self, pos: Pos, c: list[Any]) -> tuple[str, ex.Expr]:
        return (name_of(c[0]), c[1])

    def record_lit(self, pos: Pos, c: list[Any]) -> ex.Record:
        return ex.Record(c[0].parts, tuple(c[1:]), span=self._span(pos))

    def row(self, pos: Pos, c: list[Any]) -> tuple[ex.Expr, ...]:
        return tuple(c)

    def tuple_lit(self, pos: Pos, c: list[Any]) -> ex.Vector:
        return ex.Vector(tuple(c), span=self._span(pos))

    def matrix_lit(self, pos: Pos, c: list[Any]) -> ex.Matrix:
        return ex.Matrix(tuple(c), span=self._span(pos))

    def seq_lit(self, pos: Pos, c: list[Any]) -> ex.Seq:
        return ex.Seq(tuple(x for x in c if x is not None), span=self._span(pos))

    def if_expr(self, pos: Pos, c: list[Any]) -> ex.IfExpr:
        return ex.IfExpr(c[0], c[1], c[2], span=self._span(pos))


# Binding powers, loosest first; right-associative operators parse their right side at their
# own level, left-associative ones one above.
_INFIX: dict[str, tuple[int, bool]] = {
    "<=>": (10, True), "=>": (10, True),
    "\\/": (20, False),
    "/\\": (30, False),
    "==": (50, False), "!=": (50, False), "<": (50, False), "<=": (50, False),
    ">": (50, False), ">=": (50, False),
    "+": (60, False), "-": (60, False), "cat": (60, False),
    "*": (70, False), "/": (70, False), "%": (70, False),
    "^": (90, True),
}
_PREFIX = {"not": 40, "-": 80}


class _Pratt:
    """Precedence climbing over ``(kind, value)`` items: ``term`` (an Expr), ``op`` (an infix
    operator) and ``prefix`` (a tagged ``-`` or ``not`` with its span)."""

    def __init__(self, items: list[tuple[str, Any]], path: str) -> None:
        self.items = items
        self.pos = 0
        self.path = path

    def parse(self, min_bp: int = 0) -> ex.Expr:
        prefixes = []
        while self.items[self.pos][0] == "prefix":
            prefixes.append(self.items[self.pos][1])
            self.pos += 1
        left: ex.Expr = self.items[self.pos][1]
        self.pos += 1
        # Innermost prefix first, each taking the operators that bind tighter than itself
        # (`not a == b` is `not (a == b)`, `-x^2` is `-(x^2)`); a loop, not recursion, so a
        # run of a thousand minus signs is fine.
        for prefix in reversed(prefixes):
            operand = self._infix(left, _PREFIX[prefix.value])
            left = ex.UnaryOp(prefix.value, operand, span=self._join(prefix.span, operand.span))
        return self._infix(left, min_bp)

    def _infix(self, left: ex.Expr, min_bp: int) -> ex.Expr:
        while self.pos < len(self.items):
            kind, op = self.items[self.pos]
            bp, right_assoc = _INFIX[op]
            if bp < min_bp:
                break
            self.pos += 1
            right = self.parse(bp if right_assoc else bp + 1)
            left = ex.BinOp(op, left, right, span=self._join(left.span, right.span))
        return left

    @staticmethod
    def _join(a: Span, b: Span) -> Span:
        return Span(a.file, a.line, a.column, b.end_line, b.end_column)
