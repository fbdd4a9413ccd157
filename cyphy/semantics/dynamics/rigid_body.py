"""Rigid-body dynamics of an elaborated p-model: its kinematic tree and the joint-space
equations of motion ``M(q)·q̈ + h(q, q̇) = τ`` (issue 16).

Spatial algebra after Lynch and Park, *Modern Robotics* ch. 8 (twists and wrenches are
6-vectors with the angular part first, the convention of ``physmod::joints``), with the
recursive algorithms of Featherstone, *Rigid Body Dynamics Algorithms* (2008):

- the recursive Newton–Euler algorithm (RNEA, ch. 5) for inverse dynamics and the bias forces
  ``h(q, q̇)`` (gravity, Coriolis and centrifugal terms, the velocity-product term
  ``ad(V)·A·θ̇`` included),
- the composite-rigid-body algorithm (CRBA, ch. 6) for the mass matrix ``M(q)``,
- the articulated-body algorithm (ABA, ch. 7) for forward dynamics at linear cost.

The tree comes from the elaborated model: links joined by fixed connections (and by joints of
the ``Fixed`` family) are merged into one body; a body that no joint moves is fixed to the
world (the model frame), or with ``floating_base`` free (six coordinates: translations along
the world axes and ZYX Euler angles). Each moving body has the frame of the child link of the
joint that moves it. The model's link poses are the configuration ``q = 0``. Gravity is
``−9.81 m/s²`` along the model's z unless given. Joints have one coordinate (revolute,
prismatic) or several (universal: two angles; ball: ZYX Euler angles, singular at pitch
±π/2), with a motion subspace ``S(q)`` in the child frame and its rate ``Ṡ·q̇`` (Featherstone
ch. 4).

The algorithms take plain floats (NumPy) or SymPy expressions (object arrays): the symbolic
path, used to write the joint-space equations for the targets that need closed expressions
(small trees), is the same code as the numeric one that the tests check against Pinocchio.
``cyphy solve`` and ``simulate`` use :mod:`cyphy.semantics.dynamics.articulated` (the same transforms,
the articulated-body algorithm on named definitions, any size).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from cyphy.diagnostics import Span
from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.model.inertia import Inertial, combine, tensor
from cyphy.model.poses import Pose
from cyphy.semantics.dynamics.errors import DynamicsError

STANDARD_GRAVITY = (0.0, 0.0, -9.81)

@dataclass(frozen=True)
class TreeJoint:
    """One joint of the tree, with its ``dof`` coordinates (:data:`DOF`).

    ``parent`` is the index of the parent joint's body in ``KinematicTree.joints`` (−1: a body
    fixed to the world); ``placement`` is the child body's frame in the parent body's frame
    (the world's for −1) at ``q = 0``; ``screw`` the joint's screw axis in the child body frame
    (angular part first; for a joint of several coordinates its first column at ``q = 0``);
    ``point`` the joint's origin (a point of a revolute axis) in the child frame; ``frame`` the
    joint frame's axes in the child frame (the columns: a ball joint's and the floating base's
    Euler angles turn about them); ``axes`` a universal joint's two unit axes in the child
    frame. The floating base (``kind`` ``floating``, ``--floating-base``) is the joint of a
    root body to the world: its frame has the world's axes and its origin is the body's."""

    name: str  # the joint's qualified name (the root link's name for the floating base)
    prefix: str  # the joint's device prefix (its variables are ``<prefix>_theta`` …)
    kind: str  # revolute, prismatic, universal, spherical or floating
    parent: int
    placement: np.ndarray  # 4x4
    axis: np.ndarray  # unit 3-vector, child body frame
    point: np.ndarray  # 3-vector, child body frame
    screw: np.ndarray  # 6-vector
    inertia: np.ndarray  # 6x6 spatial inertia of the child body about its frame origin
    body: tuple[str, ...]  # the links the joint moves as one body (child link first)
    element: Joint | Link  # what a diagnostic points at (the root link: floating base)
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))  # 3x3, child body frame
    axes: tuple[np.ndarray, ...] = ()  # universal: AXIS1, AXIS2 in the child body frame

    @property
    def dof(self) -> int:
        """How many coordinates the joint has (:data:`DOF`)."""
        return DOF[self.kind]

    @property
    def scale(self) -> float:
        """The largest entry of the body's spatial inertia: what "zero" inertia along the axis
        is measured against."""
        cached = self.__dict__.get("_scale")
        if cached is None:
            cached = max(float(np.abs(self.inertia).max()), 1e-300)
            object.__setattr__(self, "_scale", cached)
        return cached

    @property
    def turn(self) -> np.ndarray:
        """``[a]`` of the axis (Rodrigues' formula), computed once."""
        cached = self.__dict__.get("_turn")
        if cached is None:
            cached = skew(self.axis).astype(float)
            object.__setattr__(self, "_turn", cached)
            object.__setattr__(self, "_turn2", cached @ cached)
        return cached

    @property
    def turn2(self) -> np.ndarray:
        """``[a]²``, computed once."""
        self.turn  # noqa: B018 - fills the cache
        return self.__dict__["_turn2"]


#: Coordinates per joint kind. A universal joint turns about AXIS1 (fixed in the parent) then
#: AXIS2 (fixed in the child); a ball joint (and the floating base's rotation) by ZYX Euler
#: angles ``(yaw, pitch, roll)``, ``R = Rz(yaw)·Ry(pitch)·Rx(roll)`` about its frame's axes, the
#: velocities being the angles' rates (singular at pitch ±π/2); the floating base first
#: translates by ``(x, y, z)`` along the world axes.
DOF = {"revolute": 1, "prismatic": 1, "universal": 2, "spherical": 3, "floating": 6}

#: The joint kinds whose coordinates include ZYX Euler angles (singular at pitch ±π/2: a
#: ``cyphy simulate`` start there is refused, :func:`euler_singularity`).
EULER = frozenset({"spherical", "floating"})

#: The floating base's coordinate names, after ``<Root>_``: positions, then ``v`` + name for the
#: velocities and ``a`` + name for the accelerations (``Body_vyaw``, ``Body_az``).
FLOATING = ("x", "y", "z", "yaw", "pitch", "roll")


@dataclass(frozen=True)
class KinematicTree:
    """The joints in tree order (parents before children) and the gravity vector. ``q``,
    ``q̇``, ``τ`` and the rows of ``M`` and ``h`` hold each joint's ``dof`` coordinates in
    this order (``offsets``)."""

    joints: tuple[TreeJoint, ...]
    gravity: np.ndarray

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def dof(self) -> int:
        """The number of coordinates (the size of ``q``)."""
        return sum(j.dof for j in self.joints)

    @property
    def offsets(self) -> tuple[int, ...]:
        """Where each joint's coordinates start in ``q``."""
        out, k = [], 0
        for joint in self.joints:
            out.append(k)
            k += joint.dof
        return tuple(out)

    def coordinates(self, variable: str = "theta") -> tuple[str, ...]:
        """The scalar variable names of ``variable`` (``theta``, ``v``, ``a`` or ``tau``) in
        the order of ``q``: ``<J>_theta`` for one coordinate, ``<J>_theta_1`` … as
        ``cyphy solve`` names a vector's components, and ``<Root>_x`` …, ``<Root>_vx`` …,
        ``<Root>_ax`` … for the floating base (which has no ``tau``: nothing touches it)."""
        return tuple(n for j in self.joints for n in coordinate_names(j, variable))

    @property
    def prefixes(self) -> tuple[str, ...]:
        return tuple(j.prefix for j in self.joints)

    def __len__(self) -> int:
        return len(self.joints)


# ----------------------------------------------------------------------------- the tree

def joint_kind(joint: Joint) -> str | None:
    """``revolute``, ``prismatic``, ``universal``, ``spherical`` or ``fixed`` from the joint's
    definition (or, when that is none of these, its annotation); None for the other families
    (revolute2, screw, gearbox, …)."""
    names = [joint.definition or ""]
    if joint.annotation is not None:
        names.append(joint.annotation.template[-1])
    for name in names:
        simple = name.split("::")[-1].lower()
        if simple in ("revolute", "continuous", "hinge"):
            return "revolute"
        if simple in ("prismatic", "slider"):
            return "prismatic"
        if simple == "universal":
            return "universal"
        if simple in ("spherical", "ball"):
            return "spherical"
        if simple == "fixed":
            return "fixed"
    return None


def coordinate_names(joint: TreeJoint, variable: str) -> tuple[str, ...]:
    """The joint's scalar variables of ``variable`` (``theta``, ``v``, ``a``, ``tau``) in
    coordinate order (see :meth:`KinematicTree.coordinates`)."""
    if joint.kind == "floating":
        if variable == "tau":
            return ()
        head = "" if variable == "theta" else variable
        return tuple(f"{joint.prefix}_{head}{n}" for n in FLOATING)
    if joint.dof == 1:
        return (f"{joint.prefix}_{variable}",)
    return tuple(f"{joint.prefix}_{variable}_{k}" for k in range(1, joint.dof + 1))


def kinematic_tree(model: ElaboratedModel,
                   gravity: Sequence[float] = STANDARD_GRAVITY,
                   floating_base: bool = False) -> KinematicTree:
    """The model's kinematic tree, joints in **tree order**: depth first from the root bodies
    (those no joint moves, in the model's link order), a body's child joints in the order of
    the elaborated model's joint list. This is the order of ``q``, ``M``'s rows and ``h``.

    The root bodies are fixed to the world, or, with ``floating_base``, each moved by a
    floating joint (six coordinates, first in its subtree) named after its first link.

    Raises ``DynamicsError`` for a joint family the equations do not cover, a zero axis, a
    loop (a body moved by two joints, or a cycle), or a link without mass properties in a
    moving body."""
    links = list(model.links)
    group = {link.name: link.name for link in links}

    def find(name: str) -> str:
        while group[name] != name:
            group[name] = group[group[name]]
            name = group[name]
        return name

    moving: list[Joint] = []
    for connection in [*model.fixed, *model.joints]:
        if connection.parent is None or connection.child is None:
            continue
        if isinstance(connection, FixedJoint) or joint_kind(connection) == "fixed":
            a, b = find(connection.parent.name), find(connection.child.name)
            if a == b:
                raise _loop(connection)
            group[b] = a
        else:
            moving.append(connection)
    incoming: dict[str, Joint] = {}
    for joint in moving:
        kind = joint_kind(joint)
        if kind is None:
            raise DynamicsError(
                f"joint {joint.name} ({joint.definition}) has no equations of motion here",
                joint.span, "the equations of motion support revolute, prismatic, universal, "
                "spherical (ball) and fixed joints; model this joint as a chain of those")
        child = find(joint.child.name)  # type: ignore[union-attr]
        if child == find(joint.parent.name) or child in incoming:  # type: ignore[union-attr]
            raise _loop(joint)
        incoming[child] = joint
    members: dict[str, list[Link]] = {}
    for link in links:
        members.setdefault(find(link.name), []).append(link)
    children: dict[str, list[Joint]] = {}
    for joint in moving:
        children.setdefault(find(joint.parent.name), []).append(joint)  # type: ignore[union-attr]

    ordered: list[TreeJoint] = []
    body_index: dict[str, int] = {}
    frame_of: dict[str, Pose] = {}

    def visit(joint: Joint, parent: int) -> None:
        child_link: Link = joint.child  # type: ignore[assignment]
        key = find(child_link.name)
        if key in body_index:
            raise _loop(joint)
        frame = child_link.pose or Pose.identity()
        parent_frame = frame_of.get(find(joint.parent.name), Pose.identity())  # type: ignore
        ordered.append(_tree_joint(joint, parent, parent_frame, frame, members[key]))
        body_index[key] = len(ordered) - 1
        frame_of[key] = frame
        for sub in children.get(key, []):
            visit(sub, body_index[key])

    for link in links:
        key = find(link.name)
        if key in incoming or key in frame_of or key in body_index:
            continue
        parent = -1
        if floating_base:  # the body's frame is its root link's (fixed connections' parent)
            root = next(m for m in members[key] if m.name == key)
            frame_of[key] = root.pose or Pose.identity()
            ordered.append(_floating_joint(root, frame_of[key], members[key]))
            parent = body_index[key] = len(ordered) - 1
        else:
            frame_of[key] = Pose.identity()  # fixed to the world: world coordinates
        for joint in children.get(key, []):
            visit(joint, parent)
    for joint in moving:
        if find(joint.child.name) not in body_index:  # type: ignore[union-attr]
            raise _loop(joint)  # a cycle of joints that no world-fixed body reaches
    return KinematicTree(tuple(ordered), np.asarray(gravity, dtype=float))


def _loop(element: Joint | FixedJoint) -> DynamicsError:
    return DynamicsError(
        f"{element.name} closes a kinematic loop: {element.child.name} is already "  # type: ignore
        f"connected to {element.parent.name}", element.span,  # type: ignore[union-attr]
        "closed chains are not supported: remove one connection of the loop (each link may "
        "have one parent)")


def _vector3(value: object) -> np.ndarray | None:
    try:
        out = np.asarray(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        return None
    return out if np.all(np.isfinite(out)) else None


def _axis(joint: Joint, constant: str, annotation: str) -> np.ndarray:
    """The joint's unit axis: its definition's ``constant`` (``AXIS``, ``AXIS1``, ``AXIS2``),
    else the annotation's ``annotation`` field (``axis``, ``axis2``)."""
    value: object = joint.axis if constant == "AXIS" else None
    if value is None and joint.device is not None:
        port = joint.device.port(constant)
        value = port.value if port is not None else None
    if value is None and joint.annotation is not None:
        found = joint.annotation.get(annotation)
        value = found.get("xyz") if hasattr(found, "get") else None  # type: ignore
    axis = _vector3(value)
    if axis is None:
        raise DynamicsError(f"joint {joint.name} has no numeric {constant}", joint.span,
                            f"give the joint `instantiation {constant} = (|0, 0, 1|)`")
    length = float(np.linalg.norm(axis))
    if not length > 1e-12:
        raise DynamicsError(f"joint {joint.name} has an axis of zero length ({constant})",
                            joint.span, "give the axis a direction, for example (|0, 0, 1|)")
    return axis / length


def _body_inertia(element: Joint | Link, what: str, frame: Pose,
                  links: list[Link]) -> np.ndarray:
    """The 6x6 spatial inertia of ``links`` (one body) about ``frame``, in its axes."""
    parts: list[Inertial] = []
    to_body = frame.inverse()
    for link in links:
        if link.inertial is None or link.inertial.mass is None:
            raise DynamicsError(
                f"link {link.name} has no mass properties but is moved by {what}",
                link.span, "give the link an `inertial information` (mass and inertia) or "
                "bodies with masses")
        com = to_body.compose(link.pose or Pose.identity()).compose(link.inertial.com)
        parts.append(Inertial(link.inertial.mass, com, link.inertial.inertia))
    try:
        body = combine(parts)
    except ValueError:
        raise DynamicsError(f"the body moved by {what} has no positive mass",
                            element.span, "give its links positive masses") from None
    return spatial_inertia(body.mass, np.array(body.com.position), tensor(body.inertia))


def _tree_joint(joint: Joint, parent: int, parent_frame: Pose, frame: Pose,
                links: list[Link]) -> TreeJoint:
    kind = joint_kind(joint) or ""
    placement = (joint.child.pose or Pose.identity()).compose(  # type: ignore[union-attr]
        joint.pose) if joint.pose is not None else \
        (joint.parent.pose or Pose.identity()).compose(  # type: ignore[union-attr]
            joint.local_pose or Pose.identity())
    in_child = frame.inverse().compose(placement)
    rotation = np.array(in_child.rotation, dtype=float)
    point = np.array(in_child.position, dtype=float)
    axes: tuple[np.ndarray, ...] = ()
    if kind in ("revolute", "prismatic"):
        axis_c = rotation @ _axis(joint, "AXIS", "axis")
    elif kind == "universal":
        axes = (rotation @ _axis(joint, "AXIS1", "axis"), rotation @ _axis(joint, "AXIS2", "axis2"))
        if not np.linalg.norm(np.cross(*axes)) > 1e-9:
            raise DynamicsError(f"universal joint {joint.name} has parallel axes", joint.span,
                                "give AXIS1 and AXIS2 different directions")
        axis_c = axes[0]
    else:  # spherical: the first angle (yaw) turns about the joint frame's z
        axis_c = rotation[:, 2]
    screw = np.concatenate([np.zeros(3), axis_c]) if kind == "prismatic" else \
        np.concatenate([axis_c, np.cross(point, axis_c)])
    inertia = _body_inertia(joint, f"joint {joint.name}", frame, links)
    return TreeJoint(joint.name, joint.device.prefix if joint.device else joint.simple_name,
                     kind, -1 if parent < 0 else parent,
                     parent_frame.inverse().compose(frame).matrix(), axis_c, point, screw,
                     inertia, tuple(link.name for link in links), joint, rotation, axes)


def _floating_joint(root: Link, frame: Pose, links: list[Link]) -> TreeJoint:
    """The floating base of the root body whose frame (at rest, in the world) is ``frame``:
    its joint frame has the world's axes (in the body frame, ``R0ᵀ``) and the body's
    origin."""
    world_axes = np.array(frame.rotation, dtype=float).T
    inertia = _body_inertia(root, "the floating base", frame, links)
    screw = np.concatenate([np.zeros(3), world_axes[:, 0]])
    return TreeJoint(root.name, root.qname[-1], "floating", -1, frame.matrix(),
                     world_axes[:, 0], np.zeros(3), screw, inertia,
                     tuple(link.name for link in links), root, world_axes)


def spatial_inertia(mass: float, com: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """The 6x6 spatial inertia about a frame's origin of a body with ``mass``, centre of mass
    ``com`` and rotational ``inertia`` about the centre of mass, both in the frame's axes
    (MR eq. 8.32 moved to the origin: ``[[I − m[c]², m[c]], [−m[c], m·E]]``)."""
    c = skew(com)
    top = np.hstack([inertia - mass * (c @ c), mass * c])
    bottom = np.hstack([-mass * c, mass * np.eye(3)])
    return np.vstack([top, bottom])


# ----------------------------------------------------------------------------- spatial algebra

def skew(v: Any) -> np.ndarray:
    """``[v]``, the matrix of ``v ×``."""
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def adjoint(rotation: np.ndarray, position: Any) -> np.ndarray:
    """``[Ad_T]`` of ``T = (R, p)``: twists in T's inner frame to its outer frame (MR 3.83)."""
    zero = np.zeros((3, 3))
    return np.vstack([np.hstack([rotation, zero]),
                      np.hstack([skew(position) @ rotation, rotation])])


def ad(twist: Any) -> np.ndarray:
    """``[ad_V]`` of ``V = (ω, v)``: the Lie bracket ``[ad_V]·W = V × W`` (MR eq. 8.38)."""
    w, v = skew(twist[:3]), skew(twist[3:])
    return np.vstack([np.hstack([w, np.zeros((3, 3))]), np.hstack([v, w])])


def _rotation(axis: np.ndarray, angle: Any, cos: Any, sin: Any) -> np.ndarray:
    """Rodrigues' formula ``E + sin θ [a] + (1 − cos θ) [a]²`` (MR eq. 3.51)."""
    k = skew(axis)  # a float array on the left keeps SymPy scalars element by element
    return np.eye(3) + k * sin(angle) + (k @ k) * (1 - cos(angle))


def parent_to_child(joint: TreeJoint, q: Any, cos: Any, sin: Any) -> np.ndarray:
    """``[Ad_T]`` of the parent frame's pose in the child frame at joint value ``q``: it
    carries twists from the parent body's frame to the child's (MR eq. 8.47)."""
    base_r, base_p = joint.placement[:3, :3], joint.placement[:3, 3]
    if joint.kind == "revolute":
        r = _rotation(joint.axis, q, cos, sin)  # child frame turned about the axis
        p = (np.eye(3) - r) @ joint.point
    elif joint.kind == "prismatic":
        r = np.eye(3)
        p = joint.axis * q
    else:
        r, p = _joint_motion(joint, q, cos, sin)
    # pose of the child frame in the parent frame: placement · (r, p)
    rotation = base_r @ r
    position = base_r @ p + base_p
    inverse_r = rotation.T
    return adjoint(inverse_r, -(inverse_r @ position))


def _euler(q: Sequence[Any], cos: Any, sin: Any) -> tuple[np.ndarray, np.ndarray]:
    """ZYX Euler angles ``(yaw, pitch, roll)``: the rotation ``Rz(yaw)·Ry(pitch)·Rx(roll)`` and
    the matrix whose columns turn the angles' rates into the angular velocity in the turned
    frame (singular where ``cos(pitch) = 0``)."""
    cy, sy, cp, sp, cr, sr = cos(q[0]), sin(q[0]), cos(q[1]), sin(q[1]), cos(q[2]), sin(q[2])
    rotation = np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                         [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                         [-sp, cp * sr, cp * cr]])
    rates = np.array([[-sp, 0, 1], [cp * sr, cr, 0], [cp * cr, -sr, 0]])
    return rotation, rates


def _euler_rate(q: Sequence[Any], qd: Sequence[Any], cos: Any, sin: Any) -> np.ndarray:
    """The time derivative of :func:`_euler`'s rate matrix (its entries as functions of the
    angles) times the rates: ``Ṡ·q̇``."""
    cp, sp, cr, sr = cos(q[1]), sin(q[1]), cos(q[2]), sin(q[2])
    dy, dp, dr = qd
    return np.array([-cp * dp * dy,
                     (-sp * dp * sr + cp * cr * dr) * dy - sr * dr * dp,
                     (-sp * dp * cr - cp * sr * dr) * dy - cr * dr * dp])


def _joint_motion(joint: TreeJoint, q: Sequence[Any], cos: Any, sin: Any
                  ) -> tuple[np.ndarray, np.ndarray]:
    """``(r, p)``: where a joint of several coordinates takes its child body from its pose at
    rest, in the child frame (the child frame at ``q`` is ``placement · (r, p)``)."""
    if joint.kind == "universal":
        r = _rotation(joint.axes[0], q[0], cos, sin) @ _rotation(joint.axes[1], q[1], cos, sin)
        return r, joint.point - r @ joint.point
    turn, _ = _euler(q[-3:], cos, sin)
    r = joint.frame @ turn @ joint.frame.T
    if joint.kind == "spherical":
        return r, joint.point - r @ joint.point
    return r, joint.frame @ np.array(list(q[:3]))  # floating: along the world axes


def motion_subspace(joint: TreeJoint, q: Any, cos: Any, sin: Any) -> np.ndarray:
    """``S(q)`` (6 × dof): the child body's twist relative to its parent, in the child frame,
    per unit rate of each coordinate (Featherstone's motion subspace)."""
    if joint.dof == 1:
        return joint.screw.reshape(6, 1)
    point = skew(joint.point)
    if joint.kind == "universal":
        first = _rotation(joint.axes[1], q[1], cos, sin).T @ joint.axes[0]
        turns = np.stack([first, joint.axes[1]], axis=1)
        return np.vstack([turns, point @ turns])
    rotation, rates = _euler(q[-3:], cos, sin)
    turns = joint.frame @ rates
    if joint.kind == "spherical":
        return np.vstack([turns, point @ turns])
    zero = np.zeros((3, 3))
    return np.vstack([np.hstack([zero, turns]), np.hstack([joint.frame @ rotation.T, zero])])


def subspace_factors(joint: TreeJoint, q: Any, cos: Any, sin: Any, inverse_cos: Any
                     ) -> tuple[np.ndarray, np.ndarray]:
    """``(S0, B⁻¹)`` with ``S(q) = S0·B(q)`` for a joint of several coordinates: the motion
    subspace in the rates ``w = B·q̇`` (a ball joint's angular velocity, a floating base's
    linear and angular velocity), which has no singularity, and the map back to the
    coordinates' rates. ``B`` is the ZYX Euler rate matrix of :func:`_euler` (a floating
    base: the identity on the translations) and ``B⁻¹`` its inverse in closed form, with
    ``inverse_cos`` the reciprocal of ``cos(pitch)``; a universal joint has ``B`` the identity.
    Solving for ``w`` and then ``q̈ = B⁻¹·w`` keeps the articulated-body algorithm's ``D``
    well conditioned up to the singularity (a factorisation of ``S``, not an inverse of
    ``D = Bᵀ·D0·B`` by its determinant), the loss of accuracy being only the inherent
    ``1/cos(pitch)`` of Euler-angle rates."""
    if joint.kind not in EULER:
        return motion_subspace(joint, q, cos, sin), np.eye(joint.dof)
    _, sp, cr, sr = cos(q[-2]), sin(q[-2]), cos(q[-1]), sin(q[-1])
    inverse = np.array([[0, sr * inverse_cos, cr * inverse_cos], [0, cr, -sr],
                        [1, sp * sr * inverse_cos, sp * cr * inverse_cos]])
    if joint.kind == "spherical":
        return np.vstack([joint.frame, skew(joint.point) @ joint.frame]), inverse
    rotation, _ = _euler(q[-3:], cos, sin)
    zero = np.zeros((3, 3))
    s0 = np.vstack([np.hstack([zero, joint.frame]), np.hstack([joint.frame @ rotation.T, zero])])
    b_inverse = np.zeros((6, 6), dtype=inverse.dtype)
    b_inverse[:3, :3] = np.eye(3)
    b_inverse[3:, 3:] = inverse
    return s0, b_inverse


def motion_subspace_rate(joint: TreeJoint, q: Any, qd: Any, cos: Any, sin: Any) -> np.ndarray:
    """``Ṡ(q)·q̇``: the change of the motion subspace's entries in the child frame times the
    rates (zero for one coordinate; Featherstone's ``c_J``)."""
    if joint.kind == "universal":
        first = _rotation(joint.axes[1], q[1], cos, sin).T @ joint.axes[0]
        turn = -(skew(joint.axes[1]) @ first) * (qd[0] * qd[1])
        return np.concatenate([turn, skew(joint.point) @ turn])
    turn = joint.frame @ _euler_rate(q[-3:], qd[-3:], cos, sin)
    if joint.kind == "spherical":
        return np.concatenate([turn, skew(joint.point) @ turn])
    rotation, rates = _euler(q[-3:], cos, sin)
    spin = rates @ np.array(list(qd[3:]))
    linear = joint.frame @ (-(skew(spin) @ (rotation.T @ np.array(list(qd[:3])))))
    return np.concatenate([turn, linear])


def euler_singularity(tree: KinematicTree, q: Sequence[float]) -> None:
    """Raise ``DynamicsError`` at the first ball joint or floating base whose pitch is within
    1e-9 of ±π/2 in ``q``: there the ZYX Euler angles lose a degree of freedom (yaw and roll
    turn about one axis) and the mass matrix is singular."""
    for joint, start in zip(tree.joints, tree.offsets):
        if joint.kind not in EULER:
            continue
        pitch = float(q[start + joint.dof - 2])
        if abs(math.cos(pitch)) < 1e-9:
            what = "floating base" if joint.kind == "floating" else "ball joint"
            raise DynamicsError(
                f"the {what} {joint.name} is at pitch {pitch:g} rad, where its ZYX Euler "
                "angles are singular (the mass matrix loses rank at pitch ±π/2)",
                joint.element.span, "start it away from pitch ±π/2, or turn the joint frame "
                "(its pose) so that the motion stays away from it")


_EYE3 = np.eye(3)


def _numeric_parent_to_child(joint: TreeJoint, q: float) -> np.ndarray:
    """``parent_to_child`` for a float ``q``, built entry by entry: the recursive algorithms
    call it once per joint and step, where NumPy's per-call overhead dominates."""
    base_r, base_p = joint.placement[:3, :3], joint.placement[:3, 3]
    if joint.kind == "revolute":
        k = joint.turn
        r = _EYE3 + k * math.sin(q) + joint.turn2 * (1.0 - math.cos(q))
        p = joint.point - r @ joint.point
    else:
        r = None
        p = joint.axis * q
    rotation = base_r @ r if r is not None else base_r
    e = rotation.T
    x, y, z = (-(e @ (base_r @ p + base_p))).tolist()
    out = np.zeros((6, 6))
    out[:3, :3] = e
    out[3:, 3:] = e
    out[3:, :3] = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]) @ e
    return out


