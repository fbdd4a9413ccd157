"""Spatial algebra over a kinematic tree's joints (issue 16; split from
:mod:`cyphy.semantics.dynamics.rigid_body` for issue 31), after Lynch and Park, *Modern
Robotics* ch. 8: twists and wrenches are 6-vectors with the angular part first (the
convention of ``physmod::joints``), ``X`` the Adjoint that carries a parent's twist into the
child frame. Each joint has a motion subspace ``S(q)`` in the child frame and its rate
``Ṡ·q̇`` (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 4). The functions take
plain floats (NumPy) or SymPy expressions: the numeric and symbolic algorithms share them.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from cyphy.semantics.dynamics.errors import DynamicsError
from cyphy.semantics.dynamics.tree import EULER, KinematicTree, TreeJoint
from cyphy.semantics.dynamics.tree_numbers import skew


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


def numeric_parent_to_child(joint: TreeJoint, q: float) -> np.ndarray:
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


def ad_numeric(twist: np.ndarray) -> np.ndarray:
    """``ad(V)`` of a float twist in one array construction."""
    a, b, c, d, e, f = twist.tolist()
    return np.array([[0.0, -c, b, 0.0, 0.0, 0.0], [c, 0.0, -a, 0.0, 0.0, 0.0],
                     [-b, a, 0.0, 0.0, 0.0, 0.0], [0.0, -f, e, 0.0, -c, b],
                     [f, 0.0, -d, c, 0.0, -a], [-e, d, 0.0, -b, a, 0.0]])


def math_functions(values: Sequence[Any]) -> tuple[Any, Any, bool]:
    """``cos`` and ``sin`` for the scalars given, and whether they are symbolic."""
    if any(not isinstance(v, (int, float, np.floating, np.integer)) for v in values):
        import sympy  # lazy: SymPy (0.5-1 s); only symbolic arguments need it

        return sympy.cos, sympy.sin, True
    return np.cos, np.sin, False
