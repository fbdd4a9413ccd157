"""Which link of a rigid group a user takes for its root.

Links joined by fixed connections move as one rigid body, and a fixed connection carries no
motion, so which of them is the root is a choice, not something the connections decide:
RoboSim writes ``link Root fixed to Palm`` in the finger, which makes each finger's root the
palm's parent, while a user sees the palm hold the fingers. The tree-based exports
(:mod:`cyphy.semantics.sdf.orientation`) and the floating base of the dynamics
(:mod:`cyphy.semantics.dynamics.tree`) choose by the same rule, so that ``--mjcf-free-base``
and ``simulate --floating-base`` name and place the same base.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping

from cyphy.model.elements import Link, is_index_value


def part_depth(link: Link) -> int:
    """How deep in the model's parts the link is declared: 2 for the p-model's own link
    (``Hand::Palm``), 3 in a part (``Hand::Fingers::0::Root``: index values do not count)."""
    return sum(1 for component in link.qname if not is_index_value(component))


def preferred_root(candidates: Iterable[Link], children: Collection[int],
                   order: Mapping[int, int]) -> Link:
    """The root among ``candidates`` (rigidly joined links, none moved by a joint): the
    shallowest in the model's parts (the palm before a finger's root), then one that no
    connection makes a child (``children``, by id: the root the model declares, so that a
    model without parts keeps it), then the first in ``order`` (link id → position)."""
    return min(candidates, key=lambda link: (part_depth(link), id(link) in children,
                                             order[id(link)]))
