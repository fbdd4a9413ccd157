"""Timing shared by the benchmarks that time calls in one warm process."""

from __future__ import annotations

import statistics
import time
from typing import Callable


def median_time(fn: Callable[[], object], runs: int) -> float:
    """The median wall-clock seconds of ``runs`` calls of ``fn`` (no warm-up: the first call
    counts, as a user's first call would)."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)
