"""The solving steps of the reduction to explicit ODEs (:mod:`cyphy.semantics.dynamics.reduce`):
matching unknowns to residuals, solving a block of residuals that is linear in its unknowns,
and the order of the blocks. Split from the reducer for issue 31.
"""

from __future__ import annotations

from typing import Any

import networkx as nx
import sympy


def match_unknowns(equations: list[tuple[int, set[str]]]) -> dict[str, int]:
    """A maximum matching of variables to the equations that mention them, preferring state
    derivatives (``derivative(x) == y`` defines x', and then y is what is missing).

    Kuhn's augmenting paths, variables taken in order of preference: once matched, a variable
    stays matched, which is the preference NetworkX's Hopcroft-Karp cannot express. Plain
    sorted order, so the same model gives the same reduction in every run."""
    names = sorted(set().union(*(v for _, v in equations)),
                   key=lambda n: (not n.startswith("d_"), n)) if equations else []
    mentions: dict[str, list[int]] = {n: [] for n in names}
    for k, (_, variables) in enumerate(equations):
        for v in variables:
            mentions[v].append(k)
    owner: dict[int, str] = {}  # equation → variable

    def augment(v: str, seen: set[int]) -> bool:
        for k in mentions[v]:
            if k in seen:
                continue
            seen.add(k)
            if k not in owner or augment(owner[k], seen):
                owner[k] = v
                return True
        return False

    for v in names:
        augment(v, set())
    return {v: equations[k][0] for k, v in sorted(owner.items())}


def solve_linear(eqs: list[Any], objs: list[Any]) -> list[dict[Any, Any]] | None:
    """The solution of one equation linear in its one unknown, ``a·x + b = 0`` with ``a``
    free of ``x`` and not zero: ``x = -b/a`` (what ``sympy.solve`` gives, without its
    general machinery: most blocks are of this kind); None for anything else."""
    if len(eqs) != 1:
        return None
    [r], [x] = eqs, objs
    if any(d.has(x) for d in r.atoms(sympy.Derivative)):
        return None
    if isinstance(r, sympy.Add):  # the usual, expanded case, read off term by term
        a, rest, linear = [], [], True
        for term in r.args:
            free, bound = term.as_independent(x, as_Add=False)
            if bound == x:
                a.append(free)
            elif not term.has(x):
                rest.append(term)
            else:
                linear = False
                break
        if linear and a:
            coefficient = sympy.Add(*a)
            if coefficient != 0:
                return [{x: -sympy.Add(*rest) / coefficient}]
    a = sympy.expand(sympy.diff(r, x))
    if a == 0 or a.has(x):
        return None
    return [{x: -r.xreplace({x: 0}) / a}]


def cancel_sums(value: Any) -> Any:
    """``sympy.cancel`` where there is something to cancel: a denominator that is a sum
    (cancelling the rest, most solutions, cost a third of a 10-link chain's reduction,
    measured; they are expanded at the end anyway)."""
    if any(p.exp.is_negative and p.base.is_Add for p in value.atoms(sympy.Pow)):
        return sympy.cancel(value)
    return value


def blocks_in_order(graph: nx.DiGraph) -> list[list[str]]:
    condensed = nx.condensation(graph)
    return [sorted(condensed.nodes[n]["members"]) for n in nx.topological_sort(condensed)]
