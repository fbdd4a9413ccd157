"""The values constant expressions evaluate to, and the checks every operation makes on
them: what a :data:`Value` is (see :mod:`cyphy.model.evaluate` for the semantics), the errors
evaluation raises, and the small guards (``scalar``, ``integer``, ``boolean``…) that the
operators and the library functions share, so that each message is written once.
"""

from __future__ import annotations

import math
import numbers
import sys
from typing import TypeAlias, Union

from cyphy.diagnostics import Span
from cyphy.model.array import Array

Vec: TypeAlias = Array
Value: TypeAlias = Union[float, int, bool, str, Vec]

NO_SPAN = Span.unknown()

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


class Invalid(ValueError):
    """A ``ValueError`` with a hint; like any other, the node that catches it adds the span."""

    def __init__(self, message: str, hint: str) -> None:
        super().__init__(message)
        self.hint = hint


# --------------------------------------------------------------------------- values


def is_number(value: object) -> bool:
    """True for ints and floats; bools are Python ints but are not numbers here."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def frozen(data: object) -> Vec:
    """The :class:`~cyphy.model.array.Array` of ``data`` (nested sequences of numbers, an
    Array, a NumPy array): values are immutable however they were computed."""
    return Array.of(data)


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


def from_env(name: str, value: object) -> Value:
    """An ``env`` entry as a :data:`Value`: NumPy scalars become Python ones, arrays
    :class:`~cyphy.model.array.Array` (recognised without importing NumPy)."""
    if isinstance(value, Array):
        return value
    if isinstance(value, bool) or is_numpy(value, "bool"):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if is_numpy(value, "ndarray") and value.ndim in (1, 2) \
            and value.dtype.kind in "iuf":  # type: ignore[attr-defined]
        return frozen(value)
    raise ValueError(
        f"the value given for '{name}' ({type(value).__name__}) is not a number, boolean, "
        "string, vector or matrix"
    )


def is_numpy(value: object, kind: str) -> bool:
    """Whether ``value`` is NumPy's ``ndarray`` or ``bool`` (``bool_``), asked of its type's
    name so that a model without NumPy values never imports NumPy."""
    cls = type(value)
    return cls.__module__ == "numpy" and cls.__name__ in ((kind, "bool_") if kind == "bool"
                                                          else (kind,))


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


def require_finite(value: Value) -> None:
    """Overflow and NaN are errors, not values: SDF has no way to write ``inf``."""
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError("the result is not a finite number (overflow)")
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > _LARGEST:
        raise ValueError("the result is too large (beyond ±1.8e308)")
    if isinstance(value, Array) and not all(map(math.isfinite, value.flat)):
        raise ValueError("the result has an entry that is not a finite number (overflow)")


def arithmetic(op: str, value: Value) -> Value:
    """``value`` if it may take part in arithmetic (a number or an array)."""
    if is_number(value) or isinstance(value, Array):
        return value
    raise ValueError(f"'{op}' needs numbers, vectors or matrices, not {describe(value)}")


def scalar(what: str, value: Value) -> int | float:
    if not is_number(value):
        raise ValueError(f"{what} must be a number, not {describe(value)}")
    return value  # type: ignore[return-value]


def integer(what: str, value: Value) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{what} must be an integer, not {describe(value)}")
    return value


def boolean(what: str, value: Value) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"{what} must be a boolean, not {describe(value)}")
    return value
