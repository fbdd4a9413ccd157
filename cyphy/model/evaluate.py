"""Numeric evaluation of constant expressions (sdf.md decision 5, notation.md A.11).

SDF needs numbers where a model writes expressions: ``(0.085*cos(2*i*PI/24))m``, ``HEIGHT/2``,
``[| 0, -Axis[3], Axis[2]; … |]``. RoboTool prints 0 for every call and ignores unit suffixes;
this module evaluates them properly.

Values (:data:`Value`):

* ``int`` and ``float`` are the notation's ``int``/``nat`` and ``real``. An integer literal is an
  ``int``, any other literal a ``float``; ``+ - * %`` and ``^`` with a non-negative exponent keep
  two ints an int (so ``2*3`` is ``6``, an exact index or count); ``/`` is real division, always
  a float (``7/2 == 3.5``, ``6/2 == 3.0``); ``%`` is Python's remainder, whose sign follows the
  divisor as Isabelle's ``mod`` does. A quantity with a unit (``3cm``) is a real.
* ``bool`` and ``str`` are ``boolean`` and ``string``; they take part in comparisons, connectives
  and conditions only, never in arithmetic (Python's ``True + 1`` is refused).
* :data:`Vec`, a read-only ``float64`` NumPy array: 1-D for ``(|a, b, c|)`` and a single-row
  ``[|a, b, c|]``, 2-D for several rows (``[|1; 2; 3|]`` is a 3x1 matrix). Entries are reals.
  Arrays are frozen (``writeable = False``) so a value shared through ``env`` cannot be changed
  behind the caller's back. A 1-D vector acts as a column in ``M * v`` and as a row in ``v * M``.

Indexing counts from 1, as RoboChart and the library do (``Axis[3]`` is the z component of
``Axis = (|1, 0, 0|)``): ``v[i]`` is a component, ``M[i, j]`` an entry, ``M[i]`` row ``i``.
``submatrix`` alone counts from 0, because the library declares it so.

Every problem with the input (an unknown name, division by zero, ``sqrt(-1)``, a wrong number of
arguments, a condition that is not a boolean, a derivative…) raises :class:`EvalError` with the
span of the offending node; nothing else escapes :func:`evaluate`. Internally, operators and
functions raise ``ValueError`` without a location and the node that called them turns it into an
``EvalError`` with its own span, so every check is written once and still points at the source.

This module must stay cheap to import: NumPy yes, SymPy no.
"""

from __future__ import annotations

import functools
import inspect
import math
import sys
import numbers
from types import MappingProxyType
from typing import Callable, Mapping, TypeAlias, Union

import numpy as np
from numpy.typing import NDArray

from cyphy.diagnostics import Span, did_you_mean
from cyphy.model.units import units
from cyphy.expr import (
    BinOp,
    Bool,
    Call,
    Derivative,
    Expr,
    IfExpr,
    Index,
    Integral,
    Matrix,
    Member,
    Name,
    Num,
    Quantity,
    Record,
    Seq,
    Str,
    UnaryOp,
    Vector,
    path_of,
)

Vec: TypeAlias = NDArray[np.float64]
Value: TypeAlias = Union[float, int, bool, str, Vec]

_NO_SPAN = Span.unknown()

MAX_INT_BITS = 100_000
"""Largest integer a power may produce: beyond it ``10^10^10`` would hang the tool."""


class EvalError(Exception):
    """An expression that has no value: ``message`` says why, ``span`` is the offending node's."""

    def __init__(self, message: str, span: Span, hint: str = "") -> None:
        super().__init__(message)
        self.message = message
        self.span = span
        self.hint = hint


class UnboundName(EvalError):
    """A name with no value in ``env``; ``name`` lets the caller list every missing constant."""

    def __init__(self, name: str, span: Span, hint: str = "") -> None:
        super().__init__(f"'{name}' has no value", span, hint)
        self.name = name


class _Invalid(ValueError):
    """A ``ValueError`` with a hint; like any other, the node that catches it adds the span."""

    def __init__(self, message: str, hint: str) -> None:
        super().__init__(message)
        self.hint = hint


# --------------------------------------------------------------------------- values