def _ad_numeric(twist: np.ndarray) -> np.ndarray:
    """``ad(V)`` of a float twist in one array construction."""
    a, b, c, d, e, f = twist.tolist()
    return np.array([[0.0, -c, b, 0.0, 0.0, 0.0], [c, 0.0, -a, 0.0, 0.0, 0.0],
                     [-b, a, 0.0, 0.0, 0.0, 0.0], [0.0, -f, e, 0.0, -c, b],
                     [f, 0.0, -d, c, 0.0, -a], [-e, d, 0.0, -b, a, 0.0]])


def _math(values: Sequence[Any]) -> tuple[Any, Any, bool]:
    """``cos`` and ``sin`` for the scalars given, and whether they are symbolic."""
    if any(not isinstance(v, (int, float, np.floating, np.integer)) for v in values):
        import sympy

        return sympy.cos, sympy.sin, True
    return np.cos, np.sin, False


# ----------------------------------------------------------------------------- algorithms

def _coordinates(joint: TreeJoint, start: int, values: Sequence[Any]) -> Any:
    """The joint's coordinates in ``values``: a scalar for one, a list for several."""
    return values[start] if joint.dof == 1 else list(values[start:start + joint.dof])


def inverse_dynamics(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any],
                     qdd: Sequence[Any], gravity: bool = True) -> np.ndarray:
    """RNEA: the joint efforts ``τ = M(q)·q̈ + h(q, q̇)`` (tree order), at linear cost."""
    cos, sin, symbolic = _math([*q, *qd, *qdd])
    base = np.concatenate([np.zeros(3), -tree.gravity]) if gravity else np.zeros(6)
    transforms, twists, forces, subspaces = [], [], [], []
    accelerations = []
    for joint, k in zip(tree.joints, tree.offsets):
        qi = _coordinates(joint, k, q)
        x = parent_to_child(joint, qi, cos, sin)
        v_parent = twists[joint.parent] if joint.parent >= 0 else np.zeros(6)
        a_parent = accelerations[joint.parent] if joint.parent >= 0 else base
        if joint.dof == 1:
            s = joint.screw
            v_joint, a_joint = joint.screw * qd[k], joint.screw * qdd[k]
        else:
            s = motion_subspace(joint, qi, cos, sin)
            rates = _coordinates(joint, k, qd)
            v_joint = s @ np.array(rates)
            a_joint = s @ np.array(_coordinates(joint, k, qdd)) + \
                motion_subspace_rate(joint, qi, rates, cos, sin)
        v = x @ v_parent + v_joint
        a = x @ a_parent + a_joint + ad(v) @ v_joint
        transforms.append(x)
        twists.append(v)
        accelerations.append(a)
        subspaces.append(s)
        forces.append(joint.inertia @ a - ad(v).T @ (joint.inertia @ v))
    tau = np.zeros(tree.dof, dtype=object if symbolic else float)
    for i in range(len(tree) - 1, -1, -1):
        joint, k = tree.joints[i], tree.offsets[i]
        tau[k:k + joint.dof] = subspaces[i].T @ forces[i]
        if joint.parent >= 0:
            forces[joint.parent] = forces[joint.parent] + transforms[i].T @ forces[i]
    return tau


