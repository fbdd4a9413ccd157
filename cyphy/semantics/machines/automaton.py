"""A state machine compiled, under RoboSim's cycle semantics, to a finite automaton over its
input events: what the Flow* export turns into modes and jumps (one jump per cycle).

The compilation runs the interpreter (:mod:`cyphy.semantics.machines.cycle`) from every reachable
configuration under every combination of the input events (present or absent), so the
automaton *is* the interpreter's behaviour, not a second reading of the rules:

- a **mode** is a configuration at the end of a cycle together with the operation calls
  that cycle performed (the mode's calls take effect when it is entered; a mode without
  calls leaves the actuators as they were, and is given the calls every path into it made
  last when they agree: calls set actuator values, so repeating them changes nothing);
- clock counts **saturate** at the first count past the largest constant the clock is
  compared with (``since(C) < PI/av``: beyond it every comparison keeps its value), so
  clocks add finitely many configurations; variables are explored by value and must take
  finitely many (at most :data:`MAX_CONFIGURATIONS` configurations), except those that no
  guard, call or output depends on (:mod:`~cyphy.semantics.machines.relevance`), which stay
  at their initial values: what the machine does is the same without them;
- modes with the same calls and the same successors are merged (partition refinement),
  and the input combinations leading from one mode to another are written as few
  conjunctions of event literals as a prime-implicant cover gives;
- the automaton starts in the mode the first cycle leads to. When that mode depends on the
  input events (the machine reads them before its first ``exec``), the compilation is
  refused unless the caller asks for the first cycle's edges (``first_cycle``): then
  ``Automaton.first`` holds, per input combination, the mode the first cycle ends in, as
  edges from before the first cycle (the Flow* export starts in a mode of its own that takes
  them at time 0, the events being the mapping's predicates at the initial state).

Operation definitions the machine calls are part of the configurations (the operation
running and its callers' frames), so they compile like the machine itself; their clocks
saturate in the same way. Output events the platform mapping maps are kept with the calls
(their mapping gives their effect, as an operation's does); those it does not map
(``interpreter.observable``) reach no input of the p-model and are left out. Typed input
events (their values are not modelled) and clocks compared with anything but constants are
reported, not approximated.
"""

from __future__ import annotations

import copy
import itertools
import math
from typing import Any, Callable, Sequence, TypeVar

from cyphy import expr as ex
from cyphy.model.machines import Machine, expressions
from cyphy.records import record
from cyphy.semantics.machines.cycle import Configuration, MachineError, MachineInterpreter, Output
from cyphy.semantics.machines.relevance import unread_variables

#: A key of :func:`explore`: a configuration, or a tuple of modes.
K = TypeVar("K")

MAX_CONFIGURATIONS = 5000
MAX_EVENTS = 8
_COMPARISONS = {"<", "<=", ">", ">=", "==", "!="}

Literal = tuple[str, bool]  # (event, negated)


@record(frozen=True, slots=False)
class Mode:
    name: str
    node: str  # the machine node the mode rests in (in the operation running, if any)
    calls: tuple[tuple[str, tuple[float, ...]], ...]


@record(frozen=True, slots=False)
class Edge:
    source: str
    target: str
    guard: tuple[Literal, ...]  # a conjunction; () is true


@record(frozen=True, slots=False)
class Automaton:
    events: tuple[str, ...]
    modes: tuple[Mode, ...]
    initial: str
    edges: tuple[Edge, ...]  # only between different modes: staying is the rest
    # The first cycle when its outcome depends on the input events (``compile_machine``'s
    # ``first_cycle``): edges from before it (``source`` is "") to the mode it ends in, whose
    # guards cover every combination; ``initial`` is then where it ends with no event. Empty:
    # the first cycle ends in ``initial`` whatever the events.
    first: tuple[Edge, ...] = ()

    def start(self, present: dict[str, bool]) -> str:
        """The mode the first cycle ends in when the events ``present`` (name → present)
        are read in it."""
        for e in self.first:
            if all(present.get(ev, False) != negated for ev, negated in e.guard):
                return e.target
        return self.initial


