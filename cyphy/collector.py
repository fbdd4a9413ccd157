"""Pausing Python's cyclic garbage collector while a large result is built.

Elaborating, checking and translating a model of thousands of links allocate hundreds of
thousands of objects that all stay alive until the command ends. Each allocation threshold the
collector meets triggers a collection that traverses the older generations, which hold the
(live) syntax tree: seconds of work on a 10,000-link model, finding no garbage, and growing
faster than the model. Pausing the collector for the build removes that; what the build leaves
goes to the oldest generation, collected by the next full collection as usual.
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
            # What the block built is long-lived: move it (and whatever else is tracked) to
            # the oldest generation instead of letting the next allocation start a young
            # collection that would traverse all of it and free nothing. Freezing and
            # unfreezing only splice lists; the objects stay tracked, and cyclic garbage
            # among them is found by the next full collection.
            gc.freeze()
            gc.unfreeze()
            gc.enable()
