"""The one expression AST shared by every stage (parser, model, checks, semantics, printers).

Nodes are frozen dataclasses with tuple children. ``span`` does not take part in equality, so
two expressions that mean the same thing compare equal wherever they were written; passes return
new trees instead of mutating. Printers dispatch on the class name (``_print_BinOp``).
"""

from __future__ import annotations

from dataclasses import field, fields, replace
from operator import attrgetter
from typing import Any, Callable, Iterator

from cyphy.diagnostics import Span
from cyphy.pickling import FastPickle
from cyphy.records import record

_NO_SPAN = Span.unknown()


@record
class Expr(FastPickle):
    """Base class of expressions; never instantiated itself."""

    def children(self) -> Iterator[Expr]:
        return iter(_children(self))

    def walk(self) -> Iterator[Expr]:
        """This node and all its descendants, parents first (iterative: expressions from
        generated files can be thousands of levels deep)."""
        stack: list[Expr] = [self]
        while stack:
            node = stack.pop()
            yield node
            found = _children(node)
            if found:
                found.reverse()
                stack.extend(found)


@record
class Num(Expr):
    """A numeric literal, kept as written (``0.05``, ``1e+16``) so integers stay integers."""

    text: str
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)

    @property
    def is_integer(self) -> bool:
        return self.text.isdigit()


@record
class Quantity(Expr):
    """A value with a unit suffix: ``0.03m``, ``(0.085*cos(i))m``, ``1.0 metre``."""

    value: Expr
    unit: str
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Str(Expr):
    value: str
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Bool(Expr):
    value: bool
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Name(Expr):
    """A possibly qualified name: ``PI``, ``Core::LHinge::LMotor`` (parts split at ``::``)."""

    parts: tuple[str, ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)

    @property
    def text(self) -> str:
        return "::".join(self.parts)


