"""Each moving body's Newton–Euler equations as equations of the shared expression AST
(``cyphy show`` lists them per link; Lynch and Park, *Modern Robotics* eqs. 8.47–8.53, in
the conventions of :mod:`cyphy.semantics.dynamics.rigid_body`). For the body moved by joint ``p``
(its device prefix), in the body's frame:

- ``p_A == (|…|)``: the joint's screw axis (motion subspace); for a joint of several
  coordinates (universal, ball, the floating base) the 6×n matrix ``S(q)`` of its
  coordinates, followed by ``p_dA == (|…|)``, the rate of the subspace ``Ṡ·q̇``;
- ``p_G == [|…|]``: the body's spatial inertia about its frame origin;
- ``p_X == [|…|]``: the Adjoint of the parent's pose in the body frame, a function of
  ``p_theta`` (it carries the parent's twists into this frame);
- ``p_V == p_X * q_V + p_A * p_v``: the twist, from the parent ``q``'s (none at the root);
- ``p_dV == p_X * q_dV + ad(p_V) * p_A * p_v + p_A * p_a``: its derivative (at the root,
  ``p_X`` applied to ``(|0, 0, 0, −g|)``, gravity as an upward acceleration of the world;
  ``+ p_dA`` for a joint of several coordinates);
- ``p_F == p_G * p_dV - transpose(ad(p_V)) * p_G * p_V + transpose(c_X) * c_F + …``: the
  wrench the joint transmits, balancing the body's inertia and its children ``c``'s wrenches;
- ``p_tau == transpose(p_A) * p_F``: the joint effort (a floating base has none:
  ``transpose(p_A) * p_F == (|0, …|)``).

A joint of several coordinates has vector variables, read item by item (``Wrist_theta[2]``);
a floating base's coordinates are the variables ``<Root>_x`` … of
:func:`cyphy.semantics.dynamics.rigid_body.coordinate_names`, its rates and accelerations
written as vectors ``(|Body_vx, …|)``.

The components of ``p_V`` and ``p_dV`` are the twist and acceleration definitions of
:mod:`cyphy.semantics.dynamics.articulated` (``p_V_1`` … ``p_V_6``), which ``cyphy solve`` writes;
the tests check both derivations against each other and against Pinocchio.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cyphy import expr as ex
from cyphy.semantics.dynamics.articulated import subspace
from cyphy.semantics.dynamics.polynomial import Polynomial, _cos, _sin
from cyphy.semantics.dynamics.spatial import (motion_subspace, motion_subspace_rate,
                                              parent_to_child)
from cyphy.semantics.dynamics.tree import KinematicTree, TreeJoint, coordinate_names


@dataclass(frozen=True)
class LinkEquations:
    """The Newton–Euler equations of the body that ``joint`` moves, in the order above."""

    joint: TreeJoint
    equations: tuple[ex.Expr, ...]


def _number(value: float) -> ex.Expr:
    value = float(value)
    text = repr(abs(value)) if value != int(value) or abs(value) >= 1e15 else str(int(abs(value)))
    return ex.UnaryOp("-", ex.Num(text)) if value < 0 else ex.Num(text)


def _name(*parts: str) -> ex.Name:
    return ex.Name(("_".join(parts),))


def _call(name: str, *args: ex.Expr) -> ex.Call:
    return ex.Call(ex.Name((name,)), args)


def _sum(*terms: ex.Expr) -> ex.Expr:
    out = terms[0]
    for term in terms[1:]:
        out = ex.BinOp("+", out, term)
    return out


def _product(*factors: ex.Expr) -> ex.Expr:
    out = factors[0]
    for factor in factors[1:]:
        out = ex.BinOp("*", out, factor)
    return out


def _matrix(m: np.ndarray) -> ex.Expr:
    return ex.Matrix(tuple(tuple(_number(v) for v in row) for row in m))


def _column(v: np.ndarray) -> ex.Expr:
    """A vector (one column) as the library writes one, ``(|a, b, c|)``; a subspace of
    several columns as a matrix."""
    if v.ndim == 2 and v.shape[1] > 1:
        return _matrix(v)
    return ex.Vector((tuple(_number(x) for x in np.ravel(v)),))


def link_equations(tree: KinematicTree, theta: str = "theta", v: str = "v", a: str = "a",
                   tau: str = "tau") -> list[LinkEquations]:
    """Per joint in tree order, the Newton–Euler equations of the body it moves, in the
    joints' variables ``<prefix>_<theta>`` … (``physmod::joints``'s names by default)."""
    out = []
    children: dict[int, list[int]] = {}
    for i, joint in enumerate(tree.joints):
        children.setdefault(joint.parent, []).append(i)
    for i, joint in enumerate(tree.joints):
        p = joint.prefix
        span = joint.element.span
        parent = tree.joints[joint.parent].prefix if joint.parent >= 0 else None
        # a joint of several coordinates: its coordinates as solve names them, for the
        # arithmetic (``_variables`` says how the equations write them)
        names = {port: (f"{p}_{port}",) if joint.dof == 1 else coordinate_names(joint, key)
                 for port, key in ((theta, "theta"), (v, "v"), (a, "a"))}
        shown = _variables(joint, names, (theta, v, a))
        q = [Polynomial.atom(n) for n in names[theta]]
        raw = parent_to_child(joint, q[0] if joint.dof == 1 else q, _cos, _sin)
        x = _matrix_of(raw, shown)
        axis = _name(p, "A")
        rate, accel = shown[v], shown[a]
        motion = _product(axis, rate)
        twist = motion if parent is None else _sum(_product(_name(p, "X"), _name(parent, "V")),
                                                    motion)
        base = _name(parent, "dV") if parent is not None else \
            _column(np.concatenate([np.zeros(3), -np.asarray(tree.gravity, dtype=float)]))
        terms = [_product(_name(p, "X"), base), _product(_call("ad", _name(p, "V")), axis, rate),
                 _product(axis, accel)]
        pairs: list[tuple[ex.Expr, ex.Expr]]
        if joint.dof == 1:
            pairs = [(axis, _column(subspace(joint)))]
        else:
            qd = [Polynomial.atom(n) for n in names[v]]
            pairs = [(axis, _matrix_of(motion_subspace(joint, q, _cos, _sin), shown)),
                     (_name(p, "dA"), _vector_of(motion_subspace_rate(joint, q, qd, _cos, _sin),
                                                 shown))]
            terms.append(_name(p, "dA"))
        wrench = ex.BinOp("-", _product(_name(p, "G"), _name(p, "dV")),
                          _product(_call("transpose", _call("ad", _name(p, "V"))),
                                   _name(p, "G"), _name(p, "V")))
        for c in children.get(i, []):
            child = tree.joints[c].prefix
            wrench = ex.BinOp("+", wrench, _product(_call("transpose", _name(child, "X")),
                                                    _name(child, "F")))
        effort = _product(_call("transpose", axis), _name(p, "F"))
        pairs += [(_name(p, "G"), _matrix(joint.inertia)),
                  (_name(p, "X"), x),
                  (_name(p, "V"), twist),
                  (_name(p, "dV"), _sum(*terms)),
                  (_name(p, "F"), wrench),
                  (effort, _column(np.zeros(6))) if joint.kind == "floating" else
                  (_name(p, tau), effort)]
        out.append(LinkEquations(joint, tuple(ex.BinOp("==", left, right, span=span)
                                              for left, right in pairs)))
    return out


def _variables(joint: TreeJoint, names: dict[str, tuple[str, ...]], ports: tuple[str, ...]
               ) -> dict[str, ex.Expr]:
    """How the equations write each port's value: the scalar ``p_theta``; a joint of several
    coordinates its vector port (``p_v``), read item by item where a coordinate appears
    alone (``p_theta[2]``, see :func:`_matrix_of`); a floating base's coordinates as the
    vector of its variables (``(|Body_vx, …|)``)."""
    out: dict[str, ex.Expr] = {}
    for port in ports:
        if joint.dof == 1:
            out[port] = _name(names[port][0])
        elif joint.kind == "floating":
            out[port] = ex.Vector((tuple(_name(n) for n in names[port]),))
        else:
            out[port] = _name(joint.prefix, port)
            for k, n in enumerate(names[port], start=1):
                out[n] = ex.Index(out[port], (ex.Num(str(k)),))
    return out


def _entry(value: object, shown: dict[str, ex.Expr]) -> ex.Expr:
    """An entry of a transform or subspace as an expression, without float noise, its
    products of rotations collected, a vector port's coordinates read item by item."""
    expr = Polynomial.lift(value).trig_reduced().chopped().to_expr()

    def item(node: ex.Expr) -> ex.Expr | None:
        if isinstance(node, ex.Name) and node.text in shown and \
                isinstance(shown[node.text], ex.Index):
            return shown[node.text]
        return None

    return ex.transform(expr, item)


def _matrix_of(values: np.ndarray, shown: dict[str, ex.Expr]) -> ex.Expr:
    return ex.Matrix(tuple(tuple(_entry(values[r, k], shown) for k in range(values.shape[1]))
                           for r in range(values.shape[0])))


def _vector_of(values: np.ndarray, shown: dict[str, ex.Expr]) -> ex.Expr:
    return ex.Vector((tuple(_entry(x, shown) for x in values),))