def bias_forces(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any]) -> np.ndarray:
    """``h(q, q̇)``: gravity, Coriolis and centrifugal efforts (RNEA with ``q̈ = 0``)."""
    return inverse_dynamics(tree, q, qd, [0.0] * tree.dof)


def mass_matrix(tree: KinematicTree, q: Sequence[Any]) -> np.ndarray:
    """CRBA: the joint-space mass matrix ``M(q)`` (symmetric, tree order)."""
    cos, sin, symbolic = _math(list(q))
    n = len(tree)
    offsets = tree.offsets
    parts = [_coordinates(j, k, q) for j, k in zip(tree.joints, offsets)]
    transforms = [parent_to_child(j, p, cos, sin) for j, p in zip(tree.joints, parts)]
    subspaces = [motion_subspace(j, p, cos, sin) for j, p in zip(tree.joints, parts)]
    composite = [j.inertia for j in tree.joints]
    for i in range(n - 1, -1, -1):
        parent = tree.joints[i].parent
        if parent >= 0:
            composite[parent] = composite[parent] + transforms[i].T @ composite[i] @ \
                transforms[i]
    matrix = np.zeros((tree.dof, tree.dof), dtype=object if symbolic else float)
    for i in range(n):
        rows = slice(offsets[i], offsets[i] + tree.joints[i].dof)
        force = composite[i] @ subspaces[i]
        matrix[rows, rows] = subspaces[i].T @ force
        j = i
        while tree.joints[j].parent >= 0:
            force = transforms[j].T @ force
            j = tree.joints[j].parent
            block = subspaces[j].T @ force
            other = slice(offsets[j], offsets[j] + tree.joints[j].dof)
            matrix[other, rows] = block
            matrix[rows, other] = block.T
    return matrix


