"""The numbers of one joint of a kinematic tree (:class:`~cyphy.semantics.dynamics.tree.TreeJoint`),
computed with NumPy from the poses and links the tree holds: its placement, axis, screw,
joint frame and the spatial inertia of the body it moves.

The tree (:mod:`cyphy.semantics.dynamics.tree`) is data built without NumPy, so that a run
whose equations of motion are cached (:mod:`cyphy.semantics.dynamics.motion_cache`) never
imports it; the algorithms read these numbers through the tree joint's properties, which
import this module on first use. It does not import the tree (the tree imports it).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from cyphy.model.elements import Joint, Link
from cyphy.model.inertia import Inertial, combine, tensor
from cyphy.model.poses import Pose
from cyphy.records import record
from cyphy.semantics.dynamics.errors import DynamicsError


@record(frozen=True, eq=False)  # arrays: compared by no one
class JointNumbers:
    """A tree joint's numbers (see :class:`~cyphy.semantics.dynamics.tree.TreeJoint`)."""

    placement: np.ndarray  # 4x4
    axis: np.ndarray  # unit 3-vector, child body frame
    point: np.ndarray  # 3-vector, child body frame
    screw: np.ndarray  # 6-vector
    inertia: np.ndarray  # 6x6 spatial inertia of the child body about its frame origin
    frame: np.ndarray  # 3x3, child body frame
    axes: tuple[np.ndarray, ...]  # universal: AXIS1, AXIS2 in the child body frame


def joint_numbers(kind: str, element: Joint | Link, links: Sequence[Link], body_pose: Pose,
                  parent_pose: Pose, joint_pose: Pose | None) -> JointNumbers:
    """The numbers of a joint of ``kind`` moving ``links`` (the body whose frame is
    ``body_pose``, its parent body's ``parent_pose``, both in the world at ``q = 0``), its
    frame being ``joint_pose`` in the body's (None: the floating base of a root body, whose
    joint frame has the world's axes and the body's origin). Raises ``DynamicsError`` for an
    axis that is not numeric or of zero length, parallel axes of a universal joint, a link
    without mass properties, a body without positive mass (in that order)."""
    if joint_pose is None:
        world_axes = np.array(body_pose.rotation, dtype=float).T
        inertia = _body_inertia(element, "the floating base", body_pose, links)
        screw = np.concatenate([np.zeros(3), world_axes[:, 0]])
        return JointNumbers(body_pose.matrix(), world_axes[:, 0], np.zeros(3), screw, inertia,
                            world_axes, ())
    joint: Joint = element  # type: ignore[assignment]
    rotation = np.array(joint_pose.rotation, dtype=float)
    point = np.array(joint_pose.position, dtype=float)
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
    inertia = _body_inertia(joint, f"joint {joint.name}", body_pose, links)
    return JointNumbers(parent_pose.inverse().compose(body_pose).matrix(), axis_c, point,
                        screw, inertia, rotation, axes)


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
                  links: Sequence[Link]) -> np.ndarray:
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


def spatial_inertia(mass: float, com: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """The 6x6 spatial inertia about a frame's origin of a body with ``mass``, centre of mass
    ``com`` and rotational ``inertia`` about the centre of mass, both in the frame's axes
    (MR eq. 8.32 moved to the origin: ``[[I − m[c]², m[c]], [−m[c], m·E]]``)."""
    c = skew(com)
    top = np.hstack([inertia - mass * (c @ c), mass * c])
    bottom = np.hstack([-mass * c, mass * np.eye(3)])
    return np.vstack([top, bottom])


def skew(v: Any) -> np.ndarray:
    """``[v]``, the matrix of ``v ×``."""
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
