"""The shape of the kinematic graph, for targets that need trees (PyBullet, URDF, MuJoCo): the
connected groups of links, the connections that close loops (cut, each with a comment and a
warning), and the warning where the links do not form one tree (or trees, when split).
"""

from __future__ import annotations

from typing import Union

from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.semantics.sdf.links import parts_rule
from cyphy.semantics.sdf.translation import CUT, NOT_TREE, Translation
from cyphy.semantics.sdf.tree import Comment, Node

Connection = Union[Joint, FixedJoint]


def link_trees(model: ElaboratedModel, cut: dict[int, Connection]) -> list[list[Link]]:
    """The links in connected groups (the kinematic graph without the ``cut`` connections,
    edges in either direction), each in Rule 6 order, groups ordered by their first link."""
    import networkx as nx  # lazy: only when splitting; NetworkX takes a quarter second to import

    order = {id(link): i for i, link in enumerate(parts_rule(model))}
    graph = model.kinematic_graph()
    graph.remove_edges_from([(u, v, k) for u, v, k, j in graph.edges(keys=True, data="element")
                             if id(j) in cut])
    groups = [sorted((graph.nodes[n]["element"] for n in names), key=lambda l: order[id(l)])
              for names in nx.weakly_connected_components(graph)]
    return sorted(groups, key=lambda links: order[id(links[0])])


def loop_cuts(model: ElaboratedModel) -> list[Connection]:
    """The connections a tree-based simulator cannot have: of those into one link, all but
    the first (joints in model order, then fixed connections); then, in each cycle of what
    is left, the connection into the cycle's first link in Rule 6 order."""
    order = {id(link): i for i, link in enumerate(parts_rule(model))}
    parent_of: dict[int, Connection] = {}
    cuts: list[Connection] = []
    for j in [*model.joints, *model.fixed]:
        if j.parent is None or j.child is None:
            continue
        if id(j.child) in parent_of or j.child is j.parent:
            cuts.append(j)
        else:
            parent_of[id(j.child)] = j
    done: set[int] = set()
    for link in parts_rule(model):
        path: list[Link] = []
        on_path: set[int] = set()
        node: Link | None = link
        while node is not None and id(node) not in done and id(node) not in on_path:
            path.append(node)
            on_path.add(id(node))
            edge = parent_of.get(id(node))
            node = edge.parent if edge is not None else None
        if node is not None and id(node) in on_path:  # back on the path: a cycle
            cycle = path[[id(p) for p in path].index(id(node)):]
            first = min(cycle, key=lambda l: order[id(l)])
            cuts.append(parent_of.pop(id(first)))
        done.update(on_path)
    return cuts


def left_out(t: Translation, j: Connection) -> list[Node | Comment]:
    """A connection left out for PyBullet: a comment in the file and a warning."""
    assert j.parent is not None and j.child is not None
    what = "fixed connection" if isinstance(j, FixedJoint) else f"joint {j.name}"
    extra = (" (with its sensors and actuators)"
             if isinstance(j, Joint) and (j.sensors or j.actuators) else "")
    t.report.report(CUT, f"{what} from {j.parent.name} to {j.child.name} closes a kinematic "
                    f"loop: it is left out for {t.simulator}{extra}", j.span,
                    "add it in the simulator as a constraint (PyBullet: p.createConstraint; "
                    "--mjcf writes a MuJoCo equality constraint), or generate SDF for "
                    "Gazebo, which loads loops")
    return [Comment(f"{what} from {j.parent.name} to {j.child.name} closes a loop: left out "
                    f"for {t.simulator}")]


def check_tree(t: Translation, kept: list[tuple[Link, Link]], split: bool) -> None:
    """SDF allows any graph of links; PyBullet, URDF and MuJoCo need one tree (each link
    but one root with exactly one parent, every link reachable from the root). Say where
    the model is not one, leaving out the several roots that ``split`` has made trees.
    Counted with dictionaries rather than the kinematic graph: every ``gen --sdf`` runs
    this, and importing NetworkX would cost it a quarter of a second."""
    links = t.model.links
    if not links:
        return
    parents: dict[int, int] = {}
    children: dict[int, list[Link]] = {}
    for parent, child in kept:  # (parent, child) as written, fixed connections turned
        parents[id(child)] = parents.get(id(child), 0) + 1
        children.setdefault(id(parent), []).append(child)
    roots = [link for link in links if id(link) not in parents]
    shared = [link for link in links if parents.get(id(link), 0) > 1]
    reached = {id(r) for r in roots}
    todo = list(roots)
    while todo:
        for child in children.get(id(todo.pop()), []):
            if id(child) not in reached:
                reached.add(id(child))
                todo.append(child)
    circling = [link for link in links if id(link) not in reached]
    problems = []
    if len(roots) > 1 and not split:
        problems.append(f"{len(roots)} links have no parent joint ({_some(roots)})")
    if shared:
        problems.append(f"{len(shared)} links have more than one parent ({_some(shared)})")
    if circling:
        problems.append(f"{len(circling)} links are joined in a cycle that no root reaches "
                        f"({_some(circling)})")
    if problems:
        hint = "connect every link to one root by exactly one joint or fixed connection"
        if shared or circling:
            hint += " (or generate with --target pybullet, --urdf or --mjcf, which turn a " \
                    "fixed connection round where that makes a tree and leave out the " \
                    "connections that close loops)"
        elif len(roots) > 1 and not split:
            hint += " (or write one model per tree with --split-trees)"
        t.report.report(NOT_TREE, f"the links of {t.model.name} do not form "
                        f"{'trees' if split else 'one tree'}: " + "; ".join(problems)
                        + ". Gazebo loads the model; PyBullet and URDF tools cannot",
                        t.model.pmodel.span, hint)


def _some(links: list[Link]) -> str:
    return ", ".join(link.name for link in links[:4]) + (", …" if len(links) > 4 else "")