def forward_dynamics(tree: KinematicTree, q: Sequence[float], qd: Sequence[float],
                     tau: Sequence[float]) -> np.ndarray:
    """ABA: the joint accelerations ``q̈ = M(q)⁻¹(τ − h(q, q̇))`` at linear cost (numeric).
    ``tau`` has one effort per coordinate (zeros for a floating base).

    Raises ``DynamicsError`` at a ball joint or floating base at an Euler-angle singularity,
    and at the joint whose articulated inertia along its motion is not positive definite (a
    massless subtree: the mass matrix is singular)."""
    n = len(tree)
    offsets = tree.offsets
    if any(j.kind in EULER for j in tree.joints):
        euler_singularity(tree, q)
    base = np.concatenate([np.zeros(3), -tree.gravity])
    xs, vs, cs, inertias, biases, subspaces = [], [], [], [], [], []
    factors: dict[int, np.ndarray] = {}  # B⁻¹ of a joint of several coordinates
    for i, joint in enumerate(tree.joints):
        k = offsets[i]
        if joint.dof == 1:
            x = _numeric_parent_to_child(joint, float(q[k]))
            s = joint.screw
            v_joint = joint.screw * float(qd[k])
            c_joint = None
        else:
            qi = [float(v) for v in q[k:k + joint.dof]]
            rates = [float(v) for v in qd[k:k + joint.dof]]
            x = parent_to_child(joint, qi, math.cos, math.sin).astype(float)
            v_joint = motion_subspace(joint, qi, math.cos, math.sin).astype(float) @ np.array(rates)
            c_joint = motion_subspace_rate(joint, qi, rates, math.cos, math.sin).astype(float)
            pitch = math.cos(qi[-2]) if joint.kind in EULER else 1.0
            s, b_inverse = (m.astype(float) for m in subspace_factors(
                joint, qi, math.cos, math.sin, 1.0 / pitch))
            factors[i] = b_inverse
        v = x @ vs[joint.parent] + v_joint if joint.parent >= 0 else v_joint
        cross = _ad_numeric(v)
        xs.append(x)
        vs.append(v)
        cs.append(cross @ v_joint if c_joint is None else cross @ v_joint + c_joint)
        subspaces.append(s)
        inertias.append(joint.inertia.copy())
        biases.append(-(cross.T @ (joint.inertia @ v)))
    us: list[Any] = [None] * n
    ds: list[Any] = [None] * n
    uu: list[Any] = [None] * n
    for i in range(n - 1, -1, -1):
        joint, k = tree.joints[i], offsets[i]
        s = subspaces[i]
        u_vec = inertias[i] @ s
        if joint.dof == 1:
            d = float(s @ u_vec)
            if not d > 1e-12 * joint.scale:
                raise _singular(joint)
            u = float(tau[k]) - float(s @ biases[i])
            d_inv_u, spread = u / d, np.outer(u_vec, u_vec) / d
            us[i], ds[i], uu[i] = u_vec, d, u
        else:  # in the rates w = B·q̇ of S = S0·B: D0 = S0ᵀ·IA·S0 stays well conditioned
            d_matrix = s.T @ u_vec
            eigenvalues = np.linalg.eigvalsh(d_matrix)
            if not eigenvalues[0] > 1e-12 * max(float(eigenvalues[-1]), joint.scale):
                raise _singular(joint)
            d_inverse = np.linalg.solve(d_matrix, np.eye(joint.dof))  # LU, not the adjugate
            efforts = np.array([float(t) for t in tau[k:k + joint.dof]])
            u = factors[i].T @ efforts - s.T @ biases[i]
            d_inv_u, spread = d_inverse @ u, u_vec @ d_inverse @ u_vec.T
            us[i], ds[i], uu[i] = u_vec, d_inverse, u
        if joint.parent >= 0:
            articulated = inertias[i] - spread
            bias = biases[i] + articulated @ cs[i] + (u_vec * d_inv_u if joint.dof == 1
                                                      else u_vec @ d_inv_u)
            inertias[joint.parent] = inertias[joint.parent] + xs[i].T @ articulated @ xs[i]
            biases[joint.parent] = biases[joint.parent] + xs[i].T @ bias
    qdd = np.zeros(tree.dof)
    accelerations: list[np.ndarray] = []
    for i, joint in enumerate(tree.joints):
        k = offsets[i]
        a_parent = accelerations[joint.parent] if joint.parent >= 0 else base
        a = xs[i] @ a_parent + cs[i]
        if joint.dof == 1:
            qdd[k] = (uu[i] - float(us[i] @ a)) / ds[i]
            accelerations.append(a + joint.screw * qdd[k])
        else:
            rates = ds[i] @ (uu[i] - us[i].T @ a)  # w = B·q̈
            qdd[k:k + joint.dof] = factors[i] @ rates
            accelerations.append(a + subspaces[i] @ rates)
    return qdd