@record
class BinOp(Expr):
    """A binary operation; ``op`` is the notation's operator (``+``, ``/\\``, ``==``, ``^``…)."""

    op: str
    left: Expr
    right: Expr
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class UnaryOp(Expr):
    """``-e`` or ``not e``."""

    op: str
    operand: Expr
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Call(Expr):
    """An application ``f(a, b)``; also curried calls ``submatrix(M)(0,0,3,3)``."""

    func: Expr
    args: tuple[Expr, ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Index(Expr):
    """``x[i]``, ``x[i, j]``; an index whose single argument is ``t == e`` is an IBCondition."""

    base: Expr
    args: tuple[Expr, ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Member(Expr):
    """Field or port access ``base.name`` (``LMotor.T``, ``su.shoulderAngle``)."""

    base: Expr
    name: str
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Derivative(Expr):
    """``derivative(e)``: the time derivative, classified from a call after parsing."""

    operand: Expr
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Integral(Expr):
    """``integral(e)`` (running integral from 0) or ``integral(e, lo, hi)``."""

    operand: Expr
    lower: Expr | None = None
    upper: Expr | None = None
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Vector(Expr):
    """``(| a, b, c |)``: a vector or tuple; rows separated by ``;`` make it a matrix."""

    rows: tuple[tuple[Expr, ...], ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Matrix(Expr):
    """``[| a, b; c, d |]``: a matrix (a single row is also used for vectors)."""

    rows: tuple[tuple[Expr, ...], ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Seq(Expr):
    """``< a, b >``: a sequence."""

    items: tuple[Expr, ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


@record
class Record(Expr):
    """``Geom (| geomType = "box", geomVal = [|…|] |)``: a record constructor."""

    type_name: tuple[str, ...]
    fields: tuple[tuple[str, Expr], ...]
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)

    def children(self) -> Iterator[Expr]:
        for _, value in self.fields:
            yield value


@record
class PlatformRef(Expr):
    """RoboSim's ``$e`` (an event, operation or variable of the robotic platform, read or
    called by a state machine) and ``$e?x`` (the event's value bound to ``x`` when it
    occurs). Only d-model behaviour uses it."""

    name: tuple[str, ...]
    binding: str | None = None
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)

    @property
    def text(self) -> str:
        return "::".join(self.name)


@record
class IfExpr(Expr):
    cond: Expr
    then: Expr
    orelse: Expr
    span: Span = field(default=_NO_SPAN, compare=False, repr=False)


_FIELDS: dict[type, tuple[Any, ...]] = {}


def fields_of(cls: type) -> tuple[Any, ...]:
    """``dataclasses.fields`` per class, once: walks and transforms visit every node, and
    ``fields`` itself filters the class's field table at each call."""
    found = _FIELDS.get(cls)
    if found is None:
        found = _FIELDS[cls] = fields(cls)
    return found


#: Per class, the function that reads all its fields' values at once (``attrgetter`` reads
#: them in C): walks visit every node of every expression, many times per command.
_VALUES: dict[type, Callable[[Any], tuple[Any, ...]]] = {}


def _field_values(cls: type) -> Callable[[Any], tuple[Any, ...]]:
    names = [f.name for f in fields_of(cls)]
    if not names:
        return lambda node: ()
    if len(names) == 1:
        one = attrgetter(names[0])
        return lambda node: (one(node),)
    return attrgetter(*names)


def _children(node: Expr) -> list[Expr]:
    """The node's sub-expressions in field order: fields that hold one, tuples of them and
    tuples of tuples of them (a record's fields, a matrix's rows)."""
    cls = type(node)
    values = _VALUES.get(cls)
    if values is None:
        values = _VALUES[cls] = _field_values(cls)
    out: list[Expr] = []
    for value in values(node):
        if isinstance(value, Expr):
            out.append(value)
        elif isinstance(value, tuple):
            for item in value:
                if isinstance(item, Expr):
                    out.append(item)
                elif isinstance(item, tuple):
                    out.extend(x for x in item if isinstance(x, Expr))
    return out


def conjuncts(e: Expr) -> list[Expr]:
    """The operands of a conjunction ``a /\\ b /\\ …`` (``[e]`` when ``e`` is not one)."""
    if isinstance(e, BinOp) and e.op == "/\\":
        return conjuncts(e.left) + conjuncts(e.right)
    return [e]


def transform(expr: Expr, fn: Callable[[Expr], Expr | None]) -> Expr:
    """Rebuild ``expr`` bottom-up; ``fn`` may return a replacement for a node or ``None``."""
    changes: dict[str, object] = {}
    for f in fields_of(type(expr)):
        value = getattr(expr, f.name)
        if isinstance(value, Expr):
            new = transform(value, fn)
            if new is not value:
                changes[f.name] = new
        elif isinstance(value, tuple) and value and f.name != "type_name":
            new_items = tuple(_transform_item(item, fn) for item in value)
            if any(a is not b for a, b in zip(new_items, value)):
                changes[f.name] = new_items
    rebuilt = replace(expr, **changes) if changes else expr
    result = fn(rebuilt)
    return rebuilt if result is None else result


def _transform_item(item: object, fn: Callable[[Expr], Expr | None]) -> object:
    if isinstance(item, Expr):
        return transform(item, fn)
    if isinstance(item, tuple):
        new = tuple(_transform_item(x, fn) for x in item)
        return item if all(a is b for a, b in zip(new, item)) else new
    return item


def conjunction(items: list[Expr]) -> Expr:
    """``a /\\ b /\\ …`` (left-nested, as the parser builds it) of one or more predicates."""
    out = items[0]
    for item in items[1:]:
        out = BinOp("/\\", out, item, span=getattr(item, "span", _NO_SPAN))
    return out


def path_of(expr: Expr) -> tuple[str, ...] | None:
    """The element path an expression denotes, or None when it is not a plain path.

    ``Core::LHinge::LMotor.das`` → ``('Core', 'LHinge', 'LMotor', 'das')``; ``.`` and ``::``
    are equivalent for navigation (notation A.12.6). Index steps are not plain paths.
    """
    if isinstance(expr, Name):
        return expr.parts
    if isinstance(expr, Member):
        base = path_of(expr.base)
        return None if base is None else base + (expr.name,)
    return None
