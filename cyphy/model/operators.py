"""The operators of constant expressions on :data:`~cyphy.model.values.Value`: arithmetic on
numbers, vectors and matrices, comparisons, and the short-circuit connectives. Each raises
``ValueError`` without a location; the evaluator's node adds its span."""

from __future__ import annotations

import math
import operator
from types import MappingProxyType
from typing import Callable, Mapping

from cyphy.model.array import Array, from_numpy, numpy_array, strict_numpy
from cyphy.model.values import (
    MAX_INT_BITS,
    Invalid,
    Value,
    arithmetic,
    boolean,
    describe,
    integer,
    is_number,
    scalar,
)

def _mismatch(op: str, a: Value, b: Value) -> ValueError:
    return ValueError(f"'{op}' cannot combine {describe(a)} and {describe(b)}")


def _add(a: Value, b: Value) -> Value:
    a, b = arithmetic("+", a), arithmetic("+", b)
    if is_number(a) and is_number(b):
        return a + b  # type: ignore[operator]
    if isinstance(a, Array) and isinstance(b, Array) and a.shape == b.shape:
        return a.zip_with(b, operator.add)
    raise _mismatch("+", a, b)


def _sub(a: Value, b: Value) -> Value:
    a, b = arithmetic("-", a), arithmetic("-", b)
    if is_number(a) and is_number(b):
        return a - b  # type: ignore[operator]
    if isinstance(a, Array) and isinstance(b, Array) and a.shape == b.shape:
        return a.zip_with(b, operator.sub)
    raise _mismatch("-", a, b)


def _mul(a: Value, b: Value) -> Value:
    """Scalars multiply, a scalar scales an array, and two arrays take the matrix product
    (NumPy's: its rounding is the one every output was written with)."""
    a, b = arithmetic("*", a), arithmetic("*", b)
    if is_number(a) and is_number(b):
        return a * b  # type: ignore[operator]
    if is_number(a):
        factor = float(a)  # type: ignore[arg-type]
        return b.map(lambda x: factor * x)  # type: ignore[union-attr]
    if is_number(b):
        factor = float(b)  # type: ignore[arg-type]
        return a.map(lambda x: x * factor)  # type: ignore[union-attr]
    assert isinstance(a, Array) and isinstance(b, Array)
    if a.ndim == 1 and b.ndim == 1:
        raise Invalid(
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
    with strict_numpy():
        return from_numpy(numpy_array(a) @ numpy_array(b))


def _div(a: Value, b: Value) -> Value:
    """Real division: ``7/2`` is 3.5 (sdf.md decision 5); only a scalar may divide."""
    a, b = arithmetic("/", a), arithmetic("/", b)
    if not is_number(b):
        raise _mismatch("/", a, b)
    if b == 0:
        raise ValueError("division by zero")
    if isinstance(a, Array):
        divisor = float(b)  # type: ignore[arg-type]
        return a.map(lambda x: x / divisor)
    return a / b  # type: ignore[operator]


def _mod(a: Value, b: Value) -> Value:
    a, b = scalar("an operand of '%'", a), scalar("an operand of '%'", b)
    if b == 0:
        raise ValueError("division by zero in '%'")
    return a % b


def _pow(a: Value, b: Value) -> Value:
    """``x^y`` on numbers; ``M^n`` is the matrix power of a square matrix (n may be negative)."""
    a, b = arithmetic("^", a), arithmetic("^", b)
    if isinstance(a, Array):
        if a.ndim != 2 or a.shape[0] != a.shape[1]:
            raise ValueError(f"only a square matrix can be raised to a power, not {describe(a)}")
        n = integer("the exponent of a matrix", b)
        with strict_numpy() as np:
            try:
                return from_numpy(np.linalg.matrix_power(numpy_array(a), n))
            except np.linalg.LinAlgError:
                raise ValueError("a singular matrix has no negative power") from None
    b = scalar("an exponent", b)
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
    if is_number(a) and is_number(b):
        return a == b
    if isinstance(a, Array) and isinstance(b, Array):
        return a.shape == b.shape and all(x == y for x, y in zip(a.flat, b.flat))
    if type(a) is type(b) and isinstance(a, (bool, str)):
        return a == b
    raise ValueError(f"cannot compare {describe(a)} with {describe(b)}")


def _ordered(op: str, test: Callable[[float, float], bool]) -> Callable[[Value, Value], bool]:
    def compare(a: Value, b: Value) -> bool:
        if isinstance(a, bool):
            raise Invalid(
                f"'{op}' cannot order {describe(a)}",
                "comparisons do not chain: write a < b /\\ b < c",
            )
        return test(scalar(f"an operand of '{op}'", a), scalar(f"an operand of '{op}'", b))

    return compare


STRICT_OPS: Mapping[str, Callable[[Value, Value], Value]] = MappingProxyType(
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
        "<=>": lambda a, b: boolean("an operand of '<=>'", a) == boolean("an operand", b),
    }
)
"""Operators that evaluate both operands. Comparisons do not chain: ``a < b < c`` is
``(a < b) < c`` as the tree says, an error (a boolean is not ordered)."""

SHORT_CIRCUIT: Mapping[str, tuple[bool, bool]] = MappingProxyType(
    {"/\\": (False, False), "\\/": (True, True), "=>": (False, True)}
)
"""Connectives as (left value that settles them, their value then). A settled connective does not
evaluate its right operand, so ``x != 0 /\\ 1/x > 2`` is false, not an error, at ``x = 0``."""