def _is_number(value: object) -> bool:
    """True for ints and floats; bools are Python ints but are not numbers here."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _frozen(data: object) -> Vec:
    """A read-only float copy of ``data``: values are immutable however they were computed."""
    array = np.array(data, dtype=np.float64)
    array.flags.writeable = False
    return array


def describe(value: object) -> str:
    """What a value is, for messages: ``a 3-vector``, ``the boolean true``, ``the real 2.5``."""
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    if isinstance(value, int):
        return f"the integer {value}"
    if isinstance(value, float):
        return f"the real {value:g}"
    if isinstance(value, str):
        return f"the string {value!r}"
    shape = getattr(value, "shape", ())
    if len(shape) == 1:
        return f"a {shape[0]}-vector"
    if len(shape) == 2:
        return f"a {shape[0]}x{shape[1]} matrix"
    return "a value"


def _from_env(name: str, value: object) -> Value:
    """An ``env`` entry as a :data:`Value`: NumPy scalars become Python ones, arrays frozen."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if isinstance(value, np.ndarray) and value.ndim in (1, 2) and value.dtype.kind in "iuf":
        return _frozen(value)
    raise ValueError(
        f"the value given for '{name}' ({type(value).__name__}) is not a number, boolean, "
        "string, vector or matrix"
    )


def literal_value(text: str) -> int | float:
    """The value of a numeric literal. One beyond the range of a double (``1e309``, a
    400-digit integer) is an error, not infinity: every later computation and SDF would
    carry it (ValueError)."""
    try:
        value: int | float = int(text) if text.isdigit() else float(text)
        if not math.isfinite(float(value)):
            raise OverflowError
    except (OverflowError, ValueError):
        shown = text if len(text) <= 24 else text[:20] + "…"
        raise ValueError(f"the number {shown} is too large (beyond ±1.8e308)") from None
    return value


_LARGEST = int(sys.float_info.max)


