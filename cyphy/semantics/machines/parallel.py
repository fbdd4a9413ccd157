"""Several state machines of one module run together: RoboSim's module runs each of its
controllers' machines every cycle, on the same input events read at the cycle's start (spec
semantics.md; the paper's module process is the controllers in parallel, synchronised on
the cycle). The machines share no variables (a platform variable that one reads and
another uses is refused: :func:`unshared`), so a cycle of the module is each machine's
cycle in turn, in the order the module's controllers are declared, the calls of all of them
made in that order (as the theory's ``ReceiveFromDModel`` takes them: in sequence, a later
call to the same actuator input winning).

:class:`ModuleInterpreter` runs them (``cyphy simulate``'s sampled controller), and
:func:`compile_module` composes their automata (:mod:`cyphy.semantics.machines.automaton`)
into one, the product, for the Flow* export and the theory's ``D``.
"""

from __future__ import annotations

import itertools
from typing import Mapping, Sequence

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.model.machines import Machine, statement_expressions, statements
from cyphy.semantics.machines.automaton import MAX_EVENTS, Automaton, assemble, \
    compile_machine, explore, minimise
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter, Output

#: Product modes explored before the composition is called too large.
MAX_PRODUCT_MODES = 5000


class ModuleInterpreter:
    """The machines of one module, run in lockstep: the interface of
    :class:`~cyphy.semantics.machines.cycle.MachineInterpreter` that a sampled controller
    needs (``cycle``, ``reset``, ``period``, ``observable``, ``machine``)."""

    def __init__(self, interpreters: Sequence[MachineInterpreter]) -> None:
        same_cycle(interpreters)
        unshared(interpreters)
        self.interpreters = list(interpreters)
        self.machine = interpreters[0].machine  # where the composition is reported
        self.period = interpreters[0].period
        self.observable = frozenset().union(*(i.observable for i in interpreters))

    @property
    def parts(self) -> tuple[MachineInterpreter, ...]:
        """The machines run, in the module's order."""
        return tuple(self.interpreters)

    def reset(self) -> None:
        for i in self.interpreters:
            i.reset()

    def cycle(self, events: Mapping[str, object]) -> tuple[Output, ...]:
        out: list[Output] = []
        for i in self.interpreters:
            out += i.cycle(events)
        return tuple(out)


def same_cycle(interpreters: Sequence[MachineInterpreter]) -> None:
    """Raises :class:`MachineError` unless the machines have one cycle: the product takes
    one step per cycle of each (RoboSim's module synchronises its controllers per cycle;
    machines with different cycleDefs would need a common multiple, not done)."""
    periods = {i.period for i in interpreters}
    if len(periods) > 1:
        raise MachineError(
            f"the machines {', '.join(i.machine.name for i in interpreters)} run with "
            f"different cycles ({', '.join(f'{p:g}' for p in sorted(periods))} time units): "
            "they cannot be run as one controller", interpreters[0].machine.decl.span,
            "give the module's machines the same cycleDef, or choose one with --machine")


def unshared(interpreters: Sequence[MachineInterpreter]) -> None:
    """Raises :class:`MachineError` when a machine reads a platform variable that another
    machine of the module also uses: each interpreter (and each automaton of the product)
    keeps its own value, so the reader would not see the other's writes. Writes alone are
    fine: each is an output, in the module's order, the later one winning."""
    uses: list[tuple[MachineInterpreter, set[str], set[str]]] = []
    for i in interpreters:
        machines = [i.machine, *i.operations.values()]
        written = {n for m in machines for n in m.platform.written}
        read = {name for m in machines for e in _read(m) for node in e.walk()
                for name in [node.text if isinstance(node, ex.Name) else node.name[-1]
                             if isinstance(node, ex.PlatformRef) else ""] if name in written}
        uses.append((i, written, read))
    for (a, wa, ra), (b, wb, rb) in itertools.combinations(uses, 2):
        shared = sorted((ra | rb) & wa & wb)
        if shared:
            raise MachineError(
                f"the machines {a.machine.name} and {b.machine.name} both use the platform "
                f"variable {shared[0]}, and one reads it: the machines of a module sharing a "
                "variable is not modelled (each would read its own writes)",
                a.machine.decl.span, "let one machine read it, or choose one with --machine")


def _read(m: Machine) -> list[ex.Expr]:
    """The expressions a machine evaluates: an assignment's plain target is written, not
    read."""
    out = [e for t in m.transitions for e in (t.decl.trigger, t.decl.condition) if e]
    for s, _ in statements(m):
        if isinstance(s, ast.Assign) and isinstance(s.target, (ex.Name, ex.PlatformRef)):
            out.append(s.value)
        else:
            out.extend(statement_expressions(s))
    return out


def compile_module(interpreters: Sequence[MachineInterpreter], first_cycle: bool = False
                   ) -> Automaton:
    """One machine's automaton, or the product of several: a product mode is a mode of each,
    its calls theirs in the module's order; under each combination of the input events every
    machine moves along its own edge (or stays), and the product's edges are those moves
    written again as few conjunctions of event literals. ``first_cycle``: as for
    :func:`~cyphy.semantics.machines.automaton.compile_machine` (the product's first cycle
    ends, per combination, in the product of where each machine's ends)."""
    same_cycle(interpreters)
    unshared(interpreters)
    automata = [compile_machine(i, first_cycle) for i in interpreters]
    if len(automata) == 1:
        return automata[0]
    return product(automata, interpreters[0].machine.decl.span)


def product(automata: Sequence[Automaton], span: Span) -> Automaton:
    """The synchronous product of the automata (see :func:`compile_module`)."""
    events = tuple(dict.fromkeys(e for a in automata for e in a.events))
    if len(events) > MAX_EVENTS:
        raise MachineError(f"the module's machines read {len(events)} input events: more "
                           f"than {MAX_EVENTS} make too many combinations", span)
    combos = list(itertools.product((False, True), repeat=len(events)))
    modes = [{m.name: m for m in a.modes} for a in automata]

    def move(a: Automaton, mode: str, combo: tuple[bool, ...]) -> str:
        value = dict(zip(events, combo))
        for e in a.edges:
            if e.source == mode and all(value[ev] != negated for ev, negated in e.guard):
                return e.target
        return mode

    firsts = [tuple(a.start(dict(zip(events, combo))) for a in automata) for combo in combos]
    starts = list(dict.fromkeys(firsts))

    def too_many() -> MachineError:
        return MachineError(f"the module's machines together have more than "
                            f"{MAX_PRODUCT_MODES} modes", span,
                            "choose one machine with --machine")

    keys, successors = explore(
        starts, combos, lambda key, combo: tuple(move(a, m, combo)
                                                for a, m in zip(automata, key)),
        MAX_PRODUCT_MODES, too_many)
    calls = [tuple(c for m, table in zip(key, modes) for c in table[m].calls) for key in keys]
    blocks = minimise(calls, successors)
    nodes = ["|".join(table[m].node for m, table in zip(key, modes)) for key in keys]
    return assemble(events, combos, ["_".join(key) for key in keys], nodes, calls,
                    successors, blocks, [starts.index(f) for f in firsts])
