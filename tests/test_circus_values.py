"""Numbers written as CyPhyCircus, Isabelle and Flow* literals: positional, the shortest
digits that read back as the value (``cyphy.semantics.circus.values``), against NumPy's
``format_float_positional(unique=True, trim="0")`` as the independent writer (cyphy wrote
them with it until its import was taken off the start-up path)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy import expr as ex
from cyphy.semantics.circus.values import value_expr


@settings(max_examples=3000, deadline=None)
@given(st.floats(allow_nan=False, allow_infinity=False))
def test_a_number_is_written_as_numpy_writes_it(value: float) -> None:
    e = value_expr(value)
    negative = isinstance(e, ex.UnaryOp)
    text = (e.operand if negative else e).text  # type: ignore[attr-defined]
    assert text == np.format_float_positional(abs(value), unique=True, trim="0")
    assert negative == (value < 0)
    assert float(text) == abs(value)  # reads back as the value


def test_edge_values() -> None:
    for value, text in [(1e-5, "0.00001"), (1e16, "10000000000000000.0"), (0.1, "0.1"),
                        (-0.0, "0.0"), (5e-324, "0." + "0" * 323 + "5"), (2.0, "2.0")]:
        e = value_expr(value)
        assert isinstance(e, ex.Num) and e.text == text, (value, e)
