"""The translation of an elaborated p-model to SDF 1.6: the paper's section 5, Rules 1-6,
as ``../shared/spec/sdf.md`` decides them.

Elaboration has already done what the paper's rules do to the model's structure: parts are
flattened (every element carries its part's qualified prefix), indexed elements replicated,
poses composed, constants evaluated. The rules turn the result into SDF elements, one
function per rule (this module holds Rule 1 and imports the others; they share
:mod:`~cyphy.semantics.sdf.translation`):

* Rule 1 :func:`pmodel_rule` — the p-model becomes a ``<model>``: its links, joints and fixed
  connections (``fixed`` joints, the rule's last line);
* Rule 2 :func:`~cyphy.semantics.sdf.links.link_rule` — a link becomes a ``<link>`` with its
  pose in the model frame, its inertial, bodies, sensors and actuators;
* Rule 3 :func:`~cyphy.semantics.sdf.links.body_rule` — a body becomes a ``<collision>`` and a
  ``<visual>``;
* Rule 4 :func:`~cyphy.semantics.sdf.links.inertial_rule` — the link's inertial: its own, else
  combined from its bodies;
* Rule 5 :func:`~cyphy.semantics.sdf.joints.joint_rule` — one ``<joint>`` per joint instance
  (container copies × target copies), its pose relative to the child link;
* Rule 6 :func:`~cyphy.semantics.sdf.links.parts_rule` — the order of declarations: a
  container's parts (recursively) before its own links.

Sensors and actuators follow the paper's annotation-driven translation (§5.3):
:mod:`~cyphy.semantics.sdf.devices`. A target that needs trees has its loops cut
(:mod:`~cyphy.semantics.sdf.topology`). Equations never reach SDF.

The result is a :class:`~cyphy.semantics.sdf.tree.Node` tree plus the name table; the XML is
written by :mod:`cyphy.backends.robot_formats.sdf_xml`.
"""

from __future__ import annotations

from cyphy import collector
from cyphy.diagnostics import Report
from cyphy.lang.workspace import Workspace
from cyphy.model.elements import AnnotationValue, ElaboratedModel, Link
from cyphy.semantics.sdf.joints import fixed_rule, joint_rule
from cyphy.semantics.sdf.links import link_rule, parts_rule
from cyphy.semantics.sdf.orientation import TreeShape, tree_shape
from cyphy.semantics.sdf.topology import check_tree, left_out, link_trees
from cyphy.semantics.sdf.translation import NO_CHILD, SdfDocument, SdfOptions, Translation
from cyphy.semantics.sdf.tree import Comment, Node


def translate(model: ElaboratedModel, ws: Workspace, report: Report,
              options: SdfOptions = SdfOptions()) -> SdfDocument:
    """The SDF document of an elaborated p-model whose constants all have values."""
    t = Translation(model, ws, report, options)
    root = Node("sdf", {"version": "1.6"})
    with collector.paused():  # a tree as large as the model, all of it live
        root.children.append(pmodel_rule(t))
    return SdfDocument(root, t.names.table)


def pmodel_rule(t: Translation) -> Node:
    """Rule 1: the p-model is a ``<model>`` named after it, with ``self_collide`` and the
    model pose chosen by the user, holding its links (in the order of Rule 6), one joint per
    joint instance (Rule 5) and one ``fixed`` joint per fixed connection instance.

    With ``split_trees`` (ours), a model whose links form several trees becomes a ``<world>``
    named after it holding one such ``<model>`` per tree: a tree-based simulator (PyBullet)
    loads each as a body, where it refuses a model with several root links, and libsdformat
    12 accepts a world of models where it refuses several models at the top. ``--target
    pybullet`` (and the URDF and MJCF exports) splits trees and first cuts the connections
    that close loops (each reported), turning round the fixed connections that would
    otherwise give a link a second parent (:mod:`~cyphy.semantics.sdf.orientation`), as a
    tree-based simulator needs."""
    model = t.model
    shape = tree_shape(model) if t.pybullet else TreeShape((), frozenset())
    cut = {id(j): j for j in shape.cuts}
    pieces: list[tuple[Link | None, list[Node | Comment]]] = []
    for link in parts_rule(model):
        pieces.append((link, link_rule(t, link)))
    for joint in model.unconnected:
        pieces.append((None, [Comment(f"joint {joint.name} has no flexible connection: it "
                                      "has no SDF joint")]))
        t.report.report(NO_CHILD, f"joint {joint.name} is not connected to a link, so SDF "
                        "has no joint for it", joint.span,
                        "add `flexibly connected to LINK` to the joint")
    for joint in model.joints:
        pieces.append((joint.parent, left_out(t, joint) if id(joint) in cut
                       else joint_rule(t, joint)))
    for fixed in model.fixed:
        pieces.append((fixed.parent, left_out(t, fixed) if id(fixed) in cut
                       else fixed_rule(t, fixed, id(fixed) in shape.turned)))
    kept = [shape.ends(j) for j in [*model.joints, *model.fixed]
            if id(j) not in cut and j.parent is not None and j.child is not None]
    split = t.options.split_trees or t.pybullet
    trees = link_trees(model, cut) if split else []
    check_tree(t, kept, split=len(trees) > 1)
    if len(trees) <= 1:
        return _model_node(t, model.name, f"p-model {model.name}",
                           [n for _, nodes in pieces for n in nodes])
    tree_of = {id(link): i for i, links in enumerate(trees) for link in links}
    world = Node("world", {"name": model.name})
    world.comment(f"p-model {model.name}: one model per tree of links (split trees)")
    for i, links in enumerate(trees):
        name = t.names.tree(model.name, links[0])
        members = [n for owner, nodes in pieces
                   if tree_of.get(id(owner), 0) == i for n in nodes]
        world.children.append(_model_node(
            t, name, f"links of p-model {model.name} connected to {links[0].name}", members))
    return world


def _model_node(t: Translation, name: str, comment: str,
                children: list[Node | Comment]) -> Node:
    node = Node("model", {"name": name})
    node.comment(comment)
    node.add("self_collide", True)
    node.add("pose", t.options.pose)
    node.children.extend(children)
    return node


def unvalued(model: ElaboratedModel) -> list[str]:
    """Qualified names of the elements with a value that SDF needs and that depends on a
    constant without a value (a pose, a size, a mass, an annotation field). Constants that
    only the equations use (a motor's resistance) do not stop SDF generation."""
    out: list[str] = []

    def annotation_complete(a: AnnotationValue | None) -> bool:
        if a is None:
            return True
        return all(v is not None and (not isinstance(v, AnnotationValue)
                                      or annotation_complete(v)) for _, v in a.args)

    for link in model.links:
        if link.pose is None or (link.inertial is None and link.inertial_source == "link"):
            out.append(link.name)
    for body in model.bodies:
        if body.pose is None or any(v is None for v in body.size.values()) \
                or any(v is None for v in body.surface.values()):
            out.append(body.name)
    for j in model.joints:
        if j.pose is None or not annotation_complete(j.annotation):
            out.append(j.name)
    for s in [*model.sensors, *model.actuators]:
        if s.pose is None or not annotation_complete(s.annotation):
            out.append(s.name)
    return out
