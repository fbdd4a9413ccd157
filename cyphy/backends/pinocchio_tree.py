"""A Pinocchio model of an elaborated kinematic tree, for compiled forward dynamics (issue 31).

``cyphy simulate --numeric`` calls the dynamics at every integrator stage: cyphy's
articulated-body algorithm in NumPy costs about 0.5 ms per call at 10 links, Pinocchio's
compiled ``aba`` about 5 µs. The model is built from :class:`KinematicTree` directly (not
through the URDF export, which the oracle tests read), so that the tests comparing against
Pinocchio-from-URDF, MuJoCo and the symbolic path stay independent of this builder.

Frames: Pinocchio turns a revolute joint about an axis through its joint frame's origin, while
the tree puts each body's frame at its child link and the axis through ``point``. Each joint
frame here is the child body frame moved (not turned) to ``point``, so

    joint placement = Trans(−point_parent) · placement · Trans(point),

and the body's inertia sits at ``Trans(−point)`` in its joint frame. Only revolute and
prismatic joints are mapped: the tree's universal joints, ball joints and floating base use
ZYX Euler-angle coordinates (rates as velocities) that Pinocchio's quaternion joints do not
share, so such trees keep the NumPy algorithm (:func:`pinocchio_model` returns ``None``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from cyphy.semantics.dynamics.rigid_body import KinematicTree, TreeJoint

#: The joint kinds mapped to a Pinocchio joint of the same coordinates.
MAPPED = frozenset({"revolute", "prismatic"})


@dataclass(frozen=True)
class CompiledTree:
    """A Pinocchio model of a tree and its data (the work arrays ``aba`` fills)."""

    model: Any
    data: Any

    def forward_dynamics(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """``q̈ = M(q)⁻¹(τ − h(q, q̇))`` (Pinocchio's ABA), coordinates in tree order."""
        import pinocchio

        return pinocchio.aba(self.model, self.data, q, qd, tau)

    def jacobian(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """``∂(q̇, q̈)/∂(q, q̇)``, the state Jacobian a stiff method needs, from Pinocchio's
        analytic ABA derivatives (no finite differences)."""
        import pinocchio

        n = self.model.nv
        pinocchio.computeABADerivatives(self.model, self.data, q, qd, tau)
        out = np.zeros((2 * n, 2 * n))
        out[:n, n:] = np.eye(n)
        out[n:, :n] = self.data.ddq_dq
        out[n:, n:] = self.data.ddq_dv
        return out


def available() -> bool:
    """Whether Pinocchio (the ``pin`` package) can be imported."""
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        return False
    return True


def pinocchio_model(tree: KinematicTree) -> CompiledTree | None:
    """The tree as a Pinocchio model, or ``None`` when Pinocchio is absent or the tree has a
    joint that is not revolute or prismatic (see the module's docstring)."""
    if not tree.joints or any(j.kind not in MAPPED for j in tree.joints) or not available():
        return None
    import pinocchio

    model = pinocchio.Model()
    model.gravity = pinocchio.Motion(np.asarray(tree.gravity, dtype=float), np.zeros(3))
    ids: list[int] = []
    for joint in tree.joints:
        parent_point = tree.joints[joint.parent].point if joint.parent >= 0 else np.zeros(3)
        placement = _translation(-parent_point) @ joint.placement @ _translation(joint.point)
        parent_id = ids[joint.parent] if joint.parent >= 0 else 0
        axis = np.asarray(joint.axis, dtype=float)
        kind = (pinocchio.JointModelRevoluteUnaligned if joint.kind == "revolute"
                else pinocchio.JointModelPrismaticUnaligned)
        index = model.addJoint(parent_id, kind(axis), _se3(placement), joint.name)
        model.appendBodyToJoint(index, _inertia(joint),
                                pinocchio.SE3(np.eye(3), -np.asarray(joint.point, float)))
        ids.append(index)
    return CompiledTree(model, model.createData())


def _translation(p: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = p
    return out


def _se3(matrix: np.ndarray) -> Any:
    import pinocchio

    return pinocchio.SE3(np.asarray(matrix[:3, :3], float), np.asarray(matrix[:3, 3], float))


def _inertia(joint: TreeJoint) -> Any:
    """The body's inertia for Pinocchio (mass, centre of mass, rotational inertia about the
    centre of mass), read back from the tree's 6x6 spatial inertia about the body frame's
    origin ``[[I_c − m[c]², m[c]], [−m[c], m·E]]`` (angular part first)."""
    import pinocchio

    g = np.asarray(joint.inertia, dtype=float)
    mass = float(g[3, 3])
    if mass > 0.0:
        mc = g[:3, 3:]
        com = np.array([mc[2, 1], mc[0, 2], mc[1, 0]]) / mass
    else:
        com = np.zeros(3)
    c = np.array([[0.0, -com[2], com[1]], [com[2], 0.0, -com[0]], [-com[1], com[0], 0.0]])
    rotational = g[:3, :3] + mass * (c @ c)
    return pinocchio.Inertia(mass, com, (rotational + rotational.T) / 2)
