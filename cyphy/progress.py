"""Progress of a long command on stderr: what it is doing, once it has run for a second.

A 5 MB model takes tens of seconds to check; without a word, a user cannot tell a slow run
from a hung one. The pipeline names its stage with :func:`stage` and, within a long stage, how far it
has gone with :func:`step` (``line 120000``, ``link 40000 of 90198``): string assignments,
free when nobody looks, so that a stage of minutes still moves. :func:`tick`, called by the
thread that waits for the command (``cyphy.deep.run_deep``), shows them after
:data:`AFTER_S` seconds: on a terminal as one line rewritten in place and erased at the end,
elsewhere (``CYPHY_PROGRESS=1``, for logs) as a line per stage and at most one a second
within a stage. ``-q`` and a stderr that is not a terminal turn it off.
"""

from __future__ import annotations

import os
import sys
import time
from cyphy.diagnostics import RENDERING

AFTER_S = 1.0
#: Seconds between two lines of one stage in a log (a terminal's line is rewritten instead).
LOG_EVERY_S = 1.0

_current = ""
_detail = ""
_started = time.monotonic()
_shown = ""
_shown_stage = ""
_shown_at = 0.0
_inline = False


def stage(text: str) -> None:
    """What the command is doing now (``reading Treel.rsm (3/120)``)."""
    global _current, _detail
    _current, _detail = text, ""


def step(detail: str) -> None:
    """How far the current stage has gone (``link 300 of 5000``); the next :func:`stage`
    clears it."""
    global _detail
    _detail = detail


def start() -> None:
    """A command begins: the clock restarts and nothing has been shown."""
    global _current, _detail, _started, _shown, _shown_stage, _shown_at, _inline
    _current, _detail, _started = "", "", time.monotonic()
    _shown, _shown_stage, _shown_at, _inline = "", "", 0.0, False


def _enabled() -> bool:
    if RENDERING.quiet:
        return False
    forced = os.environ.get("CYPHY_PROGRESS")
    if forced is not None:
        return forced not in ("", "0")
    return sys.stderr.isatty()


def tick() -> None:
    """Show the current stage if the command has run long enough and it changed."""
    global _shown, _shown_stage, _shown_at, _inline
    now = time.monotonic()
    elapsed = now - _started
    if elapsed < AFTER_S or not _current or not _enabled():
        return
    current, detail = _current, _detail  # (set by the command's thread meanwhile)
    text = f"{current}: {detail}" if detail else current
    if sys.stderr.isatty():
        sys.stderr.write(f"\r\x1b[Kcyphy: {text} ({elapsed:.0f} s)")
        _inline = True
    elif text != _shown and (current != _shown_stage or now - _shown_at >= LOG_EVERY_S):
        sys.stderr.write(f"cyphy: {text} ({elapsed:.1f} s)\n")
        _shown_stage, _shown_at = current, now
    else:
        return
    _shown = text
    sys.stderr.flush()


def finish() -> None:
    """Erase the progress line, so that the command's own output starts on a clean line."""
    global _inline
    if _inline:
        sys.stderr.write("\r\x1b[K")
        sys.stderr.flush()
        _inline = False
