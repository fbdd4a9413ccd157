"""The library functions of ``physmod::math`` (``sin``, ``Rot``, ``Adjoint``…) on
:data:`~cyphy.model.values.Value`, and the argument counts the evaluator checks calls
against."""

from __future__ import annotations

import functools
import inspect
import math
from types import MappingProxyType
from typing import Callable, Mapping

import numpy as np

from cyphy.model.values import Value, Vec, describe, frozen, is_number

# Library functions (physmod::math) on Values. They raise ValueError with a message that reads
# after the function's name ("sqrt is undefined for ..."); the evaluator adds name and span.


def _number(value: Value) -> int | float:
    if not is_number(value):
        raise ValueError(f"expects a number, not {describe(value)}")
    return value  # type: ignore[return-value]


def _real(value: Value) -> float:
    return float(_number(value))


def _nat(value: Value) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError(f"expects a natural number, not {describe(value)}")
    return value


def _vector(value: Value, size: int | None = None) -> Vec:
    if not isinstance(value, np.ndarray) or value.ndim != 1:
        raise ValueError(f"expects a vector, not {describe(value)}")
    if size is not None and value.shape[0] != size:
        raise ValueError(f"expects a {size}-vector, not {describe(value)}")
    return value


def _matrix(value: Value, square: bool = False, size: int | None = None) -> Vec:
    if not isinstance(value, np.ndarray) or value.ndim != 2:
        raise ValueError(f"expects a matrix, not {describe(value)}")
    if (square or size is not None) and value.shape[0] != value.shape[1]:
        raise ValueError(f"expects a square matrix, not {describe(value)}")
    if size is not None and value.shape[0] != size:
        raise ValueError(f"expects a {size}x{size} matrix, not {describe(value)}")
    return value


def _unary_real(fn: Callable[[float], float]) -> Callable[[Value], float]:
    def apply(x: Value) -> float:
        return fn(_real(x))

    apply.__doc__ = fn.__doc__
    return apply


def _asin(x: Value) -> float:
    r = _real(x)
    if not -1 <= r <= 1:
        raise ValueError(f"needs -1 <= x <= 1, not {r:g}")
    return math.asin(r)


def _acos(x: Value) -> float:
    r = _real(x)
    if not -1 <= r <= 1:
        raise ValueError(f"needs -1 <= x <= 1, not {r:g}")
    return math.acos(r)


def _atan2(y: Value, x: Value) -> float:
    return math.atan2(_real(y), _real(x))


def _sqrt(x: Value) -> float:
    r = _real(x)
    if r < 0:
        raise ValueError(f"is undefined for a negative number ({r:g})")
    return math.sqrt(r)


def _log(x: Value) -> float:
    r = _real(x)
    if r <= 0:
        raise ValueError(f"is defined for positive numbers only, not {r:g}")
    return math.log(r)


def _abs(x: Value) -> int | float:
    """Keeps an integer an integer, like the arithmetic operators."""
    return abs(_number(x))


def _sgn(x: Value) -> int | float:
    """-1, 0 or 1, of the argument's own kind (integer or real)."""
    n = _number(x)
    sign = (n > 0) - (n < 0)
    return sign if isinstance(n, int) else float(sign)


def _transpose(m: Value) -> Vec:
    """A 1-D vector is a column, so its transpose is a 1xn row matrix."""
    if isinstance(m, np.ndarray) and m.ndim == 1:
        return frozen(m[np.newaxis, :])
    return frozen(_matrix(m).T)


def _inverse(m: Value) -> Vec:
    try:
        return frozen(np.linalg.inv(_matrix(m, square=True)))
    except np.linalg.LinAlgError:
        raise ValueError("needs an invertible matrix; this one is singular") from None


def _det(m: Value) -> float:
    return float(np.linalg.det(_matrix(m, square=True)))


def _identity(n: Value) -> Vec:
    return frozen(np.eye(_nat(n)))


def _zeroes(m: Value, n: Value | None = None) -> Vec:
    """``zeroes(m, n)`` is m-by-n; ``zeroes(n)`` is n-by-n, as ``identity(n)`` (and MATLAB)."""
    rows = _nat(m)
    return frozen(np.zeros((rows, rows if n is None else _nat(n))))


