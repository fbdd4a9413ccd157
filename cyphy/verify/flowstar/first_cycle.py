"""The first cycle of a machine that reads its input events before its first ``exec``:
which modes the automaton may start in, decided on the scenario's initial set.

RoboSim's first cycle reads the events at time 0, so the mode it ends in (whose calls act
from time 0) depends on the mapping's event predicates at the initial state, as
``simulate``'s interpreter evaluates them. The compiled machine gives, per combination of
the events, the state the first cycle ends in (``Scenario.first``); here each
combination's guard is decided on the initial box:

- a **point** box (every coordinate an event reads has one value): each predicate is
  evaluated exactly (rationals), so one combination holds and the automaton starts in its
  mode, as it would for a machine whose first cycle reads nothing: exact;
- an **interval** box: each predicate is evaluated over the box with interval arithmetic
  (outward rounded, ``mpmath.iv``) on the closed polynomial constraints Flow* writes for it
  and for its negation; a combination is kept unless some literal of it is impossible
  everywhere on the box. One combination left: exact again. Several: the export starts in
  a mode of its own (:data:`START`) that does not move and jumps at time 0 to each kept
  mode under the combination's guard (Flow*'s guard intersection restricts each mode's
  start to the part of the box where its guard may hold, aggregated to a parallelotope): an
  over-approximation of the first cycle, sound for reachability, and said in the verdict.

Splitting the box (``cyphy.verify.flowstar.check.split``) decides again on each piece, so a
piece inside one combination's region starts exactly.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import sympy

from cyphy.verify.flowstar.constraints import dnf
from cyphy.verify.flowstar.guards import targets
from cyphy.verify.flowstar.printer import NotExpressible
from cyphy.verify.flowstar.problem import CLOCK, TIMER, Problem, initial_interval, symbol
from cyphy.verify.flowstar.scenario import Transition

#: The mode the automaton starts in when the first cycle may end in several: no flow, and
#: jumps at time 0 (``timer = 0``) to the modes the first cycle may end in.
START = "cyphy_first_cycle"


def first_events(p: Problem) -> list[str]:
    """The events the first cycle reads (those its guards name), in order."""
    return list(dict.fromkeys(e for t in p.scenario.first for e, _ in t.literals))


def unreadable(p: Problem) -> tuple[str, list[str]] | None:
    """A first-cycle event whose predicate reads an actuator input, and those inputs: before
    the first cycle's calls nothing sets them (``simulate`` takes 0, the export a mode's
    value), so the events of the first cycle cannot be decided; None when there is none."""
    inputs = {symbol(u) for u in p.inputs}
    for event in first_events(p):
        read = sorted(str(s) for s in p.events[event].free_symbols & inputs)
        if read:
            return event, read
    return None


def settle(p: Problem) -> Problem:
    """``p`` with its first cycle decided on its initial box: the combinations that cannot
    hold there dropped from ``Scenario.first``, and when all that remain lead to one mode,
    that mode as ``Scenario.initial`` and no ``first`` (the exact start). Unchanged when the
    first cycle reads no event."""
    s = p.scenario
    if not s.first:
        return p
    kept = [t for t in s.first if _possible(p, t)]
    modes = list(dict.fromkeys(t.target for t in kept))
    if len(modes) == 1:
        scenario = dataclasses.replace(s, initial=modes[0], first=[])
    else:
        scenario = dataclasses.replace(s, first=kept)
    return dataclasses.replace(p, scenario=scenario,
                               first_events=p.first_events or tuple(first_events(p)))


def start_modes(p: Problem) -> list[str]:
    """The modes the automaton starts in at time 0 (one unless the first cycle is
    undecided on the box)."""
    if not p.scenario.first:
        return [p.scenario.initial]
    return list(dict.fromkeys(t.target for t in p.scenario.first))


def start_jumps(p: Problem, variables: set[Any]) -> list[tuple[str, Any]]:
    """The jumps out of :data:`START`: per mode the first cycle may end in, each disjoint
    cube of its combinations (:func:`cyphy.verify.flowstar.guards.targets`) as its
    predicates' conjunctions (one jump per disjunct), with ``t = timer = 0``."""
    at_zero = {symbol(CLOCK): 0, symbol(TIMER): 0}
    out = []
    leaving = [(t.target, t.literals) for t in p.scenario.first]
    for target, cubes in targets(START, leaving):
        for cube in cubes:
            pred = sympy.And(*[sympy.Not(p.events[e]) if negated else p.events[e]
                               for e, negated in cube]).xreplace(at_zero)
            out += [(target, c) for c in dnf(pred, variables)]
    return out


