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
assignment to a machine variable (a guard, a call's argument, an index, an output, ``wait``,
an operation definition's body, a platform variable's assignment) is a root.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Iterable, Mapping

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.model.machines import Machine


def unread_variables(machine: Machine, operations: Mapping[str, Machine]) -> frozenset[str]:
    """The variables of ``machine`` that no guard, call or output depends on (see the
    module docstring); ``operations`` are the operation definitions it may call, whose
    bodies count as roots."""
    own = set(machine.variables)
    roots: set[str] = set()
    feeds: dict[str, set[str]] = {}  # variable -> the variables its assignments read

    def reads(e: ex.Expr | None) -> set[str]:
        if e is None:
            return set()
        return {n.text for n in e.walk() if isinstance(n, ex.Name) and n.text in own}

    def statements(items: Iterable[ast.Statement]) -> None:
        for s in items:
            if isinstance(s, ast.Assign) and _assigned(s.target) in own:
                target = _assigned(s.target)
                feeds.setdefault(target, set()).update(reads(s.value))
                if isinstance(s.target, ex.Index):  # v[i] = e: i chooses what is written
                    for index in s.target.args:
                        feeds[target].update(reads(index))
            elif isinstance(s, ast.Assign):
                roots.update(reads(s.target) | reads(s.value))
            elif isinstance(s, ast.CallStatement):
                roots.update(reads(s.call))
            elif isinstance(s, ast.SendStatement):
                roots.update(reads(s.event) | reads(s.value))
            elif isinstance(s, ast.WaitStatement):
                roots.update(reads(s.cycles))
            elif not isinstance(s, (ast.SkipStatement, ast.ClockReset, ast.ExecStatement)):
                roots.update(own)  # a statement this analysis does not know: keep all

    for t in machine.transitions:
        roots.update(reads(t.decl.trigger) | reads(t.decl.condition))
        statements(t.decl.action or ())
    for node in machine.nodes.values():
        for kind in ("entry", "during", "exit"):
            statements(node.actions(kind))
    for op in operations.values():  # an operation's body: every name it reads is a root
        for t in op.transitions:
            roots.update(reads(t.decl.trigger) | reads(t.decl.condition))
            roots.update(n for s in t.decl.action or () for n in _names(s) if n in own)
        for node in op.nodes.values():
            roots.update(n for kind in ("entry", "during", "exit")
                         for s in node.actions(kind) for n in _names(s) if n in own)

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


def _names(s: ast.Statement) -> set[str]:
    """Every name a statement mentions (an operation body's, read conservatively)."""
    out: set[str] = set()
    for f in fields(s):
        value = getattr(s, f.name)
        if isinstance(value, ex.Expr):
            out.update(n.text for n in value.walk() if isinstance(n, ex.Name))
    return out