def _require_finite(value: Value) -> None:
    """Overflow and NaN are errors, not values: SDF has no way to write ``inf``."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError("the result is not a finite number (overflow)")
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > _LARGEST:
        raise ValueError("the result is too large (beyond ±1.8e308)")
    if isinstance(value, np.ndarray) and not np.all(np.isfinite(value)):
        raise ValueError("the result has an entry that is not a finite number (overflow)")


def _operand(op: str, value: Value) -> Value:
    """``value`` if it may take part in arithmetic (a number or an array)."""
    if _is_number(value) or isinstance(value, np.ndarray):
        return value
    raise ValueError(f"'{op}' needs numbers, vectors or matrices, not {describe(value)}")


def _scalar(what: str, value: Value) -> int | float:
    if not _is_number(value):
        raise ValueError(f"{what} must be a number, not {describe(value)}")
    return value  # type: ignore[return-value]


def _integer(what: str, value: Value) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{what} must be an integer, not {describe(value)}")
    return value


def _boolean(what: str, value: Value) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"{what} must be a boolean, not {describe(value)}")
    return value


# --------------------------------------------------------------------------- operators


def _mismatch(op: str, a: Value, b: Value) -> ValueError:
    return ValueError(f"'{op}' cannot combine {describe(a)} and {describe(b)}")


def _add(a: Value, b: Value) -> Value:
    a, b = _operand("+", a), _operand("+", b)
    if _is_number(a) and _is_number(b):
        return a + b  # type: ignore[operator]
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.shape == b.shape:
        return _frozen(a + b)
    raise _mismatch("+", a, b)


def _sub(a: Value, b: Value) -> Value:
    a, b = _operand("-", a), _operand("-", b)
    if _is_number(a) and _is_number(b):
        return a - b  # type: ignore[operator]
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.shape == b.shape:
        return _frozen(a - b)
    raise _mismatch("-", a, b)


def _mul(a: Value, b: Value) -> Value:
    """Scalars multiply, a scalar scales an array, and two arrays take the matrix product."""
    a, b = _operand("*", a), _operand("*", b)
    if _is_number(a) or _is_number(b):
        product = a * b  # type: ignore[operator]
        return product if _is_number(product) else _frozen(product)
    assert isinstance(a, np.ndarray) and isinstance(b, np.ndarray)
    if a.ndim == 1 and b.ndim == 1:
        raise _Invalid(
            f"'*' cannot multiply two vectors ({describe(a)} and {describe(b)})",
            "use dot(u, v) for the scalar product or cross(u, v) for the vector product",
        )
    inner_a = a.shape[-1]
    inner_b = b.shape[0]
    if inner_a != inner_b:
        raise ValueError(
            f"'*' cannot multiply {describe(a)} by {describe(b)}: {inner_a} columns against "
            f"{inner_b} rows"
        )
    return _frozen(a @ b)


def _div(a: Value, b: Value) -> Value:
    """Real division: ``7/2`` is 3.5 (sdf.md decision 5); only a scalar may divide."""
    a, b = _operand("/", a), _operand("/", b)
    if not _is_number(b):
        raise _mismatch("/", a, b)
    if b == 0:
        raise ValueError("division by zero")
    quotient = a / b  # type: ignore[operator]
    return quotient if _is_number(quotient) else _frozen(quotient)


def _mod(a: Value, b: Value) -> Value:
    a, b = _scalar("an operand of '%'", a), _scalar("an operand of '%'", b)
    if b == 0:
        raise ValueError("division by zero in '%'")
    return a % b


def _pow(a: Value, b: Value) -> Value:
    """``x^y`` on numbers; ``M^n`` is the matrix power of a square matrix (n may be negative)."""
    a, b = _operand("^", a), _operand("^", b)
    if isinstance(a, np.ndarray):
        if a.ndim != 2 or a.shape[0] != a.shape[1]:
            raise ValueError(f"only a square matrix can be raised to a power, not {describe(a)}")
        n = _integer("the exponent of a matrix", b)
        try:
            return _frozen(np.linalg.matrix_power(a, n))
        except np.linalg.LinAlgError:
            raise ValueError("a singular matrix has no negative power") from None
    b = _scalar("an exponent", b)
    if a == 0 and b < 0:
        raise ValueError("zero cannot be raised to a negative power (division by zero)")
    if isinstance(a, int) and isinstance(b, int):
        if b > 0 and abs(a) > 1 and b * math.log2(abs(a)) > MAX_INT_BITS:
            raise ValueError(f"{a}^{b} is too large to compute")
        return a**b
    if a < 0 and not float(b).is_integer():
        raise ValueError(f"a negative number ({a:g}) has no real power {b:g}")
    return a**b


def _equal(a: Value, b: Value) -> bool:
    """Equality of values of one kind; numbers compare across int and real."""
    if _is_number(a) and _is_number(b):
        return a == b
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray):
        return a.shape == b.shape and bool(np.array_equal(a, b))
    if type(a) is type(b) and isinstance(a, (bool, str)):
        return a == b
    raise ValueError(f"cannot compare {describe(a)} with {describe(b)}")


def _ordered(op: str, test: Callable[[float, float], bool]) -> Callable[[Value, Value], bool]:
    def compare(a: Value, b: Value) -> bool:
        if isinstance(a, bool):
            raise _Invalid(
                f"'{op}' cannot order {describe(a)}",
                "comparisons do not chain: write a < b /\\ b < c",
            )
        return test(_scalar(f"an operand of '{op}'", a), _scalar(f"an operand of '{op}'", b))

    return compare


_STRICT_OPS: Mapping[str, Callable[[Value, Value], Value]] = MappingProxyType(
    {
        "+": _add,
        "-": _sub,
        "*": _mul,
        "/": _div,
        "%": _mod,
        "^": _pow,
        # RoboTool's models write `cat` for a power (`AxisMatrix cat 2`, notation.md A.11).
        "cat": _pow,
        "==": _equal,
        "!=": lambda a, b: not _equal(a, b),
        "<": _ordered("<", lambda a, b: a < b),
        "<=": _ordered("<=", lambda a, b: a <= b),
        ">": _ordered(">", lambda a, b: a > b),
        ">=": _ordered(">=", lambda a, b: a >= b),
        "<=>": lambda a, b: _boolean("an operand of '<=>'", a) == _boolean("an operand", b),
    }
)
"""Operators that evaluate both operands. Comparisons do not chain: ``a < b < c`` is
``(a < b) < c`` as the tree says, an error (a boolean is not ordered)."""

_SHORT_CIRCUIT: Mapping[str, tuple[bool, bool]] = MappingProxyType(
    {"/\\": (False, False), "\\/": (True, True), "=>": (False, True)}
)
"""Connectives as (left value that settles them, their value then). A settled connective does not
evaluate its right operand, so ``x != 0 /\\ 1/x > 2`` is false, not an error, at ``x = 0``."""


# --------------------------------------------------------------------------- units

UNIT_FACTORS: Mapping[str, float] = MappingProxyType(
    {name: unit.factor for name, unit in units().items()})
"""SI factor of each unit suffix the grammar accepts (from Pint, ``cyphy/model/units.py``): a
quantity is its value times the factor."""


# --------------------------------------------------------------------------- math functions
# Library functions (physmod::math) on Values. They raise ValueError with a message that reads
# after the function's name ("sqrt is undefined for ..."); the evaluator adds name and span.


def _number(value: Value) -> int | float:
    if not _is_number(value):
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
        return _frozen(m[np.newaxis, :])
    return _frozen(_matrix(m).T)


def _inverse(m: Value) -> Vec:
    try:
        return _frozen(np.linalg.inv(_matrix(m, square=True)))
    except np.linalg.LinAlgError:
        raise ValueError("needs an invertible matrix; this one is singular") from None


def _det(m: Value) -> float:
    return float(np.linalg.det(_matrix(m, square=True)))


def _identity(n: Value) -> Vec:
    return _frozen(np.eye(_nat(n)))


def _zeroes(m: Value, n: Value | None = None) -> Vec:
    """``zeroes(m, n)`` is m-by-n; ``zeroes(n)`` is n-by-n, as ``identity(n)`` (and MATLAB)."""
    rows = _nat(m)
    return _frozen(np.zeros((rows, rows if n is None else _nat(n))))


def _submatrix(m: Value, i: Value, j: Value, rows: Value, cols: Value) -> Vec:
    """The block at row ``i``, column ``j`` counted from 0, as the library declares."""
    matrix = _matrix(m)
    top, left, height, width = _nat(i), _nat(j), _nat(rows), _nat(cols)
    if top + height > matrix.shape[0] or left + width > matrix.shape[1]:
        raise ValueError(
            f"block of {height}x{width} at ({top}, {left}) does not fit in {describe(matrix)}"
        )
    return _frozen(matrix[top : top + height, left : left + width])


def _skew_matrix(v: Vec) -> Vec:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _skew(v: Value) -> Vec:
    """The cross-product matrix: ``skew(v) * u == cross(v, u)``."""
    return _frozen(_skew_matrix(_vector(v, 3)))


def _cross(u: Value, v: Value) -> Vec:
    return _frozen(np.cross(_vector(u, 3), _vector(v, 3)))


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
    return _frozen(np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k))


def _screw_axis(w: Value, v: Value) -> Vec:
    return _frozen(np.concatenate((_vector(w, 3), _vector(v, 3))))


def _adjoint(t: Value) -> Vec:
    """``[Ad_T] = [| R, 0; skew(p) R, R |]`` of ``T = (R, p)`` (Modern Robotics def. 3.20)."""
    transform = _matrix(t, size=4)
    r, p = transform[:3, :3], transform[:3, 3]
    return _frozen(np.block([[r, np.zeros((3, 3))], [_skew_matrix(p) @ r, r]]))


def _ad(twist: Value) -> Vec:
    """``[ad_V] = [| skew(w), 0; skew(v), skew(w) |]`` of ``V = (w; v)`` (MR eq. 8.38)."""
    vector = _vector(twist, 6)
    w, v = _skew_matrix(vector[:3]), _skew_matrix(vector[3:])
    return _frozen(np.block([[w, np.zeros((3, 3))], [v, w]]))


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
def _arity(fn: Callable[..., Value]) -> inspect.Signature | None:
    """The signature to check argument counts against, or None for a callable without one.
    Remembered: ``inspect.signature`` costs more than most calls it guards."""
    try:
        return inspect.signature(fn)
    except (TypeError, ValueError):
        return None


def _arity_text(signature: inspect.Signature) -> str:
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


# --------------------------------------------------------------------------- evaluation


_METHOD_NAMES: dict[type, str] = {}
"""The ``_eval_`` method of each node class, found once along its MRO."""


class _Evaluator:
    """Evaluates one expression: ``_eval_<Class>`` per node class, found along the MRO."""

    def __init__(self, env: Mapping[str, object], functions: Mapping[str, Callable[..., Value]]):
        self.env = env
        self.functions = functions

    def eval(self, node: Expr) -> Value:
        """Evaluate ``node``; a ``ValueError`` or arithmetic error raised for it, but not yet
        located, becomes an :class:`EvalError` with this node's span."""
        name = _METHOD_NAMES.get(type(node))
        if name is None:
            name = next("_eval_" + cls.__name__ for cls in type(node).__mro__
                        if hasattr(self, "_eval_" + cls.__name__))
            _METHOD_NAMES[type(node)] = name
        method = getattr(self, name)
        try:
            value = method(node)
            _require_finite(value)
            return value
        except (ValueError, ArithmeticError) as err:
            if isinstance(err, ZeroDivisionError):
                message = "division by zero"
            elif isinstance(err, OverflowError):
                message = "numeric overflow: the result is too large"
            elif isinstance(err, ArithmeticError):
                message = f"numeric error: {err}"
            else:
                message = str(err)
            raise EvalError(message, node.span, getattr(err, "hint", "")) from None

    def _eval_Expr(self, node: Expr) -> Value:
        raise ValueError(f"{type(node).__name__} expressions cannot be evaluated to a number")

    def _eval_Num(self, node: Num) -> Value:
        return literal_value(node.text)

    def _eval_Str(self, node: Str) -> Value:
        return node.value

    def _eval_Bool(self, node: Bool) -> Value:
        return node.value

    def _lookup(self, name: str, span: Span) -> Value:
        if name not in self.env:
            raise UnboundName(name, span, did_you_mean(name, self.env))
        return _from_env(name, self.env[name])

    def _eval_Name(self, node: Name) -> Value:
        return self._lookup(node.text, node.span)

    def _eval_Member(self, node: Member) -> Value:
        """A path ``a.b`` is the name ``a::b``: ``.`` and ``::`` navigate alike (A.12.6)."""
        path = path_of(node)
        if path is None:
            raise ValueError(f"field '{node.name}' of a computed value cannot be evaluated")
        return self._lookup("::".join(path), node.span)

    def _eval_Quantity(self, node: Quantity) -> Value:
        factor = UNIT_FACTORS.get(node.unit)
        if factor is None:
            raise _Invalid(
                f"unknown unit '{node.unit}'", "known units: " + ", ".join(sorted(UNIT_FACTORS))
            )
        value = _operand(node.unit, self.eval(node.value))
        return float(value) * factor if _is_number(value) else _frozen(value * factor)

    def _eval_UnaryOp(self, node: UnaryOp) -> Value:
        operand = self.eval(node.operand)
        if node.op == "not":
            return not _boolean("the operand of 'not'", operand)
        value = _operand("-", operand)
        return -value if _is_number(value) else _frozen(-value)  # type: ignore[operator]

    def _eval_BinOp(self, node: BinOp) -> Value:
        left = self.eval(node.left)
        if node.op in _SHORT_CIRCUIT:
            settling, result = _SHORT_CIRCUIT[node.op]
            if _boolean(f"an operand of '{node.op}'", left) == settling:
                return result
            return _boolean(f"an operand of '{node.op}'", self.eval(node.right))
        operator = _STRICT_OPS.get(node.op)
        if operator is None:
            raise ValueError(f"unknown operator '{node.op}'")
        return operator(left, self.eval(node.right))

    def _eval_IfExpr(self, node: IfExpr) -> Value:
        """Only the chosen branch is evaluated: ``if x > 0 then sqrt(x) else 0 end`` is safe."""
        condition = _boolean("the condition of 'if'", self.eval(node.cond))
        return self.eval(node.then if condition else node.orelse)

    def _eval_Vector(self, node: Vector | Matrix) -> Value:
        rows = [[self.eval(item) for item in row] for row in node.rows]
        for row in rows:
            for item in row:
                _scalar("a vector or matrix entry", item)
        widths = sorted({len(row) for row in rows})
        if len(widths) > 1:
            raise ValueError(f"the rows of a matrix have different lengths ({widths})")
        return _frozen(rows[0] if len(rows) == 1 else rows)

    _eval_Matrix = _eval_Vector

    def _eval_Index(self, node: Index) -> Value:
        """1-based, as RoboChart: ``v[1]`` is the first component, ``M[i]`` row ``i``."""
        base = self.eval(node.base)
        positions = [self.eval(arg) for arg in node.args]
        if not isinstance(base, np.ndarray):
            raise ValueError(f"only vectors and matrices can be indexed, not {describe(base)}")
        if len(positions) > base.ndim:
            raise ValueError(f"{describe(base)} takes at most {base.ndim} index(es)")
        offsets = []
        for position, size in zip(positions, base.shape):
            i = _integer("an index", position)
            if not 1 <= i <= size:
                raise ValueError(f"index {i} is out of range 1..{size} for {describe(base)}")
            offsets.append(i - 1)
        item = base[tuple(offsets)]
        return float(item) if np.ndim(item) == 0 else _frozen(item)

    def _eval_Call(self, node: Call) -> Value:
        """A call of a named function; a curried ``f(a)(b, c)`` is ``f(a, b, c)`` (that is how
        the models write ``submatrix(M)(0, 0, 3, 3)``)."""
        func, args = node.func, node.args
        while isinstance(func, Call):
            func, args = func.func, func.args + args
        if not isinstance(func, Name):
            raise ValueError("only a named function can be called")
        name = func.text
        fn = self.functions.get(name)
        if fn is None:
            if name in self.env:
                raise ValueError(f"'{name}' is a constant, not a function")
            raise _Invalid(f"unknown function '{name}'", did_you_mean(name, self.functions))
        values = [self.eval(arg) for arg in args]
        signature = _arity(fn)
        if signature is not None:
            try:
                signature.bind(*values)
            except TypeError:
                raise ValueError(
                    f"{name} takes {_arity_text(signature)}, got {len(values)}"
                ) from None
        try:
            return fn(*values)
        except ValueError as err:
            raise _Invalid(f"{name} {err}", getattr(err, "hint", "")) from None

    def _eval_Derivative(self, node: Derivative) -> Value:
        raise ValueError("a derivative has no constant value")

    def _eval_Integral(self, node: Integral) -> Value:
        raise ValueError("an integral has no constant value")

    def _eval_Seq(self, node: Seq) -> Value:
        raise ValueError("a sequence cannot be used as a number")

    def _eval_Record(self, node: Record) -> Value:
        raise ValueError(f"a record ({'::'.join(node.type_name)}) cannot be used as a number")


