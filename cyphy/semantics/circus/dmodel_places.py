"""Where the machine of :mod:`cyphy.semantics.circus.dmodel_cycle`'s ``D`` may be between
two cycles, beyond a node it rests in: the rest of an action that ``exec`` cut, and, inside
a call of an operation definition, the calls under way (each caller, suspended with the
rest of its action, as the interpreter's :class:`~cyphy.semantics.machines.cycle.Frame`
holds it). Each such place is a mode of ``D`` of its own; kept apart so that the unrolling
reads as the interpreter's loop, and what it keys its modes by is stated once.
"""

from __future__ import annotations

from dataclasses import replace

from cyphy.records import record

#: A pending step of the interpreter: ``("stmt", statement)``, ``("do", action)`` (a binding
#: already translated), ``("end", None)`` (exec: the cycle ends) or ``("enter", node)``.
Item = tuple[str, object]


@record(frozen=True, slots=False)
class Frame:
    """A caller suspended in a call of an operation definition (the interpreter's
    :class:`~cyphy.semantics.machines.cycle.Frame`): what it runs (None: the machine),
    where, whether it had rested there, the rest of its action after the call, and whether
    its during action ran in the cycle of the call (in a later cycle it has not)."""

    running: str | None
    node: str
    resting: bool
    items: tuple[Item, ...]
    during_done: bool = False


@record(frozen=True, slots=False)
class Calls:
    """The operation running (None: the machine) and its callers, outermost first."""

    running: str | None = None
    stack: tuple[Frame, ...] = ()

    def later(self) -> Calls:
        """As a later cycle finds the callers: their during actions not run in it."""
        return replace(self, stack=tuple(replace(f, during_done=False) for f in self.stack))


@record(frozen=True, slots=False)
class Place:
    """Where the machine is at the end of a cycle inside an operation: the calls under way,
    the node, and the rest of an action cut by exec (None: it rests in the node)."""

    calls: Calls
    node: str
    items: tuple[Item, ...] | None

    def __str__(self) -> str:
        path = " → ".join(f"{f.running or 'the machine'} at {f.node}" for f in self.calls.stack)
        return f"{self.node} of {self.calls.running} (called from {path})"


#: No call under way: the machine runs.
TOP = Calls()
