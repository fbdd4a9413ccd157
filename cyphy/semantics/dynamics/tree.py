"""The kinematic tree of an elaborated p-model, as data (issue 16; split from
:mod:`cyphy.semantics.dynamics.rigid_body` for issue 31, as Pinocchio splits its model from
the algorithms' data): its joints in tree order (:class:`TreeJoint`: kind, parent,
placement, axis, screw, spatial inertia) and the names of their coordinates. The algorithms
over it are functions elsewhere (:mod:`cyphy.semantics.dynamics.rigid_body`,
:mod:`cyphy.semantics.dynamics.articulated`, :mod:`cyphy.backends.pinocchio_tree`); this
module imports none of them, nor NumPy: a joint holds the poses and links its numbers come
from, and computes the numbers (:mod:`cyphy.semantics.dynamics.tree_numbers`) when they are
first read, so that the cache of equations of motion is keyed and read without NumPy
(issue 24's start-up budget).

The tree comes from the elaborated model: links joined by fixed connections (and by joints of
the ``Fixed`` family) are merged into one body; a body that no joint moves is fixed to the
world (the model frame), or with ``floating_base`` free (six coordinates: translations along
the world axes and ZYX Euler angles). Each moving body has the frame of the child link of the
joint that moves it. The model's link poses are the configuration ``q = 0``. Gravity is
``−9.81 m/s²`` along the model's z unless given. Joints have one coordinate (revolute,
prismatic) or several (universal: two angles; ball: ZYX Euler angles, singular at pitch
±π/2).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.model.poses import Pose
from cyphy.model.roots import preferred_root
from cyphy.records import record
from cyphy.semantics.dynamics.errors import DynamicsError

if TYPE_CHECKING:
    import numpy as np

    from cyphy.semantics.dynamics.tree_numbers import JointNumbers

STANDARD_GRAVITY = (0.0, 0.0, -9.81)


def _number(name: str, doc: str) -> Any:
    """A tree joint's property read from its numbers (:meth:`TreeJoint.numbers`)."""
    return property(lambda joint: getattr(joint.numbers(), name), doc=doc)


@record(frozen=True, slots=False)
class TreeJoint:
    """One joint of the tree, with its ``dof`` coordinates (:data:`DOF`): its place in the
    tree and the poses and links it is built from, as the model gives them (pure Python:
    this is what the cache of equations of motion is keyed on, without NumPy), and its
    numbers as properties, computed with NumPy from those on first use
    (:mod:`cyphy.semantics.dynamics.tree_numbers`, which also raises the errors the numbers
    can have: an axis that is not numeric or of zero length, a body without mass).

    ``parent`` is the index of the parent joint's body in ``KinematicTree.joints`` (−1: a body
    fixed to the world); ``body_pose`` and ``parent_pose`` are the child and parent bodies'
    frames in the world at ``q = 0`` (the parent's is the identity for −1); ``joint_pose`` the
    joint's frame in the child body's frame (None for the floating base). The numbers:
    ``placement`` is the child body's frame in the parent body's frame (the world's for −1) at
    ``q = 0``; ``screw`` the joint's screw axis in the child body frame (angular part first;
    for a joint of several coordinates its first column at ``q = 0``); ``point`` the joint's
    origin (a point of a revolute axis) in the child frame; ``frame`` the joint frame's axes in
    the child frame (the columns: a ball joint's and the floating base's Euler angles turn
    about them); ``axes`` a universal joint's two unit axes in the child frame. The floating
    base (``kind`` ``floating``, ``--floating-base``) is the joint of a root body to the world:
    its frame has the world's axes and its origin is the body's."""

    name: str  # the joint's qualified name (the root link's name for the floating base)
    prefix: str  # the joint's device prefix (its variables are ``<prefix>_theta`` …)
    kind: str  # revolute, prismatic, universal, spherical or floating
    parent: int
    links: tuple[Link, ...]  # the links the joint moves as one body (child link first)
    element: Joint | Link  # what a diagnostic points at (the root link: floating base)
    body_pose: Pose  # the child body's frame in the world, q = 0
    parent_pose: Pose  # the parent body's frame in the world (identity: the world)
    joint_pose: Pose | None = None  # the joint's frame in the child body's frame

    @property
    def body(self) -> tuple[str, ...]:
        """The names of the links the joint moves as one body (child link first)."""
        return tuple(link.name for link in self.links)

    @property
    def dof(self) -> int:
        """How many coordinates the joint has (:data:`DOF`)."""
        return DOF[self.kind]

    def numbers(self) -> JointNumbers:
        """The joint's numbers (NumPy), computed once; ``DynamicsError`` when they cannot be
        (see :func:`cyphy.semantics.dynamics.tree_numbers.joint_numbers`)."""
        cached = self.__dict__.get("_numbers")
        if cached is None:
            # lazy: NumPy (0.1 s to import): a tree whose equations of motion are cached is
            # built and keyed without it
            from cyphy.semantics.dynamics.tree_numbers import joint_numbers  # lazy: see above

            cached = joint_numbers(self.kind, self.element, self.links, self.body_pose,
                                   self.parent_pose, self.joint_pose)
            object.__setattr__(self, "_numbers", cached)
        return cached

    placement = _number("placement", "4x4: the child body's frame in the parent body's, q = 0")
    axis = _number("axis", "unit 3-vector, child body frame")
    point = _number("point", "3-vector, child body frame")
    screw = _number("screw", "6-vector")
    inertia = _number("inertia", "6x6 spatial inertia of the child body about its frame origin")
    frame = _number("frame", "3x3, child body frame")
    axes = _number("axes", "universal: AXIS1, AXIS2 in the child body frame")

    @property
    def scale(self) -> float:
        """The largest entry of the body's spatial inertia: what "zero" inertia along the axis
        is measured against."""
        cached = self.__dict__.get("_scale")
        if cached is None:
            cached = max(float(abs(self.inertia).max()), 1e-300)
            object.__setattr__(self, "_scale", cached)
        return cached

    @property
    def turn(self) -> np.ndarray:
        """``[a]`` of the axis (Rodrigues' formula), computed once."""
        cached = self.__dict__.get("_turn")
        if cached is None:
            # lazy: NumPy, as numbers() (the module is loaded by then)
            from cyphy.semantics.dynamics.tree_numbers import skew

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