def _singular(joint: TreeJoint) -> DynamicsError:
    return DynamicsError(f"the mass matrix is singular at joint {joint.name}: nothing it moves "
                         "has inertia along its motion", joint.element.span,
                         "give the links it moves mass and inertia")


def joint_space(model: ElaboratedModel | KinematicTree, q: Sequence[Any], qd: Sequence[Any],
                gravity: Sequence[float] = STANDARD_GRAVITY, floating_base: bool = False
                ) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """``(M(q), h(q, q̇), joint names)`` of the model's equations of motion
    ``M(q)·q̈ + h(q, q̇) = τ``, the root fixed to the world (or floating).

    **Joint order** (of the joints' coordinates in ``q``, ``q̇``, the rows of ``M`` and ``h``,
    and of the names returned, one per joint): depth first from the root bodies, taken in the
    model's link order, each body's child joints in the elaborated model's joint order; fixed
    connections are not joints. Names are the joints' qualified names
    (``Model::Link::Joint``; a floating base has its root link's). Values are SI (rad, m,
    N·m, N); for a revolute joint ``q`` is the rotation about its axis, for a prismatic joint
    the displacement along it, from the configuration the model's poses give; a joint of
    several coordinates has them in :data:`DOF`'s order (``KinematicTree.coordinates``).
    """
    tree = model if isinstance(model, KinematicTree) else \
        kinematic_tree(model, gravity, floating_base)
    return mass_matrix(tree, q), bias_forces(tree, q, qd), tree.names


