"""Walking and rebuilding CyPhyCircus actions: every node below an action, and a bottom-up
rebuild with replacements (the scalariser's and the Isabelle printers' passes over a
process)."""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Callable, Iterator

from cyphy.semantics.circus import ast as c

_ACTION_TYPES = (c.Skip, c.Stop, c.Prefix, c.Seq, c.ExtChoice, c.IndexedExtChoice,
                 c.Interleave, c.Parallel, c.Hide, c.Cond, c.Guard, c.Mu, c.Call,
                 c.Interrupt, c.InterruptCond, c.Wait, c.Assign, c.Spec, c.Evolution,
                 c.VarBlock)


def map_action(action: c.Action, fn: Callable[[c.Action], c.Action | None]) -> c.Action:
    """Rebuild ``action`` bottom-up; ``fn`` may return a replacement for a node."""
    changes = {}
    for f in fields(action):  # type: ignore[arg-type]
        value = getattr(action, f.name)
        if isinstance(value, _ACTION_TYPES):
            changes[f.name] = map_action(value, fn)
        elif isinstance(value, tuple) and value and isinstance(value[0], _ACTION_TYPES):
            changes[f.name] = tuple(map_action(v, fn) for v in value)
    rebuilt = replace(action, **changes) if changes else action  # type: ignore[type-var]
    found = fn(rebuilt)
    return rebuilt if found is None else found


def action_nodes(action: c.Action) -> Iterator[object]:
    """Every action node below ``action`` (itself included) and the communications of its
    prefixes, depth first, without descending into expressions (cheap on big evolutions)."""
    stack: list[object] = [action]
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, c.Prefix):
            yield node.comm
        stack.extend(reversed(list(_action_children(node))))


def _action_children(node: object) -> Iterator[c.Action]:
    for f in fields(node):  # type: ignore[arg-type]
        value = getattr(node, f.name)
        if isinstance(value, _ACTION_TYPES):
            yield value
        elif isinstance(value, tuple) and value and isinstance(value[0], _ACTION_TYPES):
            yield from value
