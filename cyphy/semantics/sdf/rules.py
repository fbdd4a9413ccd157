"""The translation of an elaborated p-model to SDF 1.6: the paper's section 5, Rules 1-6,
as ``../shared/spec/sdf.md`` decides them.

Elaboration has already done what the paper's rules do to the model's structure: parts are
flattened (every element carries its part's qualified prefix), indexed elements replicated,
poses composed, constants evaluated. The rules here turn the result into SDF elements, one
function per rule:

* Rule 1 :func:`pmodel_rule` — the p-model becomes a ``<model>``: its links, joints and fixed
  connections (``fixed`` joints, the rule's last line);
* Rule 2 :func:`link_rule` — a link becomes a ``<link>`` with its pose in the model frame,
  its inertial, bodies, sensors and actuators;
* Rule 3 :func:`body_rule` — a body becomes a ``<collision>`` and a ``<visual>``;
* Rule 4 :func:`inertial_rule` — the link's inertial: its own, else combined from its bodies;
* Rule 5 :func:`joint_rule` — one ``<joint>`` per joint instance (container copies × target
  copies), its pose relative to the child link;
* Rule 6 :func:`parts_rule` — the order of declarations: a container's parts (recursively)
  before its own links.

Sensors and actuators follow the paper's annotation-driven translation (§5.3):
:func:`sensor_rule` and :func:`actuator_rule`. Equations never reach SDF.

The result is a :class:`~cyphy.semantics.sdf.tree.Node` tree plus the name table; the XML is
written by :mod:`cyphy.backends.robot_formats.sdf_xml`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from cyphy import codes, collector
from cyphy.diagnostics import Report
from cyphy.lang.workspace import Workspace
from cyphy.model.elements import (
    Actuator, AnnotationValue, Body, ElaboratedModel, FixedJoint, Joint, Link, Sensor, glued,
)
from cyphy.model.inertia import Inertial
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.annotations import Templates, fill
from cyphy.semantics.sdf.names import Names
from cyphy.semantics.sdf.tree import Comment, Node

NO_JOINT_TYPE = codes.code("W-SDF-JOINT", codes.W,
                           "a joint without an annotation: SDF gets a revolute joint")
NO_AXIS = codes.code("W-SDF-AXIS", codes.W,
                     "a joint whose axis neither its annotation nor an AXIS constant gives")
NO_SENSOR = codes.code("W-SDF-SENSOR", codes.W,
                       "a sensor that has no SDF sensor element (no annotation, or no SDF type)")
NO_ACTUATOR = codes.code("W-SDF-ACTUATOR", codes.W,
                         "an actuator annotation with no SDF element valid where it sits")
NO_CHILD = codes.code("W-SDF-UNCONNECTED", codes.W,
                      "a joint without a flexible connection: not written to SDF")
NO_INERTIA = codes.code("W-SDF-INERTIA", codes.W,
                        "a link with a mass but no inertia and no body to derive one from")
LOOP = codes.code("W-SDF-LOOP", codes.W,
                  "two links connected both by a joint and by a fixed connection")
NOT_TREE = codes.code("W-SDF-TREE", codes.W,
                      "the links do not form one tree: tree-based simulators cannot load it")
CUT = codes.code("W-SDF-CUT", codes.W,
                 "--target pybullet: a joint that closes a kinematic loop is left out")
GEARBOX = codes.code("W-SDF-GEARBOX", codes.W,
                     "--target pybullet: a gearbox joint is written as a revolute joint")
DRAKE = codes.code("W-SDF-DRAKE", codes.W,
                   "--target drake: an element Drake's parser refuses is left out, and that "
                   "changes the model")

JOINT_TYPES = {"Revolute": "revolute", "Prismatic": "prismatic", "Ball": "ball",
               "Universal": "universal", "Revolute2": "revolute2", "Screw": "screw",
               "Gearbox": "gearbox", "Fixed": "fixed"}
#: Joint types and the axes SDF requires of them.
AXES = {"revolute": ("axis",), "prismatic": ("axis",), "screw": ("axis",),
        "universal": ("axis", "axis2"), "revolute2": ("axis", "axis2"),
        "gearbox": ("axis", "axis2")}
SENSOR_TYPES = {"Ray": "ray", "Sonar": "sonar", "IMU": "imu", "Camera": "camera",
                "Contact": "contact", "Logical_camera": "logical_camera", "GPS": "gps",
                "Altimeter": "altimeter", "Magnetometer": "magnetometer",
                "Force_torque": "force_torque"}
#: Targets that need trees (``split_trees``, loops cut), with the name the warnings use.
TREE_TARGETS = {"pybullet": "PyBullet", "urdf": "URDF", "mjcf": "MuJoCo"}
#: Actuator templates and the SDF element they stand for, with where it is valid.
ACTUATOR_ELEMENTS = {"Light": ("light", "link"), "Physics": ("physics", "joint")}

#: The extra rotation RoboTool applies to sensor poses for CoppeliaSim (sdf-robotool.md §3).
COPPELIASIM_SENSOR = Pose.from_xyz_rpy(0.0, 0.0, 0.0, 0.0, 1.57079632679, 0.0)
#: Mass given to a link that has no inertial anywhere (L4 warns): spread over its bodies.
DEFAULT_MASS = 1.0


@dataclass(frozen=True)
class SdfOptions:
    pose: tuple[float, float, float, float, float, float] = (0.0,) * 6
    short_names: bool = False
    #: "gazebo"; "coppeliasim": RoboTool's conventions (coded names, Ry(π/2)); "pybullet":
    #: trees only (split trees, loops cut, gearboxes as revolute joints); "drake": without
    #: the elements SDFormat 1.9 removed, which Drake's parser refuses
    target: str = "gazebo"
    split_trees: bool = False  # a <world> with one <model> per tree of links


@dataclass
class SdfDocument:
    """What the rules produce: the ``<sdf>`` element and the SDF-name → qualified-name table."""

    root: Node
    names: dict[str, str] = field(default_factory=dict)


class _Translation:
    """State shared by the rules: names, templates, the report."""

    def __init__(self, model: ElaboratedModel, ws: Workspace, report: Report,
                 options: SdfOptions) -> None:
        self.model = model
        self.report = report
        self.options = options
        self.coppeliasim = options.target == "coppeliasim"
        self.drake = options.target == "drake"
        #: Trees only (loops cut, gearboxes as revolute joints): PyBullet, URDF and MJCF.
        self.pybullet = options.target in TREE_TARGETS
        self.simulator = TREE_TARGETS.get(options.target, "PyBullet")
        self.names = Names(options.short_names or self.coppeliasim)
        self.templates = Templates(ws)
        self.bodies_by_name: dict[tuple[str, ...], list[Body]] = {}
        for b in model.bodies:
            self.bodies_by_name.setdefault(b.qname[-1 - len(b.index):], []).append(b)
        self.copies: dict[tuple[tuple[str, ...], int], int] = {}
        self.joined: dict[frozenset[int], Joint] = {}
        for j in model.joints:
            key = (j.qname, id(j.parent))
            self.copies[key] = self.copies.get(key, 0) + 1
            self.joined.setdefault(frozenset((id(j.parent), id(j.child))), j)
        self.links_by_name: dict[tuple[str, ...], list[Link]] = {}
        for link in model.links:
            self.links_by_name.setdefault(link.qname[-1 - len(link.index):], []).append(link)

    def resolver(self, owner: tuple[str, ...]):  # type: ignore[no-untyped-def]
        """Element paths in an annotation (``B``, ``Link::body``) to SDF names: the link or
        body whose qualified name ends with the path, the one closest to ``owner`` first."""

        def resolve(path: tuple[str, ...]) -> str | None:
            candidates: list[Link | Body] = []
            for table in (self.links_by_name, self.bodies_by_name):
                for key, found in table.items():
                    if key[-len(path):] == path or _strip_index(key) == path[-len(key):]:
                        candidates.extend(e for e in found
                                          if e.qname[-len(path):] == path
                                          or _strip_index(e.qname)[-len(path):] == path)
            if not candidates:
                return None
            best = max(candidates, key=lambda e: _shared(e.qname, owner))
            if isinstance(best, Body):
                return self.names.body(best)[0]
            return self.names.link(best)

        return resolve


def _strip_index(qname: tuple[str, ...]) -> tuple[str, ...]:
    return tuple(c for c in qname if not c.lstrip("-").isdigit())


def _shared(a: tuple[str, ...], b: tuple[str, ...]) -> int:
    n = 0
    for x, y in zip(a, b):
        if x != y:
            break
        n += 1
    return n


# --------------------------------------------------------------------------- Rule 1


def translate(model: ElaboratedModel, ws: Workspace, report: Report,
              options: SdfOptions = SdfOptions()) -> SdfDocument:
    """The SDF document of an elaborated p-model whose constants all have values."""
    t = _Translation(model, ws, report, options)
    root = Node("sdf", {"version": "1.6"})
    with collector.paused():  # a tree as large as the model, all of it live
        root.children.append(pmodel_rule(t))
    return SdfDocument(root, t.names.table)


def pmodel_rule(t: _Translation) -> Node:
    """Rule 1: the p-model is a ``<model>`` named after it, with ``self_collide`` and the
    model pose chosen by the user, holding its links (in the order of Rule 6), one joint per
    joint instance (Rule 5) and one ``fixed`` joint per fixed connection instance.

    With ``split_trees`` (ours), a model whose links form several trees becomes a ``<world>``
    named after it holding one such ``<model>`` per tree: a tree-based simulator (PyBullet)
    loads each as a body, where it refuses a model with several root links, and libsdformat
    12 accepts a world of models where it refuses several models at the top. ``--target
    pybullet`` splits trees and first cuts the connections that close loops (each reported),
    as a tree-based simulator needs."""
    model = t.model
    cut = {id(j): j for j in _loop_cuts(model)} if t.pybullet else {}
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
        pieces.append((joint.parent, _cut(t, joint) if id(joint) in cut
                       else joint_rule(t, joint)))
    for fixed in model.fixed:
        pieces.append((fixed.parent, _cut(t, fixed) if id(fixed) in cut
                       else fixed_rule(t, fixed)))
    kept = [j for j in [*model.joints, *model.fixed] if id(j) not in cut]
    split = t.options.split_trees or t.pybullet
    trees = _trees(model, cut) if split else []
    _check_tree(t, kept, split=len(trees) > 1)
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


def _model_node(t: _Translation, name: str, comment: str,
                children: list[Node | Comment]) -> Node:
    node = Node("model", {"name": name})
    node.comment(comment)
    node.add("self_collide", True)
    node.add("pose", t.options.pose)
    node.children.extend(children)
    return node


Connection = Union[Joint, FixedJoint]


def _trees(model: ElaboratedModel, cut: dict[int, Connection]) -> list[list[Link]]:
    """The links in connected groups (the kinematic graph without the ``cut`` connections,
    edges in either direction), each in Rule 6 order, groups ordered by their first link."""
    import networkx as nx  # only when splitting: NetworkX takes a quarter second to import

    order = {id(link): i for i, link in enumerate(parts_rule(model))}
    graph = model.kinematic_graph()
    graph.remove_edges_from([(u, v, k) for u, v, k, j in graph.edges(keys=True, data="element")
                             if id(j) in cut])
    groups = [sorted((graph.nodes[n]["element"] for n in names), key=lambda l: order[id(l)])
              for names in nx.weakly_connected_components(graph)]
    return sorted(groups, key=lambda links: order[id(links[0])])


def _loop_cuts(model: ElaboratedModel) -> list[Connection]:
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


def _cut(t: _Translation, j: Connection) -> list[Node | Comment]:
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


def fixed_rule(t: _Translation, fixed: FixedJoint) -> list[Node | Comment]:
    """Rule 1, last line: a fixed connection instance is a ``fixed`` joint whose parent is the
    link that declares ``fixed to`` and whose child is its target (sdf.md decision 10)."""
    assert fixed.parent is not None and fixed.child is not None
    parent, child = t.names.link(fixed.parent), t.names.link(fixed.child)
    qualified = f"{fixed.parent.name}::fixedJoint::{fixed.child.name}"
    node = Node("joint", {"name": t.names.fixed(fixed.parent, fixed.child, qualified),
                          "type": "fixed"})
    node.add("pose", Pose.identity())
    node.add("parent", parent)
    node.add("child", child)
    both = t.joined.get(frozenset((id(fixed.parent), id(fixed.child))))
    if both is not None:
        t.report.report(LOOP, f"links {fixed.parent.name} and {fixed.child.name} are connected "
                        f"by joint {both.name} and by a fixed connection", fixed.span,
                        "keep either the joint or the fixed connection")
    return [Comment(f"fixed joint {qualified} from {fixed.parent.name} to {fixed.child.name}"),
            node]


def _check_tree(t: _Translation, kept: list[Connection], split: bool) -> None:
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
    for j in kept:
        if j.parent is not None and j.child is not None:
            parents[id(j.child)] = parents.get(id(j.child), 0) + 1
            children.setdefault(id(j.parent), []).append(j.child)
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
            hint += " (or generate with --target pybullet, which leaves out the connections " \
                    "that close loops)"
        elif len(roots) > 1 and not split:
            hint += " (or write one model per tree with --split-trees)"
        t.report.report(NOT_TREE, f"the links of {t.model.name} do not form "
                        f"{'trees' if split else 'one tree'}: " + "; ".join(problems)
                        + ". Gazebo loads the model; PyBullet and URDF tools cannot",
                        t.model.pmodel.span, hint)


def _some(links: list[Link]) -> str:
    return ", ".join(link.name for link in links[:4]) + (", …" if len(links) > 4 else "")


# --------------------------------------------------------------------------- Rule 6


def parts_rule(model: ElaboratedModel) -> list[Link]:
    """Rule 6: the declarations of a container come part by part (each part's own parts
    first, recursively), then the container's own links, in declaration order."""
    children: dict[tuple[str, ...], list[tuple[str, ...]]] = {}
    own: dict[tuple[str, ...], list[Link]] = {}
    for link in model.links:
        container = link.qname[:len(link.qname) - 1 - len(link.index)]
        own.setdefault(container, []).append(link)
        for depth in range(len(container), 1, -1):
            parent, sub = container[:depth - 1], container[:depth]
            kids = children.setdefault(parent, [])
            if sub not in kids:
                kids.append(sub)
    out: list[Link] = []

    def emit(prefix: tuple[str, ...]) -> None:
        for sub in children.get(prefix, []):
            emit(sub)
        out.extend(own.get(prefix, []))

    emit((model.name,))
    return out


