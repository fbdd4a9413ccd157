"""U1: a value written with a unit has the dimension of the place it is used in.

Values are converted to SI by their suffix (``3cm`` is 0.03), but nothing read the suffix's
dimension: ``mass 2m``, ``box(length = 3kg)`` and ``length = 30deg`` were silently taken as
2 kg, 3 m and 0.52 m. The dimensions come from Pint (``cyphy/model/units.py``); where each
place expects which is the notation's meaning (sdf.md: SI lengths, masses, radians) and, for
the library's constants, the units its comments give. A value without a unit is a number in
SI and is never questioned; a named constant is not followed (its unit is checked where it is
defined, if that is one of these places).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.model.units import Dimension, units
from cyphy.wellformed.registry import WFContext, rule

LENGTH = Dimension.of({"[length]": 1})
MASS = Dimension.of({"[mass]": 1})
TIME = Dimension.of({"[time]": 1})
ANGLE = Dimension()  # radians and degrees are dimensionless (Pint, SI)
INERTIA = MASS * LENGTH ** 2
FORCE = MASS * LENGTH / TIME ** 2

POSE = {"x": LENGTH, "y": LENGTH, "z": LENGTH, "roll": ANGLE, "pitch": ANGLE, "yaw": ANGLE}
# The library's constants a model instantiates, with the units the library's comments give
# (cyphy/lang/library/physmod): the rotor's inertia, viscous friction (torque per angular
# speed, force per speed) and the joints' axes (directions).
LIBRARY_CONSTANTS: dict[str, dict[str, Dimension]] = {
    "SpeedControlMotor": {"J": INERTIA, "b": FORCE * LENGTH * TIME},
    "LinearSpeedControlMotor": {"b": FORCE * TIME / LENGTH},
    **{joint: {"AXIS": Dimension()} for joint in ("Revolute", "Prismatic", "Helical")},
}


class _Mixed(Exception):
    """An expression that adds or compares values of different dimensions."""

    def __init__(self, node: ex.Expr, left: Dimension, right: Dimension) -> None:
        super().__init__(node)
        self.node, self.left, self.right = node, left, right


def dimension_of(e: ex.Expr) -> Dimension | None:
    """The dimension of ``e`` from its unit suffixes; None when no unit decides it (plain
    numbers, names, calls). Raises :class:`_Mixed` for ``2m + 3kg``."""
    if isinstance(e, ex.Quantity):
        unit = units().get(e.unit)
        inner = dimension_of(e.value)
        if unit is None:  # E-EVAL reports an unknown unit
            return None
        return unit.dimension * inner if inner is not None else unit.dimension
    if isinstance(e, ex.UnaryOp) and e.op == "-":
        return dimension_of(e.operand)
    if isinstance(e, ex.BinOp):
        left, right = dimension_of(e.left), dimension_of(e.right)
        if e.op in ("+", "-"):
            if left is not None and right is not None and left != right:
                raise _Mixed(e, left, right)
            return left if left is not None else right
        if e.op == "*":
            if left is None or right is None:
                return right if left is None else left
            return left * right
        if e.op == "/":
            if left is None and right is None:
                return None
            return (left or Dimension()) / (right or Dimension())
        if e.op == "^" and left is not None and isinstance(e.right, ex.Num):
            return left ** float(e.right.text)
    return None


def _places(ctx: WFContext) -> Iterator[tuple[ex.Expr, Dimension, str]]:
    """Every value the notation gives a dimension: (expression, expected, what it is)."""
    for site in ctx.blocks():
        where = f"{site.block.kind.value} {site.qualified}"
        yield from _pose(site.block.pose, where)
        for d in site.block.definitions:
            yield from _members(d.members, where)
        target = ctx.target(site.block)
        if isinstance(target, ast.Definition) and target.name in LIBRARY_CONSTANTS:
            expected = LIBRARY_CONSTANTS[target.name]
            for i in site.block.instantiations:
                if i.name in expected:
                    yield i.value, expected[i.name], f"{target.name}'s {i.name} in {where}"
    for _, d in ctx.definitions():
        yield from _members(d.members, f"{d.kind.value} {d.name}")
    for _, pm in ctx.pmodels():
        for part in pm.parts:
            yield from _pose(part.pose, f"part {pm.name}::{part.name}")


def _pose(pose: ast.Pose | None, where: str) -> Iterator[tuple[ex.Expr, Dimension, str]]:
    for f in pose.fields if pose is not None else ():
        yield f.value, POSE[f.key], f"the pose's {f.key} of {where}"


def _members(members: Any, where: str) -> Iterator[tuple[ex.Expr, Dimension, str]]:
    for m in members:
        if isinstance(m, ast.Shape):
            for a in m.args:
                yield a.value, LENGTH, f"the {m.kind}'s {a.name} of {where}"
        elif isinstance(m, ast.Mesh) and m.scaling is not None:
            yield m.scaling, Dimension(), f"the mesh scaling of {where}"
        elif isinstance(m, ast.Inertial):
            if m.mass is not None:
                yield m.mass, MASS, f"the mass of {where}"
            for entry in m.inertia or ():
                yield entry.value, INERTIA, f"the inertia {entry.name} of {where}"
            yield from _pose(m.pose, f"the inertial information of {where}")


def _written(ctx: WFContext, span: Span) -> str:
    """The expression as written (one line), for the message."""
    text = ctx.workspace.texts.get(span.file)
    if text is None or span.line != span.end_line or span.line < 1:
        return ""
    line = text.splitlines()[span.line - 1]
    return line[span.column - 1:span.end_column - 1].strip()


def _dimension(d: Dimension) -> str:
    return "dimensionless (an angle or a plain number)" if not d.exponents else str(d)


def _is(d: Dimension) -> str:
    return "is dimensionless (an angle)" if not d.exponents else f"has the dimension {d}"


def _how(expected: Dimension) -> str:
    """The suffixes (from Pint's table) that have the expected dimension."""
    fitting = sorted((n for n, u in units().items() if u.dimension == expected and len(n) <= 3),
                     key=lambda n: (units()[n].factor != 1.0, n))
    if not fitting:
        return "write it as a plain number in SI units (no suffix has this dimension)"
    return f"write it in {', '.join(fitting)}, or as a plain number in SI units"


@rule("U1", "a value with a unit has the dimension of the place it is used in (Pint's units)")
def check_U1_unit_dimensions(ctx: WFContext) -> None:
    """Each value written with a unit suffix (``0.03m``, ``2kg``, ``30deg``) has the dimension
    where it is used: lengths for sizes and positions, angles for orientations, a mass, a mass
    times a length squared for inertia entries, the library's units for its constants; the
    terms of a sum agree with each other."""
    for value, expected, what in _places(ctx):
        try:
            found = dimension_of(value)
        except _Mixed as err:
            ctx.error("U1", err.node.span, f"{what} ({_written(ctx, err.node.span)}) adds "
                      f"{_dimension(err.left)} to {_dimension(err.right)}; expected "
                      f"{_dimension(expected)}", _how(expected))
            continue
        if found is not None and found != expected:
            ctx.error("U1", value.span, f"{what} ({_written(ctx, value.span)}) {_is(found)}; "
                      f"expected {_dimension(expected)}",
                      _how(expected))