def evaluate(
    expr: Expr,
    env: Mapping[str, object],
    functions: Mapping[str, Callable[..., Value]] | None = None,
) -> Value:
    """The value of ``expr``; raises :class:`EvalError` (never anything else) when it has none.

    Names are looked up in ``env`` by their text (``"::".join(parts)``; a path ``a.b`` as
    ``a::b``), so the caller decides which spellings a constant answers to (``HEIGHT`` and
    ``Treel::HEIGHT``) and which ``PI`` applies. ``env`` values may be Python or NumPy numbers,
    booleans, strings and 1-D or 2-D arrays. A missing name raises :class:`UnboundName`.
    ``functions`` are merged over :data:`MATH_FUNCTIONS`; a function gets evaluated arguments and
    signals bad input with ``ValueError`` (its message reads after the function's name).
    Evaluation recurses, so nesting deeper than a few hundred levels raises ``EvalError`` too;
    constant expressions are far shallower.
    """
    table = {**MATH_FUNCTIONS, **functions} if functions else MATH_FUNCTIONS
    evaluator = _Evaluator(env, table)
    try:
        with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
            return evaluator.eval(expr)
    except RecursionError:
        raise EvalError("the expression is too deeply nested to evaluate", expr.span) from None


Compiled = Callable[[Mapping[str, object]], Value]
_COMPILED: dict[int, tuple[Expr, Compiled | None]] = {}


