"""Explicit joint accelerations of a kinematic tree as a linear-size sequence of named
definitions: the articulated-body algorithm (Featherstone, *Rigid Body Dynamics Algorithms*,
2008, ch. 7, Table 7.1) run on symbols, in the conventions of :mod:`cyphy.semantics.dynamics.rigid_body`
(Lynch and Park, *Modern Robotics* ch. 8: twists and wrenches angular part first, ``X`` the
Adjoint that carries the parent's twists into the child frame), with the same transforms
(``dynamics.parent_to_child``).

Why named definitions: written as one expression, ``q̈ = M(q)⁻¹(τ − h(q, q̇))`` grows
exponentially with the depth of the tree, and SymPy's reduction with it (2.1-2.4 s for a
7-link chain, measured; larger trees were refused). Here every intermediate quantity of the
algorithm is a name of its own, defined once from the joint variables and the names before
it: about a hundred short definitions per link, derived in time linear in the number of
links. The arithmetic is a small polynomial type (:class:`Polynomial`), not SymPy's, whose
canonicalisation of every product cost 20 s for a 10-link arm (measured). Per joint, with
``p`` its device prefix (``physmod::joints``: ``p_theta``, ``p_v``, ``p_tau``, ``p_a``) and
``k`` a component (1…6, angular first):

- ``p_V_k``      the body's twist ``V = X·V_parent + S·v`` (pass 1),
- ``p_c_k``      the velocity-product acceleration ``ad(V)·S·v``,
- ``p_IA_j_k``   the articulated inertia ``IA = G + Σ_children Xᵀ·Ia·X`` (symmetric, j ≤ k),
- ``p_pB_k``     the articulated bias wrench ``pB = −ad(V)ᵀ·G·V + Σ_children Xᵀ·pa``,
- ``p_U_k``      ``U = IA·S``, ``p_D`` ``D = Sᵀ·U``, ``p_u`` ``u = τ − Sᵀ·pB``,
- ``p_Ia_j_k``   ``Ia = IA − U·Uᵀ/D`` and ``p_pa_k`` ``pa = pB + Ia·c + U·u/D`` (pass 2),
- ``p_IX_j_k``   ``Ia·X`` (on the way to the parent's ``Xᵀ·Ia·X``),
- ``p_ap_k``     ``a' = X·a_parent + c`` (the root's parent accelerates at ``−g``),
- ``p_qdd``      ``q̈ = (u − Uᵀ·a')/D``, and ``p_dV_k`` ``dV = a' + S·q̈`` (pass 3).

Numbers (zeros, constants) are never named: a quantity's component that has no definition is
a number written where it is used. The recursion is written over the joint's motion
subspace ``S`` (6×nᵢ, :func:`joint_subspace`): the screw axis of a revolute or prismatic
joint as one column of numbers; for a joint of several coordinates (universal, ball, the
floating base: ``dynamics.DOF``) ``S(q)`` depends on the coordinates, its entries named
``p_S_k_c``, and the twist gains the rate of the subspace ``Ṡ·q̇`` (``p_Sdq_k``, in ``c``).
Such a joint has ``p_U_k_c``, ``p_D_a_b`` (symmetric, a ≤ b), ``D⁻¹`` by its LDLᵀ
factorisation (``p_Dd_k``, ``p_L_a_b``, ``p_Li_a_b``, ``p_Dinv_a_b``), ``p_u_a`` and
``p_qdd_a``. A ball joint or floating base runs the recursion in the rates ``w = B·q̇`` of
``S(q) = S0·B(q)`` (its angular velocity, ``p_S0_k_c``), whose ``D`` has no singularity, and
turns ``p_w_a`` into ``p_qdd_a = B⁻¹·w`` (``1/cos(pitch)`` as ``1/p_cp``), the only loss of
accuracy near pitch ±π/2 being the Euler rates' own. Its coordinates are named as
``cyphy solve`` names a vector's components (``Wrist_theta_1``; a floating base's
``<Root>_x`` … and rates ``<Root>_vx`` …, :func:`cyphy.semantics.dynamics.rigid_body.coordinate_names`,
with no effort: nothing drives it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.dynamics.errors import DynamicsError
from cyphy.semantics.dynamics.joint_forces import AxisForces, axis_forces, passive_efforts
from cyphy.semantics.dynamics.motion import port_size
from cyphy.semantics.dynamics.polynomial import Polynomial, _cos, _dot, _sin, _single
from cyphy.semantics.dynamics.rigid_body import forward_dynamics, mass_matrix
from cyphy.semantics.dynamics.spatial import (motion_subspace, motion_subspace_rate,
                                              parent_to_child, subspace_factors)
from cyphy.semantics.dynamics.tree import (EULER, STANDARD_GRAVITY, KinematicTree, TreeJoint,
                                           coordinate_names, joint_kind, kinematic_tree)
from cyphy.semantics.scalarise.shapes import component_name


@dataclass(frozen=True)
class Definition:
    """``name = value``: ``value`` a polynomial in the joint variables, their cosines and
    sines, the joint efforts and the definitions before it (and their reciprocals);
    ``joint`` the joint (body) whose link the quantity belongs to."""

    name: str
    value: "Polynomial"
    joint: TreeJoint


@dataclass(frozen=True)
class Stop:
    """A bounded coordinate's limit effort ``name`` (a variable the definitions use, which
    :func:`cyphy.semantics.dynamics.joint_forces.stop_expr` defines): the coordinate's and
    its rate's names, its bounds, and the joint's inertia at rest along it."""

    name: str
    joint: TreeJoint
    position: str
    rate: str
    forces: AxisForces
    inertia: float


@dataclass(frozen=True)
class ExplicitMotion:
    """The definitions in order, per joint (tree order) the names of its accelerations
    (``p_qdd``: one per coordinate), and the limit stops the efforts include."""

    definitions: tuple[Definition, ...]
    accelerations: tuple[tuple[TreeJoint, tuple[str, ...]], ...]
    stops: tuple[Stop, ...] = ()


def subspace(joint: TreeJoint) -> np.ndarray:
    """The joint's motion subspace ``S`` (6×n, child frame): its screw axis as one column,
    without the float noise of the frames (``1.8e-16`` where a rotated axis has a zero)."""
    s = np.asarray(joint.screw, dtype=float).reshape(6, 1)
    return np.where(np.abs(s) < 1e-12 * max(float(np.abs(s).max()), 1e-300), 0.0, s)


class _Namer:
    """Collects definitions; a value that is a number is used as it is (so a component
    that is not defined is a number: zero for a twist's)."""

    def __init__(self) -> None:
        self.definitions: list[tuple[str, Polynomial, TreeJoint]] = []

    def __call__(self, name: str, value: Any, joint: TreeJoint, always: bool = False) -> Any:
        value = Polynomial.lift(value)
        if not always and value.is_number():
            return value
        self.definitions.append((name, value, joint))
        return Polynomial.atom(name)


def _matvec(m: Any, v: Sequence[Any]) -> list[Any]:
    return [_dot(m[i], v) for i in range(len(m))]


def _tmatvec(m: Any, v: Sequence[Any]) -> list[Any]:
    """``mᵀ·v``."""
    return [_dot([m[k][j] for k in range(len(m))], v) for j in range(len(m[0]))]


def _cross(a: Sequence[Any], b: Sequence[Any]) -> list[Any]:
    return [_dot([a[1], -a[2]], [b[2], b[1]]),
            _dot([a[2], -a[0]], [b[0], b[2]]),
            _dot([a[0], -a[1]], [b[1], b[0]])]


def _cross_motion(v: Sequence[Any], w: Sequence[Any]) -> list[Any]:
    """``ad(v)·w`` for twists (angular first): ``(ω×ω', ω×v' + v×ω')``."""
    top = _cross(v[:3], w[:3])
    bottom = [x + y for x, y in zip(_cross(v[:3], w[3:]), _cross(v[3:], w[:3]))]
    return top + bottom


def _cross_force(v: Sequence[Any], f: Sequence[Any]) -> list[Any]:
    """``−ad(v)ᵀ·f`` for a twist ``v`` and a wrench ``f`` (angular first):
    ``(ω×m + v×f_lin, ω×f_lin)``."""
    top = [x + y for x, y in zip(_cross(v[:3], f[:3]), _cross(v[3:], f[3:]))]
    return top + _cross(v[:3], f[3:])


def explicit_motion(tree: KinematicTree, variables: Callable[[TreeJoint, str], Any],
                    annotated: bool = False) -> ExplicitMotion:
    """The articulated-body algorithm on symbols: ``variables(joint, port)`` names a joint's
    ``theta``, ``v`` or ``tau`` (a list of names for a joint of several coordinates; an
    empty ``tau`` list: no effort, as for a floating base). Cost and size linear in the
    number of joints (a bounded number of short definitions per link). With ``annotated``,
    each coordinate's effort also has the damping and spring of its joint's annotation and,
    for a bounded one, its limit stop (a name, ``<coordinate>_stop``, listed in ``stops``:
    :mod:`cyphy.semantics.dynamics.joint_forces`)."""
    name = _Namer()
    n = len(tree)
    stops: list[Stop] = []
    at_rest = _rest_inertia(tree) if annotated else None  # for the stops' stiffness

    def coordinates(joint: TreeJoint, port: str) -> list[Polynomial]:
        found = variables(joint, port)
        names = [found] if isinstance(found, str) else list(found)
        if port == "tau" and not names:
            return [Polynomial()] * joint.dof
        assert len(names) == joint.dof, f"{joint.name}: {joint.dof} coordinates, {names}"
        return [Polynomial.atom(x) for x in names]

    # Pass 1: root to leaves, subspaces, twists and velocity-product accelerations
    xs: list[list[list[Any]]] = []
    subspaces: list[list[list[Any]]] = []  # S, 6 rows of dof columns
    twists: list[list[Any]] = []
    products: list[list[Any]] = []  # c = ad(V)·S·q̇ (+ Ṡ·q̇)
    factors: dict[int, tuple[list[list[Any]], list[list[Any]]]] = {}  # (S0, B⁻¹)
    for i, joint in enumerate(tree.joints):
        p = joint.prefix
        q = coordinates(joint, "theta")
        qd = coordinates(joint, "v")
        raw = parent_to_child(joint, q[0] if len(q) == 1 else q, _cos, _sin)
        xs.append([[_clean(raw[r, k]) for k in range(6)] for r in range(6)])
        s, rate = joint_subspace(joint, q, qd, name)
        subspaces.append(s)
        motion = [_dot(s[r], qd) for r in range(6)]
        v = _matvec(xs[i], twists[joint.parent]) if joint.parent >= 0 else [0.0] * 6
        v = [name(f"{p}_V_{k + 1}", v[k] + motion[k], joint) for k in range(6)]
        twists.append(v)
        c = _cross_motion(v, motion)
        products.append([name(f"{p}_c_{k + 1}", c[k] + rate[k], joint) for k in range(6)])
        if joint.kind in EULER:
            factors[i] = _euler_factors(joint, q, name)

    # Pass 2: leaves to root; a child's articulated inertia and bias are added to its
    # parent's once the child is complete (tree order puts every child after its parent)
    extra_inertia: list[list[list[Any]]] = [[[0.0] * 6 for _ in range(6)] for _ in range(n)]
    extra_bias: list[list[Any]] = [[0.0] * 6 for _ in range(n)]
    us: list[Any] = [None] * n
    d_invs: list[Any] = [None] * n
    efforts: list[Any] = [None] * n
    for i in range(n - 1, -1, -1):
        joint = tree.joints[i]
        p, s = joint.prefix, factors[i][0] if i in factors else subspaces[i]
        columns = joint.dof
        column = [[s[k][c] for k in range(6)] for c in range(columns)]
        scale = 1e-14 * float(np.abs(joint.inertia).max())  # float noise of the frames
        g = [[float(x) if abs(x) >= scale else 0.0 for x in row] for row in joint.inertia]
        bias = _cross_force(twists[i], _matvec(g, twists[i]))
        ia: list[list[Any]] = [[None] * 6 for _ in range(6)]
        for r in range(6):
            for k in range(r, 6):
                ia[r][k] = ia[k][r] = name(f"{p}_IA_{r + 1}_{k + 1}",
                                           extra_inertia[i][r][k] + g[r][k], joint)
        pa = [name(f"{p}_pB_{k + 1}", bias[k] + extra_bias[i][k], joint) for k in range(6)]
        tag = (lambda c: "") if columns == 1 else (lambda c: f"_{c + 1}")
        u_mat = [[name(f"{p}_U_{k + 1}{tag(c)}", _dot(ia[k], column[c]), joint)
                  for c in range(columns)] for k in range(6)]
        tau = coordinates(joint, "tau")
        if at_rest is not None:
            tau = _annotated(joint, tau, variables, stops, at_rest[tree.offsets[i]:])
        if columns == 1:
            d = name(f"{p}_D", _dot(column[0], [u_mat[k][0] for k in range(6)]), joint,
                     always=True)
            d_inv = [[Polynomial.atom(f"inv:{_single(d)}")]]
            u = [name(f"{p}_u", tau[0] - _dot(column[0], pa), joint)]
        else:  # several coordinates: D (at most 6×6, symmetric positive definite)
            d_m: list[list[Any]] = [[None] * columns for _ in range(columns)]
            for a in range(columns):
                for b in range(a, columns):
                    d_m[a][b] = d_m[b][a] = name(
                        f"{p}_D_{a + 1}_{b + 1}",
                        _dot(column[a], [u_mat[k][b] for k in range(6)]), joint)
            d_inv = _ldl_inverse(d_m, p, joint, name)
            if i in factors:  # the efforts in the rates w = B·q̇: B⁻ᵀ·τ
                b_inv = factors[i][1]
                tau = [_dot([b_inv[b][a] for b in range(columns)], tau) for a in range(columns)]
            u = [name(f"{p}_u_{a + 1}", tau[a] - _dot(column[a], pa), joint)
                 for a in range(columns)]
        us[i], d_invs[i], efforts[i] = u_mat, d_inv, u
        if joint.parent < 0:
            continue
        # Ia = IA − U·D⁻¹·Uᵀ,  pa = pB + Ia·c + U·D⁻¹·u
        ud = [[_dot(u_mat[k], [d_inv[a][b] for a in range(columns)]) for b in range(columns)]
              for k in range(6)]
        small: list[list[Any]] = [[None] * 6 for _ in range(6)]
        for r in range(6):
            for k in range(r, 6):
                small[r][k] = small[k][r] = name(
                    f"{p}_Ia_{r + 1}_{k + 1}", ia[r][k] - _dot(ud[r], u_mat[k]), joint)
        ic = _matvec(small, products[i])
        pa_small = [name(f"{p}_pa_{k + 1}", pa[k] + ic[k] + _dot(ud[k], u), joint)
                    for k in range(6)]
        # the parent's share Xᵀ·Ia·X and Xᵀ·pa, through IX = Ia·X
        x = xs[i]
        ix = [[name(f"{p}_IX_{r + 1}_{k + 1}", _dot(small[r], [x[m][k] for m in range(6)]),
                    joint) for k in range(6)] for r in range(6)]
        target, wrench = extra_inertia[joint.parent], extra_bias[joint.parent]
        for r in range(6):
            for k in range(r, 6):
                target[r][k] = target[r][k] + _dot([x[m][r] for m in range(6)],
                                                   [ix[m][k] for m in range(6)])
        moved = _tmatvec(x, pa_small)
        for k in range(6):
            wrench[k] = wrench[k] + moved[k]

    # Pass 3: root to leaves, the accelerations (the root's parent accelerates at −g)
    gravity = [0.0, 0.0, 0.0] + [-float(g) for g in tree.gravity]
    accelerations: list[list[Any]] = []
    out: list[tuple[TreeJoint, tuple[str, ...]]] = []
    for i, joint in enumerate(tree.joints):
        p, s = joint.prefix, factors[i][0] if i in factors else subspaces[i]
        columns = joint.dof
        parent = accelerations[joint.parent] if joint.parent >= 0 else gravity
        moved = _matvec(xs[i], parent)
        ap = [name(f"{p}_ap_{k + 1}", moved[k] + products[i][k], joint) for k in range(6)]
        rest = [efforts[i][a] - _dot([us[i][k][a] for k in range(6)], ap)
                for a in range(columns)]
        names = acceleration_names(joint)
        if i in factors:  # w = D⁻¹·(…) in the rates w = B·q̇, then q̈ = B⁻¹·w
            w = [name(f"{p}_w_{a + 1}", _dot(d_invs[i][a], rest), joint, always=True)
                 for a in range(columns)]
            b_inv = factors[i][1]
            for a in range(columns):
                name(names[a], _dot(b_inv[a], w), joint, always=True)
        else:
            w = [name(names[a], _dot(d_invs[i][a], rest), joint, always=True)
                 for a in range(columns)]
        out.append((joint, tuple(names)))
        step = [_dot(s[k], w) for k in range(6)]
        accelerations.append([name(f"{p}_dV_{k + 1}", ap[k] + step[k], joint)
                              for k in range(6)])
    definitions = tuple(Definition(key, value, joint) for key, value, joint in name.definitions)
    return ExplicitMotion(definitions, tuple(out), tuple(stops))


def acceleration_names(joint: TreeJoint) -> list[str]:
    """The names of the joint's accelerations (``p_qdd``, or ``p_qdd_1`` … for a joint of
    several coordinates), which ``simulate`` also gives Pinocchio's values."""
    p = joint.prefix
    return [f"{p}_qdd" if joint.dof == 1 else f"{p}_qdd_{a + 1}" for a in range(joint.dof)]


def _annotated(joint: TreeJoint, tau: list[Any], variables: Callable[[TreeJoint, str], Any],
                stops: list[Stop], rest: np.ndarray) -> list[Any]:
    """``tau`` with the joint's annotated damping, spring and limit stops added to its
    efforts (see :func:`explicit_motion`); ``rest``: the diagonal of the mass matrix at
    ``q = 0`` from the joint's first coordinate on."""
    forces = axis_forces(joint.kind, joint.element)
    if not forces:
        return tau
    names = {port: [variables(joint, port)] if joint.dof == 1 else list(variables(joint, port))
             for port in ("theta", "v")}
    q = [Polynomial.atom(x) for x in names["theta"]]
    qd = [Polynomial.atom(x) for x in names["v"]]
    out = [value + extra for value, extra in zip(tau, passive_efforts(forces, q, qd))]
    for k, force in enumerate(forces):
        if force.limited:
            stop = Stop(f"{names['theta'][k]}_stop", joint, names["theta"][k], names["v"][k],
                        force, float(rest[k]))
            stops.append(stop)
            out[k] = out[k] + Polynomial.atom(stop.name)
    return out


def _rest_inertia(tree: KinematicTree) -> np.ndarray:
    """The diagonal of the mass matrix at ``q = 0`` (a stop's stiffness scales with it);
    zeros when no joint is bounded (nothing to compute)."""
    if not any(f.limited for j in tree.joints for f in axis_forces(j.kind, j.element)):
        return np.zeros(tree.dof)
    return np.diag(mass_matrix(tree, [0.0] * tree.dof)).astype(float)


def _clean(value: Any) -> Any:
    """An entry of a transform or subspace as a polynomial without float noise, its
    products of rotations collected."""
    return Polynomial.lift(value).trig_reduced().chopped()


def joint_subspace(joint: TreeJoint, q: Sequence[Polynomial], qd: Sequence[Polynomial],
                   name: Callable[..., Any]) -> tuple[list[list[Any]], list[Any]]:
    """``(S, Ṡ·q̇)`` of the joint at coordinates ``q`` and rates ``qd`` (6 rows of ``dof``
    columns, and a 6-vector): numbers for one coordinate (:func:`subspace`, no rate); for
    several, ``dynamics.motion_subspace`` and ``motion_subspace_rate`` on symbols, each
    entry that is not a number named (``p_S_k_c``, ``p_Sdq_k``) through ``name``."""
    if joint.dof == 1:
        return [[float(x) for x in row] for row in subspace(joint)], [0.0] * 6
    p = joint.prefix
    raw = motion_subspace(joint, list(q), _cos, _sin)
    s = [[name(f"{p}_S_{k + 1}_{c + 1}", _clean(raw[k, c]), joint)
          for c in range(joint.dof)] for k in range(6)]
    rate = motion_subspace_rate(joint, list(q), list(qd), _cos, _sin)
    return s, [name(f"{p}_Sdq_{k + 1}", _clean(rate[k]), joint) for k in range(6)]


def _euler_factors(joint: TreeJoint, q: Sequence[Polynomial], name: Callable[..., Any]
                   ) -> tuple[list[list[Any]], list[list[Any]]]:
    """``(S0, B⁻¹)`` of a ball joint or floating base
    (:func:`cyphy.semantics.dynamics.rigid_body.subspace_factors`): the recursion solves for
    the rates ``w = B·q̇`` (``p_w_k``), whose ``D`` stays well conditioned up to pitch
    ±π/2, and ``q̈ = B⁻¹·w``, ``1/cos(pitch)`` being ``1/p_cp``. A floating base's ``S0``
    depends on its rotation: its entries are named ``p_S0_k_c``."""
    p = joint.prefix
    cosine = name(f"{p}_cp", _cos(q[-2]), joint, always=True)
    raw, inverse = subspace_factors(joint, list(q), _cos, _sin,
                                    Polynomial.atom(f"inv:{_single(cosine)}"))
    s0 = [[name(f"{p}_S0_{k + 1}_{c + 1}", _clean(raw[k, c]), joint)
           for c in range(joint.dof)] for k in range(6)]
    return s0, [[_clean(x) for x in row] for row in inverse]


def _ldl_inverse(d: list[list[Any]], p: str, joint: TreeJoint, name: Callable[..., Any]
                 ) -> list[list[Any]]:
    """The inverse of a small symmetric positive definite ``d`` through its factorisation
    ``D = L·diag(p_Dd_k)·Lᵀ`` (``L`` unit lower triangular, ``p_L_i_j``; its inverse
    ``p_Li_i_j``), named ``p_Dinv_a_b``: pivots on the diagonal, no determinant, which loses
    its digits (``det`` cancels) where ``D`` is nearly singular."""
    size = len(d)
    lower: list[list[Any]] = [[0.0] * size for _ in range(size)]
    pivots: list[Any] = []
    for j in range(size):
        pivot = d[j][j] - _dot([lower[j][k] * lower[j][k] for k in range(j)], pivots)
        pivots.append(name(f"{p}_Dd_{j + 1}", pivot, joint, always=True))
        inverse = Polynomial.atom(f"inv:{_single(pivots[j])}")
        for i in range(j + 1, size):
            value = d[i][j] - _dot([lower[i][k] * lower[j][k] for k in range(j)], pivots)
            lower[i][j] = name(f"{p}_L_{i + 1}_{j + 1}", value * inverse, joint)
    unit: list[list[Any]] = [[1.0 if i == j else 0.0 for j in range(size)] for i in range(size)]
    for i in range(size):  # L⁻¹, unit lower triangular too
        for j in range(i):
            value = -_dot([lower[i][k] for k in range(j, i)], [unit[k][j] for k in range(j, i)])
            unit[i][j] = name(f"{p}_Li_{i + 1}_{j + 1}", value, joint)
    reciprocal = [Polynomial.atom(f"inv:{_single(x)}") for x in pivots]
    out: list[list[Any]] = [[None] * size for _ in range(size)]
    for a in range(size):  # D⁻¹ = L⁻ᵀ·diag(1/pivots)·L⁻¹
        for b in range(a, size):
            value = _dot([unit[k][a] * unit[k][b] for k in range(b, size)],
                         reciprocal[b:])
            out[a][b] = out[b][a] = name(f"{p}_Dinv_{a + 1}_{b + 1}", value, joint)
    return out


_JOINT_PORTS = ("theta", "v", "a", "tau")


def model_motion(model: ElaboratedModel, gravity: Sequence[float] = STANDARD_GRAVITY,
                 floating_base: bool = False) -> ExplicitMotion | None:
    """The explicit accelerations of the model's kinematic tree in its joints' own variables
    (``physmod::joints``: ``<J>_theta``, ``<J>_v``, ``<J>_tau``; ``<J>_a == <J>_qdd``; a joint
    of several coordinates has vector ports, named by component, ``<J>_theta_1`` …), the
    root fixed to the world or, with ``floating_base``, free (its coordinates ``<Root>_x`` …
    are new variables, :func:`cyphy.semantics.dynamics.rigid_body.coordinate_names`). None when the
    tree has no moving joint, or when a joint's definition lacks one of these variables
    (nothing here can name its motion). Raises ``DynamicsError`` for a tree without
    equations of motion (a singular mass matrix included: the numeric algorithm checks it
    at ``q = 0``) and for a joint whose variables do not have its number of coordinates."""
    moving = [j for j in model.joints if j.parent is not None and j.child is not None
              and joint_kind(j) != "fixed"]
    if not moving and not floating_base:
        return None
    for joint in moving:  # before the tree: a model whose joints cannot say it is left alone
        if joint.device is None or any(joint.device.port(p) is None for p in _JOINT_PORTS):
            return None
    tree = kinematic_tree(model, gravity, floating_base)
    if not len(tree):
        return None
    zero = [0.0] * tree.dof
    forward_dynamics(tree, zero, zero, zero)

    def port(joint: TreeJoint, name: str) -> Any:
        if joint.kind == "floating":
            return coordinate_names(joint, name)
        found = joint.element.device.port(name)  # type: ignore[union-attr]
        size = port_size(found.type)
        if (joint.dof == 1) != (size is None) or (size is not None and size != joint.dof):
            raise DynamicsError(
                f"joint {joint.name} has {joint.dof} coordinate"
                f"{'s' if joint.dof > 1 else ''}, but its variable {name} is not "
                + ("a scalar" if joint.dof == 1 else f"a vector of {joint.dof}"),
                joint.element.span, f"declare {name}: " + (
                    "real" if joint.dof == 1 else f"vector(real, {joint.dof})"))
        if joint.dof == 1:
            return found.mangled
        return [component_name(found.mangled, k) for k in range(joint.dof)]

    return explicit_motion(tree, port, annotated=True)
