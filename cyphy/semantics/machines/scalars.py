"""What the machine interpreter asks of a value — a truth value, a number, a vector —
without importing NumPy.

Why: the interpreter runs on every ``gen --isabelle`` (the automaton of the d-model's
machines), whose start-up budget NumPy's import alone would exceed. NumPy's types are told
by :func:`cyphy.model.values.is_numpy` (their type's module and name, as the model's values
are); NumPy is imported only to build a vector variable's value.
"""

from __future__ import annotations

import numbers
from typing import Any

from cyphy.model.array import Array
from cyphy.model.values import is_numpy


def is_truth(value: object) -> bool:
    return isinstance(value, bool) or is_numpy(value, "bool")


def is_number(value: object) -> bool:
    """A number, not a truth value (``True`` is an ``int`` to Python; NumPy's numbers are
    ``numbers.Real``)."""
    return isinstance(value, numbers.Real) and not is_truth(value)


#: Per primitive type of a machine's constant: what it is, and what to give it.
_TYPES = {"boolean": ("a boolean", "true or false"), "real": ("a number", "a number"),
          "int": ("declared int", "a whole number"),
          "nat": ("declared nat", "a whole number of at least 0")}


def misfit(type_name: str, value: object) -> tuple[str, str] | None:
    """Why ``value`` cannot be a constant of the primitive type ``type_name`` (what the
    constant is, what to give it), or None when it can (any value for another type)."""
    whole = is_number(value) and float(value).is_integer()  # type: ignore[arg-type]
    fits = {"boolean": is_truth(value), "real": is_number(value), "int": whole,
            "nat": whole and value >= 0}  # type: ignore[operator]
    return None if fits.get(type_name, True) else _TYPES[type_name]


def is_vector(value: object) -> bool:
    return isinstance(value, Array) or is_numpy(value, "ndarray")


def array(value: Any, dtype: Any = None) -> Any:
    """A NumPy array of ``value`` (a vector variable's value)."""
    import numpy as np  # lazy: only machines with vector variables need it

    return np.array(value, dtype=dtype)


def zeros(size: int) -> Any:
    import numpy as np  # lazy: only machines with vector variables need it

    return np.zeros(size)
