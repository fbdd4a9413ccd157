"""Values and types of the model as CyPhyCircus expressions and types.

Evaluated constants (numbers, booleans, NumPy vectors and matrices) become literals; vectors
and matrices are sequences (a matrix a sequence of rows), as the paper's expression
semantics says. Quantities (``0.06m``) become their SI values, so no printer sees a unit.
"""

from __future__ import annotations

from decimal import Decimal
from typing import Any, Sequence


from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.model.evaluate import UNIT_FACTORS
from cyphy.semantics.circus import ast as c

_BASIC = {"real": c.REAL, "int": c.INT, "nat": c.NAT, "boolean": c.BOOL, "bool": c.BOOL}


def type_of(t: ast.TypeRef | None) -> c.Type:
    """The CyPhyCircus type of a declared RoboSim type: vectors and matrices are sequences,
    named types stay named (given sets)."""
    if t is None:
        return c.REAL
    if isinstance(t, ast.PrimitiveType):
        return _BASIC.get(t.name, c.TBasic(t.name))
    if isinstance(t, ast.VectorType):
        return c.TSeq(type_of(t.element), _size(t.size))
    if isinstance(t, ast.MatrixType):
        rows, cols = _size(t.rows), _size(t.cols)
        return c.TSeq(c.TSeq(type_of(t.element), cols), rows)
    if isinstance(t, ast.SeqType):
        return c.TSeq(type_of(t.element))
    if isinstance(t, ast.NamedType):
        name = t.name[-1]
        return _BASIC.get(name, c.TBasic(name))
    return c.TBasic(type(t).__name__)


def held_type(t: ast.TypeRef | None) -> c.Type:
    """How the theory's ``D`` holds a machine's variable or open constant: a Boolean as
    one, any number as a real (the interpreter computes on numbers alike, ``n / 2`` of an
    ``int`` is a half; and UTP expressions have no implicit conversion from ``int`` or
    ``nat`` to ``real``, so mixed arithmetic over declared types would not type-check)."""
    return c.BOOL if type_of(t) == c.BOOL else c.REAL


def open_type(t: ast.TypeRef | None) -> c.Type:
    """How the theory declares a machine's open constant: an ``int`` or ``nat`` as one
    (a real would widen the family to values the model cannot take; where ``D`` computes
    with it, the printer embeds it in the reals: ``real_of_int``, ``real``), a Boolean as
    one, any other number as a real."""
    declared = type_of(t)
    return declared if declared in (c.INT, c.NAT) else held_type(t)


def _size(e: ex.Expr | None) -> int | None:
    """A declared size when it is a positive literal (``matrix(real, 0, 0)`` is the
    notation's "any size")."""
    if isinstance(e, ex.Num) and e.is_integer and int(e.text) > 0:
        return int(e.text)
    return None


def constant_type(value: Any) -> c.Type:
    """The type of an evaluated constant that has no declaration at hand."""
    if isinstance(value, bool):
        return c.BOOL
    if isinstance(value, int):
        return c.INT
    shape = getattr(value, "shape", None)
    if shape is not None:
        if len(shape) == 2:
            return c.TSeq(c.TSeq(c.REAL, int(shape[1])), int(shape[0]))
        return c.TSeq(c.REAL, int(shape[0]))
    return c.REAL


def value_expr(value: Any) -> ex.Expr:
    """An evaluated value as a literal expression (shortest round-trip decimal text)."""
    if isinstance(value, bool):
        return ex.Bool(value)
    if isinstance(value, int):
        return ex.Num(str(value)) if value >= 0 else ex.UnaryOp("-", ex.Num(str(-value)))
    if isinstance(value, float):
        return _number(value)
    if isinstance(value, str):
        return ex.Str(value)
    tolist = getattr(value, "tolist", None)
    if tolist is not None:
        return value_expr(tolist())
    if isinstance(value, (list, tuple)):
        return ex.Seq(tuple(value_expr(v) for v in value))
    raise TypeError(f"no literal for {value!r}")


def _number(value: float) -> ex.Expr:
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(f"{value} has no literal")
    if value == 0:
        value = 0.0  # no -0.0

    # Positional, shortest round-trip digits: no exponent (Flow* and CZT reject `1e-5`).
    # repr gives the shortest digits that read back as the value, Decimal writes them
    # without an exponent (as NumPy's format_float_positional(unique=True, trim="0") does,
    # whose import costs start-up: tests/test_circus_values.py compares the two).
    text = format(Decimal(repr(abs(value))), "f")
    text = text if "." in text else text + ".0"
    return ex.Num(text) if value >= 0 else ex.UnaryOp("-", ex.Num(text))


def si_units(e: ex.Expr) -> ex.Expr:
    """The expression as CyPhyCircus sees it: every quantity replaced by its value in SI
    units (``0.06m`` → ``0.06``, ``90 deg`` → ``1.5707963267948966``; an expression value is
    multiplied), vectors and matrices as sequences (a matrix a sequence of rows), numbers
    with an exponent positional (``1e-5`` → ``0.00001``: CyPhyCircus numerals have none)."""

    def swap(node: ex.Expr) -> ex.Expr | None:
        if isinstance(node, ex.Num) and ("e" in node.text or "E" in node.text):
            return _number(float(node.text))
        if isinstance(node, (ex.Vector, ex.Matrix)):
            rows = tuple(ex.Seq(r, span=node.span) for r in node.rows)
            return rows[0] if len(rows) == 1 else ex.Seq(rows, span=node.span)
        if not isinstance(node, ex.Quantity):
            return None
        factor = UNIT_FACTORS.get(node.unit, 1.0)
        if factor == 1.0:
            return node.value
        if isinstance(node.value, ex.Num):
            return _number(float(node.value.text) * factor)
        return ex.BinOp("*", node.value, _number(factor), span=node.span)

    return ex.transform(e, swap)


def literal(value: float) -> ex.Expr:
    """A given number (a scenario's) as a literal: an integral value without a point (``3``:
    the theories' numerals), any other positional (``1e-7`` → ``0.0000001``)."""
    if float(value).is_integer():
        text = ex.Num(str(abs(int(value))))
        return text if value >= 0 else ex.UnaryOp("-", text)
    return _number(float(value))


def within(ranges: Sequence[tuple[str, ex.Expr, ex.Expr]]) -> c.Spec:
    """``x, y : [true, lo ≤ x ≤ hi ∧ …]``: the frame starts anywhere in its boxes (a frame
    name in a specification's postcondition is its after-state value)."""
    bounds: list[ex.Expr] = []
    for name, lo, hi in ranges:
        x = ex.Name((name,))
        bounds.extend((ex.BinOp("<=", lo, x), ex.BinOp("<=", x, hi)))
    return c.Spec(tuple(n for n, _, _ in ranges), ex.Bool(True), c.Exists((), tuple(bounds)))