def compile_machine(interpreter: MachineInterpreter, first_cycle: bool = False) -> Automaton:
    """The automaton of the machine (see the module docstring); raises
    :class:`MachineError` when the machine cannot be compiled. ``first_cycle``: a first
    cycle whose outcome depends on the input events is compiled to ``Automaton.first``
    (without it such a machine is refused: the theory's ``D`` and ``simulate`` run the
    machine itself then)."""
    m = interpreter.machine
    typed = [e for e, d in m.platform.input_events.items()
             if d.type is not None and e not in m.unconnected]
    if typed:
        raise MachineError(f"the typed input event{'s' if len(typed) > 1 else ''} "
                           f"{', '.join(typed)} of {m.name} cannot be compiled: the automaton "
                           "models events as present or absent, not their values",
                           m.decl.span, "use untyped events: reach and the theory's D run "
                           "this automaton, which models an event as present or absent "
                           "(simulate runs the machine itself, with the events' values)")
    events = tuple(e for e in m.platform.input_events if e not in m.unconnected)
    if len(events) > MAX_EVENTS:
        raise MachineError(f"{m.name} reads {len(events)} input events: more than "
                           f"{MAX_EVENTS} make too many combinations", m.decl.span)
    # variables no guard, call or output reads: kept at their initial values, so a counter
    # the machine only writes does not make every cycle a new configuration
    interpreter.reset()
    unread = {n: interpreter.variables[n]
              for n in unread_variables(m, interpreter.operations)}
    caps: dict[str | None, dict[str, int]] = {None: clock_caps(interpreter)}
    caps.update({name: clock_caps(interpreter, name) for name in interpreter.operations})
    combos = list(itertools.product((False, True), repeat=len(events)))

    def step(config: Configuration | None, combo: tuple[bool, ...]
             ) -> tuple[Configuration, tuple[Output, ...]]:
        if config is None:
            interpreter.reset()
        else:
            interpreter.restore(config)
        outputs = interpreter.cycle({e: (True if on else None)
                                     for e, on in zip(events, combo)})
        outputs = tuple(o for o in outputs if o[0] not in interpreter.observable)
        interpreter.saturate(caps)
        if unread and interpreter.running is None and not interpreter.stack:
            interpreter.variables.update(copy.deepcopy(unread))
        return interpreter.configuration(), outputs

    firsts = [step(None, combo) for combo in combos]
    starts = list(dict.fromkeys(firsts))  # in the order of the combinations: deterministic
    if len(starts) > 1 and not first_cycle:
        raise MachineError(f"the first cycle of {m.name} depends on its inputs: the Flow* "
                           "automaton first samples them at the end of the first cycle",
                           m.decl.span, "let the first cycle end (exec) before reading events")

    def too_many() -> MachineError:
        return MachineError(
            f"{m.name} has more than {MAX_CONFIGURATIONS} configurations: its "
            "variables take too many values to be compiled", m.decl.span,
            "let the variables that its guards and calls read take fewer values: reach "
            "runs the compiled automaton (simulate and the theory's D run the machine "
            "itself)")

    keys, successors = explore(starts, combos, lambda key, combo: step(key[0], combo),
                               MAX_CONFIGURATIONS, too_many)
    # a first cycle that reads the events (exported to Flow* only) makes its calls before
    # and after them: ``drive(8, 8)`` on entering Ahead, then ``drive(4, -4)`` on turning
    # at once; only the last call of each operation sets its inputs, so only it is kept, and
    # the mode is the one a later turn enters (otherwise two modes, and those after them)
    outputs = [_last_calls(o) if len(starts) > 1 else o for _, o in keys]
    calls = _held_calls(outputs, successors, len(starts))
    blocks = minimise(calls, successors)
    return _automaton(events, combos, keys, calls, successors, blocks,
                      [starts.index(f) for f in firsts])


def explore(starts: Sequence[K], combos: Sequence[tuple[bool, ...]],
            step: Callable[[K, tuple[bool, ...]], K], limit: int,
            too_many: Callable[[], MachineError]) -> tuple[list[K], list[list[int]]]:
    """Every key reachable from the ``starts`` (distinct; breadth first, in the order
    found: the modes' numbering, so the output is deterministic) and, for each, the index
    of its successor under each input combination; ``too_many()`` is raised past ``limit``
    keys."""
    index = {start: k for k, start in enumerate(starts)}
    keys = list(starts)
    successors: list[list[int]] = []
    k = 0
    while k < len(keys):
        row = []
        for combo in combos:
            nxt = step(keys[k], combo)
            if nxt not in index:
                if len(keys) >= limit:
                    raise too_many()
                index[nxt] = len(keys)
                keys.append(nxt)
            row.append(index[nxt])
        successors.append(row)
        k += 1
    return keys, successors


def _last_calls(outputs: tuple[Output, ...]) -> tuple[Output, ...]:
    """The calls of a cycle with each operation's earlier calls left out: a later call of
    the same operation sets the same actuator inputs (the mapping's equations of that
    operation), so the earlier ones have no lasting effect (the Flow* export's reading)."""
    last = {o[0]: k for k, o in enumerate(outputs)}
    return tuple(o for k, o in enumerate(outputs) if last[o[0]] == k)