def _compile(node: Expr) -> Compiled | None:
    """A closure computing ``node`` with the interpreter's own operations, for the node kinds
    that dominate repeated evaluation (poses of indexed blocks); None for anything else."""
    if isinstance(node, Num):
        try:
            value: Value = literal_value(node.text)
        except ValueError:
            return None  # the interpreter reports it
        return lambda env: value
    if isinstance(node, Name):
        key = node.text
        return lambda env: _from_env(key, env[key])
    if isinstance(node, Quantity):
        inner, factor = _compile(node.value), UNIT_FACTORS.get(node.unit)
        if inner is None or factor is None:
            return None
        unit = node.unit
        return lambda env: float(_scalar(unit, inner(env))) * factor
    if isinstance(node, UnaryOp) and node.op == "-":
        operand = _compile(node.operand)
        if operand is None:
            return None
        return lambda env: -_scalar("-", operand(env))
    if isinstance(node, BinOp) and node.op in _STRICT_OPS:
        left, right, op = _compile(node.left), _compile(node.right), _STRICT_OPS[node.op]
        if left is None or right is None:
            return None
        return lambda env: op(left(env), right(env))
    if isinstance(node, Call) and isinstance(node.func, Name) \
            and node.func.text in MATH_FUNCTIONS:
        args = [_compile(a) for a in node.args]
        if any(a is None for a in args):
            return None
        fn = MATH_FUNCTIONS[node.func.text]
        return lambda env: fn(*[a(env) for a in args])  # type: ignore[misc]
    return None


