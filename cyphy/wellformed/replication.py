"""Replicated elements: IX3 (a joint to a replicated link, element i to element i) and IX4
(qualified names are unique), on the elaborated model.

They need the copies an index range makes, so they read the elaborated top-level p-models that
the value checks share (``values._models``). RoboTool joins a joint to every copy of an indexed
target and names all those joints alike (sdf-robotool.md 1.8: ``IJTIL``, ``75_jointtest``): the
model then has one joint with several children, ``show`` lists one name twice, and the joints'
equations are not renamed apart, so ``solve`` fails far from the cause. The notation's rule is
that element i of an indexed joint goes to element i of the indexed link it is connected to.
"""

from __future__ import annotations

from typing import Any

from cyphy.wellformed.indexing import reported
from cyphy.wellformed.registry import WFContext, rule
from cyphy.wellformed.values import _models


def _copies(targets: list[Any]) -> str:
    names = ", ".join(t.name for t in targets[:4])
    return names + (", …" if len(targets) > 4 else "")


@rule("IX3", "a joint connected to an indexed link (or a link of an indexed part) is indexed "
      "over the same values: element i to element i")
def check_IX3_indexed_connection(ctx: WFContext) -> None:
    """A joint joins one parent to one child. When its target has several copies, the joint
    (or the link that holds it) must have one copy per target copy, with the same index
    values: copy i of the joint is connected to copy i of the target. Anything else would
    give one joint several children (RoboTool's cross product)."""
    for m in _models(ctx):
        for joint, count, targets in m.mismatched:
            target = targets[0].simple_name
            if count == 1:
                what = f"joint {joint.name} is one joint"
            else:
                what = f"joint {joint.simple_name} has {count} copies"
            ctx.error("IX3", joint, f"{what} but is connected to {len(targets)} copies of "
                      f"{target} ({_copies(targets)}): a joint connects one parent to one "
                      "child, and element i goes to element i",
                      f"give the joint (or the link holding it) the index range of {target}, "
                      f"so that each copy is connected to the copy of {target} with its "
                      "index values, or connect it to a link that is not indexed")


@rule("IX4", "no two elements of the elaborated model have the same qualified name")
def check_IX4_unique_names(ctx: WFContext) -> None:
    """Every link, body, joint, fixed connection, sensor and actuator of the elaborated model
    has its own qualified name (``Model::part::i::link::j::…``): tables, the SDF's names,
    the semantics' variables and ``--element`` are keyed by it. A joint IX3 reports is
    left out here (its copies share its name because of that one mistake)."""
    for m in _models(ctx):
        seen: dict[str, Any] = {}
        for e in [*m.links, *m.bodies, *m.joints, *m.unconnected, *m.fixed, *m.sensors,
                  *m.actuators]:
            if getattr(e, "target_copy", 0):
                continue
            first = seen.setdefault(e.name, e)
            if first is not e and not reported(ctx, "S2", e.span):  # two blocks, one name
                ctx.error("IX4", e, f"two elements are named {e.name} (the first is at "
                          f"{first.span})", "rename or remove one of them (a connection "
                          "written twice, two elements of one name)")
