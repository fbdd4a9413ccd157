"""A whole model's ODEs compiled once for ``cyphy simulate`` (issue 31): the devices'
equations as generated code, the kinematic tree by Pinocchio's compiled articulated-body
algorithm when it is installed, and the state Jacobian a stiff method needs.

The reduced ODEs (:class:`cyphy.semantics.dynamics.reduce.Reduced`) use the tree's
accelerations ``<J>_qdd`` as names whose values are the articulated-body algorithm written
as some hundred named definitions per link. Evaluating those in Python costs ~5 ms per
call at 50 links; here they are replaced by one ``pinocchio.aba`` call (the same tree, built
from :class:`cyphy.semantics.dynamics.rigid_body.KinematicTree` as ``--numeric`` does), fed
with the joints' coordinates and rates (states) and efforts (inputs or the devices' algebraic
quantities, ``J_tau = Kt·i − b·ω``, computed by generated code first). The rest of the
right-hand side (the motors' currents, the controllers' integrals) and the outputs are
generated code of the arguments and the accelerations. When something does not fit (an
effort that depends on an acceleration, a joint whose variables are not states), the whole
symbolic tree is compiled instead, as before: the reference the tests compare with.

Jacobian: ``f(x) = r(x, q̈(x))`` with ``q̈ = ABA(q, q̇, τ(x))``, so
``∂f/∂x = ∂r/∂x + ∂r/∂q̈ · (∂q̈/∂q·P_q + ∂q̈/∂q̇·P_v + M⁻¹·∂τ/∂x)``, Pinocchio's analytic
ABA derivatives and M⁻¹ and SymPy's derivatives of the devices' equations (no finite
differences). A model without a tree has ``∂r/∂x`` alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from cyphy.backends.generated import compiled, lambdified, needed, sparse_jacobian, uses
from cyphy.backends.pinocchio_tree import pinocchio_model
from cyphy.semantics.dynamics.joint_forces import axis_forces, passive_efforts, stop
from cyphy.semantics.dynamics.rigid_body import mass_matrix
from cyphy.semantics.dynamics.spatial import euler_singularity
from cyphy.semantics.dynamics.tree import EULER


@dataclass(frozen=True)
class SystemDynamics:
    """``rhs(*x, *u, t)`` and ``outputs(*x, *u, t)`` (lists of floats), what builds the
    state Jacobian ``J(*x, *u, t)`` when it is analytic (else None), and what evaluates the
    tree. The Jacobian is built only for a stiff method: SymPy's derivatives and their code
    cost about a second for a 50-link chain with motors, more than its whole integration."""

    rhs: Callable[..., Sequence[float]]
    outputs: Callable[..., Sequence[float]]
    make_jacobian: Callable[[], Callable[..., np.ndarray]] | None
    engine: str


def acceleration_names(tree: Any) -> list[str]:
    """The names of the tree's accelerations in coordinate order, as the articulated-body
    definitions name them (:func:`cyphy.semantics.dynamics.articulated.acceleration_names`)."""
    # lazy: the semantics' articulated module pulls in the model
    from cyphy.semantics.dynamics.articulated import acceleration_names as names

    return [n for joint in tree.joints for n in names(joint)]


def system_dynamics(states: Sequence[str], inputs: Sequence[str], rhs_expr: Sequence[Any],
                    out_exprs: Sequence[Any], definitions: Sequence[tuple[str, Any]],
                    tree: Any = None) -> SystemDynamics:
    """The compiled ODEs (see the module's docstring); ``tree`` the model's kinematic tree
    when its accelerations are among the definitions."""
    args = [*states, *inputs, "t"]
    if definitions and tree is not None:
        hybrid = _with_pinocchio(states, inputs, rhs_expr, out_exprs, definitions, tree)
        if hybrid is not None:
            return hybrid
    if definitions:
        rhs, out = compiled(args, definitions, rhs_expr, out_exprs)
        return SystemDynamics(rhs, out, None, "the compiled equations")
    rhs, out = lambdified(args, rhs_expr), lambdified(args, out_exprs)
    return SystemDynamics(rhs, out, lambda: sparse_jacobian(args, rhs_expr, states),
                          "the compiled equations")


def _with_pinocchio(states: Sequence[str], inputs: Sequence[str], rhs_expr: Sequence[Any],
                    out_exprs: Sequence[Any], definitions: Sequence[tuple[str, Any]],
                    tree: Any) -> SystemDynamics | None:
    """The dynamics with the tree's accelerations from Pinocchio, or None when Pinocchio is
    absent or the model does not have the shape this needs."""
    # lazy: SymPy is not needed by `cyphy check`
    import sympy

    args = [*states, *inputs, "t"]
    known = set(args)
    defined = {n for n, _ in definitions}
    qdd = acceleration_names(tree)
    thetas, speeds = list(tree.coordinates("theta")), list(tree.coordinates("v"))
    efforts = list(tree.coordinates("tau"))
    if not set(qdd) <= defined or not set(thetas + speeds) <= set(states) or \
            not set(efforts) <= known | defined:
        return None
    effort_defs = needed(definitions, efforts, known)
    if any(not hasattr(v, "free_symbols") or n in qdd for n, v in effort_defs):
        return None  # an effort through the tree's internals (an acceleration): a loop
    compiled_tree = pinocchio_model(tree)
    if compiled_tree is None:
        return None
    symbols = [sympy.Symbol(n, real=True) for n in efforts]
    (tau_fn,) = compiled(args, effort_defs, symbols)
    given = known | set(qdd)
    rhs_defs = needed(definitions, {n for e in rhs_expr for n in uses(sympy.sympify(e))},
                      given)
    out_defs = needed(definitions, {n for e in out_exprs for n in uses(sympy.sympify(e))},
                      given)
    (rhs_fn,) = compiled([*args, *qdd], rhs_defs, rhs_expr)
    (out_fn,) = compiled([*args, *qdd], out_defs, out_exprs)
    index = {n: k for k, n in enumerate(states)}
    iq = np.array([index[n] for n in thetas], dtype=int)
    iv = np.array([index[n] for n in speeds], dtype=int)
    slots = np.array([k for j, start in zip(tree.joints, tree.offsets) if j.kind != "floating"
                      for k in range(start, start + j.dof)], dtype=int)
    annotated = annotated_efforts(tree)
    euler = any(j.kind in EULER for j in tree.joints)
    n = tree.dof

    def joint_state(values: Sequence[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x = np.asarray(values[:len(states)], dtype=float)
        q, qd = x[iq], x[iv]
        tau = np.zeros(n)
        tau[slots] = tau_fn(*values)
        if annotated is not None:
            tau += annotated(q, qd)
        if euler:  # Pinocchio divides by cos(pitch) without a word: refuse as the NumPy ABA
            euler_singularity(tree, q)
        return q, qd, tau

    def accelerations(*values: float) -> np.ndarray:
        return compiled_tree.forward_dynamics(*joint_state(values))

    def rhs(*values: float) -> Sequence[float]:
        return rhs_fn(*values, *accelerations(*values))

    def outputs(*values: float) -> Sequence[float]:
        return out_fn(*values, *accelerations(*values))

    make_jacobian = None
    # analytic when the rest of the right-hand side is SymPy (no tree internals) and the
    # efforts do not depend on the state through annotated damping, springs or stops
    if compiled_tree.derivatives and annotated is None and not rhs_defs:
        def make_jacobian() -> Callable[..., np.ndarray]:
            return _jacobian(args, states, qdd, rhs_expr, efforts, effort_defs, slots, iq,
                             iv, joint_state, compiled_tree)
    return SystemDynamics(rhs, outputs, make_jacobian, "Pinocchio's articulated-body algorithm "
                          "for the kinematic tree and the compiled equations of the devices")


def _jacobian(args: Sequence[str], states: Sequence[str], qdd: Sequence[str],
              rhs_expr: Sequence[Any], efforts: Sequence[str],
              effort_defs: Sequence[tuple[str, Any]], slots: np.ndarray, iq: np.ndarray,
              iv: np.ndarray, joint_state: Callable[..., Any], compiled_tree: Any
              ) -> Callable[..., np.ndarray]:
    """``∂f/∂x`` by the chain rule of the module's docstring."""
    # lazy: SymPy and Pinocchio are not needed by `cyphy check`
    import pinocchio
    import sympy  # lazy: SymPy (see above)

    written: dict[Any, Any] = {}  # the efforts written out in the arguments (SymPy only)
    for name, value in effort_defs:
        written[sympy.Symbol(name, real=True)] = sympy.sympify(value).xreplace(written)
    tau_exprs = [written.get(sympy.Symbol(n, real=True), sympy.Symbol(n, real=True))
                 for n in efforts]
    direct = sparse_jacobian([*args, *qdd], rhs_expr, states)
    through = sparse_jacobian([*args, *qdd], rhs_expr, qdd)
    dtau = sparse_jacobian(args, tau_exprs, states)
    model, data = compiled_tree.model, compiled_tree.data
    size = len(states)

    def jacobian(*values: float) -> np.ndarray:
        q, qd, tau = joint_state(values)
        pinocchio.computeABADerivatives(model, data, q, qd, tau)
        ddq = np.array(data.ddq, dtype=float)
        minv = np.triu(data.Minv) + np.triu(data.Minv, 1).T  # Pinocchio fills the upper half
        dqdd = np.zeros((len(qdd), size))
        dqdd[:, iq] = data.ddq_dq
        dqdd[:, iv] += data.ddq_dv
        dqdd += minv[:, slots] @ dtau(*values)
        full = (*values, *ddq)
        return direct(*full) + through(*full) @ dqdd

    return jacobian


def annotated_efforts(tree: Any) -> Callable[[np.ndarray, np.ndarray], np.ndarray] | None:
    """The efforts of the joints' annotated damping, springs and limit stops as a function
    of the coordinates and rates (:mod:`cyphy.semantics.dynamics.joint_forces`, as the
    symbolic path has them), or None when no joint has any."""

    forces = [(k, f) for joint, start in zip(tree.joints, tree.offsets)
              for k, f in enumerate(axis_forces(joint.kind, joint.element), start=start)
              if f.passive or f.limited]
    if not forces:
        return None
    rest = np.diag(mass_matrix(tree, [0.0] * tree.dof)).astype(float)
    index = np.array([k for k, _ in forces], dtype=int)
    axes = [f for _, f in forces]

    def efforts(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        out = np.zeros(len(q))
        out[index] = passive_efforts(axes, q[index], qd[index])
        out[index] += [stop(f, rest[k], q[k], qd[k]) for k, f in forces]
        return out

    return efforts
