"""What the machine interpreter asks of a value — a truth value, a number, a vector —
without importing NumPy.

Why: the interpreter runs on every ``gen --isabelle`` (the automaton of the d-model's
machines), whose start-up budget NumPy's import alone would exceed. A NumPy value exists
only once NumPy has been imported, so its types are looked up in ``sys.modules`` rather
than imported; NumPy is imported only to build a vector variable's value.
"""

from __future__ import annotations

import sys
from typing import Any

from cyphy.model.array import Array


def _numpy() -> Any:
    return sys.modules.get("numpy")


def is_truth(value: object) -> bool:
    np = _numpy()
    return isinstance(value, bool) or (np is not None and isinstance(value, np.bool_))


def is_number(value: object) -> bool:
    """A number, not a truth value (``True`` is an ``int`` to Python)."""
    if isinstance(value, bool):
        return False
    np = _numpy()
    return isinstance(value, (int, float)) or (np is not None and isinstance(value, np.number))


def is_vector(value: object) -> bool:
    np = _numpy()
    return isinstance(value, Array) or (np is not None and isinstance(value, np.ndarray))


def array(value: Any, dtype: Any = None) -> Any:
    """A NumPy array of ``value`` (a vector variable's value)."""
    import numpy as np  # lazy: only machines with vector variables need it

    return np.array(value, dtype=dtype)


def zeros(size: int) -> Any:
    import numpy as np  # lazy: only machines with vector variables need it

    return np.zeros(size)
