"""The library functions of ``physmod::math`` (``sin``, ``Rot``, ``Adjoint``…) on
:data:`~cyphy.model.values.Value`, and the argument counts the evaluator checks calls
against."""

from __future__ import annotations

import functools
import inspect
import math
from types import MappingProxyType
from typing import Callable, Mapping

from cyphy.model.array import Array, from_numpy, matrix, numpy_array, strict_numpy, vector
from cyphy.model.values import Value, Vec, describe, is_number

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
    if not isinstance(value, Array) or value.ndim != 1:
        raise ValueError(f"expects a vector, not {describe(value)}")
    if size is not None and value.shape[0] != size:
        raise ValueError(f"expects a {size}-vector, not {describe(value)}")
    return value


def _matrix(value: Value, square: bool = False, size: int | None = None) -> Vec:
    if not isinstance(value, Array) or value.ndim != 2:
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
    if isinstance(m, Array) and m.ndim == 1:
        return Array(m.flat, (1, m.shape[0]))
    return _matrix(m).T


def _inverse(m: Value) -> Vec:
    square = _matrix(m, square=True)
    with strict_numpy() as np:  # LAPACK's inverse, as every output was written with
        try:
            return from_numpy(np.linalg.inv(numpy_array(square)))
        except np.linalg.LinAlgError:
            raise ValueError("needs an invertible matrix; this one is singular") from None


def _det(m: Value) -> float:
    square = _matrix(m, square=True)
    with strict_numpy() as np:  # LAPACK's determinant, as every output was written with
        return float(np.linalg.det(numpy_array(square)))


def _identity(n: Value) -> Vec:
    size = _nat(n)
    return Array(tuple(1.0 if i == j else 0.0 for i in range(size) for j in range(size)),
                 (size, size))


def _zeroes(m: Value, n: Value | None = None) -> Vec:
    """``zeroes(m, n)`` is m-by-n; ``zeroes(n)`` is n-by-n, as ``identity(n)`` (and MATLAB)."""
    rows = _nat(m)
    cols = rows if n is None else _nat(n)
    return Array((0.0,) * (rows * cols), (rows, cols))


def _submatrix(m: Value, i: Value, j: Value, rows: Value, cols: Value) -> Vec:
    """The block at row ``i``, column ``j`` counted from 0, as the library declares."""
    matrix = _matrix(m)
    top, left, height, width = _nat(i), _nat(j), _nat(rows), _nat(cols)
    if top + height > matrix.shape[0] or left + width > matrix.shape[1]:
        raise ValueError(
            f"block of {height}x{width} at ({top}, {left}) does not fit in {describe(matrix)}"
        )
    return matrix[top : top + height, left : left + width]


def _skew_matrix(v: Vec) -> Vec:
    x, y, z = v
    return matrix(((0.0, -z, y), (z, 0.0, -x), (-y, x, 0.0)))


def _skew(v: Value) -> Vec:
    """The cross-product matrix: ``skew(v) * u == cross(v, u)``."""
    return _skew_matrix(_vector(v, 3))


def _cross(u: Value, v: Value) -> Vec:
    """Each entry one difference of two products, as NumPy's ``cross`` computes it."""
    (a1, a2, a3), (b1, b2, b3) = _vector(u, 3), _vector(v, 3)
    return vector((a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1))


def _dot(u: Value, v: Value) -> float:
    a, b = _vector(u), _vector(v)
    if a.shape != b.shape:
        raise ValueError(f"needs vectors of one size, not {describe(a)} and {describe(b)}")
    with strict_numpy():  # BLAS's sum, as every output was written with
        return float(numpy_array(a) @ numpy_array(b))


def _norm(v: Value) -> float:
    entries = _vector(v)
    with strict_numpy() as np:  # NumPy's sum of squares, as every output was written with
        return float(np.linalg.norm(numpy_array(entries)))


def _rot(w: Value, theta: Value) -> Vec:
    """Rodrigues' formula, ``I + sin θ [w] + (1 - cos θ) [w]²`` (Modern Robotics eq. 3.51)."""
    skew, angle = _skew_matrix(_vector(w, 3)), _real(theta)
    with strict_numpy() as np:  # [w]² is a matrix product: NumPy's rounding
        k = numpy_array(skew)
        return from_numpy(np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k))


def _screw_axis(w: Value, v: Value) -> Vec:
    return vector(_vector(w, 3).flat + _vector(v, 3).flat)


def _blocks(top: tuple[Vec, Vec], bottom: tuple[Vec, Vec]) -> Vec:
    """The 6x6 matrix ``[| a, b; c, d |]`` of four 3x3 blocks."""
    return matrix([left + right for pair in (top, bottom)
                   for left, right in zip(pair[0].rows(), pair[1].rows())])


_ZERO3 = Array((0.0,) * 9, (3, 3))


def _adjoint(t: Value) -> Vec:
    """``[Ad_T] = [| R, 0; skew(p) R, R |]`` of ``T = (R, p)`` (Modern Robotics def. 3.20)."""
    transform = _matrix(t, size=4)
    r, p = transform[:3, :3], transform[:3, 3]
    with strict_numpy():  # a matrix product: NumPy's rounding
        turned = from_numpy(numpy_array(_skew_matrix(p)) @ numpy_array(r))
    return _blocks((r, _ZERO3), (turned, r))


def _ad(twist: Value) -> Vec:
    """``[ad_V] = [| skew(w), 0; skew(v), skew(w) |]`` of ``V = (w; v)`` (MR eq. 8.38)."""
    entries = _vector(twist, 6)
    w, v = _skew_matrix(entries[:3]), _skew_matrix(entries[3:])
    return _blocks((w, _ZERO3), (v, w))


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
