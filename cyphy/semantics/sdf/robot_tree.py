"""The robot as tree-based formats see it: links in trees, joints from parent to child, and
the connections cut to make trees. Shared by the URDF and MJCF exports and by ``cyphy view``.

Built from the SDF translation with a tree target (:data:`cyphy.semantics.sdf.translation.TREE_TARGETS`),
so that the three exports agree with ``gen --sdf --target pybullet`` on everything the paper's
rules decide: names, inertials (Rule 4), geometry (Rule 3), joint types, axes, limits and
dynamics with the annotation templates' defaults (Rule 5), which connections close loops
and which links form which tree (each cut reported once, by that translation).

Frames: every pose here is in the model frame. A joint's frame is the frame SDF gives it
(its pose relative to the child link); its axis is a unit vector in that frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cyphy.diagnostics import Report
from cyphy.lang.workspace import Workspace
from cyphy.model.array import Array
from cyphy.model.elements import ElaboratedModel, FixedJoint
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.rules import translate
from cyphy.semantics.sdf.orientation import tree_shape
from cyphy.semantics.sdf.translation import SdfOptions
from cyphy.semantics.sdf.tree import Node

#: Warnings of the SDF translation about what only SDF holds (sensors, actuators).
SDF_ONLY = frozenset({"W-SDF-SENSOR", "W-SDF-ACTUATOR"})
#: SDF's "no limit" (the templates' default bounds are ±1e16): beyond this, a bound is none.
UNBOUNDED = 1e15


@dataclass(frozen=True)
class Shape:
    """One body's geometry: ``kind`` box (``size`` = full lengths x y z), cylinder (radius,
    length along z), sphere (radius) or mesh (``uri``, ``scale``); ``pose`` in the model
    frame; ``qualified`` the RoboSim name of the body."""

    name: str
    qualified: str
    kind: str
    pose: Pose
    size: tuple[float, ...] = ()
    uri: str = ""
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)


@dataclass
class RobotLink:
    name: str
    qualified: str
    pose: Pose  # the link frame in the model frame
    mass: float
    com: Pose  # the inertial frame in the model frame
    inertia: tuple[float, float, float, float, float, float]  # ixx ixy ixz iyy iyz izz in com
    shapes: list[Shape] = field(default_factory=list)


@dataclass
class RobotJoint:
    name: str
    qualified: str
    kind: str  # SDF's type: revolute, prismatic, fixed, ball, universal, revolute2, screw
    parent: str
    child: str
    frame: Pose  # the joint frame in the model frame
    axes: list[np.ndarray] = field(default_factory=list)  # unit vectors in the joint frame
    lower: float = -math.inf
    upper: float = math.inf
    effort: float | None = None  # None: no limit given
    velocity: float | None = None
    damping: float = 0.0
    friction: float = 0.0
    stiffness: float = 0.0  # the axis's spring_stiffness, about spring_reference
    spring_reference: float = 0.0
    driven: bool = False  # an actuator sits in the joint (the joint's aref)
    turned: bool = False  # a fixed connection written from its target (sdf/orientation.py)

    @property
    def bounded(self) -> bool:
        return math.isfinite(self.lower) and math.isfinite(self.upper)


@dataclass
class Cut:
    """A connection left out to make trees: a joint (``kind`` its SDF type) or a fixed
    connection, with the pose of its frame in the model frame."""

    name: str
    kind: str
    parent: str
    child: str
    frame: Pose


@dataclass
class Tree:
    name: str  # the model name SDF's split gives the tree (the p-model's for one tree)
    links: list[RobotLink]  # depth first from the root, children in SDF order
    joints: list[RobotJoint]  # the joint into each link but the root, in the same order

    @property
    def root(self) -> RobotLink:
        return self.links[0]


@dataclass
class Robot:
    name: str
    trees: list[Tree]
    cuts: list[Cut]

    def links(self) -> dict[str, RobotLink]:
        return {link.name: link for tree in self.trees for link in tree.links}

    def joints(self) -> list[RobotJoint]:
        """Every joint of every tree, depth first: the order of URDF files, of MJCF's
        ``qpos`` and of the mass matrices (moving joints only there)."""
        return [j for tree in self.trees for j in tree.joints]


def build_robot(model: ElaboratedModel, ws: Workspace, report: Report, target: str) -> Robot:
    """The robot of an elaborated p-model for ``target`` (``urdf`` or ``mjcf``): the SDF
    translation for that target (which reports cuts, gearboxes, missing axes, but not its
    warnings about sensors and actuators, which these formats do not hold), read back as
    trees."""
    scratch = Report()
    document = translate(model, ws, scratch, SdfOptions(target=target, split_trees=True))
    report.extend(d for d in scratch.reported_since(0) if d.code.id not in SDF_ONLY)
    top = document.root.children[0]
    assert isinstance(top, Node)
    models = [top] if top.tag == "model" else [n for n in top.children
                                                 if isinstance(n, Node) and n.tag == "model"]
    qualified = document.names
    driven = {j.name for j in model.joints if j.actuators}
    trees = [_tree(m, qualified, driven) for m in models]
    sdf_name = {q: n for n, q in qualified.items()}
    cuts = []
    for c in tree_shape(model).cuts:
        assert c.parent is not None and c.child is not None
        if isinstance(c, FixedJoint):
            name, kind, frame = f"{c.parent.name}::fixedJoint::{c.child.name}", "fixed", \
                c.child.pose
        else:
            name, kind = c.name, _cut_kind(c.annotation)
            frame = c.child.pose.compose(c.pose)  # type: ignore[union-attr]
        cuts.append(Cut(name, kind, sdf_name[c.parent.name], sdf_name[c.child.name],
                        frame or Pose.identity()))
    return Robot(model.name, trees, cuts)


def _cut_kind(annotation: object) -> str:
    template = getattr(annotation, "template", None)
    return template[-1].lower() if template else "revolute"


def _tree(node: Node, qualified: dict[str, str], driven: set[str]) -> Tree:
    links = {}
    for child in node.children:
        if isinstance(child, Node) and child.tag == "link":
            links[child.attrs["name"]] = _link(child, qualified)
    joints: dict[str, list[RobotJoint]] = {}
    has_parent = set()
    for child in node.children:
        if isinstance(child, Node) and child.tag == "joint":
            j = _joint(child, links, qualified, driven)
            joints.setdefault(j.parent, []).append(j)
            has_parent.add(j.child)
    root = next(name for name in links if name not in has_parent)
    order_links: list[RobotLink] = []
    order_joints: list[RobotJoint] = []

    def visit(name: str) -> None:
        order_links.append(links[name])
        for j in joints.get(name, []):
            order_joints.append(j)
            visit(j.child)

    visit(root)
    return Tree(node.attrs["name"], order_links, order_joints)


def _value(node: Node | None, *path: str) -> object:
    for tag in path:
        if node is None:
            return None
        node = node.find(tag)
    return None if node is None else node.text


def _float(value: object, default: float) -> float:
    if value is None or isinstance(value, (str, tuple, Pose, Array)):
        return default
    return float(value)  # type: ignore[arg-type]


def _link(node: Node, qualified: dict[str, str]) -> RobotLink:
    pose = _value(node, "pose")
    assert isinstance(pose, Pose)
    inertial = node.find("inertial")
    com = _value(inertial, "pose")
    inertia = tuple(_float(_value(inertial, "inertia", k), 0.0)
                    for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    shapes = []
    for child in node.children:
        if isinstance(child, Node) and child.tag == "visual":
            shape = _shape(child, pose, qualified)
            if shape is not None:
                shapes.append(shape)
    name = node.attrs["name"]
    return RobotLink(name, qualified.get(name, name), pose, _float(_value(inertial, "mass"), 1.0),
                     pose.compose(com if isinstance(com, Pose) else Pose.identity()),
                     inertia, shapes)  # type: ignore[arg-type]


def _shape(visual: Node, link: Pose, qualified: dict[str, str]) -> Shape | None:
    local = _value(visual, "pose")
    pose = link.compose(local if isinstance(local, Pose) else Pose.identity())
    geometry = visual.find("geometry")
    kind = next((c for c in geometry.children if isinstance(c, Node)), None) \
        if geometry is not None else None
    name = visual.attrs["name"].removesuffix("_visual")
    owner = qualified.get(visual.attrs["name"], name)
    if kind is None or kind.tag == "empty":
        return None
    if kind.tag == "box":
        size = tuple(float(v) for v in _vector(_value(kind, "size")))
        return Shape(name, owner, "box", pose, size)
    if kind.tag == "cylinder":
        return Shape(name, owner, "cylinder", pose, (_float(_value(kind, "radius"), 0.0),
                                                     _float(_value(kind, "length"), 0.0)))
    if kind.tag == "sphere":
        return Shape(name, owner, "sphere", pose, (_float(_value(kind, "radius"), 0.0),))
    scale = _value(kind, "scale")
    return Shape(name, owner, "mesh", pose, (), str(_value(kind, "uri") or ""),
                 tuple(float(v) for v in _vector(scale)) if scale is not None
                 else (1.0, 1.0, 1.0))  # type: ignore[arg-type]


def _vector(value: object) -> list[float]:
    if isinstance(value, Array):
        return list(value.flat)
    if isinstance(value, (tuple, list)):
        return [float(v) for v in value]
    if isinstance(value, str):
        return [float(v) for v in value.split()]
    return []


def _joint(node: Node, links: dict[str, RobotLink], qualified: dict[str, str],
           driven: set[str]) -> RobotJoint:
    name = node.attrs["name"]
    child = str(_value(node, "child"))
    local = _value(node, "pose")
    frame = links[child].pose.compose(local if isinstance(local, Pose) else Pose.identity())
    declared = qualified.get(name, name).split("::fixedJoint::")[0]
    joint = RobotJoint(name, qualified.get(name, name), node.attrs["type"],
                       str(_value(node, "parent")), child, frame,
                       driven=qualified.get(name, name) in driven,
                       turned=node.attrs["type"] == "fixed"
                       and declared == qualified.get(child, child))
    rotation = np.array(frame.rotation)
    for tag in ("axis", "axis2"):
        axis = node.find(tag)
        if axis is None:
            continue
        xyz = np.array(_vector(_value(axis, "xyz")) or [0.0, 0.0, 1.0])
        if _value(axis, "use_parent_model_frame") is True:
            xyz = rotation.T @ xyz  # given in the model frame: into the joint frame
        norm = float(np.linalg.norm(xyz))
        joint.axes.append(xyz / norm if norm > 0 else np.array([0.0, 0.0, 1.0]))
        if tag != "axis":
            continue
        lower = _float(_value(axis, "limit", "lower"), -math.inf)
        upper = _float(_value(axis, "limit", "upper"), math.inf)
        joint.lower = lower if lower > -UNBOUNDED else -math.inf
        joint.upper = upper if upper < UNBOUNDED else math.inf
        effort = _float(_value(axis, "limit", "effort"), -1.0)
        velocity = _float(_value(axis, "limit", "velocity"), -1.0)
        joint.effort = effort if effort >= 0 else None
        joint.velocity = velocity if velocity >= 0 else None
        joint.damping = _float(_value(axis, "dynamics", "damping"), 0.0)
        joint.friction = _float(_value(axis, "dynamics", "friction"), 0.0)
        joint.stiffness = _float(_value(axis, "dynamics", "spring_stiffness"), 0.0)
        joint.spring_reference = _float(_value(axis, "dynamics", "spring_reference"), 0.0)
    return joint


def moved(robot: Robot, positions: dict[str, float]) -> dict[str, Pose]:
    """Forward kinematics: for each link, the rigid motion ``D`` that takes its model-frame
    poses (link, bodies, centre of mass) at rest to where they are with the joints at
    ``positions`` (joint name → radians or metres; a joint not given stays at 0): a revolute
    joint turns its child about its axis through the joint origin, a prismatic joint slides
    it along the axis. Other joint types stay at rest."""
    motion: dict[str, Pose] = {}
    for tree in robot.trees:
        motion[tree.root.name] = Pose.identity()
        for j in tree.joints:  # depth first: the parent's motion is known
            q = positions.get(j.name, 0.0)
            axis = j.axes[0] if j.axes else np.array([0.0, 0.0, 1.0])
            if j.kind in ("revolute", "gearbox", "screw", "universal", "revolute2") and q:
                local = Pose((0.0, 0.0, 0.0), _rotation(axis, q))
            elif j.kind == "prismatic" and q:
                local = Pose.at(tuple(q * axis))
            else:
                local = Pose.identity()
            # D_child = D_parent · F0 · local · F0⁻¹, with F0 the joint frame at rest
            motion[j.child] = motion[j.parent].compose(j.frame).compose(local).compose(
                j.frame.inverse())
    return motion


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' formula: the rotation by ``angle`` about the unit vector ``axis``."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)
