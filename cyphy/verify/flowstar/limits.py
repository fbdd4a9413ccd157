"""Bounds on ``cyphy reach``'s settings: what Flow* or the checker would otherwise turn into
a crash or a day-long run is refused (exit 2) with the limit and the reason.

- ``max jumps`` is read by Flow* as a C ``int``: above 2^31 − 1 it wraps to a negative
  number, which disables the bound instead of raising it.
- A Taylor-model order of thousands makes every step of Flow* take hours (the number of
  monomials grows as the order to the power of the state count); orders above
  :data:`MAX_ORDER` are never useful.
- Each box of ``--split`` is one Flow* run; :data:`MAX_SPLIT` bounds the runs of a round.
- An initial bound beyond :data:`MAX_BOUND` keeps no digit below the units in a double: its
  boxes, simulations and Flow*'s intervals mean nothing, and the box's width may overflow.
- A timeout must be a finite positive number of seconds (``nan`` compares false with
  everything, so it would never fire).
"""

from __future__ import annotations

import argparse

MAX_JUMPS = 2 ** 31 - 1
MAX_ORDER = 50
MAX_SPLIT = 64
MAX_PRECISION = 1024  # MPFR bits; 53 is a double
MAX_BOUND = 1e15


def boxes(text: str) -> int:
    """``--split``: 1 to :data:`MAX_SPLIT` boxes."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if not 1 <= value <= MAX_SPLIT:
        raise argparse.ArgumentTypeError(
            f"{value} boxes: give 1 to {MAX_SPLIT} (each box is one Flow* run)")
    return value
