"""The d-model process ``D`` (spec Structure, ours): the d-model's state machine under
RoboSim's cycle semantics, written from the machine compiled to an automaton
(:mod:`cyphy.semantics.machines.automaton`), the very automaton ``cyphy simulate`` and
``cyphy reach`` run, so the theory and the tools have one source of truth.

The automaton's modes are configurations at the end of a cycle with the calls that cycle
made; its edges are guarded by input events present or absent. ``D`` keeps the mode (a
number, the mode's position in the automaton) and the events read in the cycle as its
state, and each cycle:

``<D>Read`` reads every input event the mapping maps (``registerRead.e?b → e := b``;
one the machine does not read, as one its module connects to no machine, is read and
dropped, ``registerRead.e?b → Skip``: ``P`` offers it every cycle, and it never occurs for
the machine);
``<D>Step`` moves to the mode the events lead to (``if mode = s ∧ e then mode := t …``;
staying is the rest); ``<D>Write`` sends the mode's calls (``registerWrite.op!args``); then
``Wait(cycle)`` for the cycle's tocks. The first cycle reads the events and enters the
automaton's initial mode, which does not depend on them (the automaton's own rule).
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.values import value_expr
from cyphy.semantics.machines.automaton import Automaton

MODE = "mode"
#: The names ``D`` derives from its own name ``<D>``: its actions (``Start`` is the first
#: cycle of :mod:`~cyphy.semantics.circus.dmodel_cycle`'s), schemas and fields (an
#: event's flag ``<D>_<event>`` starts with ``<D>_`` and is kept apart by the event's name).
DERIVED = ("Init", "Read", "Start", "Step", "Write", "State", "Local", f"_{MODE}")


def _name(text: str) -> ex.Name:
    return ex.Name((text,))


def dmodel_process(name: str, automaton: Automaton, reads: dict[str, tuple[c.Type, ...]],
                   writes: dict[str, tuple[c.Type, ...]]) -> c.BasicProcess:
    """``D`` for the compiled machine: ``reads`` are the input events that the mapping maps
    with their ``registerRead`` payload types (an event it does not map never occurs; one
    it maps that the automaton does not read is dropped), ``writes`` the
    operations and output events it maps with their parameters' types. Raises ``ValueError`` naming a
    call the mapping has no ``registerWrite`` variant for (the rules report it)."""
    prefix = name  # D's names: <D>_mode, <D>_<event>, <D>Read, …
    mode = f"{prefix}_{MODE}"
    read = [e for e in automaton.events if e in reads]
    fields = [c.SchemaField(mode, c.NAT)] + [c.SchemaField(f"{prefix}_{e}", c.BOOL)
                                             for e in read]
    index = {m.name: i for i, m in enumerate(automaton.modes)}
    init = c.Assign((mode, *(f.name for f in fields[1:])),
                    (ex.Num(str(index[automaton.initial])), *(ex.Bool(False) for _ in read)))
    receive: list[c.Action] = [
        c.Prefix(c.Comm("registerRead", e, (c.In(f"{e}_in"),)),
                 c.Assign((f"{prefix}_{e}",), (_name(f"{e}_in"),))) for e in read]
    receive += [dropped_read(e, types) for e, types in reads.items() if e not in read]
    step: c.Action = c.Skip()
    for edge in reversed(automaton.edges):  # nested: the first edge is tested first
        if any(e not in read and not negated for e, negated in edge.guard):
            continue  # needs an event the mapping does not map, which never occurs
        # an event read is a Boolean compared with true or false (Z has no Boolean
        # predicates); one the mapping does not map is absent: its negation holds
        literals: list[ex.Expr] = [ex.BinOp("==", _name(mode), ex.Num(str(index[edge.source])))]
        literals += [ex.BinOp("==", _name(f"{prefix}_{e}"), ex.Bool(not negated))
                     for e, negated in edge.guard if e in read]
        step = c.Cond(ex.conjunction(literals),
                      c.Assign((mode,), (ex.Num(str(index[edge.target])),)), step)
    write: c.Action = c.Skip()
    for i, m in reversed(list(enumerate(automaton.modes))):
        if not m.calls:
            continue
        sends: list[c.Action] = []
        for call, args in m.calls:
            types = writes.get(call)
            if types is None or len(types) != len(args):
                raise ValueError(call)
            values = tuple(c.Out(literal(a, t)) for a, t in zip(args, types))
            sends.append(c.Prefix(c.Comm("registerWrite", call, values), c.Skip()))
        body = sends[0] if len(sends) == 1 else c.Seq(tuple(sends))
        write = c.Cond(ex.BinOp("==", _name(mode), ex.Num(str(i))), body, write)
    actions = (
        c.ActionDef(f"{prefix}Init", (), init),
        c.ActionDef(f"{prefix}Read", (), _sequence(receive)),
        c.ActionDef(f"{prefix}Step", (), step),
        c.ActionDef(f"{prefix}Write", (), write),
    )
    wait = c.Wait(_name("cycle"))
    calls = {a.name: c.Call(a.name) for a in actions}
    main = c.Seq((calls[f"{prefix}Init"], calls[f"{prefix}Read"], calls[f"{prefix}Write"], wait,
                  c.Mu("X", c.Seq((calls[f"{prefix}Read"], calls[f"{prefix}Step"],
                                   calls[f"{prefix}Write"], wait, c.Call("X"))))))
    return c.BasicProcess(name, (), c.Schema(f"{prefix}State", tuple(fields)),
                          c.Schema(f"{prefix}Local", ()), actions, main)


def dropped_read(event: str, types: tuple[c.Type, ...]) -> c.Action:
    """``registerRead.e?e_in[?e_value_in] → Skip``: an event ``P`` offers that no machine
    of ``D`` reads (the module connects it to none), taken so that ``P`` is not blocked,
    and dropped."""
    fields = (c.In(f"{event}_in"),) + ((c.In(f"{event}_value_in"),) if len(types) == 2 else ())
    return c.Prefix(c.Comm("registerRead", event, fields), c.Skip())


def literal(value: float, type_: c.Type) -> ex.Expr:
    """An argument as a literal of its parameter's type (an ``int`` or ``nat`` channel takes
    a whole number, ``1``, not ``1.0``), written as the parser writes literals: a negative
    one is the negation of its magnitude (a Num's text is never signed; the printers and
    the theory readers rely on it)."""
    if type_ in (c.INT, c.NAT) and float(value).is_integer():
        return value_expr(int(value))
    return value_expr(float(value))


def _sequence(actions: list[c.Action]) -> c.Action:
    if not actions:
        return c.Skip()
    return actions[0] if len(actions) == 1 else c.Seq(tuple(actions))


def read_events_action(name: str, events: list[str], typed: set[str],
                       reads: dict[str, tuple[c.Type, ...]]) -> c.Action:
    """``<D>Read`` of :mod:`~cyphy.semantics.circus.dmodel_cycle`'s ``D``: each mapped event
    the machines read, its value too if typed; then each mapped event none reads
    (unconnected), read and dropped."""
    receive: list[c.Action] = []
    for e in events:
        if e in typed:
            comm = c.Comm("registerRead", e, (c.In(f"{e}_in"), c.In(f"{e}_value_in")))
            then = c.Assign((f"{name}_{e}", f"{name}_{e}_value"),
                            (_name(f"{e}_in"), _name(f"{e}_value_in")))
        else:
            comm = c.Comm("registerRead", e, (c.In(f"{e}_in"),))
            then = c.Assign((f"{name}_{e}",), (_name(f"{e}_in"),))
        receive.append(c.Prefix(comm, then))
    receive += [dropped_read(e, types) for e, types in reads.items() if e not in events]
    if not receive:
        return c.Skip()
    return receive[0] if len(receive) == 1 else c.Seq(tuple(receive))
