"""Limits that keep hostile or mistaken input from exhausting the machine.

A trajectory of ``--samples 100000000`` would take gigabytes before the integrator reports
anything: :func:`trajectory_refusal` refuses it first, for ``simulate`` and ``animate`` alike.

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


#: The most memory a trajectory may take (see :func:`trajectory_refusal`).
MEMORY_BUDGET = 2 * 2**30
#: Each value is held about three times (the integrator's output, the table, its text).
BYTES_PER_VALUE = 40


def trajectory_refusal(samples: int, columns: int) -> tuple[str, str] | None:
    """Why a trajectory of ``samples`` rows and ``columns`` columns (plus time) would not fit
    in :data:`MEMORY_BUDGET`, with a hint giving the most samples that fit; None if it fits."""
    needed = samples * (columns + 1) * BYTES_PER_VALUE
    if needed <= MEMORY_BUDGET:
        return None
    most = max(2, MEMORY_BUDGET // ((columns + 1) * BYTES_PER_VALUE))
    return (f"--samples {samples}: a trajectory of {columns} column"
            f"{'s' if columns != 1 else ''} would take about {needed / 2**30:.1f} GiB "
            f"(the budget is {MEMORY_BUDGET / 2**30:.0f} GiB)",
            f"give at most --samples {most}")