# --------------------------------------------------------------------------- Rules 2-4


def link_rule(t: _Translation, link: Link) -> list:  # type: ignore[type-arg]
    """Rule 2: a link is a ``<link>`` with its pose relative to the model frame, its inertial
    (Rule 4), a collision and a visual per body (Rule 3), its sensors and its actuators."""
    node = Node("link", {"name": t.names.link(link)})
    node.add("pose", link.pose)
    node.children.append(inertial_rule(t, link))
    for body in link.bodies:
        node.children.extend(body_rule(t, body))
    for sensor in link.sensors:
        node.children.extend(sensor_rule(t, sensor, Pose.identity()))
    for actuator in link.actuators:
        node.children.extend(actuator_rule(t, actuator, "link", Pose.identity()))
    return [Comment(f"link {link.name}"), node]


def inertial_rule(t: _Translation, link: Link) -> Node:
    """Rule 4: the link's own inertial if it has one; otherwise the combination of its bodies'
    (mass, centre of mass, inertia by rotation and the parallel-axis theorem), which
    elaboration computes. A link with no mass anywhere (warning L4) gets ``DEFAULT_MASS``
    spread over its bodies by volume, or SDF's default (1 kg, unit inertia) without bodies.
    A mass with no inertia and no body geometry gets SDF's unit inertia and a warning."""
    inertial = link.inertial
    if inertial is None:
        inertial = _default_inertial(link)
    elif inertial.inertia == (0.0,) * 6:
        t.report.report(NO_INERTIA, f"link {link.name} gives a mass but no inertia matrix and "
                        "has no body to compute one from: SDF gets the unit inertia",
                        link.span, "add `inertia matrix { … }` or a body with a geometry")
        inertial = Inertial(inertial.mass, inertial.com, (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))
    node = Node("inertial")
    node.add("pose", inertial.com)
    node.add("mass", inertial.mass)
    inertia = node.add("inertia")
    for key, value in zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), inertial.inertia):
        inertia.add(key, value)
    return node