# ----------------------------------------------------------------------------- model equations

SYMBOLIC_LIMIT = 6
"""The largest tree (in coordinates) whose joint-space equations ``tau == M(q)*a + h(q, v)``
are written out as closed expressions, for the targets that need them (CyPhyCircus
``Evolve``, Isabelle, Flow*): the expressions grow quickly with depth, and SymPy's reduction
with them. ``cyphy solve`` and ``cyphy simulate`` take trees of any
size and joint kind (the floating base included), with the explicit accelerations as named
definitions (:mod:`cyphy.semantics.dynamics.articulated`)."""

_JOINT_PORTS = ("theta", "v", "a", "tau")


def written_out(tree: KinematicTree) -> bool:
    """Whether :func:`motion_equations` writes the tree's equations out: at most
    ``SYMBOLIC_LIMIT`` coordinates of one each, or one joint of several alone."""
    if any(j.dof > 1 for j in tree.joints):
        return len(tree) == 1
    return tree.dof <= SYMBOLIC_LIMIT


def motion_equations(model: ElaboratedModel,
                     gravity: Sequence[float] = STANDARD_GRAVITY,
                     floating_base: bool = False) -> list[tuple[Any, TreeJoint]]:
    """The model's equations of motion as equations of the expression AST, one per coordinate
    in tree order with the joint it belongs to: ``J_tau == Σⱼ M_ij(q)·Jⱼ_a + h_i(q, v)`` in the
    joints' own variables (``physmod::joints``: ``theta``, ``v``, ``a``, ``tau``; a joint of
    several coordinates has vector ports, read item by item, ``J_tau[2]``). A floating base's
    coordinates are new variables (:meth:`KinematicTree.coordinates`): its equations are
    ``derivative(B_x) == B_vx``, ``derivative(B_vx) == B_ax`` and ``0 == M·a + h`` (nothing
    touches it).

    Empty when the model has no moving joint (and no floating base), or when a joint's
    definition lacks one of these variables (then nothing here can name its motion). Raises
    ``DynamicsError`` for a tree that has no equations of motion, one of more than
    ``SYMBOLIC_LIMIT`` coordinates, or a joint of several coordinates (a ball or universal
    joint, a floating base) with other joints: expanded, their products of sines and cosines
    swell past what SymPy expands in minutes (a ball joint and a universal joint in a chain,
    measured; the unexpanded recursion shares subterms that any printer writes out
    exponentially often). Such a joint alone is written out."""
    import sympy

    from cyphy import expr as ex
    from cyphy.translate.to_sympy import to_expr  # SymPy to the shared AST (no printer state)

    moving = [j for j in model.joints if j.parent is not None and j.child is not None
              and joint_kind(j) != "fixed"]
    for joint in moving:  # before the tree: a model whose joints cannot say it is left alone
        if joint.device is None or any(joint.device.port(p) is None for p in _JOINT_PORTS):
            return []
    if not moving and not floating_base:
        return []
    tree = kinematic_tree(model, gravity, floating_base)
    if not len(tree):
        return []
    zero = [0.0] * tree.dof
    forward_dynamics(tree, zero, zero, zero)  # singular?
    several = [j for j in tree.joints if j.dof > 1]
    if not written_out(tree) and several:
        raise DynamicsError(
            f"the kinematic tree has {len(tree)} joints, {several[0].name} of {several[0].dof} "
            "coordinates: written out symbolically, its equations of motion swell past what "
            "SymPy expands in minutes (a joint of several coordinates is written out alone)",
            several[0].element.span,
            "`cyphy solve` and `cyphy simulate` take it (the accelerations as named "
            "definitions); here, restrict the system with --element")
    if not written_out(tree):
        first = tree.joints[0].element
        raise DynamicsError(
            f"the kinematic tree has {tree.dof} coordinates: its equations of motion are too "
            f"large to write out as closed expressions (at most {SYMBOLIC_LIMIT}), which this "
            "target needs", first.span,
            "`cyphy solve` and `cyphy simulate` take trees of any size (the accelerations "
            "as named definitions); here, restrict the system to fewer "
            "joints (--element, --isabelle-element or the scenario's elements)")

    variables: dict[str, ex.Expr] = {}  # scalar name → the model's expression for it

    def scalars(joint: TreeJoint, name: str) -> list[Any]:
        span = joint.element.span
        names = coordinate_names(joint, name)
        if joint.kind == "floating":
            for n in names:
                variables[n] = ex.Name((n,), span=span)
        else:
            port = joint.element.device.port(name)  # type: ignore[union-attr]
            size = port_size(port.type)  # type: ignore[union-attr]
            if (joint.dof == 1) != (size is None) or (size is not None and size != joint.dof):
                raise DynamicsError(
                    f"joint {joint.name} has {joint.dof} coordinate"
                    f"{'s' if joint.dof > 1 else ''}, but its variable {name} is not "
                    + ("a scalar" if joint.dof == 1 else f"a vector of {joint.dof}"),
                    span, f"declare {name}: " + ("real" if joint.dof == 1 else
                                                 f"vector(real, {joint.dof})"))
            whole = ex.Name((port.mangled,), span=span)  # type: ignore[union-attr]
            for k, n in enumerate(names, start=1):
                variables[n] = whole if joint.dof == 1 else \
                    ex.Index(whole, (ex.Num(str(k)),), span=span)
        return [sympy.Symbol(n, real=True) for n in names]

    q = [x for j in tree.joints for x in scalars(j, "theta")]
    qd = [x for j in tree.joints for x in scalars(j, "v")]
    qdd = [x for j in tree.joints for x in scalars(j, "a")]
    # One symbolic Newton-Euler pass gives M(q)*a + h(q, v) at once; the composite-body
    # algorithm's products of symbolic transforms swell (34 s for 6 joints, measured).
    efforts = inverse_dynamics(tree, q, qd, qdd)
    _passive(tree, q, qd, efforts)

    def model_names(node: ex.Expr) -> ex.Expr | None:
        return variables.get(node.text) if isinstance(node, ex.Name) else None

    out = []
    for joint, start in zip(tree.joints, tree.offsets):
        span = joint.element.span
        if joint.kind == "floating":
            for position, speed, acceleration in zip(
                    *(coordinate_names(joint, v) for v in ("theta", "v", "a"))):
                for left, right in ((position, speed), (speed, acceleration)):
                    out.append((ex.BinOp("==", ex.Derivative(ex.Name((left,), span=span),
                                                             span=span),
                                         ex.Name((right,), span=span), span=span), joint))
            lefts: list[ex.Expr] = [ex.Num("0", span=span)] * joint.dof
        else:
            scalars(joint, "tau")
            lefts = [variables[n] for n in coordinate_names(joint, "tau")]
        for k, left in enumerate(lefts):
            rhs = _chop(sympy.expand(efforts[start + k]))
            right = ex.transform(to_expr(rhs, decimals=True), model_names)
            out.append((ex.BinOp("==", left, right, span=span), joint))
    return out


