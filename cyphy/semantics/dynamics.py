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
world (the model frame). Each moving body has the frame of the child link of the joint that
moves it. The model's link poses are the configuration ``q = 0``. Gravity is ``−9.81 m/s²``
along the model's z unless given.

The algorithms take plain floats (NumPy) or SymPy expressions (object arrays): the symbolic
path, used to write the joint-space equations for the targets that need closed expressions
(small trees), is the same code as the numeric one that the tests check against Pinocchio.
``cyphy solve`` and ``simulate`` use :mod:`cyphy.semantics.articulated` (the same transforms,
the articulated-body algorithm on named definitions, any size).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from cyphy import codes
from cyphy.diagnostics import Span
from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.model.inertia import Inertial, combine, tensor
from cyphy.model.poses import Pose
from cyphy.semantics.equations import AssemblyError

STANDARD_GRAVITY = (0.0, 0.0, -9.81)

TREE = codes.code("E-DYNAMICS", codes.E,
                  "the kinematic tree has no well-defined equations of motion")


class DynamicsError(AssemblyError):
    """Why the model's tree has no equations of motion, at the element to blame (an
    ``AssemblyError``, so every command that assembles equations reports it; ``code`` says
    which diagnostic)."""

    code = TREE


@dataclass(frozen=True)
class TreeJoint:
    """One degree of freedom of the tree.

    ``parent`` is the index of the parent joint's body in ``KinematicTree.joints`` (−1: a body
    fixed to the world); ``placement`` is the child body's frame in the parent body's frame
    (the world's for −1) at ``q = 0``; ``screw`` the joint's screw axis in the child body frame
    (angular part first); ``point`` a point of the axis in the child frame (revolute joints)."""

    name: str  # the joint's qualified name
    prefix: str  # the joint's device prefix (its variables are ``<prefix>_theta`` …)
    kind: str  # "revolute" or "prismatic"
    parent: int
    placement: np.ndarray  # 4x4
    axis: np.ndarray  # unit 3-vector, child body frame
    point: np.ndarray  # 3-vector, child body frame
    screw: np.ndarray  # 6-vector
    inertia: np.ndarray  # 6x6 spatial inertia of the child body about its frame origin
    body: tuple[str, ...]  # the links the joint moves as one body (child link first)
    element: Joint

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


@dataclass(frozen=True)
class KinematicTree:
    """The joints in tree order (parents before children) and the gravity vector."""

    joints: tuple[TreeJoint, ...]
    gravity: np.ndarray

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def prefixes(self) -> tuple[str, ...]:
        return tuple(j.prefix for j in self.joints)

    def __len__(self) -> int:
        return len(self.joints)


# ----------------------------------------------------------------------------- the tree

def joint_kind(joint: Joint) -> str | None:
    """``revolute``, ``prismatic`` or ``fixed`` from the joint's definition (or annotation),
    None for the other families (spherical, universal, …), which have no single axis."""
    names = [joint.definition or ""]
    if joint.annotation is not None:
        names.append(joint.annotation.template[-1])
    for name in names:
        simple = name.split("::")[-1].lower()
        if simple in ("revolute", "continuous", "hinge"):
            return "revolute"
        if simple in ("prismatic", "slider"):
            return "prismatic"
        if simple == "fixed":
            return "fixed"
    return None


def kinematic_tree(model: ElaboratedModel,
                   gravity: Sequence[float] = STANDARD_GRAVITY) -> KinematicTree:
    """The model's kinematic tree, joints in **tree order**: depth first from the bodies fixed
    to the world (in the model's link order), a body's child joints in the order of the
    elaborated model's joint list. This is the order of ``q``, ``M``'s rows and ``h``.

    Raises ``DynamicsError`` for a joint family with more than one degree of freedom, a zero
    axis, a loop (a body moved by two joints, or a cycle), or a link without mass properties
    in a moving body."""
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
                f"joint {joint.name} ({joint.definition}) has more than one degree of freedom",
                joint.span, "the equations of motion support revolute, prismatic and fixed "
                "joints; model a multi-axis joint as a chain of revolute joints")
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
        frame_of[key] = Pose.identity()  # fixed to the world: world coordinates
        for joint in children.get(key, []):
            visit(joint, -1)
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


