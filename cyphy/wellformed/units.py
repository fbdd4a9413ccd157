"""U1: a value written with a unit has the dimension of the place it is used in.

Values are converted to SI by their suffix (``3cm`` is 0.03), but nothing read the suffix's
dimension: ``mass 2m``, ``box(length = 3kg)`` and ``length = 30deg`` were silently taken as
2 kg, 3 m and 0.52 m. The dimensions come from Pint (``cyphy/model/units.py``); where each
place expects which is the notation's meaning (sdf.md: SI lengths, masses, radians) and, for
the library's constants, the units its comments give. A value without a unit is a number in
SI and is never questioned; a named constant has the dimension of its value.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.model.units import Dimension, units
from cyphy.wellformed.indexing import Lookup, lookup_in, part_names, site_names
from cyphy.wellformed.registry import WFContext, rule

LENGTH = Dimension.of({"[length]": 1})
MASS = Dimension.of({"[mass]": 1})
TIME = Dimension.of({"[time]": 1})
ANGLE = Dimension()  # radians and degrees are dimensionless (Pint, SI)
INERTIA = MASS * LENGTH ** 2
FORCE = MASS * LENGTH / TIME ** 2

POSE = {"x": LENGTH, "y": LENGTH, "z": LENGTH, "roll": ANGLE, "pitch": ANGLE, "yaw": ANGLE}
FREQUENCY = TIME ** -1
# Annotation values (physmod::sdf::annotations, SDFormat's units): a joint axis's position,
# limits and dynamics, rotational or translational by the joint's template, and sensor ranges
# and rates. Paths are the nested template parameters, the last one the value's.
_ROTATION = {("limit", "lower"): ANGLE, ("limit", "upper"): ANGLE,
             ("limit", "velocity"): ANGLE / TIME, ("limit", "effort"): FORCE * LENGTH,
             ("initial_position",): ANGLE, ("dynamics", "spring_reference"): ANGLE,
             ("dynamics", "damping"): FORCE * LENGTH * TIME}
_TRANSLATION = {("limit", "lower"): LENGTH, ("limit", "upper"): LENGTH,
                ("limit", "velocity"): LENGTH / TIME, ("limit", "effort"): FORCE,
                ("initial_position",): LENGTH, ("dynamics", "spring_reference"): LENGTH,
                ("dynamics", "damping"): FORCE * TIME / LENGTH}
_SENSOR = {("update_rate",): FREQUENCY, ("sonar", "min"): LENGTH, ("sonar", "max"): LENGTH,
           ("sonar", "_radius"): LENGTH, ("ray", "range", "min"): LENGTH,
           ("ray", "range", "max"): LENGTH}
ANNOTATIONS: dict[str, dict[tuple[str, ...], Dimension]] = {
    **{t: {(axis, *k): d for axis in ("axis", "axis2") for k, d in _ROTATION.items()}
       for t in ("Revolute", "Revolute2", "Universal", "Gearbox")},
    "Prismatic": {("axis", *k): d for k, d in _TRANSLATION.items()},
    **{t: _SENSOR for t in ("Sonar", "Ray", "Camera", "IMU", "Contact", "Logical_camera")},
}
# The library's constants a model instantiates, with the units the library's comments give
# (cyphy/lang/library/physmod): the rotor's inertia, viscous friction (torque per angular
# speed, force per speed) and the joints' axes (directions).
LIBRARY_CONSTANTS: dict[str, dict[str, Dimension]] = {
    "SpeedControlMotor": {"J": INERTIA, "b": FORCE * LENGTH * TIME},
    "LinearSpeedControlMotor": {"b": FORCE * TIME / LENGTH},
    **{joint: {"AXIS": Dimension()} for joint in ("Revolute", "Prismatic", "Helical")},
}


class MixedDimensions(Exception):
    """An expression that adds or compares values of different dimensions."""

    def __init__(self, node: ex.Expr, left: Dimension, right: Dimension) -> None:
        super().__init__(node)
        self.node, self.left, self.right = node, left, right


NameDimension = Callable[[ex.Name], "Dimension | None"]


def dimension_of(e: ex.Expr, named: NameDimension = lambda n: None) -> Dimension | None:
    """The dimension of ``e`` from its unit suffixes (``named`` gives a name's: that of the
    constant's value); None when no unit decides it (plain numbers, calls, constants written
    without a unit). Raises :class:`MixedDimensions` for ``2m + 3kg``."""
    if isinstance(e, (ex.Name, ex.Member, ex.Index)):  # a mapping's element path too
        return named(e)  # type: ignore[arg-type]
    if isinstance(e, ex.Quantity):
        unit = units().get(e.unit)
        inner = dimension_of(e.value, named)
        if unit is None:  # E-EVAL reports an unknown unit
            return None
        return unit.dimension * inner if inner is not None else unit.dimension
    if isinstance(e, ex.UnaryOp) and e.op == "-":
        return dimension_of(e.operand, named)
    if isinstance(e, ex.BinOp):
        left, right = dimension_of(e.left, named), dimension_of(e.right, named)
        if e.op in ("+", "-"):
            if left is not None and right is not None and left != right:
                raise MixedDimensions(e, left, right)
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


Place = tuple[ex.Expr, Dimension, Callable[[], str], Callable[[], Lookup]]


def _places(ctx: WFContext) -> Iterator[Place]:
    """Every value the notation gives a dimension: (expression, expected, what it is, how to
    look up the names visible there). The texts and lookups are made only for the few values
    that are not plain numbers: most blocks of a large model have only numbers."""
    for site in ctx.blocks():
        def where(site: Any = site) -> str:
            return f"{site.block.kind.value} {site.qualified}"

        def lookup(site: Any = site) -> Lookup:
            return lookup_in(ctx, site.file, site_names(ctx, site))

        def outer(site: Any = site) -> Lookup:
            return lookup_in(ctx, site.file, site_names(ctx, site, inside=False))

        yield from _pose(site.block.pose, where, lookup)
        for a in site.block.annotations:
            yield from _annotation(a.instance, where, lookup)
        for d in site.block.definitions:
            yield from _members(d.members, where, lookup)
        target = ctx.target(site.block)
        if isinstance(target, ast.Definition) and target.name in LIBRARY_CONSTANTS:
            expected = LIBRARY_CONSTANTS[target.name]
            for i in site.block.instantiations:  # evaluated where the block is written
                if i.name in expected:
                    yield (i.value, expected[i.name],
                           lambda n=target.name, i=i.name, w=where: f"{n}'s {i} in {w()}",
                           outer)
    for f, d in ctx.definitions():
        names = {m.name: m for m in d.members if isinstance(m, ast.VarDecl)}
        yield from _members(d.members, lambda d=d: f"{d.kind.value} {d.name}",
                            lambda f=f, names=names: lookup_in(ctx, f, names))
    for f, pm in ctx.pmodels():
        for part in pm.parts:
            yield from _pose(part.pose, lambda pm=pm, part=part: f"part {pm.name}::{part.name}",
                             lambda f=f, pm=pm, part=part: lookup_in(ctx, f,
                                                                     part_names(pm, part)))


def _pose(pose: ast.Pose | None, where: Callable[[], str], lookup: Callable[[], Lookup]
          ) -> Iterator[Place]:
    for f in pose.fields if pose is not None else ():
        if not isinstance(f.value, ex.Num):  # nearly every value: a plain number in SI
            yield f.value, POSE[f.key], lambda k=f.key: f"the pose's {k} of {where()}", lookup


def _annotation(instance: ast.TemplateInstance, where: Callable[[], str],
                lookup: Callable[[], Lookup]) -> Iterator[Place]:
    expected = ANNOTATIONS.get(instance.template[-1])
    if expected is None:
        return
    stack: list[tuple[tuple[str, ...], ast.TemplateInstance]] = [((), instance)]
    while stack:
        path, inst = stack.pop()
        for arg in inst.args:
            at = (*path, arg.name)
            if isinstance(arg.value, ast.TemplateInstance):
                stack.append((at, arg.value))
            elif at in expected and not isinstance(arg.value, ex.Num):
                yield (arg.value, expected[at],
                       lambda at=at: f"the annotation's {'.'.join(at)} of {where()}", lookup)


def _members(members: Any, where: Callable[[], str], lookup: Callable[[], Lookup]
             ) -> Iterator[Place]:
    for m in members:
        if isinstance(m, ast.Annotation):
            yield from _annotation(m.instance, where, lookup)
        if isinstance(m, ast.Shape):
            for a in m.args:
                if isinstance(a.value, ex.Num):
                    continue
                yield (a.value, LENGTH, lambda k=m.kind, n=a.name: f"the {k}'s {n} of {where()}",
                       lookup)
        elif isinstance(m, ast.Mesh) and m.scaling is not None:
            yield m.scaling, Dimension(), lambda: f"the mesh scaling of {where()}", lookup
        elif isinstance(m, ast.Inertial):
            if m.mass is not None:
                yield m.mass, MASS, lambda: f"the mass of {where()}", lookup
            for entry in m.inertia or ():
                yield (entry.value, INERTIA,
                       lambda n=entry.name: f"the inertia {n} of {where()}", lookup)
            yield from _pose(m.pose, lambda: f"the inertial information of {where()}", lookup)


def _constants(lookup: Lookup) -> NameDimension:
    """A name's dimension: that of the value of the constant it names (``const H: real =
    0.05m``), followed through constants defined by constants; None for anything else."""
    busy: set[int] = set()

    def named(name: ex.Name) -> Dimension | None:
        if not isinstance(name, ex.Name):
            return None  # an element path: no constant
        decl = lookup(name)
        if not isinstance(decl, ast.VarDecl) or decl.kind is not ast.DeclKind.CONST \
                or decl.value is None or id(decl) in busy:
            return None
        busy.add(id(decl))  # a constant defined by itself: E-EVAL's, not followed
        try:
            return dimension_of(decl.value, named)
        finally:
            busy.discard(id(decl))

    return named


def written_text(ctx: WFContext, span: Span) -> str:
    """The expression as written (one line), for the message."""
    text = ctx.workspace.texts.get(span.file)
    if text is None or span.line != span.end_line or span.line < 1:
        return ""
    line = text.splitlines()[span.line - 1]
    return line[span.column - 1:span.end_column - 1].strip()


def dimension_text(d: Dimension) -> str:
    return "dimensionless (an angle or a plain number)" if not d.exponents else str(d)


def _is(d: Dimension) -> str:
    return "is dimensionless (an angle)" if not d.exponents else f"has the dimension {d}"


def unit_hint(expected: Dimension) -> str:
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
    mixed: set[Span] = set()
    for value, expected, what, lookup in _places(ctx):
        if isinstance(value, ex.Num):
            continue
        try:
            found = dimension_of(value, _constants(lookup()))
        except MixedDimensions as err:
            if err.node.span in mixed:  # a constant's sum, met again where it is used
                continue
            mixed.add(err.node.span)
            ctx.error("U1", err.node.span, f"{what()} ({written_text(ctx, err.node.span)}) adds "
                      f"{dimension_text(err.left)} to {dimension_text(err.right)}; expected "
                      f"{dimension_text(expected)}", unit_hint(expected))
            continue
        if found is not None and found != expected:
            ctx.error("U1", value.span, f"{what()} ({written_text(ctx, value.span)}) {_is(found)}; "
                      f"expected {dimension_text(expected)}",
                      unit_hint(expected))