def evaluate_fast(expr: Expr, env: Mapping[str, object]) -> Value:
    """:func:`evaluate` with the library's functions, compiling the expression once (cached by
    identity) for when the same expression is evaluated many times. Any failure re-runs the
    interpreter, which raises the precise :class:`EvalError`."""
    hit = _COMPILED.get(id(expr))
    if hit is None or hit[0] is not expr:
        if len(_COMPILED) > 8192:
            _COMPILED.clear()
        hit = (expr, _compile(expr))
        _COMPILED[id(expr)] = hit
    compiled = hit[1]
    if compiled is not None:
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
                value = compiled(env)
            _require_finite(value)
            return value
        except Exception:  # noqa: BLE001 - the interpreter says exactly what is wrong
            pass
    return evaluate(expr, env)


def free_names(expr: Expr) -> set[str]:
    """The names ``expr`` needs from ``env``: every name and path, except functions called.

    Iterative, like :meth:`Expr.walk`, because generated expressions can be very deep.
    """
    names: set[str] = set()
    stack = [expr]
    while stack:
        node = stack.pop()
        if isinstance(node, Call):
            stack.extend(node.args)
            if not isinstance(node.func, Name):
                stack.append(node.func)
            continue
        path = path_of(node)
        if path is not None:
            names.add("::".join(path))
        else:
            stack.extend(node.children())
    return names


