"""Structural analysis of a system of equations before any reduction: which equations could
determine which variables, whatever their coefficients (Pantelides, "The consistent
initialization of differential-algebraic systems", SIAM J. Sci. Stat. Comput. 9(2), 1988;
what Modelica tools check before index reduction).

Each equation is a row of the incidence matrix: the variables it mentions. A variable and
its derivatives are one column, as index reduction treats them: ``derivative(v) == a`` and
``av == v`` both mention ``v``, and differentiating the second to ``av' == v'`` adds no
unknown. A maximum matching of rows to columns then shows an equation that nothing is left
for (the system is over-determined: the equation competes with others for every variable
it names). Equations are matched in the order :func:`overdetermined` is given them, each
trying its differentiated variables first, so the equations left over are the last ones
(the user's relations, when they are given last) and the equations they compete with are
those that define the variables' derivatives.

Pure graph work on names: the callers (:mod:`cyphy.semantics.dynamics.reduce`) build the rows
from their residuals.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic, TypeVar

E = TypeVar("E")


@dataclass(frozen=True)
class Row(Generic[E]):
    """One scalar equation: ``variables`` it mentions (unknowns only), those it may be solved
    for (``matchable``: an equation of motion gives an acceleration, never an effort) and
    those it differentiates (tried first)."""

    equation: E
    variables: frozenset[str]
    matchable: frozenset[str]
    differentiated: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Competition(Generic[E]):
    """An equation left over: each variable it names is determined by another equation
    (``rivals``: variable → the equation that determines it)."""

    equation: E
    rivals: tuple[tuple[str, E], ...]


@dataclass(frozen=True)
class Freedom(Generic[E]):
    """Variables among which the equations leave ``free`` unknowns undetermined (the
    under-determined part of the Dulmage–Mendelsohn decomposition), with those equations."""

    variables: tuple[str, ...]
    free: int
    equations: tuple[E, ...]


def match(rows: list[Row[E]]) -> dict[str, int]:
    """A maximum matching, variable → row, in the order described above."""
    owner: dict[str, int] = {}
    for k in range(len(rows)):
        _augment(rows, k, owner)
    return owner


def overdetermined(rows: list[Row[E]]) -> list[Competition[E]]:
    """The equations no maximum matching can give a variable of their own, with the
    equations they compete with; empty when every equation has one. Rows without variables
    (relations among inputs and constants) are no part of the structure."""
    rows = [r for r in rows if r.variables]
    owner = match(rows)
    matched = set(owner.values())
    out: list[Competition[E]] = []
    for k, row in enumerate(rows):
        if k in matched:
            continue
        rivals = tuple((v, rows[owner[v]].equation)
                       for v in sorted(row.matchable or row.variables) if v in owner)
        out.append(Competition(row.equation, rivals))
    return out


def underdetermined(rows: list[Row[E]], states: set[str]) -> Freedom[E] | None:
    """The variables that the equations leave free and that the evolution needs: from each
    unmatched variable, those reachable along alternating paths (a variable, a row that may
    be solved for it, the variable that row is matched to), kept when any of them is in a
    row that mentions a state (a differentiated variable, directly or through a definition);
    None when there are none."""
    rows = [r for r in rows if r.variables]
    owner = match(rows)
    of_row = {k: v for v, k in owner.items()}
    solvable: dict[str, list[int]] = {}
    for k, row in enumerate(rows):
        for v in row.matchable:
            solvable.setdefault(v, []).append(k)
    everything: set[str] = set().union(*(r.variables for r in rows)) if rows else set()
    needed: set[str] = set().union(*(r.variables for r in rows if r.variables & states)) \
        if rows else set()
    variables: set[str] = set()
    used: set[int] = set()
    free = 0
    for start in sorted(everything - set(owner)):
        reached, frontier, tree = {start}, [start], set()
        while frontier:
            for k in solvable.get(frontier.pop(), []):
                tree.add(k)
                w = of_row[k]
                if w not in reached:
                    reached.add(w)
                    frontier.append(w)
        if reached & needed:
            variables |= reached
            used |= tree
            free += 1
    if not free:
        return None
    return Freedom(tuple(sorted(variables)), free, tuple(rows[k].equation for k in sorted(used)))


def _augment(rows: list[Row[E]], start: int, owner: dict[str, int]) -> bool:
    """Kuhn's augmenting path from row ``start`` (iterative: a chain of 30 links has
    hundreds of rows); ``owner`` is updated along the path when one is found."""
    def choices(k: int) -> list[str]:
        row = rows[k]
        return sorted(row.matchable, key=lambda v: (v not in row.differentiated, v))

    seen: set[str] = set()
    stack: list[tuple[int, list[str]]] = [(start, choices(start))]
    path: list[tuple[int, str]] = []  # (row, variable) pairs tried along the way
    while stack:
        k, options = stack[-1]
        if not options:
            stack.pop()
            if path:
                path.pop()
            continue
        v = options.pop(0)
        if v in seen:
            continue
        seen.add(v)
        path.append((k, v))
        if v not in owner:
            for row, var in path:
                owner[var] = row
            return True
        stack.append((owner[v], choices(owner[v])))
    return False