def _tree_joint(joint: Joint, parent: int, parent_frame: Pose, frame: Pose,
                links: list[Link]) -> TreeJoint:
    axis_value = joint.axis
    if axis_value is None and joint.annotation is not None:
        found = joint.annotation.get("axis")
        axis_value = found.get("xyz") if hasattr(found, "get") else None  # type: ignore
    try:
        axis = np.asarray(axis_value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise DynamicsError(f"joint {joint.name} has no numeric axis", joint.span,
                            "give the joint `instantiation AXIS = (|0, 0, 1|)`") from None
    length = float(np.linalg.norm(axis))
    if not length > 1e-12 or not math.isfinite(length):
        raise DynamicsError(f"joint {joint.name} has an axis of zero length", joint.span,
                            "give the axis a direction, for example (|0, 0, 1|)")
    placement = (joint.child.pose or Pose.identity()).compose(  # type: ignore[union-attr]
        joint.pose) if joint.pose is not None else \
        (joint.parent.pose or Pose.identity()).compose(  # type: ignore[union-attr]
            joint.local_pose or Pose.identity())
    in_child = frame.inverse().compose(placement)
    axis_c = np.array(in_child.rotation) @ (axis / length)
    point = np.array(in_child.position)
    kind = joint_kind(joint) or ""
    screw = np.concatenate([axis_c, np.cross(point, axis_c)]) if kind == "revolute" else \
        np.concatenate([np.zeros(3), axis_c])
    parts: list[Inertial] = []
    to_body = frame.inverse()
    for link in links:
        if link.inertial is None or link.inertial.mass is None:
            raise DynamicsError(
                f"link {link.name} has no mass properties but is moved by joint {joint.name}",
                link.span, "give the link an `inertial information` (mass and inertia) or "
                "bodies with masses")
        com = to_body.compose(link.pose or Pose.identity()).compose(link.inertial.com)
        parts.append(Inertial(link.inertial.mass, com, link.inertial.inertia))
    try:
        body = combine(parts)
    except ValueError:
        raise DynamicsError(f"the body moved by joint {joint.name} has no positive mass",
                            joint.span, "give its links positive masses") from None
    return TreeJoint(joint.name, joint.device.prefix if joint.device else joint.simple_name,
                     kind, -1 if parent < 0 else parent,
                     parent_frame.inverse().compose(frame).matrix(), axis_c, point, screw,
                     spatial_inertia(body.mass, np.array(body.com.position),
                                     tensor(body.inertia)),
                     tuple(link.name for link in links), joint)


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


def _parent_to_child(joint: TreeJoint, q: Any, cos: Any, sin: Any) -> np.ndarray:
    """``[Ad_T]`` of the parent frame's pose in the child frame at joint value ``q``: it
    carries twists from the parent body's frame to the child's (MR eq. 8.47)."""
    base_r, base_p = joint.placement[:3, :3], joint.placement[:3, 3]
    if joint.kind == "revolute":
        r = _rotation(joint.axis, q, cos, sin)  # child frame turned about the axis
        p = (np.eye(3) - r) @ joint.point
    else:
        r = np.eye(3)
        p = joint.axis * q
    # pose of the child frame in the parent frame: placement · (r, p)
    rotation = base_r @ r
    position = base_r @ p + base_p
    inverse_r = rotation.T
    return adjoint(inverse_r, -(inverse_r @ position))


_EYE3 = np.eye(3)


def _numeric_parent_to_child(joint: TreeJoint, q: float) -> np.ndarray:
    """``_parent_to_child`` for a float ``q``, built entry by entry: the recursive algorithms
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

def inverse_dynamics(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any],
                     qdd: Sequence[Any], gravity: bool = True) -> np.ndarray:
    """RNEA: the joint efforts ``τ = M(q)·q̈ + h(q, q̇)`` (tree order), at linear cost."""
    cos, sin, symbolic = _math([*q, *qd, *qdd])
    n = len(tree)
    base = np.concatenate([np.zeros(3), -tree.gravity]) if gravity else np.zeros(6)
    transforms, twists, forces = [], [], []
    accelerations = []
    for i, joint in enumerate(tree.joints):
        x = _parent_to_child(joint, q[i], cos, sin)
        v_parent = twists[joint.parent] if joint.parent >= 0 else np.zeros(6)
        a_parent = accelerations[joint.parent] if joint.parent >= 0 else base
        v = x @ v_parent + joint.screw * qd[i]
        a = x @ a_parent + joint.screw * qdd[i] + ad(v) @ joint.screw * qd[i]
        transforms.append(x)
        twists.append(v)
        accelerations.append(a)
        forces.append(joint.inertia @ a - ad(v).T @ (joint.inertia @ v))
    tau = np.zeros(n, dtype=object if symbolic else float)
    for i in range(n - 1, -1, -1):
        joint = tree.joints[i]
        tau[i] = joint.screw @ forces[i]
        if joint.parent >= 0:
            forces[joint.parent] = forces[joint.parent] + transforms[i].T @ forces[i]
    return tau


def bias_forces(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any]) -> np.ndarray:
    """``h(q, q̇)``: gravity, Coriolis and centrifugal efforts (RNEA with ``q̈ = 0``)."""
    return inverse_dynamics(tree, q, qd, [0.0] * len(tree))


def mass_matrix(tree: KinematicTree, q: Sequence[Any]) -> np.ndarray:
    """CRBA: the joint-space mass matrix ``M(q)`` (symmetric, tree order)."""
    cos, sin, symbolic = _math(list(q))
    n = len(tree)
    transforms = [_parent_to_child(j, q[i], cos, sin) for i, j in enumerate(tree.joints)]
    composite = [j.inertia for j in tree.joints]
    for i in range(n - 1, -1, -1):
        parent = tree.joints[i].parent
        if parent >= 0:
            composite[parent] = composite[parent] + transforms[i].T @ composite[i] @ \
                transforms[i]
    matrix = np.zeros((n, n), dtype=object if symbolic else float)
    for i in range(n):
        force = composite[i] @ tree.joints[i].screw
        matrix[i, i] = tree.joints[i].screw @ force
        j = i
        while tree.joints[j].parent >= 0:
            force = transforms[j].T @ force
            j = tree.joints[j].parent
            matrix[i, j] = matrix[j, i] = tree.joints[j].screw @ force
    return matrix


def forward_dynamics(tree: KinematicTree, q: Sequence[float], qd: Sequence[float],
                     tau: Sequence[float]) -> np.ndarray:
    """ABA: the joint accelerations ``q̈ = M(q)⁻¹(τ − h(q, q̇))`` at linear cost (numeric).

    Raises ``DynamicsError`` at the joint whose articulated inertia along its axis is not
    positive (a massless subtree: the mass matrix is singular)."""
    n = len(tree)
    base = np.concatenate([np.zeros(3), -tree.gravity])
    xs, vs, cs, inertias, biases = [], [], [], [], []
    for i, joint in enumerate(tree.joints):
        x = _numeric_parent_to_child(joint, float(q[i]))
        v = joint.screw * float(qd[i])
        if joint.parent >= 0:
            v = x @ vs[joint.parent] + v
        cross = _ad_numeric(v)
        xs.append(x)
        vs.append(v)
        cs.append(cross @ joint.screw * float(qd[i]))
        inertias.append(joint.inertia.copy())
        biases.append(-(cross.T @ (joint.inertia @ v)))
    us, ds, uu = [None] * n, np.zeros(n), np.zeros(n)
    for i in range(n - 1, -1, -1):
        joint = tree.joints[i]
        u_vec = inertias[i] @ joint.screw
        d = float(joint.screw @ u_vec)
        if not d > 1e-12 * joint.scale:
            raise DynamicsError(f"the mass matrix is singular at joint {joint.name}: nothing "
                                "it moves has inertia along its axis", joint.element.span,
                                "give the links it moves mass and inertia")
        us[i], ds[i] = u_vec, d
        uu[i] = float(tau[i]) - float(joint.screw @ biases[i])
        if joint.parent >= 0:
            articulated = inertias[i] - np.outer(u_vec, u_vec) / d
            bias = biases[i] + articulated @ cs[i] + u_vec * (uu[i] / d)
            inertias[joint.parent] = inertias[joint.parent] + xs[i].T @ articulated @ xs[i]
            biases[joint.parent] = biases[joint.parent] + xs[i].T @ bias
    qdd = np.zeros(n)
    accelerations: list[np.ndarray] = []
    for i, joint in enumerate(tree.joints):
        a_parent = accelerations[joint.parent] if joint.parent >= 0 else base
        a = xs[i] @ a_parent + cs[i]
        qdd[i] = (uu[i] - float(us[i] @ a)) / ds[i]  # type: ignore[operator]
        accelerations.append(a + joint.screw * qdd[i])
    return qdd


def joint_space(model: ElaboratedModel | KinematicTree, q: Sequence[Any], qd: Sequence[Any],
                gravity: Sequence[float] = STANDARD_GRAVITY
                ) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """``(M(q), h(q, q̇), joint names)`` of the model's equations of motion
    ``M(q)·q̈ + h(q, q̇) = τ``, the root fixed to the world.

    **Joint order** (of ``q``, ``q̇``, the rows of ``M`` and ``h``, and the names returned):
    depth first from the bodies fixed to the world, taken in the model's link order, each
    body's child joints in the elaborated model's joint order; fixed connections are not
    joints. Names are the joints' qualified names (``Model::Link::Joint``). Values are SI
    (rad, m, N·m, N); for a revolute joint ``q`` is the rotation about its axis, for a
    prismatic joint the displacement along it, from the configuration the model's poses give.
    """
    tree = model if isinstance(model, KinematicTree) else kinematic_tree(model, gravity)
    return mass_matrix(tree, q), bias_forces(tree, q, qd), tree.names


# ----------------------------------------------------------------------------- model equations

SYMBOLIC_LIMIT = 6
"""The largest tree (in joints) whose joint-space equations ``tau == M(q)*a + h(q, v)`` are
written out as closed expressions, for the targets that need them (CyPhyCircus ``Evolve``,
Isabelle, Flow*): the expressions grow quickly with depth, and SymPy's reduction with them.
``cyphy solve`` and ``cyphy simulate`` take trees of any size, with the explicit
accelerations as named definitions (:mod:`cyphy.semantics.articulated`)."""

_JOINT_PORTS = ("theta", "v", "a", "tau")


def motion_equations(model: ElaboratedModel,
                     gravity: Sequence[float] = STANDARD_GRAVITY) -> list[tuple[Any, TreeJoint]]:
    """The model's equations of motion as equations of the expression AST, one per joint in
    tree order with the joint it belongs to: ``J_tau == Σⱼ M_ij(q)·Jⱼ_a + h_i(q, v)`` in the
    joints' own variables (``physmod::joints``: ``theta``, ``v``, ``a``, ``tau``).

    Empty when the model has no moving joint, or when a joint's definition lacks one of these
    variables (then nothing here can name its motion). Raises ``DynamicsError`` for a tree
    that has no equations of motion, or one larger than ``SYMBOLIC_LIMIT``."""
    import sympy

    from cyphy import expr as ex
    from cyphy.backends.sympy import to_expr  # SymPy to the shared AST (no printer state)

    moving = [j for j in model.joints if j.parent is not None and j.child is not None
              and joint_kind(j) != "fixed"]
    for joint in moving:  # before the tree: a model whose joints cannot say it is left alone
        if joint.device is None or any(joint.device.port(p) is None for p in _JOINT_PORTS):
            return []
    if not moving:
        return []
    tree = kinematic_tree(model, gravity)
    forward_dynamics(tree, [0.0] * len(tree), [0.0] * len(tree), [0.0] * len(tree))  # singular?
    if len(tree) > SYMBOLIC_LIMIT:
        first = tree.joints[0].element
        raise DynamicsError(
            f"the kinematic tree has {len(tree)} joints: its equations of motion are too large "
            f"to write out as closed expressions (at most {SYMBOLIC_LIMIT}), which this "
            "target needs", first.span,
            "`cyphy solve` and `cyphy simulate` take trees of any size (the accelerations as "
            "named definitions); here, restrict the system to fewer joints (--element, "
            "--isabelle-element or the scenario's elements)")

    def port(joint: TreeJoint, name: str) -> str:
        return joint.element.device.port(name).mangled  # type: ignore[union-attr]

    q = [sympy.Symbol(port(j, "theta"), real=True) for j in tree.joints]
    qd = [sympy.Symbol(port(j, "v"), real=True) for j in tree.joints]
    qdd = [sympy.Symbol(port(j, "a"), real=True) for j in tree.joints]
    # One symbolic Newton-Euler pass gives M(q)*a + h(q, v) at once; the composite-body
    # algorithm's products of symbolic transforms swell (34 s for 6 joints, measured).
    efforts = inverse_dynamics(tree, q, qd, qdd)
    out = []
    for i, joint in enumerate(tree.joints):
        rhs = _chop(sympy.expand(efforts[i]))
        span = joint.element.span
        out.append((ex.BinOp("==", ex.Name((port(joint, "tau"),), span=span),
                             to_expr(rhs, decimals=True), span=span), joint))
    return out


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
