"""Platform mappings: IX5, an index into an indexed element names one of its copies.

``Core::Proximity[1].voltage`` reads copy 1 of the ring of 24 sensors ``index j : [0,24)``.
An index outside the range (``Proximity[24]``), or as many indices as the element does not
have, names no sensor: the semantics would read a variable that does not exist, and the
mapping's event would never (or always) occur. Indices and bounds that are integer literals
are compared; others (a constant, an expression) are left to the elaboration.
"""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.resolution.names import block_children, steps_of
from cyphy.wellformed.mapping_names import pmodel_of_part
from cyphy.wellformed.platform_services import Site, label_of, members_of, sites
from cyphy.wellformed.registry import WFContext, rule


def _literal(e: ex.Expr) -> int | None:
    """An integer literal, possibly negated; None for anything else."""
    if isinstance(e, ex.UnaryOp) and e.op == "-":
        inner = _literal(e.operand)
        return -inner if inner is not None else None
    return int(e.text) if isinstance(e, ex.Num) and e.is_integer else None


def _block(ctx: WFContext, site: Site, names: list[str]) -> ast.Block | None:
    """The block an element path names (``Core::Proximity``), or None."""
    if site.pmodel is None or site.pmodel_file is None:
        return None
    if names and names[0] == site.pmodel.name:
        names = names[1:]
    current: ast.PModel | ast.Block | ast.Part = site.pmodel
    file = site.pmodel_file
    for name in names:
        if isinstance(current, ast.Part):
            inner = pmodel_of_part(ctx, current, file)
            if inner is None:
                return None
            current, file = inner
        children = block_children(current)
        if name in children:
            current = children[name][0]
            continue
        nested = [block_children(b)[name][0] for b in getattr(current, "blocks", ())
                  if name in block_children(b)]
        if not nested:
            return None
        current = nested[0]
    return current if isinstance(current, ast.Block) else None


def _indexed_paths(e: ex.Expr) -> Iterator[ex.Index]:
    for node in e.walk():
        if isinstance(node, ex.Index) and steps_of(node.base):
            yield node


@rule("IX5", "an index into an indexed element names one of its copies")
def check_IX5_mapping_indices(ctx: WFContext) -> None:
    """In a platform mapping, ``E[i]`` names copy ``i`` of an element declared with
    ``index v : [a, b)`` (or ``[a, b]``): as many indices as the element has index
    declarations, each within its range."""
    for site in sites(ctx):
        for member in members_of(site.mapping):
            for node in (n for m in member.members for e in ast.expressions_in(m)
                         for n in _indexed_paths(e)):
                steps = steps_of(node.base) or []
                block = _block(ctx, site, [s[0] for s in steps])
                if block is None:
                    continue
                where = f"the mapping of {label_of(member)}"
                if len(node.args) != len(block.indices):
                    ctx.error("IX5", node, f"{where} gives {block.name} {len(node.args)} "
                              f"ind{'ex' if len(node.args) == 1 else 'ices'}; it has "
                              f"{len(block.indices)}", f"write one index per 'index' of "
                              f"{block.name}")
                    continue
                for arg, decl in zip(node.args, block.indices):
                    value, low, high = (_literal(arg), _literal(decl.lower),
                                        _literal(decl.upper))
                    if value is None or low is None or high is None:
                        continue
                    last = high if decl.closed else high - 1
                    if not low <= value <= last:
                        ctx.error("IX5", arg, f"{where} reads copy {value} of {block.name}, "
                                  f"whose index {decl.var} ranges over {low}..{last}",
                                  f"use an index from {low} to {last}")
