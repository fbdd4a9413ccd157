"""Running a command where deeply nested models fit: a thread with a large stack.

The syntax tree, the expression tree and the elaborated parts are recursive structures, and
so are the functions that walk them (typing, evaluation, pickling for the parse cache). A
500-term sum is a left-nested tree 500 deep; Python's default limit of 1000 frames is then
reached by walks that take two frames per level. Rather than rewrite every walk, a command
runs in a thread whose stack holds :data:`DEPTH` frames; deeper input still ends in a
:class:`RecursionError`, which the CLI reports as a model nested too deeply. The public API's
entry points (:func:`deep`) run there too, so a script gets what the command gets.
"""

from __future__ import annotations

import functools
import sys
import threading
from typing import Callable, ParamSpec, TypeVar
from cyphy import interrupts
from cyphy.diagnostics import Span

T = TypeVar("T")
P = ParamSpec("P")

#: The recursion limit while a command runs (Python's default is 1000).
DEPTH = 40_000
#: The stack of the thread that runs it: room for :data:`DEPTH` frames that recurse through C
#: (pickling, hashing of frozen dataclasses). It is address space, used only as it is reached.
STACK_BYTES = 512 * 1024 * 1024
_THREAD = "cyphy"
#: Seconds an interrupt waits for the command to unwind once its external runs are killed.
INTERRUPT_GRACE = 10.0


def run_deep(fn: Callable[[], T], tick: Callable[[], None] | None = None) -> T:
    """``fn()`` in a thread with a large stack and a high recursion limit; what it raises
    (``SystemExit`` too) is raised here. A ``KeyboardInterrupt`` reaches the caller while it
    waits; the thread is a daemon, so it does not keep the process alive. ``tick`` is called
    about five times a second while ``fn`` runs (progress)."""
    outcome: list[tuple[bool, object]] = []
    done = threading.Event()

    def body() -> None:
        try:
            outcome.append((True, fn()))
        except BaseException as err:  # noqa: BLE001 - handed to the caller as it is
            outcome.append((False, err))
        finally:
            done.set()

    old_limit, old_stack = sys.getrecursionlimit(), threading.stack_size()
    try:
        threading.stack_size(STACK_BYTES)
        thread = threading.Thread(target=body, name=_THREAD, daemon=True)
        thread.start()
    finally:
        threading.stack_size(old_stack)
    sys.setrecursionlimit(max(old_limit, DEPTH))
    try:
        while thread.is_alive():
            thread.join(0.2)  # a timed wait, so that Ctrl-C is seen at once
            if tick is not None and thread.is_alive():
                tick()
    except KeyboardInterrupt:
        # Kill the external runs (Flow*) the thread waits on; it then unwinds, removing
        # its scratch folders, which is worth a short wait.

        if interrupts.stop_all():  # (not thread.join: an interrupted join marks the
            done.wait(INTERRUPT_GRACE)  # thread stopped while it runs, bpo-45274)
        interrupts.resume_all()
        raise
    finally:
        sys.setrecursionlimit(old_limit)
    ok, value = outcome[0]
    if not ok:
        raise value  # type: ignore[misc]
    return value  # type: ignore[return-value]


def deep(fn: Callable[P, T]) -> Callable[P, T]:
    """An API entry point that runs with the deep stack: in a new thread of
    :func:`run_deep`, or directly when it is called from one (the CLI, or another entry
    point), so that nesting costs no further threads."""
    @functools.wraps(fn)
    def entry(*args: P.args, **kwargs: P.kwargs) -> T:
        if threading.current_thread().name == _THREAD:
            return fn(*args, **kwargs)
        return run_deep(lambda: fn(*args, **kwargs))
    return entry


def where_too_deep(err: RecursionError) -> str:
    """Where a :class:`RecursionError` happened in the model: ``FILE:LINE:COLUMN: `` of the
    outermost expression (else syntax node) that the frames of the failed walk were visiting (the top of the
    runaway nesting), or ``""`` when no frame holds one. Found after the fact from the
    traceback, so that no walk pays for tracking it."""
    from cyphy.expr import Expr  # lazy: `cyphy --help` imports this module, not the expressions

    fallback = ""
    frame_tb = err.__traceback__
    while frame_tb is not None:
        for value in frame_tb.tb_frame.f_locals.values():
            span = getattr(value, "span", None)
            if isinstance(span, Span) and span.line > 0:
                where = f"{span.file}:{span.line}:{span.column}: "
                if isinstance(value, Expr):  # the expression, rather than its file or block
                    return where
                fallback = fallback or where
        frame_tb = frame_tb.tb_next
    return fallback

