"""What an interrupt (Ctrl-C, SIGINT, or SIGTERM as ``timeout`` and service managers send)
must stop besides cyphy itself: the external processes its layers start.

A command runs in a worker thread (:mod:`cyphy.deep`); signals reach the main thread only.
On an interrupt the main thread calls every registered stopper (which kills that layer's
processes and makes the worker's wait on them raise :class:`Interrupted`), then waits briefly
for the worker to unwind, which removes its scratch folders. Layers register here rather than
being imported by the CLI, so the foundation knows none of them.
"""

from __future__ import annotations

import signal
from typing import Callable

#: Stoppers: each kills what its layer runs and returns whether anything was running.
_STOPPERS: list[Callable[[], bool]] = []
#: Resumers: each allows new runs again, once the interrupted command has unwound.
_RESUMERS: list[Callable[[], None]] = []


class Interrupted(KeyboardInterrupt):
    """An interrupt by a signal; ``signum`` gives the exit status, 128 + signum, as a shell
    reports a process that signal ended."""

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__(signum)
        self.signum = signum


def register(stop: Callable[[], bool], resume: Callable[[], None]) -> None:
    if stop not in _STOPPERS:
        _STOPPERS.append(stop)
        _RESUMERS.append(resume)


def stop_all() -> bool:
    """Call every stopper; whether any of them stopped something (worth waiting for)."""
    return any([stop() for stop in _STOPPERS])


def resume_all() -> None:
    for resume in _RESUMERS:
        resume()


def raise_on_sigterm() -> None:
    """SIGTERM as an interrupt of the main thread, so that it is cleaned up after like
    Ctrl-C (Python's default ends the process at once, leaving children and scratch)."""
    def handler(signum: int, frame: object) -> None:
        raise Interrupted(signum)

    signal.signal(signal.SIGTERM, handler)


def exit_status(err: KeyboardInterrupt) -> int:
    return 128 + (err.signum if isinstance(err, Interrupted) else signal.SIGINT)
