"""Interleavings that lose state updates, and the name-set partition that keeps them.

The paper's ``A ||| B`` is Circus interleaving with empty name sets: whatever state ``A`` or
``B`` updates is discarded when both end (``../shared/spec/isabelle.md`` section 2.4). In the
marXbot, ``ReceiveFromDModel ≙ MoveFromDModel ||| StopFromDModel`` therefore throws away what
``MoveCall`` sets. Circus keeps updates with ``A ⟦ ns1 | ns2 ⟧ B``, where ``ns1`` and ``ns2``
are disjoint sets of the variables each side may update; such a partition exists exactly when
the branches write disjoint variables (move and stop both write ``LMotor_das``, so the
marXbot has none). :func:`find_lossy_interleavings` says where updates are lost and whether
a partition exists; :func:`with_namesets` replaces each interleaving that has one.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Callable, Iterator

from cyphy.semantics.circus import ast as c

_ACTION_TYPES = (c.Skip, c.Stop, c.Prefix, c.Seq, c.ExtChoice, c.IndexedExtChoice,
                 c.Interleave, c.Parallel, c.Hide, c.Cond, c.Guard, c.Mu, c.Call,
                 c.Interrupt, c.InterruptCond, c.Wait, c.Assign, c.Spec, c.Evolution,
                 c.VarBlock)


@dataclass(frozen=True)
class LossyInterleaving:
    """An interleaving in ``action`` whose ``branches`` update ``writes`` (one set per
    branch); ``partition`` says whether those sets are pairwise disjoint."""

    action: str
    branches: tuple[str, ...]
    writes: tuple[frozenset[str], ...]

    @property
    def partition(self) -> bool:
        seen: set[str] = set()
        for w in self.writes:
            if seen & w:
                return False
            seen |= w
        return True

    @property
    def overlap(self) -> frozenset[str]:
        out: set[str] = set()
        for i, w in enumerate(self.writes):
            for other in self.writes[i + 1:]:
                out |= w & other
        return frozenset(out)

    @property
    def updated(self) -> frozenset[str]:
        return frozenset().union(*self.writes)


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


def writes(action: c.Action, defs: dict[str, c.ActionDef]) -> frozenset[str]:
    """The state variables ``action`` may update (assignments, specification frames,
    evolutions, through named actions; an interleaving's updates are discarded)."""
    out: set[str] = set()
    stack: list[object] = [action]
    seen: set[str] = set()
    while stack:
        node = stack.pop()
        if isinstance(node, c.Assign):
            out.update(node.targets)
        elif isinstance(node, c.Spec):
            out.update(node.frame)
        elif isinstance(node, c.Parallel):
            out.update(node.left_names + node.right_names)
            continue
        elif isinstance(node, c.Interleave):
            continue
        elif isinstance(node, c.Evolution):
            out.add("*")  # everything: never interleaved by the rules
        elif isinstance(node, c.Call) and node.name in defs and node.name not in seen:
            seen.add(node.name)
            stack.append(defs[node.name].body)
        stack.extend(_action_children(node))
    return frozenset(out)


def _label(a: c.Action) -> str:
    return a.name if isinstance(a, c.Call) else type(a).__name__


def find_lossy_interleavings(process: c.BasicProcess) -> list[LossyInterleaving]:
    """Every interleaving of a named action at least one of whose branches updates the
    state, in definition order."""
    defs = {d.name: d for d in process.actions}
    found: list[LossyInterleaving] = []
    for d in process.actions:
        for node in action_nodes(d.body):
            if isinstance(node, c.Interleave):
                w = tuple(writes(i, defs) for i in node.items)
                if any(w):
                    found.append(LossyInterleaving(d.name, tuple(map(_label, node.items)), w))
    return found


def with_namesets(process: c.BasicProcess) -> c.BasicProcess:
    """The process with each update-losing interleaving whose branches write disjoint
    variables replaced by ``A1 ⟦ w1 | w2 ∪ … ⟧ (A2 ⟦ … ⟧ An)``; the others stay."""
    defs = {d.name: d for d in process.actions}

    def swap(node: c.Action) -> c.Action | None:
        if not isinstance(node, c.Interleave):
            return None
        w = [writes(i, defs) for i in node.items]
        finding = LossyInterleaving("", (), tuple(w))
        if not any(w) or not finding.partition or "*" in finding.updated:
            return None
        out: c.Action = node.items[-1]
        right = set(w[-1])
        for item, names in zip(reversed(node.items[:-1]), reversed(w[:-1])):
            out = c.Parallel(item, tuple(sorted(names)), (), tuple(sorted(right)), out)
            right |= names
        return out

    actions = tuple(replace(d, body=map_action(d.body, swap)) for d in process.actions)
    return replace(process, actions=actions, main=map_action(process.main, swap))