@record(frozen=True, slots=False)
class KinematicTree:
    """The joints in tree order (parents before children) and the gravity vector. ``q``,
    ``q̇``, ``τ`` and the rows of ``M`` and ``h`` hold each joint's ``dof`` coordinates in
    this order (``offsets``)."""

    joints: tuple[TreeJoint, ...]
    gravity: tuple[float, ...]  # m/s², the model frame's axes

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
                   floating_base: bool = False, numeric: bool = True) -> KinematicTree:
    """The model's kinematic tree, joints in **tree order**: depth first from the root bodies
    (those no joint moves, in the model's link order), a body's child joints in the order of
    the elaborated model's joint list. This is the order of ``q``, ``M``'s rows and ``h``.

    The root bodies are fixed to the world, or, with ``floating_base``, each moved by a
    floating joint (six coordinates, first in its subtree) named after its root link and in
    that link's frame: of the links fixed together, the one a user expects
    (:func:`~cyphy.model.roots.preferred_root`; the palm of a hand whose fingers' roots are
    ``fixed to`` it, as ``gen --mjcf`` roots the tree there).

    Raises ``DynamicsError`` for a joint family the equations do not cover, a zero axis, a
    loop (a body moved by two joints, or a cycle), or a link without mass properties in a
    moving body: the first in tree order. ``numeric=False`` builds the tree without its
    numbers (no NumPy): they, and their errors, come when first read, and a loop is then
    reported before the numbers of the joints visited ahead of it."""
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
    fixed_children = {id(c.child) for c in [*model.fixed, *model.joints]
                      if c.child is not None and (isinstance(c, FixedJoint)
                                                  or joint_kind(c) == "fixed")}
    order = {id(link): i for i, link in enumerate(links)}
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
        ordered.append(_tree_joint(joint, parent, parent_frame, frame, members[key], numeric))
        body_index[key] = len(ordered) - 1
        frame_of[key] = frame
        for sub in children.get(key, []):
            visit(sub, body_index[key])

    for link in links:
        key = find(link.name)
        if key in incoming or key in frame_of or key in body_index:
            continue
        parent = -1
        if floating_base:  # the body's frame is its root link's, the one a user expects
            root = preferred_root(members[key], fixed_children, order)
            frame_of[key] = root.pose or Pose.identity()
            ordered.append(_with_numbers(TreeJoint(
                root.name, root.qname[-1], "floating", -1, tuple(members[key]), root,
                frame_of[key], Pose.identity()), numeric))
            parent = body_index[key] = len(ordered) - 1
        else:
            frame_of[key] = Pose.identity()  # fixed to the world: world coordinates
        for joint in children.get(key, []):
            visit(joint, parent)
    for joint in moving:
        if find(joint.child.name) not in body_index:  # type: ignore[union-attr]
            raise _loop(joint)  # a cycle of joints that no world-fixed body reaches
    return KinematicTree(tuple(ordered), tuple(float(g) for g in gravity))


def _loop(element: Joint | FixedJoint) -> DynamicsError:
    return DynamicsError(
        f"{element.name} closes a kinematic loop: {element.child.name} is already "  # type: ignore
        f"connected to {element.parent.name}", element.span,  # type: ignore[union-attr]
        "closed chains are not supported: remove one connection of the loop (each link may "
        "have one parent)")


def _tree_joint(joint: Joint, parent: int, parent_frame: Pose, frame: Pose,
                links: list[Link], numeric: bool) -> TreeJoint:
    """The tree joint of ``joint``, whose child body (``links``) has the frame ``frame`` and
    its parent body ``parent_frame``, both in the world at ``q = 0``."""
    placement = (joint.child.pose or Pose.identity()).compose(  # type: ignore[union-attr]
        joint.pose) if joint.pose is not None else \
        (joint.parent.pose or Pose.identity()).compose(  # type: ignore[union-attr]
            joint.local_pose or Pose.identity())
    return _with_numbers(TreeJoint(
        joint.name, joint.device.prefix if joint.device else joint.simple_name,
        joint_kind(joint) or "", -1 if parent < 0 else parent, tuple(links), joint, frame,
        parent_frame, frame.inverse().compose(placement)), numeric)


def _with_numbers(joint: TreeJoint, numeric: bool) -> TreeJoint:
    """``joint``, its numbers computed now when ``numeric`` (their errors raised in tree
    order, as the tree is built)."""
    if numeric:
        joint.numbers()
    return joint