def _submatrix(m: Value, i: Value, j: Value, rows: Value, cols: Value) -> Vec:
    """The block at row ``i``, column ``j`` counted from 0, as the library declares."""
    matrix = _matrix(m)
    top, left, height, width = _nat(i), _nat(j), _nat(rows), _nat(cols)
    if top + height > matrix.shape[0] or left + width > matrix.shape[1]:
        raise ValueError(
            f"block of {height}x{width} at ({top}, {left}) does not fit in {describe(matrix)}"
        )
    return frozen(matrix[top : top + height, left : left + width])


def _skew_matrix(v: Vec) -> Vec:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _skew(v: Value) -> Vec:
    """The cross-product matrix: ``skew(v) * u == cross(v, u)``."""
    return frozen(_skew_matrix(_vector(v, 3)))


def _cross(u: Value, v: Value) -> Vec:
    return frozen(np.cross(_vector(u, 3), _vector(v, 3)))


def _dot(u: Value, v: Value) -> float:
    a, b = _vector(u), _vector(v)
    if a.shape != b.shape:
        raise ValueError(f"needs vectors of one size, not {describe(a)} and {describe(b)}")
    return float(a @ b)


def _norm(v: Value) -> float:
    return float(np.linalg.norm(_vector(v)))


def _rot(w: Value, theta: Value) -> Vec:
    """Rodrigues' formula, ``I + sin θ [w] + (1 - cos θ) [w]²`` (Modern Robotics eq. 3.51)."""
    k = _skew_matrix(_vector(w, 3))
    angle = _real(theta)
    return frozen(np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k))


def _screw_axis(w: Value, v: Value) -> Vec:
    return frozen(np.concatenate((_vector(w, 3), _vector(v, 3))))


def _adjoint(t: Value) -> Vec:
    """``[Ad_T] = [| R, 0; skew(p) R, R |]`` of ``T = (R, p)`` (Modern Robotics def. 3.20)."""
    transform = _matrix(t, size=4)
    r, p = transform[:3, :3], transform[:3, 3]
    return frozen(np.block([[r, np.zeros((3, 3))], [_skew_matrix(p) @ r, r]]))


def _ad(twist: Value) -> Vec:
    """``[ad_V] = [| skew(w), 0; skew(v), skew(w) |]`` of ``V = (w; v)`` (MR eq. 8.38)."""
    vector = _vector(twist, 6)
    w, v = _skew_matrix(vector[:3]), _skew_matrix(vector[3:])
    return frozen(np.block([[w, np.zeros((3, 3))], [v, w]]))


MATH_FUNCTIONS: Mapping[str, Callable[..., Value]] = MappingProxyType(
    {
        "sin": _unary_real(math.sin),
        "cos": _unary_real(math.cos),
        "tan": _unary_real(math.tan),
        "asin": _asin,
        "acos": _acos,
        "atan": _unary_real(math.atan),
        "atan2": _atan2,
        "sqrt": _sqrt,
        "exp": _unary_real(math.exp),
        "log": _log,
        "abs": _abs,
        "sgn": _sgn,
        "transpose": _transpose,
        # The library's adj is the (conjugate) transpose of spatial operator algebra.
        "adj": _transpose,
        "inverse": _inverse,
        "det": _det,
        "identity": _identity,
        "zeroes": _zeroes,
        "submatrix": _submatrix,
        "skew": _skew,
        "cross": _cross,
        "dot": _dot,
        "norm": _norm,
        "Rot": _rot,
        "ScrewAxis": _screw_axis,
        "Adjoint": _adjoint,
        "ad": _ad,
    }
)
"""The functions of ``physmod::math`` (library/physmod/math.rsm), by name. ``PI`` is not here: it
is a constant, and whether it is the library's exact π or a model's own ``3.1415`` is the
caller's choice, made when it builds ``env``."""


@functools.cache
def arity(fn: Callable[..., Value]) -> inspect.Signature | None:
    """The signature to check argument counts against, or None for a callable without one.
    Remembered: ``inspect.signature`` costs more than most calls it guards."""
    try:
        return inspect.signature(fn)
    except (TypeError, ValueError):
        return None


def arity_text(signature: inspect.Signature) -> str:
    positional = [
        p
        for p in signature.parameters.values()
        if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
    ]
    required = sum(p.default is p.empty for p in positional)
    if any(p.kind is p.VAR_POSITIONAL for p in signature.parameters.values()):
        return f"at least {required} argument{'s' * (required != 1)}"
    if required == len(positional):
        return f"{required} argument{'s' * (required != 1)}"
    return f"{required} to {len(positional)} arguments"
