"""Rigid-body dynamics over a kinematic tree (:mod:`cyphy.semantics.dynamics.tree`, the data;
:mod:`cyphy.semantics.dynamics.spatial`, the algebra): the joint-space equations of motion
``M(q)·q̈ + h(q, q̇) = τ`` (issue 16), with the recursive algorithms of Featherstone, *Rigid
Body Dynamics Algorithms* (2008):

- the recursive Newton–Euler algorithm (RNEA, ch. 5) for inverse dynamics and the bias forces
  ``h(q, q̇)`` (gravity, Coriolis and centrifugal terms, the velocity-product term
  ``ad(V)·A·θ̇`` included),
- the composite-rigid-body algorithm (CRBA, ch. 6) for the mass matrix ``M(q)``,
- the articulated-body algorithm (ABA, ch. 7) for forward dynamics at linear cost.

The algorithms take plain floats (NumPy) or SymPy expressions (object arrays): the symbolic
path, used to write the joint-space equations for the targets that need closed expressions
(small trees, :mod:`cyphy.semantics.dynamics.motion`), is the same code as the numeric one
that the tests check against Pinocchio.
``cyphy solve`` and ``simulate`` use :mod:`cyphy.semantics.dynamics.articulated` (the same transforms,
the articulated-body algorithm on named definitions, any size).

The tree's and the algebra's names are imported here from their modules (where the
algorithms use them), and callers may still reach them here.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.dynamics.errors import DynamicsError
from cyphy.semantics.dynamics.spatial import (ad, ad_numeric, euler_singularity, math_functions,
                                              motion_subspace, motion_subspace_rate,
                                              numeric_parent_to_child, parent_to_child,
                                              subspace_factors)
from cyphy.semantics.dynamics.tree import (EULER, STANDARD_GRAVITY, KinematicTree,  # noqa: F401
                                           TreeJoint, coordinate_names, joint_kind,
                                           kinematic_tree)


# ----------------------------------------------------------------------------- algorithms

def _coordinates(joint: TreeJoint, start: int, values: Sequence[Any]) -> Any:
    """The joint's coordinates in ``values``: a scalar for one, a list for several."""
    return values[start] if joint.dof == 1 else list(values[start:start + joint.dof])


def inverse_dynamics(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any],
                     qdd: Sequence[Any], gravity: bool = True) -> np.ndarray:
    """RNEA: the joint efforts ``τ = M(q)·q̈ + h(q, q̇)`` (tree order), at linear cost."""
    cos, sin, symbolic = math_functions([*q, *qd, *qdd])
    base = np.concatenate([np.zeros(3), -np.asarray(tree.gravity, dtype=float)]) \
        if gravity else np.zeros(6)
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
    cos, sin, symbolic = math_functions(list(q))
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
    base = np.concatenate([np.zeros(3), -np.asarray(tree.gravity, dtype=float)])
    xs, vs, cs, inertias, biases, subspaces = [], [], [], [], [], []
    factors: dict[int, np.ndarray] = {}  # B⁻¹ of a joint of several coordinates
    for i, joint in enumerate(tree.joints):
        k = offsets[i]
        if joint.dof == 1:
            x = numeric_parent_to_child(joint, float(q[k]))
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
        cross = ad_numeric(v)
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