def _default_inertial(link: Link) -> Inertial:
    from cyphy.model.body_inertia import distribute_mass  # as for a mass-only link

    unit = Inertial(DEFAULT_MASS, Pose.identity(), (0.0,) * 6)
    spread = distribute_mass(unit, link.bodies) if link.bodies else None
    return spread or Inertial(DEFAULT_MASS, Pose.identity(), (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))


def body_rule(t: _Translation, body: Body) -> list:  # type: ignore[type-arg]
    """Rule 3: a body is a ``<collision>`` and a ``<visual>`` (different names) with its pose
    relative to the link and its geometry; the surface (bounce, friction) and laser retro are
    collision properties only (sdf.md decision 8)."""
    collision_name, visual_name = t.names.body(body)
    collision = Node("collision", {"name": collision_name})
    visual = Node("visual", {"name": visual_name})
    for node in (collision, visual):
        node.add("pose", body.pose)
        node.children.append(_geometry(body))
    s = body.surface
    if "laser_retro" in s:
        collision.add("laser_retro", s["laser_retro"])
    if any(k in s for k in ("restitution_coefficient", "threshold", "coefficient1",
                            "coefficient2", "direction", "slip1", "slip2")):
        surface = collision.add("surface")
        if "restitution_coefficient" in s or "threshold" in s:
            bounce = surface.add("bounce")
            _optional(bounce, "restitution_coefficient", s.get("restitution_coefficient"))
            _optional(bounce, "threshold", s.get("threshold"))
        friction_keys = ("coefficient1", "coefficient2", "direction", "slip1", "slip2")
        if any(k in s for k in friction_keys):
            ode = surface.add("friction").add("ode")
            for key, tag in zip(friction_keys, ("mu", "mu2", "fdir1", "slip1", "slip2")):
                _optional(ode, tag, s.get(key))
    return [Comment(f"body {body.name}"), collision, visual]


