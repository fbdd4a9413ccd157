"""The variables of a machine that nothing it does depends on: no guard, call, output event,
``wait`` or platform variable reads them, nor any variable that one of those reads.

Why: the Flow* automaton (:mod:`cyphy.semantics.machines.automaton`) is the set of the
interpreter's configurations, variables included. A counter the machine only writes (``n =
n + 1`` on every turn, for a log or a later extension) takes a new value in every cycle, so the
configurations never repeat and the machine was refused ("more than 5000 configurations"),
although what it does — the modes, the calls and their arguments — is finite. Such a
variable cannot change which transition is taken or what is sent: leaving it out of the
configuration (reset to its initial value after every cycle the compilation explores) gives
the same modes, edges and calls. This is the cone of influence of model checking: a variable
is kept when a root reads it, or a kept variable's assignment does.

Conservative by construction: a variable read anywhere else than the right side of an
assignment to a machine variable (a guard, a call's argument, an output, ``wait``,
an operation definition's body, a platform variable's assignment) is a root.
"""

from __future__ import annotations

from typing import Mapping

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.model.machines import Machine, expressions, statement_expressions, statements


def unread_variables(machine: Machine, operations: Mapping[str, Machine]) -> frozenset[str]:
    """The variables of ``machine`` that no guard, call or output depends on (see the
    module docstring); ``operations`` are the operation definitions it may call, whose
    bodies count as roots."""
    own = set(machine.variables)

    def reads(e: ex.Expr) -> set[str]:
        return {n.text for n in e.walk() if isinstance(n, ex.Name) and n.text in own}

    roots: set[str] = set()
    feeds: dict[str, set[str]] = {}  # variable -> the variables its assignments read
    for t in machine.transitions:
        for guard in (t.decl.trigger, t.decl.condition):
            if guard is not None:
                roots |= reads(guard)
    for s, _ in statements(machine):
        target = _assigned(s.target) if isinstance(s, ast.Assign) else None
        if target in own:  # x = e, x[i] = e: what e (and i) read feeds x
            feeds.setdefault(target, set()).update(
                *(reads(e) for e in statement_expressions(s)))
        else:  # a call, an output, wait, a platform variable written: read for effect
            roots.update(*(reads(e) for e in statement_expressions(s)))
    for op in operations.values():  # an operation's body: every name it reads is a root
        roots.update(*(reads(e) for e, _ in expressions(op)))

    kept, todo = set(), list(roots)
    while todo:
        v = todo.pop()
        if v not in kept:
            kept.add(v)
            todo.extend(feeds.get(v, ()))
    return frozenset(own - kept)


def _assigned(target: ex.Expr) -> str | None:
    """The variable an assignment writes: ``x`` or ``x[i]`` (None for a platform one)."""
    if isinstance(target, ex.Index):
        target = target.base
    return target.text if isinstance(target, ex.Name) else None