def _held_calls(outputs: list[tuple[Output, ...]], successors: list[list[int]],
                starts: int = 1) -> list[tuple[Output, ...]]:
    """The calls of each configuration, where one without calls is given the calls that
    every path into it performed last, when they are the same (least fixpoint of the sets of
    last calls): calls set actuator values, so repeating them changes nothing, and the
    automaton needs fewer modes (a stopped machine's mode keeps ``stop()``). The first
    ``starts`` configurations are where the first cycle may end."""
    last: list[set[tuple[Output, ...]]] = [{o} if o else set() for o in outputs]
    for k in range(starts):
        last[k] = last[k] or {()}  # before any call: the actuators' initial values
    changed = True
    while changed:
        changed = False
        for i, row in enumerate(successors):
            for j in row:
                if not outputs[j] and not last[i] <= last[j]:
                    last[j] |= last[i]
                    changed = True
    return [o if o else next(iter(last[i])) if len(last[i]) == 1 else ()
            for i, o in enumerate(outputs)]


def clock_caps(interpreter: MachineInterpreter, operation: str | None = None
               ) -> dict[str, int]:
    """Per clock of the machine (or of the operation definition named), the count from
    which every comparison ``since(C) op v`` has the same value: one past the largest ``v``
    in cycles."""
    m = interpreter.machine if operation is None else interpreter.operations[operation]
    constants = interpreter.constants if operation is None else \
        interpreter.op_constants[operation]
    caps = {c: 0 for c in m.clocks}
    for e, where in expressions(m):
        for node in e.walk():
            if isinstance(node, ex.BinOp) and node.op in _COMPARISONS:
                for clock, other in ((_since(node.left), node.right),
                                     (_since(node.right), node.left)):
                    if clock is None or clock not in caps:
                        continue
                    value = _constant(interpreter, m, constants, other)
                    if value is None:
                        raise MachineError(
                            f"{where}: since({clock}) is compared with something that is not "
                            "a constant, so its clock cannot be bounded", node.span,
                            "compare clocks with constants to compile the machine")
                    caps[clock] = max(caps[clock],
                                      math.floor(value / interpreter.period) + 1)
    for e, where in expressions(m):
        for node in e.walk():
            clock = _since(node)
            if clock is not None and not _compared(e, node):
                raise MachineError(f"{where}: since({clock}) is used as a value, so its clock "
                                   "cannot be bounded", node.span,
                                   "compare clocks with constants to compile the machine")
    return caps


def _since(e: ex.Expr) -> str | None:
    if isinstance(e, ex.Call) and isinstance(e.func, ex.Name) and e.func.text == "since" \
            and len(e.args) == 1 and isinstance(e.args[0], ex.Name):
        return e.args[0].text
    return None


def _compared(root: ex.Expr, call: ex.Expr) -> bool:
    return any(isinstance(n, ex.BinOp) and n.op in _COMPARISONS and (
        n.left is call or n.right is call) for n in root.walk())


def _constant(interpreter: MachineInterpreter, m: Machine, constants: dict[str, object],
              e: ex.Expr) -> float | None:
    if any(isinstance(n, ex.PlatformRef) or _since(n) is not None for n in e.walk()):
        return None
    params = {p.name for p in m.decl.params}  # bound per call: not one value
    if any(isinstance(n, ex.Name) and (n.text in m.variables or n.text in params)
           for n in e.walk()):
        return None
    try:
        value = interpreter._value(e, constants)
    except MachineError:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def minimise(outputs: list[tuple[Output, ...]], successors: list[list[int]]) -> list[int]:
    """Block of each configuration: the coarsest partition with equal calls and, per input
    combination, successors in equal blocks (numbered in order of first appearance)."""
    def renumber(keys: list[Any]) -> list[int]:
        seen: dict[Any, int] = {}
        return [seen.setdefault(key, len(seen)) for key in keys]

    blocks = renumber(outputs)
    while True:
        refined = renumber([(blocks[i], tuple(blocks[j] for j in successors[i]))
                            for i in range(len(blocks))])
        if max(refined) == max(blocks):
            return refined
        blocks = refined


def _automaton(events: tuple[str, ...], combos: list[tuple[bool, ...]],
               keys: list[tuple[Configuration, tuple[Output, ...]]],
               calls: list[tuple[Output, ...]], successors: list[list[int]],
               blocks: list[int], firsts: list[int]) -> Automaton:
    bases = [(f"{c.running}::{c.node}" if c.running else c.node).replace("::", "_")
             for c, _ in keys]
    return assemble(events, combos, bases, [c.node for c, _ in keys], calls, successors,
                    blocks, firsts)


