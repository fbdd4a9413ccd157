"""Pausing Python's cyclic garbage collector while a large result is built.

Elaborating, checking and translating a model of thousands of links allocate hundreds of
thousands of objects that all stay alive until the command ends. Each allocation threshold the
collector meets triggers a collection that traverses the older generations, which hold the
(live) syntax tree: seconds of work on a 10,000-link model, finding no garbage, and growing
faster than the model. Pausing the collector for the build removes that; what the build leaves
is collected as usual afterwards.
"""

from __future__ import annotations

import gc
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def paused() -> Iterator[None]:
    """Disable the collector inside the block, and re-enable it after only if it was enabled
    before (so nested pauses and a caller's own ``gc.disable()`` are respected)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
