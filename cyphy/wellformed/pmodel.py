"""p-model conditions (paper: PM1)."""

from __future__ import annotations

from cyphy.lang import ast
from cyphy.wellformed.registry import WFContext, rule


@rule("PM1", "a p-model contains at least one link or part")
def check_PM1_has_link_or_part(ctx: WFContext) -> None:
    """A p-model (not a fragment) must contain at least one link or one part: a physical
    model with neither has nothing to simulate."""
    for _, pm in ctx.pmodels():
        if pm.fragment:
            continue
        if not pm.parts and not any(b.kind is ast.BlockKind.LINK for b in pm.blocks):
            ctx.error("PM1", pm, f"p-model {pm.name} contains no link and no part",
                      "add a 'local link' (or a part) to it")