def assemble(events: tuple[str, ...], combos: list[tuple[bool, ...]], bases: list[str],
             nodes: list[str], calls: list[tuple[Output, ...]], successors: list[list[int]],
             blocks: list[int], firsts: list[int] | None = None) -> Automaton:
    """The automaton of explored configurations (``bases``: each one's name before
    numbering, ``nodes``: where it rests) and their blocks of :func:`minimise`: a mode per
    block, named after its first configuration, and edges whose guards cover the input
    combinations leading from block to block. ``firsts``: per combination, the
    configuration the first cycle ends in (None: the first one, whatever the events); when
    they fall in more than one block, ``Automaton.first`` holds the edges to them."""
    first_of: dict[int, int] = {}
    for i, b in enumerate(blocks):
        first_of.setdefault(b, i)
    names: dict[int, str] = {}
    taken: set[str] = set()
    for b in sorted(first_of):
        base = bases[first_of[b]]
        name, n = base, 2
        while name in taken:
            name, n = f"{base}_{n}", n + 1
        taken.add(name)
        names[b] = name
    modes = tuple(Mode(names[b], nodes[i], calls[i]) for b, i in sorted(first_of.items()))
    edges: list[Edge] = []
    for b, i in sorted(first_of.items()):
        by_target: dict[int, list[tuple[bool, ...]]] = {}
        for combo, j in zip(combos, successors[i]):
            if blocks[j] != b:
                by_target.setdefault(blocks[j], []).append(combo)
        for target, minterms in sorted(by_target.items()):
            for cube in cover(minterms, len(events)):
                guard = tuple((events[k], not v) for k, v in enumerate(cube) if v is not None)
                edges.append(Edge(names[b], names[target], guard))
    first = [blocks[k] for k in firsts] if firsts else [blocks[0]] * len(combos)
    if len(set(first)) == 1:
        return Automaton(events, modes, names[first[0]], tuple(edges))
    by_start: dict[int, list[tuple[bool, ...]]] = {}
    for combo, b in zip(combos, first):
        by_start.setdefault(b, []).append(combo)
    starts = tuple(Edge("", names[b], tuple((events[k], not v) for k, v in enumerate(cube)
                                            if v is not None))
                   for b, minterms in sorted(by_start.items())
                   for cube in cover(minterms, len(events)))
    return Automaton(events, modes, names[first[0]], tuple(edges), starts)


def cover(minterms: list[tuple[bool, ...]], n: int) -> list[tuple[bool | None, ...]]:
    """Few cubes (``None``: either value) whose union is exactly ``minterms``: the prime
    implicants (Quine-McCluskey), then a greedy cover."""
    current: set[tuple[bool | None, ...]] = set(minterms)
    primes: set[tuple[bool | None, ...]] = set()
    while current:
        merged: set[tuple[bool | None, ...]] = set()
        used: set[tuple[bool | None, ...]] = set()
        for a, b in itertools.combinations(sorted(current, key=repr), 2):
            diff = [k for k in range(n) if a[k] != b[k]]
            if len(diff) == 1 and a[diff[0]] is not None and b[diff[0]] is not None:
                merged.add(tuple(None if k == diff[0] else a[k] for k in range(n)))
                used.update((a, b))
        primes |= current - used
        current = merged

    def covers(cube: tuple[bool | None, ...], term: tuple[bool, ...]) -> bool:
        return all(c is None or c == t for c, t in zip(cube, term))

    left = set(minterms)
    chosen: list[tuple[bool | None, ...]] = []
    for cube in sorted(primes, key=lambda c: (sum(x is not None for x in c), repr(c))):
        if left and any(covers(cube, t) for t in left):
            chosen.append(cube)
            left = {t for t in left if not covers(cube, t)}
    return chosen


def describe(automaton: Automaton) -> str:
    """The automaton as text (for messages and tests)."""
    lines = [f"initial {automaton.initial}"]
    for e in automaton.first:
        guard = " /\\ ".join(("not " if neg else "") + ev for ev, neg in e.guard) or "true"
        lines.append(f"first cycle -> {e.target} when {guard}")
    for mode in automaton.modes:
        calls = ", ".join(f"{n}({', '.join(f'{a:g}' for a in args)})"
                          for n, args in mode.calls)
        lines.append(f"mode {mode.name} [{calls}]")
    for e in automaton.edges:
        guard = " /\\ ".join(("not " if neg else "") + ev for ev, neg in e.guard) or "true"
        lines.append(f"{e.source} -> {e.target} when {guard}")
    return "\n".join(lines)
