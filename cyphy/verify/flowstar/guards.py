"""The jumps out of one controller state as Boolean functions of its input events: per
target, the event combinations under which the state's transitions (first ``when`` that
holds, in file order; none: stay) lead there, written as **disjoint** cubes.

Why: Flow*'s jumps are "may" transitions, and an enclosure that meets two guards with the
same target and reset takes both, computing the same flowpipes twice. A self-transition
beside the "no transition holds" stay jump, or a stay guard ``not (a and b)`` written as the
overlapping ``not a`` and ``not b``, doubles the work at every cycle: exponential in the
horizon. One guard per target (its combinations merged; a self-transition together with the
stay is the whole space) and cubes that share no combination remove that duplication. What
remains is inherent: the closures of complementary comparisons share their boundary, where
Flow* rightly explores both branches.
"""

from __future__ import annotations

import itertools
from typing import Callable, Sequence

Literal = tuple[str, bool]  # (event, negated)
Cube = tuple[Literal, ...]  # a conjunction of literals; () is true


def targets(state: str, transitions: Sequence[tuple[str, tuple[Literal, ...]]]
            ) -> list[tuple[str, list[Cube]]]:
    """Per target of ``state`` (in order of first appearance among ``transitions``, given as
    (target, literals) in file order; ``state`` itself last when it only stays), the
    disjoint cubes of the event combinations whose first enabled transition leads there."""
    events = list(dict.fromkeys(e for _, literals in transitions for e, _ in literals))
    order = list(dict.fromkeys([t for t, _ in transitions] + [state]))
    chosen: dict[tuple[bool, ...], str] = {}
    for combo in itertools.product((False, True), repeat=len(events)):
        value = dict(zip(events, combo))
        chosen[combo] = next((t for t, literals in transitions
                              if all(value[e] != negated for e, negated in literals)), state)
    out = []
    for target in order:
        cubes = _disjoint_cover(lambda c, t=target: chosen[c] == t, len(events))
        if cubes:
            out.append((target, [tuple((events[k], not v) for k, v in cube)
                                 for cube in cubes]))
    return out


def _disjoint_cover(function: Callable[[tuple[bool, ...]], bool], n: int
                    ) -> list[tuple[tuple[int, bool], ...]]:
    """Cubes (``(index, value)`` literals) whose union is exactly where ``function`` holds,
    no two sharing a point: Shannon expansion, splitting only on the variables the
    function still depends on (so a function true everywhere is the one empty cube)."""

    def cover(fixed: dict[int, bool]) -> list[tuple[tuple[int, bool], ...]]:
        free = [k for k in range(n) if k not in fixed]
        points = [_point(fixed, free, bits) for bits in itertools.product(
            (False, True), repeat=len(free))]
        values = [function(p) for p in points]
        if all(values):
            return [tuple(sorted(fixed.items()))]
        if not any(values):
            return []
        k = next(k for k in free if _depends(function, fixed, free, k))
        return cover({**fixed, k: True}) + cover({**fixed, k: False})

    return cover({})


def _point(fixed: dict[int, bool], free: list[int], bits: tuple[bool, ...]
           ) -> tuple[bool, ...]:
    values = {**fixed, **dict(zip(free, bits))}
    return tuple(values[k] for k in range(len(values)))


def _depends(function: Callable[[tuple[bool, ...]], bool], fixed: dict[int, bool],
             free: list[int], k: int) -> bool:
    rest = [j for j in free if j != k]
    return any(function(_point({**fixed, k: True}, rest, bits)) !=
               function(_point({**fixed, k: False}, rest, bits))
               for bits in itertools.product((False, True), repeat=len(rest)))

