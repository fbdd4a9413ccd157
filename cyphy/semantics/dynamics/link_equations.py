"""Each moving body's Newton–Euler equations as equations of the shared expression AST
(``cyphy show`` lists them per link; Lynch and Park, *Modern Robotics* eqs. 8.47–8.53, in
the conventions of :mod:`cyphy.semantics.dynamics.rigid_body`). For the body moved by joint ``p``
(its device prefix), in the body's frame:

- ``p_A == (|…|)``: the joint's screw axis (motion subspace);
- ``p_G == [|…|]``: the body's spatial inertia about its frame origin;
- ``p_X == [|…|]``: the Adjoint of the parent's pose in the body frame, a function of
  ``p_theta`` (it carries the parent's twists into this frame);
- ``p_V == p_X * q_V + p_A * p_v``: the twist, from the parent ``q``'s (none at the root);
- ``p_dV == p_X * q_dV + ad(p_V) * p_A * p_v + p_A * p_a``: its derivative (at the root,
  ``p_X`` applied to ``(|0, 0, 0, −g|)``, gravity as an upward acceleration of the world);
- ``p_F == p_G * p_dV - transpose(ad(p_V)) * p_G * p_V + transpose(c_X) * c_F + …``: the
  wrench the joint transmits, balancing the body's inertia and its children ``c``'s wrenches;
- ``p_tau == transpose(p_A) * p_F``: the joint effort.

The components of ``p_V`` and ``p_dV`` are the twist and acceleration definitions of
:mod:`cyphy.semantics.dynamics.articulated` (``p_V_1`` … ``p_V_6``), which ``cyphy solve`` writes;
the tests check both derivations against each other and against Pinocchio.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cyphy import expr as ex
from cyphy.semantics.dynamics.articulated import Polynomial, _cos, _sin, subspace
from cyphy.semantics.dynamics.rigid_body import KinematicTree, TreeJoint, parent_to_child


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
        raw = parent_to_child(joint, Polynomial.atom(f"{p}_{theta}"), _cos, _sin)
        x = ex.Matrix(tuple(tuple(Polynomial.lift(raw[r, k]).trig_reduced().chopped()
                                  .to_expr() for k in range(6)) for r in range(6)))
        axis, motion = _name(p, "A"), _product(_name(p, "A"), _name(p, v))
        twist = motion if parent is None else _sum(_product(_name(p, "X"), _name(parent, "V")),
                                                    motion)
        base = _name(parent, "dV") if parent is not None else \
            _column(np.concatenate([np.zeros(3), -tree.gravity]))
        acceleration = _sum(_product(_name(p, "X"), base),
                            _product(_call("ad", _name(p, "V")), axis, _name(p, v)),
                            _product(axis, _name(p, a)))
        wrench = ex.BinOp("-", _product(_name(p, "G"), _name(p, "dV")),
                          _product(_call("transpose", _call("ad", _name(p, "V"))),
                                   _name(p, "G"), _name(p, "V")))
        for c in children.get(i, []):
            child = tree.joints[c].prefix
            wrench = ex.BinOp("+", wrench, _product(_call("transpose", _name(child, "X")),
                                                    _name(child, "F")))
        pairs = [(_name(p, "A"), _column(subspace(joint))),
                 (_name(p, "G"), _matrix(joint.inertia)),
                 (_name(p, "X"), x),
                 (_name(p, "V"), twist),
                 (_name(p, "dV"), acceleration),
                 (_name(p, "F"), wrench),
                 (_name(p, tau), _product(_call("transpose", axis), _name(p, "F")))]
        out.append(LinkEquations(joint, tuple(ex.BinOp("==", left, right, span=span)
                                              for left, right in pairs)))
    return out
