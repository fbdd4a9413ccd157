"""The shape a tree-based format (URDF, MuJoCo, PyBullet) gives the kinematic graph: which
connections it cuts and which **fixed** connections it turns round.

RoboSim writes ``link Root fixed to Palm`` in the link that declares it, so Rule 1 makes
``Root`` the parent: an indexed part of fingers, each root fixed to the palm, gives the palm
one parent per finger. A fixed connection carries no motion, so the same rigid attachment
may be written from either end: turned round (parent and child swapped, the joint frame at
the new child's link frame, no axis), it makes the links one tree where cutting it would
have left a loop that is not there. A moving joint is never turned (its axis, sign and
coordinates are the parent's to the child's).

The procedure, so that a model that is already a forest keeps what it had:

1. :func:`~cyphy.semantics.sdf.topology.loop_cuts` cuts, as before, every second parent and
   one connection of every directed cycle;
2. a cut connection whose ends lie in two different trees of what is left (it closes no
   loop of the undirected graph) is kept again when a tree can hold it: a **fixed**
   connection when at most one of the two rigid bodies it joins (links joined by fixed
   connections) is moved by a joint, a joint when its child's body is moved by none (a
   second parent set aside in step 1 whose first was then cut to open a cycle). Otherwise
   it closes a genuine loop (a four-bar, a chain closed by moving joints, two joints into
   one body), cut with ``W-SDF-CUT``;
3. each tree is rooted in its one body that no joint moves, at the link a user expects
   (:func:`~cyphy.model.roots.preferred_root`: the shallowest in the model's parts, the
   palm before a finger's root, then the link that was the root before, then the first in
   the model's order); every edge then points away from the root, and the fixed
   connections that point the other way are the turned ones.
"""

from __future__ import annotations

from cyphy.model.elements import ElaboratedModel, FixedJoint, Link
from cyphy.model.roots import preferred_root
from cyphy.records import record
from cyphy.semantics.sdf.topology import Connection, loop_cuts


@record(slots=False)
class TreeShape:
    """``cuts``: the connections left out (in :func:`loop_cuts` order); ``turned``: the ids
    of the fixed connections written from their target to the link that declares them."""

    cuts: tuple[Connection, ...]
    turned: frozenset[int]

    def ends(self, connection: Connection) -> tuple[Link, Link]:
        """The connection's (parent, child) as the tree has it."""
        assert connection.parent is not None and connection.child is not None
        if id(connection) in self.turned:
            return connection.child, connection.parent
        return connection.parent, connection.child


class _Groups:
    """Union-find over links (by id)."""

    def __init__(self) -> None:
        self.up: dict[int, int] = {}

    def find(self, key: int) -> int:
        self.up.setdefault(key, key)
        while self.up[key] != key:
            self.up[key] = self.up[self.up[key]]
            key = self.up[key]
        return key

    def union(self, a: int, b: int) -> int:
        ra, rb = self.find(a), self.find(b)
        self.up[rb] = ra
        return ra


def tree_shape(model: ElaboratedModel) -> TreeShape:
    """The cuts and turned fixed connections that make the model's links trees (module
    docstring)."""
    cuts = loop_cuts(model)
    cut_ids = {id(c) for c in cuts}
    connections = [c for c in [*model.joints, *model.fixed]
                   if c.parent is not None and c.child is not None]
    kept = [c for c in connections if id(c) not in cut_ids]
    trees, bodies = _Groups(), _Groups()
    for c in kept:
        trees.union(id(c.parent), id(c.child))
        if isinstance(c, FixedJoint):
            bodies.union(id(c.parent), id(c.child))
    moved = {bodies.find(id(c.child)) for c in kept if not isinstance(c, FixedJoint)}
    restored: set[int] = set()
    for c in cuts:
        if c.parent is c.child:
            continue
        a, b = id(c.parent), id(c.child)
        if trees.find(a) == trees.find(b):
            continue  # closes a loop of the undirected graph
        body_a, body_b = bodies.find(a), bodies.find(b)
        if isinstance(c, FixedJoint):
            if body_a in moved and body_b in moved:
                continue  # two bodies each moved by a joint: a loop through the world
            joined = bodies.union(a, b)
            if body_a in moved or body_b in moved:
                moved.add(joined)
        else:
            if body_b in moved:
                continue  # the child's body already hangs on a joint
            moved.add(body_b)  # its tree was rooted there: now it hangs on this joint
        trees.union(a, b)
        restored.add(id(c))
    edges = kept + [c for c in cuts if id(c) in restored]
    return TreeShape(tuple(c for c in cuts if id(c) not in restored),
                     _turned(model, edges, trees, bodies, moved))


def _turned(model: ElaboratedModel, edges: list[Connection], trees: _Groups,
            bodies: _Groups, moved: set[int]) -> frozenset[int]:
    """The fixed connections that point towards each tree's chosen root."""
    declared_child = {id(c.child) for c in edges}
    order = {id(link): i for i, link in enumerate(model.links)}
    candidates: dict[int, list[Link]] = {}
    for link in model.links:
        if bodies.find(id(link)) not in moved:
            candidates.setdefault(trees.find(id(link)), []).append(link)
    roots = {tree: preferred_root(links, declared_child, order)
             for tree, links in candidates.items()}
    around: dict[int, list[Connection]] = {}
    for c in edges:
        around.setdefault(id(c.parent), []).append(c)
        around.setdefault(id(c.child), []).append(c)
    turned: set[int] = set()
    seen: set[int] = set()
    for root in roots.values():
        todo = [root]
        seen.add(id(root))
        while todo:
            link = todo.pop()
            for c in around.get(id(link), []):
                assert c.parent is not None and c.child is not None
                far = c.child if c.parent is link else c.parent
                if id(far) in seen:
                    continue
                if far is c.parent:  # reached from the child's end: written the other way
                    assert isinstance(c, FixedJoint), "a moving joint is never turned"
                    turned.add(id(c))
                seen.add(id(far))
                todo.append(far)
    return frozenset(turned)
