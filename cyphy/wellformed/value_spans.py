"""Where a value of the elaborated model was written, for the value checks (V1-V6).

The elaborated model keeps each element's span (its block), not the spans of its values; a
diagnostic about a negative mass or a zero axis should point at the mass or the axis, not at
the block ten lines above it. These helpers find the block's source (a block of a user file)
and in it the member that gave the value; where they cannot (a reference block whose
definition is in the library), they return the element's own span.
"""

from __future__ import annotations

from typing import Any, Iterator

from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.wellformed.registry import WFContext


def _blocks(members: tuple[object, ...]) -> Iterator[ast.Block]:
    for m in members:
        if isinstance(m, ast.Block):
            yield m
            yield from _blocks(m.members)


def source_block(ctx: WFContext, element: Any) -> ast.Block | None:
    """The block of a user file that an element of the elaborated model comes from."""
    index: dict[tuple[str, int, int], ast.Block] | None = ctx.cache.get("value-spans")
    if index is None:
        index = {}
        for _, pm in ctx.items(ast.PModel):
            for b in _blocks(pm.members):
                index[(b.span.file, b.span.line, b.span.column)] = b
        ctx.cache["value-spans"] = index
    span = element.span
    return index.get((span.file, span.line, span.column))


def _members(block: ast.Block) -> Iterator[object]:
    """The block's own members and those of its local definition (``def { … }``)."""
    yield from block.members
    for d in block.definitions:
        yield from d.members


def mass_span(ctx: WFContext, element: Any) -> Span:
    """The mass as written (``mass -0.2kg``), else the element."""
    block = source_block(ctx, element)
    for m in _members(block) if block is not None else ():
        if isinstance(m, ast.Inertial) and m.mass is not None:
            return m.mass.span  # type: ignore[no-any-return]
    return element.span  # type: ignore[no-any-return]


def inertia_span(ctx: WFContext, element: Any) -> Span:
    """The inertia matrix as written: its first diagonal entry that is negative as written,
    else its first entry; else the element."""
    block = source_block(ctx, element)
    for m in _members(block) if block is not None else ():
        if isinstance(m, ast.Inertial) and m.inertia:
            negative = [e for e in m.inertia if e.name in ("ixx", "iyy", "izz")
                        and getattr(e.value, "op", None) == "-"]
            return (negative or list(m.inertia))[0].span  # type: ignore[no-any-return]
    return element.span  # type: ignore[no-any-return]


def axis_span(ctx: WFContext, joint: Any, constant: bool) -> Span:
    """The joint's ``instantiation AXIS = …`` (``constant``) or its annotation's ``xyz``,
    else the joint."""
    block = source_block(ctx, joint)
    for m in _members(block) if block is not None else ():
        if constant and isinstance(m, ast.Instantiation) and m.name == "AXIS":
            return m.span  # type: ignore[no-any-return]
        if not constant and isinstance(m, ast.Annotation):
            found = _find_arg(m.instance, "xyz")
            if found is not None:
                return found
    return joint.span  # type: ignore[no-any-return]


def _find_arg(instance: ast.TemplateInstance, name: str) -> Span | None:
    for a in instance.args:
        if a.name == name:
            return a.span  # type: ignore[no-any-return]
        nested = getattr(a, "value", None)
        if isinstance(nested, ast.TemplateInstance):
            found = _find_arg(nested, name)
            if found is not None:
                return found
    return None
