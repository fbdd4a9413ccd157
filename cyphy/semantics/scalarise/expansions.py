"""The library's vector and matrix functions written out as the literal they denote, from
their arguments' components (``skew``, ``ad``, ``Rot``, ``Adjoint``…), and the sums and
products that build them without the literal zeros a product with 0 leaves.
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.semantics.scalarise.shapes import Shape


def is_zero(e: ex.Expr) -> bool:
    return isinstance(e, ex.Num) and e.text.replace(".", "", 1).strip("0") == ""


def negate(e: ex.Expr) -> ex.Expr:
    return e if is_zero(e) else ex.UnaryOp("-", e)


def times(a: ex.Expr, b: ex.Expr) -> ex.Expr:
    return ex.Num("0") if is_zero(a) or is_zero(b) else ex.BinOp("*", a, b)


def add_all(terms: list[ex.Expr]) -> ex.Expr:
    """``a + b + …`` without the literal zeros (``0`` when nothing is left)."""
    kept = [t for t in terms if not is_zero(t)]
    if not kept:
        return ex.Num("0")
    out = kept[0]
    for t in kept[1:]:
        out = ex.BinOp("+", out, t)
    return out


def _skew(v: list[ex.Expr]) -> list[list[ex.Expr]]:
    """``physmod::math::skew``: the matrix of ``v ×``."""
    zero = ex.Num("0")
    return [[zero, negate(v[2]), v[1]], [v[2], zero, negate(v[0])], [negate(v[1]), v[0], zero]]


def _ad(v: list[ex.Expr]) -> list[list[ex.Expr]]:
    """``physmod::math::ad``: ``[| skew(w), 0; skew(v), skew(w) |]`` of ``V = (w; v)``."""
    w, u = _skew(v[:3]), _skew(v[3:])
    zero = [ex.Num("0")] * 3
    return [w[i] + zero for i in range(3)] + [u[i] + w[i] for i in range(3)]


def _rot(w: list[ex.Expr], theta: ex.Expr) -> list[list[ex.Expr]]:
    """``physmod::math::Rot``: Rodrigues' ``I + sin θ [w] + (1 - cos θ) [w]²``, with
    ``([w]²)_ij = w_i w_j - δ_ij (w·w)``."""
    k = _skew(w)
    s = ex.Call(ex.Name(("sin",)), (theta,))
    c1 = ex.BinOp("-", ex.Num("1"), ex.Call(ex.Name(("cos",)), (theta,)))
    ww = add_all([times(x, x) for x in w])
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            square = times(w[i], w[j]) if i != j else ex.BinOp("-", times(w[i], w[j]), ww)
            terms = [ex.Num("1") if i == j else ex.Num("0"), times(s, k[i][j]),
                     ex.BinOp("*", c1, square)]
            row.append(add_all(terms))
        rows.append(row)
    return rows


def _adjoint(t: list[list[ex.Expr]]) -> list[list[ex.Expr]]:
    """``physmod::math::Adjoint``: ``[| R, 0; skew(p)*R, R |]`` of ``T = (R, p)``."""
    r = [row[:3] for row in t[:3]]
    k = _skew([t[i][3] for i in range(3)])
    kr = [[add_all([times(k[i][m], r[m][j]) for m in range(3)]) for j in range(3)]
          for i in range(3)]
    zero = [ex.Num("0")] * 3
    return [r[i] + zero for i in range(3)] + [kr[i] + r[i] for i in range(3)]


#: Library functions written out as literals: name → (argument shapes, None for a scalar or
#: a literal size; the literal as rows, or a scalar expression, from the arguments'
#: components: a vector's as a list, a matrix's as rows, a scalar as itself).
EXPANSIONS: dict[str, tuple[tuple[Shape | None, ...], Callable[..., object]]] = {
    "skew": (((3,),), _skew),
    "ad": (((6,),), _ad),
    "ScrewAxis": (((3,), (3,)), lambda w, v: [w + v]),
    "cross": (((3,), (3,)), lambda u, v: [[
        ex.BinOp("-", times(u[1], v[2]), times(u[2], v[1])),
        ex.BinOp("-", times(u[2], v[0]), times(u[0], v[2])),
        ex.BinOp("-", times(u[0], v[1]), times(u[1], v[0]))]]),
    "dot": ((None, None), lambda u, v: add_all([times(a, b) for a, b in zip(u, v)])),
    "norm": ((None,), lambda v: ex.Call(ex.Name(("sqrt",)), (add_all([times(a, a) for a in v]),))),
    "Rot": (((3,), ()), _rot),
    "Adjoint": (((4, 4),), _adjoint),
    "identity": (((),), lambda n: [[ex.Num("1" if i == j else "0") for j in range(n)]
                                   for i in range(n)]),
    "zeroes": (((), ()), lambda m, n: [[ex.Num("0")] * n for _ in range(m)]),
}
SIZE_ARGUMENTS = frozenset({"identity", "zeroes"})
