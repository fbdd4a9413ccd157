"""The Flow* processes running now, so that an interrupt ends them all.

Each Flow* run is started in a session (process group) of its own, so that Ctrl-C at the
terminal reaches cyphy only and cyphy decides. On an interrupt (:mod:`cyphy.interrupts`)
every live group is killed (Flow* and whatever it started, gnuplot), no new run starts, and
a run whose process was killed raises :class:`~cyphy.interrupts.Interrupted` in its thread,
so the command unwinds and removes its scratch folders. Without this the runs in the worker
threads of ``cyphy reach`` outlived cyphy.

A cyphy killed with SIGKILL runs none of that, so on Linux each run also asks the kernel to
kill it when its parent goes (``prctl(PR_SET_PDEATHSIG, SIGKILL)`` in the child, before
Flow* is executed; the setting survives the ``exec``). The kernel's "parent" is the thread
that started the run: the worker threads of ``cyphy reach`` live until every run of their
pool has ended, so no run is killed early. What Flow* itself started (gnuplot, which the
runs of ``reach`` do not use: they write Taylor models) is not covered. Elsewhere nothing is
asked: a killed cyphy leaves its runs to finish.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from typing import Any, Callable

from cyphy import interrupts

_lock = threading.Lock()
_live: set[subprocess.Popen] = set()
_stopping = False
_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_prctl: Any = None  # libc's prctl, found once (not in the child, after fork)


def start(args: list[str], **options: Any) -> subprocess.Popen:
    """``subprocess.Popen`` in a new session, registered until :func:`finished`; refused
    (:class:`~cyphy.interrupts.Interrupted`) once an interrupt has stopped the runs."""
    with _lock:
        if _stopping:
            raise interrupts.Interrupted()
        proc = subprocess.Popen(args, start_new_session=True, preexec_fn=_die_with_parent(),
                                **options)
        _live.add(proc)
    return proc


def _die_with_parent() -> Callable[[], None] | None:
    """On Linux, the ``preexec_fn`` that makes the child die (SIGKILL) when the thread that
    starts it does, and at once when that already happened before it asked; None elsewhere
    or when libc's ``prctl`` cannot be found. Everything it needs is looked up here, in the
    parent: the child only calls a C function and reads its parent's pid."""
    global _prctl
    if not sys.platform.startswith("linux"):
        return None
    if _prctl is None:
        import ctypes  # lazy: only a Flow* run needs it

        try:
            _prctl = ctypes.CDLL(None, use_errno=True).prctl
        except (OSError, AttributeError):
            _prctl = False
    if _prctl is False:
        return None
    prctl, parent, kill = _prctl, os.getpid(), signal.SIGKILL

    def preexec() -> None:
        prctl(_PR_SET_PDEATHSIG, int(kill), 0, 0, 0)
        if os.getppid() != parent:  # the parent died before the request: no signal comes
            os.kill(os.getpid(), kill)

    return preexec


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