def _optional(node: Node, tag: str, value: object) -> None:
    if value is not None:
        node.add(tag, value)  # type: ignore[arg-type]


def _geometry(body: Body) -> Node:
    from cyphy.lang import ast

    geometry = Node("geometry")
    g, size = body.geometry, body.size
    if isinstance(g, ast.Shape) and g.kind == "box":
        geometry.add("box").add("size", (size.get("length"), size.get("width"),
                                         size.get("height")))
    elif isinstance(g, ast.Shape) and g.kind == "cylinder":
        cylinder = geometry.add("cylinder")
        cylinder.add("radius", size.get("radius"))
        cylinder.add("length", size.get("length"))
    elif isinstance(g, ast.Shape) and g.kind == "sphere":
        geometry.add("sphere").add("radius", size.get("radius"))
    elif isinstance(g, ast.Mesh):
        mesh = geometry.add("mesh")
        mesh.add("uri", body.mesh_uri or "")
        scale = size.get("scaling")
        if scale is not None:
            mesh.add("scale", (scale,) * 3 if isinstance(scale, (int, float)) else scale)
    else:
        geometry.add("empty")
    return geometry


# --------------------------------------------------------------------------- Rule 5


def joint_rule(t: _Translation, joint: Joint) -> list:  # type: ignore[type-arg]
    """Rule 5: one ``<joint>`` per joint instance. Elaboration made the instances (the cross
    product of the copies of the joint's link and of its target); a copy for one of several
    targets is named after its target. The type comes from the annotation's template (no
    annotation: ``revolute`` and a warning), the pose is relative to the child link, every
    axis the type needs is written with a ``<limit>``, and the joint's actuators are comments
    (or, for a ``Physics`` annotation, the joint's ``<physics>``)."""
    assert joint.parent is not None and joint.child is not None
    parent, child = t.names.link(joint.parent), t.names.link(joint.child)
    copies = t.copies[(joint.qname, id(joint.parent))]
    suffix = "__to__" + "__".join(glued(joint.child.qname[1:], "_")) if copies > 1 else ""
    annotation = joint.annotation
    template = annotation.template[-1] if annotation is not None else None
    kind = _joint_type(t, template)
    if annotation is None:
        t.report.report(NO_JOINT_TYPE, f"joint {joint.name} has no annotation: it is written "
                        "as a revolute joint", joint.span,
                        "annotate it, e.g. `annotation Revolute { axis = Axis { xyz = "
                        "(|0,0,1|) } }`")
    elif kind is None:
        t.report.report(NO_JOINT_TYPE, f"joint {joint.name}: annotation {template} is not an "
                        "SDF joint type; it is written as a revolute joint", joint.span,
                        "use one of " + ", ".join(JOINT_TYPES))
    kind = kind or "revolute"
    annotated_axes = frozenset(AXES.get(kind, ()))  # written by _axis, with their defaults
    if kind == "gearbox" and t.pybullet:
        kind = "revolute"
        t.report.report(GEARBOX, f"joint {joint.name} is a gearbox, which {t.simulator} does not "
                        "know: it is written as a revolute joint about its first axis",
                        joint.span, "couple it in PyBullet with p.createConstraint(…, "
                        "p.JOINT_GEAR, …) and setting its gearRatio")
    qualified = joint.name
    node = Node("joint", {"name": t.names.joint(joint, qualified, suffix),
                          "type": kind})
    node.add("pose", joint.pose)
    node.add("parent", parent)
    node.add("child", child)
    resolve = t.resolver(joint.qname)
    if annotation is not None:
        fill(node, annotation, t.templates, resolve, skip=annotated_axes)
    if kind != "gearbox":  # a gearbox written for PyBullet: its coupling has no meaning here
        node.children = [c for c in node.children if not (
            isinstance(c, Node) and c.tag in ("gearbox_ratio", "gearbox_reference_body"))]
    for name in AXES.get(kind, ()):
        node.children.append(_axis(t, joint, name))
    if kind == "gearbox" and node.find("gearbox_reference_body") is None:
        node.add("gearbox_reference_body", parent)
    elif kind == "gearbox":
        ref = node.find("gearbox_reference_body")
        if ref is not None and ref.text == "__default__":
            ref.text = parent
    for sensor in joint.sensors:
        local = joint.local_pose.inverse() if joint.local_pose is not None else None
        node.children.extend(sensor_rule(t, sensor, local))
    for actuator in joint.actuators:
        local = joint.local_pose.inverse() if joint.local_pose is not None else None
        node.children.extend(actuator_rule(t, actuator, "joint", local))
    return [Comment(f"joint {qualified} from {joint.parent.name} to {joint.child.name}"), node]