def _passive(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any], efforts: Any) -> None:
    """Take the annotated damping and springs of the joints into ``efforts`` (the effort
    the actuator gives is the rigid body's need minus them,
    :mod:`cyphy.semantics.dynamics.joint_forces`; limits are not written out)."""
    from cyphy.semantics.dynamics.joint_forces import axis_forces, passive_efforts

    for joint, start in zip(tree.joints, tree.offsets):
        forces = axis_forces(joint.kind, joint.element)
        span = slice(start, start + len(forces))
        for k, extra in enumerate(passive_efforts(forces, q[span], qd[span]), start=start):
            efforts[k] = efforts[k] - extra


def port_size(t: Any) -> int | None:
    """The literal size of a vector type, None for a scalar (or anything else)."""
    from cyphy.lang import ast

    if isinstance(t, ast.VectorType) and t.size is not None:
        text = getattr(t.size, "text", "")
        return int(text) if isinstance(text, str) and text.isdigit() else -1
    return -1 if isinstance(t, ast.MatrixType) else None


def _chop(value: Any) -> Any:
    """``value`` without the float noise of the transforms (``1e-19·v²`` where a term
    cancels exactly): coefficients below 1e-12 of the largest are dropped."""
    import sympy

    floats = [abs(float(f)) for f in value.atoms(sympy.Float)]
    if not floats:
        return value
    limit = 1e-12 * max(floats)
    terms = value.as_ordered_terms() if isinstance(value, sympy.Add) else [value]
    kept = [t for t in terms if not (t.as_coeff_Mul()[0].is_Float
                                     and abs(float(t.as_coeff_Mul()[0])) < limit)]
    return sympy.Add(*kept)