PRIMITIVE_TYPES = frozenset({"real", "int", "nat", "boolean", "string"})


def coerce(value: Value, declared: str, span: Span = _NO_SPAN) -> Value:
    """``value`` as a constant of the primitive type ``declared`` holds it.

    A ``real`` set to ``7`` is ``7.0`` (sdf.md decision 5); an ``int``/``nat`` accepts a real only
    when it is whole (``4.0`` → ``4``), a ``nat`` only when it is not negative; ``boolean`` and
    ``string`` take only their own kind. A mismatch raises :class:`EvalError` at ``span``;
    ``declared`` outside :data:`PRIMITIVE_TYPES` is a programming error (``ValueError``).
    """
    if declared not in PRIMITIVE_TYPES:
        raise ValueError(f"coerce knows the primitive types only, not {declared!r}")
    if declared == "real" and _is_number(value):
        try:
            return float(value)
        except OverflowError:
            raise EvalError("the value is too large for a real", span) from None
    if declared in ("int", "nat") and _is_number(value):
        whole = isinstance(value, int) or float(value).is_integer()
        if not whole:
            raise EvalError(
                f"an {declared} constant must be a whole number, not {describe(value)}",
                span,
                "declare the constant real, or give it a whole number",
            )
        if declared == "nat" and value < 0:
            raise EvalError(f"a nat constant cannot be negative ({value})", span)
        return int(value)
    if declared == "boolean" and isinstance(value, bool):
        return value
    if declared == "string" and isinstance(value, str):
        return value
    raise EvalError(f"a {declared} constant cannot hold {describe(value)}", span)
