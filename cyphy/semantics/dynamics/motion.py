"""The equations of motion of a model's kinematic tree written out as equations of the
expression AST (``J_tau == M(q)*a + h(q, v)``), for the targets that need closed expressions
(CyPhyCircus ``Evolve``, Isabelle, Flow*, ``cyphy solve``): SymPy runs the recursive
Newton-Euler algorithm of :mod:`cyphy.semantics.dynamics.rigid_body` on symbols, and the
result is cached on disk (:mod:`cyphy.semantics.dynamics.motion_cache`).

Split from ``rigid_body`` so that a cached derivation imports neither SymPy nor NumPy: the
tree is built and keyed as data (:mod:`cyphy.semantics.dynamics.tree`), and the algorithms
(NumPy) are imported on a miss only.
"""

from __future__ import annotations

from typing import Any, Sequence

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.dynamics.errors import DynamicsError
from cyphy.semantics.dynamics.motion_cache import derived
from cyphy.semantics.dynamics.tree import (STANDARD_GRAVITY, KinematicTree, TreeJoint,
                                           coordinate_names, joint_kind, kinematic_tree)


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
    exponentially often). Such a joint alone is written out.

    The derivation (SymPy) is cached on disk (:mod:`cyphy.semantics.dynamics.motion_cache`),
    keyed on everything the tree is built from. The checks that need the tree's numbers
    (NumPy) run on a miss, before deriving: an entry is stored only after they passed on
    the same inputs, so a hit imports neither NumPy nor SymPy."""
    moving = [j for j in model.joints if j.parent is not None and j.child is not None
              and joint_kind(j) != "fixed"]
    for joint in moving:  # before the tree: a model whose joints cannot say it is left alone
        if joint.device is None or any(joint.device.port(p) is None for p in _JOINT_PORTS):
            return []
    if not moving and not floating_base:
        return []
    try:  # the tree's layout, without its numbers (NumPy): what the cache is keyed on
        tree = kinematic_tree(model, gravity, floating_base, numeric=False)
    except DynamicsError:  # a loop: reported after the numbers of the joints ahead of it
        tree = kinematic_tree(model, gravity, floating_base)
    if not len(tree):
        return []
    return [(equation, tree.joints[i])
            for equation, i in derived(tree, lambda: _checked_derivation(tree))]


def _checked_derivation(tree: KinematicTree) -> list[tuple[Any, int]]:
    """:func:`_derive` after the checks of :func:`motion_equations`, in their order: the
    joints' numbers, a singular mass matrix, a tree too large to write out. Run on a miss of
    the cache only: an entry is stored after they passed on the same inputs."""
    # lazy: NumPy (0.1 s to import), which the numbers and the algorithms need and a
    # cached derivation does not
    from cyphy.semantics.dynamics.rigid_body import forward_dynamics  # lazy: see above

    for joint in tree.joints:
        joint.numbers()
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
    return _derive(tree)


def _derive(tree: KinematicTree) -> list[tuple[Any, int]]:
    """The tree's equations of motion written out (see :func:`motion_equations`), each with
    the index of its joint in the tree: SymPy's Newton-Euler pass, expanded, back in the
    expression AST. Reads the tree only (its joints' elements for their spans, devices and
    annotations): :func:`cyphy.semantics.dynamics.motion_cache.key` names what it reads."""
    # lazy: SymPy takes 0.5-0.9 s to import; a cached derivation never imports it
    import sympy

    # lazy: NumPy, as in _checked_derivation
    from cyphy.semantics.dynamics.rigid_body import inverse_dynamics

    # lazy: imports SymPy (the translator back to the shared AST, no printer state)
    from cyphy.translate.to_sympy import to_expr

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

    out: list[tuple[Any, int]] = []
    for i, (joint, start) in enumerate(zip(tree.joints, tree.offsets)):
        span = joint.element.span
        if joint.kind == "floating":
            for position, speed, acceleration in zip(
                    *(coordinate_names(joint, v) for v in ("theta", "v", "a"))):
                for left, right in ((position, speed), (speed, acceleration)):
                    out.append((ex.BinOp("==", ex.Derivative(ex.Name((left,), span=span),
                                                             span=span),
                                         ex.Name((right,), span=span), span=span), i))
            lefts: list[ex.Expr] = [ex.Num("0", span=span)] * joint.dof
        else:
            scalars(joint, "tau")
            lefts = [variables[n] for n in coordinate_names(joint, "tau")]
        for k, left in enumerate(lefts):
            rhs = _chop(sympy.expand(efforts[start + k]))
            right = ex.transform(to_expr(rhs, decimals=True), model_names)
            out.append((ex.BinOp("==", left, right, span=span), i))
    return out


def _passive(tree: KinematicTree, q: Sequence[Any], qd: Sequence[Any], efforts: Any) -> None:
    """Take the annotated damping and springs of the joints into ``efforts`` (the effort
    the actuator gives is the rigid body's need minus them,
    :mod:`cyphy.semantics.dynamics.joint_forces`; limits are not written out)."""
    # lazy: run on a miss of the cache only, which a warm start does not load
    from cyphy.semantics.dynamics.joint_forces import axis_forces, passive_efforts

    for joint, start in zip(tree.joints, tree.offsets):
        forces = axis_forces(joint.kind, joint.element)
        span = slice(start, start + len(forces))
        for k, extra in enumerate(passive_efforts(forces, q[span], qd[span]), start=start):
            efforts[k] = efforts[k] - extra


def port_size(t: Any) -> int | None:
    """The literal size of a vector type, None for a scalar (or anything else)."""
    if isinstance(t, ast.VectorType) and t.size is not None:
        text = getattr(t.size, "text", "")
        return int(text) if isinstance(text, str) and text.isdigit() else -1
    return -1 if isinstance(t, ast.MatrixType) else None


def _chop(value: Any) -> Any:
    """``value`` without the float noise of the transforms (``1e-19·v²`` where a term
    cancels exactly): coefficients below 1e-12 of the largest are dropped."""
    import sympy  # lazy: SymPy, on a miss of the cache only (as in _derive)

    floats = [abs(float(f)) for f in value.atoms(sympy.Float)]
    if not floats:
        return value
    limit = 1e-12 * max(floats)
    terms = value.as_ordered_terms() if isinstance(value, sympy.Add) else [value]
    kept = [t for t in terms if not (t.as_coeff_Mul()[0].is_Float
                                     and abs(float(t.as_coeff_Mul()[0])) < limit)]
    return sympy.Add(*kept)