def _joint_type(t: _Translation, template: str | None) -> str | None:
    if template is None:
        return None
    for general, kind in JOINT_TYPES.items():
        if t.templates.is_a(template, general) or template == general:
            return kind
    return None


def _axis(t: _Translation, joint: Joint, name: str) -> Node:
    """The joint's ``<axis>`` (or ``<axis2>``): the annotation's, its missing ``xyz`` taken from
    the joint's AXIS constant (for the first axis), else ``0 0 1`` with a warning; always with
    the template's defaults, so always with a ``<limit>``."""
    given = joint.annotation.get(name) if joint.annotation is not None else None
    value = given if isinstance(given, AnnotationValue) else AnnotationValue(("Axis",), ())
    if value.get("xyz") is None:
        xyz = joint.axis if name == "axis" else None
        if xyz is None:
            t.report.report(NO_AXIS, f"joint {joint.name}: no {name} direction in its "
                            "annotation or AXIS constant; SDF gets 0 0 1", joint.span,
                            f"give it, e.g. `{name} = Axis {{ xyz = (|0,0,1|) }}`")
        else:
            value = AnnotationValue(value.template, (("xyz", xyz), *value.args), value.span)
    node = Node(name)
    # SDFormat 1.9 removed <axis><initial_position> (a joint's position is a state, not a
    # property); Drake's parser, which converts our 1.6 files up, refuses it as an error.
    skip = frozenset({"initial_position"}) if t.drake else frozenset()
    fill(node, value, t.templates, t.resolver(joint.qname), skip)
    initial = value.get("initial_position")
    if t.drake and isinstance(initial, (int, float)) and initial != 0:
        t.report.report(DRAKE, f"joint {joint.name}: its {name}'s initial_position "
                        f"{initial:g} is left out (SDFormat 1.9 removed it and Drake refuses "
                        "it): Drake starts the joint at 0", joint.span,
                        "set the position in Drake (plant.SetPositions), or give the joint "
                        "pose the initial position")
    return node


