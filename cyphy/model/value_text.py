"""Comparing and printing constant values for diagnostics (W-CONST-REPLACED): a number and
the same number written as an integer are one value, vectors compare element by element,
and a value prints as the notation writes it, so the message can be pasted into a model."""

from __future__ import annotations

from cyphy.model.evaluate import Value


def same_value(a: Value, b: Value) -> bool:
    """Whether two constant values are equal (``1`` and ``1.0`` are; ``true`` and ``1``
    are not: a Boolean is no number)."""
    if isinstance(a, bool) or isinstance(b, bool) or isinstance(a, str) or isinstance(b, str):
        return type(a) is type(b) and a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b)
    if isinstance(a, (int, float)) or isinstance(b, (int, float)):
        return False
    return a.shape == b.shape and all(x == y for x, y in zip(a.flat, b.flat))


def format_value(v: Value) -> str:
    """``v`` as the notation writes it: ``3.1415``, ``true``, ``"text"``, ``(|0, 1, 0|)``."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return f'"{v}"'
    text = "; ".join(", ".join(format_value(float(x)) for x in row) for row in v.rows())
    return f"(|{text}|)"
