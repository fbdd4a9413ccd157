"""A Pinocchio model of an elaborated kinematic tree, for compiled forward dynamics (issue 31).

``cyphy simulate --numeric`` calls the dynamics at every integrator stage: cyphy's
articulated-body algorithm in NumPy costs about 0.5 ms per call at 10 links, Pinocchio's
compiled ``aba`` about 5 µs. The model is built from :class:`KinematicTree` directly (not
through the URDF export, which the oracle tests read), so that the tests comparing against
Pinocchio-from-URDF, MuJoCo and the symbolic path stay independent of this builder.

Frames: Pinocchio turns a joint about its joint frame's origin and axes, while the tree puts
each body's frame at its child link, the joint's origin at ``point`` and a ball joint's Euler
axes (and the floating base's world axes) in ``frame``. Each joint frame here is the child
body frame moved to ``point`` and, for ball joints and the floating base, turned to ``frame``:
``offset = (frame, point)``, so

    joint placement = offset_parent⁻¹ · placement · offset,

and the body's inertia sits at ``offset⁻¹`` in its joint frame. Revolute, prismatic and
universal joints map to Pinocchio's joints of the same axes; a ball joint to
``JointModelSphericalZYX`` (the tree's ZYX Euler angles, the velocities their rates, as
Pinocchio's); the floating base to a translation along the world axes then a ZYX joint, with
a massless body between. Every one has as many velocities as coordinates, in the tree's order.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from cyphy.semantics.dynamics.tree import KinematicTree, TreeJoint


@dataclass(frozen=True)
class CompiledTree:
    """A Pinocchio model of a tree and its data (the work arrays ``aba`` fills)."""

    model: Any
    data: Any
    #: Whether :meth:`jacobian` is exact: Pinocchio's ABA derivatives take each joint's motion
    #: subspace as constant in its frame, which the universal and ZYX joints' are not (their
    #: columns turn with q), so a tree with them has no analytic Jacobian here.
    derivatives: bool = True

    def forward_dynamics(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """``q̈ = M(q)⁻¹(τ − h(q, q̇))`` (Pinocchio's ABA), coordinates in tree order."""
        # lazy: Pinocchio is optional and slow to import (C++ bindings); only the tree path uses it
        import pinocchio

        return pinocchio.aba(self.model, self.data, q, qd, tau)

    def jacobian(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """``∂(q̇, q̈)/∂(q, q̇)``, the state Jacobian a stiff method needs, from Pinocchio's
        analytic ABA derivatives (no finite differences)."""
        import pinocchio  # lazy: Pinocchio is optional and slow to import (see forward_dynamics)

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
        import pinocchio  # lazy: probes whether the optional Pinocchio is installed
    except ImportError:
        return False
    return True


def pinocchio_model(tree: KinematicTree) -> CompiledTree | None:
    """The tree as a Pinocchio model (see the module's docstring), or ``None`` when Pinocchio
    is absent or the tree is empty."""
    if not tree.joints or not available():
        return None
    import pinocchio  # lazy: Pinocchio is optional and slow to import (see forward_dynamics)

    model = pinocchio.Model()
    model.gravity = pinocchio.Motion(np.asarray(tree.gravity, dtype=float), np.zeros(3))
    ids: list[int] = []
    offsets = [_offset(joint) for joint in tree.joints]
    for joint, offset in zip(tree.joints, offsets):
        parent_offset = offsets[joint.parent] if joint.parent >= 0 else np.eye(4)
        placement = _se3(np.linalg.inv(parent_offset) @ joint.placement @ offset)
        parent_id = ids[joint.parent] if joint.parent >= 0 else 0
        if joint.kind == "floating":
            parent_id = model.addJoint(parent_id, pinocchio.JointModelTranslation(),
                                       placement, f"{joint.name}_translation")
            placement = pinocchio.SE3.Identity()
        index = model.addJoint(parent_id, _joint_model(joint), placement, joint.name)
        model.appendBodyToJoint(index, _inertia(joint), _se3(np.linalg.inv(offset)))
        ids.append(index)
    if model.nq != tree.dof or model.nv != tree.dof:  # a joint kind this module does not know
        return None
    constant_subspaces = all(j.kind in ("revolute", "prismatic") for j in tree.joints)
    return CompiledTree(model, model.createData(), constant_subspaces)


def _offset(joint: TreeJoint) -> np.ndarray:
    """The joint frame in the child body frame: at ``point``, with the axes of ``frame`` for
    the joints whose Euler angles turn about them, else the body's."""
    out = np.eye(4)
    if joint.kind in ("spherical", "floating"):
        out[:3, :3] = joint.frame
    out[:3, 3] = joint.point
    return out


def _joint_model(joint: TreeJoint) -> Any:
    import pinocchio  # lazy: Pinocchio is optional and slow to import (see forward_dynamics)

    axis = np.asarray(joint.axis, dtype=float)
    if joint.kind == "revolute":
        return pinocchio.JointModelRevoluteUnaligned(axis)
    if joint.kind == "prismatic":
        return pinocchio.JointModelPrismaticUnaligned(axis)
    if joint.kind == "universal":
        first, second = (np.asarray(a, dtype=float) for a in joint.axes)
        return pinocchio.JointModelUniversal(first, second)
    return pinocchio.JointModelSphericalZYX()  # spherical, and the floating base's turn


def _se3(matrix: np.ndarray) -> Any:
    import pinocchio  # lazy: Pinocchio is optional and slow to import (see forward_dynamics)

    return pinocchio.SE3(np.asarray(matrix[:3, :3], float), np.asarray(matrix[:3, 3], float))


def _inertia(joint: TreeJoint) -> Any:
    """The body's inertia for Pinocchio (mass, centre of mass, rotational inertia about the
    centre of mass), read back from the tree's 6x6 spatial inertia about the body frame's
    origin ``[[I_c − m[c]², m[c]], [−m[c], m·E]]`` (angular part first)."""
    import pinocchio  # lazy: Pinocchio is optional and slow to import (see forward_dynamics)

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