# --------------------------------------------------------------------------- sensors, actuators


def sensor_rule(t: _Translation, sensor: Sensor, frame: Pose | None) -> list:  # type: ignore[type-arg]
    """§5.3: an annotated sensor is a ``<sensor>`` whose type is its template's (``Ray`` →
    ``ray``) and whose elements are the annotation's fields with the template's defaults.
    Its pose is the model's, relative to the link (``frame`` re-expresses it for a joint);
    ``--target coppeliasim`` adds RoboTool's ``Ry(π/2)``. Without an SDF type: a comment and
    a warning, never an invalid element."""
    annotation = sensor.annotation
    template = annotation.template[-1] if annotation is not None else None
    kind = None
    if template is not None:
        for general, sdf_type in SENSOR_TYPES.items():
            if template == general or t.templates.is_a(template, general):
                kind = sdf_type
                break
    if kind is None:
        why = "has no annotation" if template is None else \
            f"is annotated with {template}, which is no SDF sensor type"
        t.report.report(NO_SENSOR, f"sensor {sensor.name} {why}: SDF gets a comment only",
                        sensor.span, "annotate it with one of "
                        + ", ".join(SENSOR_TYPES) + " (physmod::sdf::annotations)")
        return [Comment(f"sensor {sensor.name}: {why}, so it has no SDF element")]
    pose = sensor.pose
    if pose is not None and frame is not None:
        pose = frame.compose(pose)
    if pose is not None and t.coppeliasim:
        pose = pose.compose(COPPELIASIM_SENSOR)
    node = Node("sensor", {"name": t.names.device(sensor), "type": kind})
    node.add("pose", pose)
    assert annotation is not None
    fill(node, annotation, t.templates, t.resolver(sensor.qname))
    return [Comment(f"sensor {sensor.name}"), node]


