"""Pausing Python's cyclic garbage collector while a large result is built.

Elaborating, checking and translating a model of thousands of links allocate hundreds of
thousands of objects that all stay alive until the command ends. Each allocation threshold the
collector meets triggers a collection that traverses the older generations, which hold the
(live) syntax tree: seconds of work on a 10,000-link model, finding no garbage, and growing
faster than the model. Pausing the collector for the build removes that; what the build leaves
goes to the oldest generation, collected by the next full collection as usual.

A command (the ``cyphy`` executable) asks for more: :func:`keep_frozen`. There, what a pause
built stays out of the collector's reach for good (``gc.freeze``): the command exits by
``os._exit`` without freeing anything, so a full collection of it would only be time spent.
It was: after ``check`` of a 90,198-link model, rendering the report's 90,000 warnings
allocated enough to start a full collection, 6 s of traversing the live syntax tree. A
long-running process (the language server, a script of the API) keeps the default, so that
the cycles among what one check built are freed before the next.
"""

from __future__ import annotations

import gc
from contextlib import contextmanager
from typing import Iterator


_KEEP_FROZEN = False


def keep_frozen(keep: bool = True) -> None:
    """From now on, leave what a pause built frozen when it ends (see above): for a process
    that exits without collecting. ``keep_frozen(False)`` turns it off again and hands what
    was frozen back to the collector (the language server, started by the command)."""
    global _KEEP_FROZEN
    _KEEP_FROZEN = keep
    if not keep:
        gc.unfreeze()


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
            # among them is found by the next full collection (unless kept frozen).
            gc.freeze()
            if not _KEEP_FROZEN:
                gc.unfreeze()
            gc.enable()
