"""Progress of a long command on stderr: what it is doing, once it has run for a second.

A 5 MB model takes tens of seconds to check; without a word, a user cannot tell a slow run
from a hung one. The pipeline names its stage with :func:`stage` (a string assignment: free
when nobody looks); :func:`tick`, called by the thread that waits for the command
(``cyphy.deep.run_deep``), shows it after :data:`AFTER_S` seconds: on a terminal as one line
rewritten in place and erased at the end, elsewhere (``CYPHY_PROGRESS=1``, for logs) as one
line per stage. ``-q`` and a stderr that is not a terminal turn it off.
"""

from __future__ import annotations

import os
import sys
import time
from cyphy.diagnostics import RENDERING

AFTER_S = 1.0

_current = ""
_started = time.monotonic()
_shown = ""
_inline = False


def stage(text: str) -> None:
    """What the command is doing now (``parsing Treel.rsm (3/120)``)."""
    global _current
    _current = text


def start() -> None:
    """A command begins: the clock restarts and nothing has been shown."""
    global _current, _started, _shown, _inline
    _current, _started, _shown, _inline = "", time.monotonic(), "", False


def _enabled() -> bool:
    if RENDERING.quiet:
        return False
    forced = os.environ.get("CYPHY_PROGRESS")
    if forced is not None:
        return forced not in ("", "0")
    return sys.stderr.isatty()


def tick() -> None:
    """Show the current stage if the command has run long enough and it changed."""
    global _shown, _inline
    elapsed = time.monotonic() - _started
    if elapsed < AFTER_S or not _current or not _enabled():
        return
    if sys.stderr.isatty():
        sys.stderr.write(f"\r\x1b[Kcyphy: {_current} ({elapsed:.0f} s)")
        _inline = True
    elif _current != _shown:
        sys.stderr.write(f"cyphy: {_current} ({elapsed:.1f} s)\n")
    _shown = _current
    sys.stderr.flush()


def finish() -> None:
    """Erase the progress line, so that the command's own output starts on a clean line."""
    global _inline
    if _inline:
        sys.stderr.write("\r\x1b[K")
        sys.stderr.flush()
        _inline = False