def actuator_rule(t: _Translation, actuator: Actuator, where: str, frame: Pose | None
                  ) -> list:  # type: ignore[type-arg]
    """Actuators have no SDF counterpart (sdf.md decision 12): a comment with the qualified
    name and, where the annotation's template stands for an SDF element valid there (a
    ``<light>`` in a link, a joint's ``<physics>``), that element."""
    out: list = [Comment(f"actuator {actuator.name}")]  # type: ignore[type-arg]
    annotation = actuator.annotation
    if annotation is None:
        return out
    template = annotation.template[-1]
    element = next((e for general, e in ACTUATOR_ELEMENTS.items()
                    if template == general or t.templates.is_a(template, general)), None)
    if element is None or element[1] != where:
        valid = f"a <{element[0]}> is valid only in a {element[1]}" if element else \
            f"{template} stands for no SDF element"
        t.report.report(NO_ACTUATOR, f"actuator {actuator.name} in a {where}: {valid}; SDF "
                        "gets a comment only", actuator.span,
                        "annotate actuators of links with Light and of joints with Physics")
        out[0] = Comment(f"actuator {actuator.name}: {valid}")
        return out
    tag = element[0]
    if tag == "physics":
        node = Node("physics")
    else:
        node = Node(tag, {"name": t.names.device(actuator)})
        pose = actuator.pose
        if pose is not None and frame is not None:
            pose = frame.compose(pose)
        node.add("pose", pose)
    fill(node, annotation, t.templates, t.resolver(actuator.qname))
    if tag == "light" and "type" not in node.attrs:
        node.attrs["type"] = "point"
    if tag == "light":  # attributes in SDF's order: name, type
        node.attrs = {"name": node.attrs["name"], "type": node.attrs["type"]}
    out.append(node)
    return out


# --------------------------------------------------------------------------- completeness


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
