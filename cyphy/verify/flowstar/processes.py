"""The Flow* processes running now, so that an interrupt ends them all.

Each Flow* run is started in a session (process group) of its own, so that Ctrl-C at the
terminal reaches cyphy only and cyphy decides. On an interrupt (:mod:`cyphy.interrupts`)
every live group is killed (Flow* and whatever it started, gnuplot), no new run starts, and
a run whose process was killed raises :class:`~cyphy.interrupts.Interrupted` in its thread,
so the command unwinds and removes its scratch folders. Without this the runs in the worker
threads of ``cyphy reach`` outlived cyphy.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
from typing import Any

from cyphy import interrupts

_lock = threading.Lock()
_live: set[subprocess.Popen] = set()
_stopping = False


def start(args: list[str], **options: Any) -> subprocess.Popen:
    """``subprocess.Popen`` in a new session, registered until :func:`finished`; refused
    (:class:`~cyphy.interrupts.Interrupted`) once an interrupt has stopped the runs."""
    with _lock:
        if _stopping:
            raise interrupts.Interrupted()
        proc = subprocess.Popen(args, start_new_session=True, **options)
        _live.add(proc)
    return proc


def finished(proc: subprocess.Popen) -> None:
    """The run is over: forget it; raise :class:`~cyphy.interrupts.Interrupted` when it
    ended because an interrupt killed it (its output means nothing)."""
    with _lock:
        _live.discard(proc)
        if _stopping:
            raise interrupts.Interrupted()


def kill_group(proc: subprocess.Popen) -> None:
    """Kill the process and everything it started (its own session)."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def stop_all() -> bool:
    """Kill every live run and refuse new ones; whether any was running."""
    global _stopping
    with _lock:
        _stopping = True
        for proc in _live:
            kill_group(proc)
        return bool(_live)


def resume() -> None:
    global _stopping
    with _lock:
        _stopping = False


interrupts.register(stop_all, resume)
