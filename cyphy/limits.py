"""Limits that keep hostile or mistaken input from exhausting the machine.

An index range ``[0, 1000000000)`` asks for a billion copies of a block: elaboration would
run for minutes and use gigabytes before anything is reported. Copies beyond the limit are
an error at once instead (``IX1`` on the range, ``E-INDEX`` during elaboration for nested
ranges whose product passes it). ``--max-copies N`` (or ``CYPHY_MAX_COPIES``) raises it.
"""

from __future__ import annotations

import os

#: Copies of indexed blocks and parts in one model, unless raised: 10^5 elements elaborate
#: in well under 1 GB.
DEFAULT_MAX_COPIES = 100_000


def max_copies() -> int:
    """The largest number of copies an index range (or all of them together) may make."""
    given = os.environ.get("CYPHY_MAX_COPIES", "")
    try:
        value = int(given)
    except ValueError:
        return DEFAULT_MAX_COPIES
    return value if value > 0 else DEFAULT_MAX_COPIES
