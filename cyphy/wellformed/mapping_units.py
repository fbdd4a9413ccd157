"""U2: the units written in a platform mapping agree with the ports they meet.

A mapping relates d-model values to p-model ports. RoboChart's values carry no units: the
software's ``w`` is a number in the p-model's units (SI), and so is a bare number written
in the mapping (``das == 10``, ``range <= 1.0``). A value written with a unit (``1m``,
``30deg``) says what it is, so it must have the dimension of the port it is compared
with, added to or assigned to: ``das == w * 1m`` sets a desired angular speed (rad/s) from
a length, which every command would silently take as ``das == w``. A port has the dimension
its definition declares: the library's, from its comments (:data:`LIBRARY_PORTS`); the
ports of a model's own definitions declare none and are not judged. Dimensions are U1's
(Pint's table, :func:`cyphy.wellformed.units.dimension_of`).
"""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.ast.core import fields_of
from cyphy.lang.resolve import steps_of
from cyphy.model.units import Dimension
from cyphy.wellformed.mapping_names import Names
from cyphy.wellformed.platform_services import in_user_file, label_of, members_of, sites
from cyphy.wellformed.registry import WFContext, rule
from cyphy.wellformed.units import (FORCE, LENGTH, TIME, dimension_text, unit_hint, MixedDimensions, written_text,
                                    dimension_of)

#: The ports of the library's sensors and actuators, with the units its comments give
#: (cyphy/lang/library/physmod: angular speeds in rad/s, lengths in m, torques in N m).
LIBRARY_PORTS: dict[str, dict[str, Dimension]] = {
    "SpeedControlMotor": {"das": TIME ** -1, "T": FORCE * LENGTH},
    "LinearSpeedControlMotor": {"dls": LENGTH / TIME, "F": FORCE},
    "TorqueControlMotor": {"TorqueIn": FORCE * LENGTH, "TorqueOut": FORCE * LENGTH},
    "Sonar": {"distance": LENGTH, "range": LENGTH},
    "IR": {"distance": LENGTH},  # its voltage: the notation has no volt suffix
}
_COMPARISONS = ("==", "!=", "<", "<=", ">", ">=")


def _port_dimension(ctx: WFContext, names: Names, e: ex.Expr) -> Dimension | None:
    """The dimension of the library port an element path names; None for anything else."""
    ref = names.classify(e)
    if ref.block is None or ref.block.ref is None:
        return None
    definition = ctx.target(ref.block)
    if not isinstance(definition, ast.Definition) or in_user_file(ctx, definition):
        return None  # a model's own definition declares no units
    ports = LIBRARY_PORTS.get(definition.name, {})
    steps = steps_of(e) or []
    port = next((s[0] for s in reversed(steps) if s[0] in ports), None)
    return ports.get(port) if port is not None else None


def _assignments(node: object) -> Iterator[ast.Assign]:
    if isinstance(node, ast.Assign):
        yield node
    elif isinstance(node, tuple):
        for item in node:
            yield from _assignments(item)
    elif isinstance(node, ast.Node):  # a conditional or block of statements
        for f in fields_of(type(node)):
            if f.name != "span":
                yield from _assignments(getattr(node, f.name))


def _pairs(member: object) -> Iterator[tuple[ex.Expr, ex.Expr, ex.Expr]]:
    """(left, right, where to point) for each comparison inside the member's equations and
    predicates, and each assignment of its actions."""
    for e in ast.expressions_in(getattr(member, "members", ())):
        for node in e.walk():
            if isinstance(node, ex.BinOp) and node.op in _COMPARISONS:
                yield node.left, node.right, node
    for a in _assignments(getattr(member, "members", ())):
        yield a.target, a.value, a.value


@rule("U2", "a platform mapping compares, adds and assigns values of one dimension: the "
      "library's ports and values with units (Pint's units)")
def check_U2_mapping_units(ctx: WFContext) -> None:
    """In a mapping's equations, predicates and actions, the two sides of a comparison or
    assignment, and the terms of a sum, have one dimension wherever both are known: a
    library port's, or a value's unit; the software's values and bare numbers are taken in
    the port's unit and never questioned."""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        for member in members_of(site.mapping):
            names = Names(ctx, site, member)

            def named(e: ex.Expr, names: Names = names) -> Dimension | None:
                return _port_dimension(ctx, names, e)

            for left, right, node in _pairs(member):
                try:
                    sides = dimension_of(left, named), dimension_of(right, named)
                except MixedDimensions as err:
                    ctx.error("U2", err.node.span, f"the mapping of {label_of(member)} adds "
                              f"{dimension_text(err.left)} to {dimension_text(err.right)} "
                              f"({written_text(ctx, err.node.span)})", "write both terms in "
                              "units of one dimension, or as plain numbers in the port's "
                              "SI unit")
                    continue
                if None in sides or sides[0] == sides[1]:
                    continue
                ctx.error("U2", node.span, f"the mapping of {label_of(member)} relates "
                          f"{dimension_text(sides[0])} to {dimension_text(sides[1])} "  # type: ignore
                          f"({written_text(ctx, node.span)})",
                          unit_hint(sides[0]) + ": a bare number is taken in the port's "  # type: ignore[arg-type]
                          "unit")