def description(p: Problem) -> str:
    """What the verdict says of the first cycle of the settled ``p`` (empty when it reads
    no event): the events it reads, and whether the start was exact."""
    if not p.first_events:
        return ""
    events = ", ".join(p.first_events)
    modes = start_modes(p)
    if len(modes) == 1:
        return (f"the first cycle reads {events} at the initial state: on the initial set it "
                f"ends in {modes[0]} (exact)")
    return (f"the first cycle reads {events}, which the initial set does not decide: the "
            f"automaton starts in each of {', '.join(modes)} where its guard may hold at "
            "time 0 (an over-approximation of the first cycle)")


# --------------------------------------------------------------------------- deciding


def _possible(p: Problem, t: Transition) -> bool:
    """Whether the guard of the first-cycle transition ``t`` may hold somewhere on the
    initial box (exactly at a point; with interval arithmetic otherwise)."""
    box = _box(p)
    for event, negated in t.literals:
        pred = p.events[event].xreplace({symbol(CLOCK): 0, symbol(TIMER): 0})
        read = pred.free_symbols
        if all(box[x][0] == box[x][1] for x in read if x in box) and read <= set(box):
            value = pred.xreplace({x: box[x][0] for x in read})
            if value in (sympy.true, sympy.false):
                if bool(value) == negated:
                    return False
                continue
        if not _may_hold(sympy.Not(pred) if negated else pred, box):
            return False
    return True


def _box(p: Problem) -> dict[Any, tuple[Any, Any]]:
    """The initial box as exact rationals, per state (and held input) symbol."""
    out = {}
    for name in [*p.states, *p.held_inputs]:
        lo, hi = initial_interval(p, name)
        out[symbol(name)] = (_rational(lo), _rational(hi))
    return out


def _rational(v: Any) -> Any:
    return sympy.Rational(repr(float(v))) if isinstance(v, float) else sympy.nsimplify(v)


def _may_hold(pred: Any, box: dict[Any, tuple[Any, Any]]) -> bool:
    """Whether ``pred`` may hold somewhere on ``box``: some conjunction of its closed
    polynomial form whose every atom's interval enclosure allows it (sound: False only when
    it holds nowhere)."""
    variables = set(box) | pred.free_symbols
    try:
        for conjunction in dnf(pred, variables):
            if all(_atom_may_hold(atom.poly, atom.rel, box) for atom in conjunction):
                return True
    except (NotExpressible, ValueError):
        return True  # no polynomial form to enclose: undecided, kept (the export says why)
    return False


def _atom_may_hold(poly: Any, rel: str, box: dict[Any, tuple[Any, Any]]) -> bool:
    if poly.free_symbols - set(box):
        return True  # a name without a box: undecided, kept
    from mpmath import mpf  # lazy: as _enclosure

    value = _enclosure(sympy.expand(poly), box)
    lo, hi = mpf(value.a), mpf(value.b)
    return {"<=": lo <= 0, ">=": hi >= 0, "=": lo <= 0 <= hi}[rel]


def _enclosure(e: Any, box: dict[Any, tuple[Any, Any]]) -> Any:
    """An interval (``mpmath.iv``, rounded outward) containing every value of the
    polynomial ``e`` on ``box``."""
    from mpmath import iv  # lazy: only a first cycle undecided on an interval box needs it

    def number(r: Any) -> Any:
        q = sympy.Rational(r)
        return iv.mpf(int(q.p)) / iv.mpf(int(q.q))

    def walk(node: Any) -> Any:
        if node.is_Number:
            return number(node)
        if node.is_Symbol:
            lo, hi = box[node]
            return iv.mpf([number(lo).a, number(hi).b])
        if node.is_Add:
            total = iv.mpf(0)
            for a in node.args:
                total += walk(a)
            return total
        if node.is_Mul:
            product = iv.mpf(1)
            for a in node.args:
                product *= walk(a)
            return product
        if node.is_Pow and node.exp.is_Integer and node.exp >= 0:
            return walk(node.base) ** int(node.exp)
        raise ValueError(f"not a polynomial: {node}")

    return walk(e)
