"""``D`` for a state machine that reads **typed** input events, or that the automaton
cannot hold (its first cycle reads the inputs, or it has too many configurations): one cycle
of the machine translated into Circus conditionals and assignments over the machine's own
state.

Why not the automaton (:mod:`cyphy.semantics.circus.dmodel`): the automaton's modes are the
interpreter's configurations, found by running it under every combination of events present
or absent. An event that carries a value (``event echo: real``, read as ``$echo?seen``) binds
a variable to a real number, so the configurations are not finite and the automaton cannot
be built. Here the values stay symbolic: ``D``'s state is

- ``<D>_mode``: the node the machine rests in (its position among the machine's nodes);
  a module that runs several machines has one per machine, ``<D>_<machine>_mode``, and
  their variables and clocks are named ``<D>_<machine>_x`` (each machine runs its cycle in
  turn, in the module's order, on the events read once: ``<D>Start`` and ``<D>Step`` are
  the machines' in sequence, as :class:`~cyphy.semantics.machines.parallel.ModuleInterpreter`
  runs them);
- ``<D>_<e>`` (a Boolean) per input event the mapping maps, and ``<D>_<e>_value`` for a
  typed one: what ``registerRead.e?b?v`` read at the cycle's start (P's side offers
  ``registerRead.e!true!p`` or ``!false!p``,
  :func:`cyphy.semantics.circus.rules.rule4_input_event`);
- ``<D>_<x>`` per variable of the machine, at its initial value (a number held as a real,
  :func:`~cyphy.semantics.circus.values.held_type`);
- ``<D>_<C>`` per clock: the cycles counted since ``#C`` (``since(C)`` is the count times
  the machine's cycle, as in the interpreter), a whole number held as a real: it is
  compared with real constants (``since(C) >= pause``), and utp-main's UTP expressions have
  no coercion from ``nat`` to ``real`` (a ``nat`` count there is a type error).

and each cycle runs the interpreter's rules (:mod:`cyphy.semantics.machines.cycle`, point
3) written out as an action, unrolled from each node the machine can rest in:

``<D>Read``  reads every mapped input event: ``registerRead.e?e_in?e_value_in →
(<D>_e, <D>_e_value := e_in, e_value_in)``; one no machine reads (the module does not
connect it to them) is read and dropped;

``<D>Step``  advances the clocks, then ``if <D>_mode = s then <cycle from s> else …``: the
state's ``during`` action, then its transitions in the order written (exec ones too: the
machine has rested since the last cycle), each ``if guard then (bind ; exit ; action ; enter
target ; <target's transitions, exec ones excluded>) else <next>``, the last ``else`` the
machine resting (``<D>_mode := s`` where it moved). A guard is the trigger and condition
over the state: ``$e`` is ``<D>_e = true``, a name bound by ``$e?x`` is ``<D>_e_value`` in
the guard and ``x := <D>_e_value`` when taken, a constant is its value. A call or output
event is sent where the machine makes it, ``registerWrite.op!(args)`` with the arguments
as expressions over the state (the values the interpreter would compute there);

``<D>Start`` is the first cycle: from the initial junction, exec transitions excluded, no
clock advanced. ``<D>Main ≙ <D>Init ; <D>Read ; <D>Start ; Wait(cycle) ; μ X • (<D>Read ;
<D>Step ; Wait(cycle) ; X)``.

So ``<D>Write`` has no part here: the calls are made inside the cycle, in the interpreter's
order, interleaved with the assignments that precede them. A machine without typed input
events keeps the automaton's ``D`` when the automaton can be built (its theory is unchanged);
when it cannot, ``Read`` before ``Start`` gives the first cycle the events at t = 0, as
``simulate``'s interpreter reads them.

Isabelle constructs (the printers already use each for ``P`` or the automaton's ``D``): an
input of two fields ``c?(b)?(v)`` is utp-main c9122f14's mixed prefix
(``theories/circus/utp_circus_prefix.thy:41, 58-59``: ``_mixed_prefix`` to ``_pattern x y``,
then ``InputCSP``, ``theories/sf_rdes/utp_sfrd_prog.thy:864``), and Ax_CyPhyCircus's
``c\\<^bold>?(b, v)``, a ``pttrn`` (Circus_Toolkit 97811b8 ``IsaCircus_Syntax.thy:68, 90``);
a call's argument over the state, ``c!(&d * «0.5»)``, is an output prefix whose value is a
UTP expression (``utp_circus_prefix.thy:31, 53-54, 63``: ``outp_constraint v`` is ``«x» =\\<^sub>u
v`` for any ``v`` over the state), in Ax_CyPhyCircus ``c\\<^bold>!(d * 0.5)``, an ``expr`` over
the state (``IsaCircus_Syntax.thy:48, 75, 94``: ``OutputPrefix c (e)\\<^sub>e P``);
conditionals and assignments as in the automaton's ``D``.

Composite states run as the interpreter runs them: the during actions of the states around
the one the machine rests in (outermost first), their transitions before those of the states
inside, exits innermost first, and a composite target entered through its initial junction.

``exec`` inside an action ends the cycle there, as in the interpreter: the rest of the
action (and what follows it: the target's entry, …) is a mode of its own, numbered after the
nodes, whose ``<D>Step`` branch runs that rest in the next cycle (the during action again
unless a state is entered, then the transitions, exec ones excluded); ``wait(n)``, ``n`` a
constant, is ``n`` such ends.

An open constant (no value, none given) is a constant of the theory, ``<D>_k`` (a
machine's own) or ``<D>_<machine>_k`` beside others; one computed from it is its expression.

**Operation definitions** (``operation Ramp(w: real) { … }``, called as ``Ramp(10)``) run
inline, as the interpreter runs them (``MachineInterpreter._invoke``, ``_return``): their
parameters, variables and clocks are fields of D's state, named as the machine's with the
operation's name in them (``<D>_Ramp_w``; one set per operation: no two calls of one
operation are under way at once, a recursive chain being refused). A call assigns the
parameters the arguments' values (computed over the caller's fields), then the variables
their initial values (which may read the parameters), the clocks 0, and goes on from the
operation's initial junction under the same rules, over the operation's own fields and
constants; the caller waits in a frame (:class:`~cyphy.semantics.circus.dmodel_places.Frame`:
where it is, whether it had rested there, the rest of its action, whether its during action
ran in this cycle). Entering the operation's top-level ``final`` state returns: the caller
goes on with the rest of its action in the same cycle (its during action again only when
the return comes in a later cycle, its exec transitions enabled only if it had rested, as
the interpreter restores them). An operation's clocks advance every cycle with the
machine's (a call resets them before they are read; the callers' keep counting, as the
interpreter's frames do). Where the machine may end a cycle inside an operation (the calls
under way, with each caller's continuation, and the node, or the rest of an action cut by
``exec`` or ``wait``) is a mode of its own
(:class:`~cyphy.semantics.circus.dmodel_places.Place`), numbered after the machine's own
(nodes, then the rests of its actions), so that a machine without operation definitions
has the ``D`` it had before.

A vector variable of numbers is a field per entry
(:class:`~cyphy.semantics.circus.dmodel_terms.Terms`: entries at constant indices, whole
vectors assigned at once).

Refused (``W-SEMANTICS-DMODEL``, with the reason): matrices, vectors of truth values, vector
open constants, an ``int`` or ``nat`` event value or call argument computed from the state (D
holds numbers as reals), ``wait(n)`` with ``n`` not a constant, a name bound by ``$e?x``
outside a conjunct of its guard, machines of one module with different cycles, a cycle that
passes more than :data:`MAX_DEPTH` nodes (a loop without ``exec``), a recursive chain of
operation calls (an operation called while it runs), and an operation variable's initial
value that reads another of its variables (the interpreter has no value for it there).
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel import MODE, read_events_action
from cyphy.semantics.circus.dmodel_places import TOP, Calls, Frame, Item, Place
from cyphy.semantics.circus.dmodel_terms import Terms, default, name_expr
from cyphy.semantics.circus.path_facts import Facts
from cyphy.semantics.circus.values import held_type, open_type, type_of
from cyphy.semantics.circus.walk import map_action
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter
from cyphy.semantics.machines.parallel import same_cycle

#: Nodes passed in one cycle before the unrolling is taken to loop.
MAX_DEPTH = 32
#: Conditionals in one ``D`` before it is called too large to write.
MAX_CONDITIONALS = 2000
_SCALARS = (c.REAL, c.INT, c.NAT, c.BOOL)
#: Marks a mode number not known yet (a place inside an operation: numbered last).
_PLACE = "\0place"


def _seq(actions: list[c.Action]) -> c.Action:
    actions = [a for a in actions if not isinstance(a, c.Skip)]
    if not actions:
        return c.Skip()
    return actions[0] if len(actions) == 1 else c.Seq(tuple(actions))




class _Cycle:
    """The translation of one machine (see the module docstring)."""

    def __init__(self, name: str, own: str, interpreter: MachineInterpreter,
                 reads: dict[str, tuple[c.Type, ...]],
                 writes: dict[str, tuple[c.Type, ...]]) -> None:
        """``name`` is D's (its events' fields ``<D>_e``), ``own`` prefixes the machine's
        mode, variables and clocks (``<D>``, or ``<D>_<machine>`` beside others), and
        ``<own>_<op>`` those of each operation definition it calls."""
        self.interpreter = interpreter
        self.machine = m = interpreter.machine
        self.name = name
        self.mode = f"{own}_{MODE}"
        self.index = {key: i for i, key in enumerate(m.nodes)}
        # an event the mapping does not map, or the module does not connect, never occurs;
        # an operation reads the cycle's events as its caller does
        scopes = [m, *interpreter.operations.values()]
        self.events = [e for e in dict.fromkeys(e for s in scopes for e in s.platform.input_events)
                       if e in reads and e not in m.unconnected]
        self.typed = {e: reads[e][1] for e in self.events if len(reads[e]) == 2}
        self.terms = {None: Terms(name, own, m, interpreter, interpreter.constants, self.events,
                                  self.typed, writes, self._refuse)}
        for op, scope in interpreter.operations.items():
            self.terms[op] = Terms(name, f"{own}_{op}", scope, interpreter,
                                   interpreter.op_constants[op], self.events, self.typed,
                                   writes, self._refuse)
        self.conditionals = 0
        self.rest: list[str] = []  # nodes the machine may rest in, in the order found
        #: the rests of actions cut by exec (pending steps, and the node), in the order found
        self.resumes: list[tuple[tuple[Item, ...], str]] = []
        #: where the machine may end a cycle inside an operation, in the order found
        self.inner: list[Place] = []
        self._refuse_unsupported()

    # ----- what the translation refuses
    def _refuse(self, message: str, span: object = None, hint: str = "") -> MachineError:
        return MachineError(message, span or self.machine.decl.span,  # type: ignore[arg-type]
                            hint or "the theory's D is written out for machines of states, "
                            "junctions, scalar and vector variables, clocks, operation "
                            "definitions, and calls made in one cycle")

    def _refuse_unsupported(self) -> None:
        for terms in self.terms.values():
            declared = [*terms.variables.items()]
            if terms.scope is self.machine:
                declared += self.interpreter.open.items()
            for name, decl in declared:
                if type_of(decl.type) not in _SCALARS and name not in terms.sizes:
                    what = "variable" if name in terms.variables else "open constant (no value)"
                    where = "" if terms.scope is self.machine else f" of {terms.where}"
                    raise self._refuse(f"{what} {name}{where} is not a number or a Boolean",
                                       decl.span)
        for e, t in self.typed.items():
            if t not in (c.REAL, c.BOOL):
                raise self._refuse(f"the event {e} carries a value that is not real or "
                                   "Boolean: D holds the machine's numbers as reals, and an "
                                   f"{'int' if t == c.INT else 'nat' if t == c.NAT else 'other'}"
                                   " value would need a conversion it does not write")

    # ----- the state
    def event_fields(self) -> list[c.SchemaField]:
        """What the cycle read: ``<D>_e``, and ``<D>_e_value`` for a typed event."""
        fields = []
        for e in self.events:
            fields.append(c.SchemaField(f"{self.name}_{e}", c.BOOL))
            if e in self.typed:
                fields.append(c.SchemaField(f"{self.name}_{e}_value", self.typed[e]))
        return fields

    def own_fields(self) -> list[c.SchemaField]:
        """The machine's variables and clocks (its mode is :attr:`mode`), then each
        operation definition's variables, parameters and clocks."""
        return [f for t in self.terms.values() for f in
                [c.SchemaField(f, held_type(d.type)) for x, d in t.variables.items()
                 for f in t.fields(x)] +
                [c.SchemaField(t.field(k), c.REAL) for k in t.scope.clocks]]

    def open_constants(self) -> list[c.Constant]:
        """The open constants (no value, none given) that the machine or an operation reads:
        parameters of the theory of their declared type (an ``int`` or ``nat`` one stays
        whole, so the theory's family is the model's; the printer embeds it in D's reals
        where it is read), a ``real`` one as D holds numbers."""
        out: dict[str, c.Constant] = {}
        for n, d in self.interpreter.open.items():
            for terms in self.terms.values():
                if terms.refers(n) and terms.open_name(n) not in out:
                    scope = terms.scope.name
                    out[terms.open_name(n)] = c.Constant(
                        terms.open_name(n), open_type(d.type), None,
                        f"{scope}::{n}" if n in terms.scope.constants else
                        self.interpreter.open_origins.get(n, n))
        return list(out.values())

    def initial(self) -> tuple[ex.Expr, list[ex.Expr]]:
        """The mode's initial value (the initial junction) and the own fields' (an
        operation's are set at each call: until then they hold 0 or false)."""
        it = self.interpreter
        it.reset()
        top = self.terms[None]
        values = [v for x, d in self.machine.variables.items()
                  for v in top.initial(x, it.variables[x])]
        values += [ex.Num("0")] * len(self.machine.clocks)
        for op in it.operations:
            terms = self.terms[op]
            values += [default(d) for x, d in terms.variables.items() for _ in terms.fields(x)]
            values += [ex.Num("0")] * len(terms.scope.clocks)
        return ex.Num(str(self.index[it.node])), values

    # ----- one cycle
    def actions(self) -> tuple[c.Action, c.Action]:
        """``<D>Start`` and ``<D>Step`` for the machine, the places inside operations
        numbered after the machine's own modes (nodes, then the rests of cut actions)."""
        start, step = self._start(), self._step()
        if not self.inner:
            return start, step
        base = len(self.index) + len(self.resumes)

        def numbered(a: c.Action) -> c.Action | None:
            if isinstance(a, c.Assign) and a.targets == (self.mode,) and \
                    isinstance(a.values[0], ex.Name) and a.values[0].text.startswith(_PLACE):
                k = int(a.values[0].text[len(_PLACE):])
                return c.Assign(a.targets, (ex.Num(str(base + k)),))
            return None

        return map_action(start, numbered), map_action(step, numbered)

    def _start(self) -> c.Action:
        it = self.interpreter
        it.reset()
        _, values = self.initial()  # Start runs right after Init: the initial values hold
        facts = Facts()
        for f, v in zip(self.own_fields(), values):
            facts = facts.assigned(f.name, v)
        return _seq(self._run((), it.node, it.node, 0, during_done=False, resting=False,
                              facts=facts))

    def _step(self) -> c.Action:
        clocks = [c.Assign((t.field(k),), (ex.BinOp("+", name_expr(t.field(k)), ex.Num("1")),))
                  for t in self.terms.values() for k in t.scope.clocks]
        branches: list[tuple[int, c.Action]] = []
        inner: list[tuple[int, c.Action]] = []
        nodes_done: set[str] = set()
        resumes_done = 0
        while len(nodes_done) < len(self.rest) or resumes_done < len(self.resumes) or \
                len(inner) < len(self.inner):
            for key in [k for k in self.rest if k not in nodes_done]:
                nodes_done.add(key)  # rested there: its during action, then its transitions
                body = _seq(self._run((), key, key, 0, during_done=False, resting=True,
                                      facts=Facts()))
                if not isinstance(body, c.Skip):
                    branches.append((self.index[key], body))
            while resumes_done < len(self.resumes):  # the rest of an action cut by exec
                items, node = self.resumes[resumes_done]
                branches.append((len(self.index) + resumes_done, _seq(
                    self._run(items, node, None, 0, during_done=False, resting=False,
                              facts=Facts()))))
                resumes_done += 1
            while len(inner) < len(self.inner):  # inside an operation: as above, its calls
                place = self.inner[len(inner)]
                resting = place.items is None
                inner.append((len(inner), _seq(self._run(
                    place.items or (), place.node, place if resting else None, 0,
                    during_done=False, resting=resting, facts=Facts(), calls=place.calls))))
        base = len(self.index) + len(self.resumes)
        branches += [(base + k, body) for k, body in inner if not isinstance(body, c.Skip)]
        cases: c.Action = c.Skip()
        for number, body in sorted(branches, key=lambda nb: nb[0], reverse=True):
            cases = self._cond(ex.BinOp("==", name_expr(self.mode), ex.Num(str(number))),
                               body, cases)
        return _seq([*clocks, cases])

    def _items(self, statements: tuple[ast.Statement, ...] | list[ast.Statement],
               calls: Calls) -> list[Item]:
        """Statements as the interpreter's pending steps: ``exec`` ends the cycle, and
        ``wait(n)`` is ``n`` such ends."""
        out: list[Item] = []
        for st in statements:
            if isinstance(st, ast.ExecStatement):
                out.append(("end", None))
            elif isinstance(st, ast.WaitStatement):
                out += [("end", None)] * self.terms[calls.running].cycles(st)
            else:
                out.append(("stmt", st))
        return out

    def _run(self, items: tuple[Item, ...], node: str, here: str | Place | None, depth: int,
             during_done: bool, resting: bool, facts: Facts,
             calls: Calls = TOP) -> list[c.Action]:
        """The interpreter's loop from ``node`` with ``items`` pending (its cycle's step 3):
        the pending steps in order (an ``end`` cuts the cycle: the rest resumes in the next
        one, a mode of its own), then the during action unless a state was entered, then the
        transitions (``here``: where the cycle began resting, None when it resumed;
        ``facts``: what is known of D's state on the way here; ``calls``: the operation
        running and its callers)."""
        terms = self.terms[calls.running]
        out: list[c.Action] = []
        for n, (kind, item) in enumerate(items):
            if kind == "end":
                return [*out, c.Assign((self.mode,), (self._resume(items[n + 1:], node,
                                                                    calls),))]
            if kind == "do":
                out.append(item)  # type: ignore[arg-type]
                facts = facts.forgotten(item.targets)  # type: ignore[attr-defined]
            elif kind == "stmt" and self._called(item) is not None:
                return [*out, *self._invoke(item, items[n + 1:], node, here,  # type: ignore
                                            depth, during_done, resting, facts, calls)]
            elif kind == "stmt":
                out.append(terms.statement(item))  # type: ignore[arg-type]
                if isinstance(out[-1], c.Assign):  # it tells its field (a clock reset: 0)
                    facts = facts.after(out[-1].targets, out[-1].values)
            else:
                key = str(item)
                return [*out, *self._enter(key, items[n + 1:], here, depth + 1, facts, calls)]
        if not during_done:
            nodes = terms.scope.nodes
            during = [st for k in self._ancestors(node, calls)
                      for st in nodes[k].actions("during")] \
                if nodes[node].kind == "state" else []
            return [*out, *self._run(tuple(self._items(during, calls)), node, here, depth,
                                     True, resting, facts, calls)]
        return [*out, self._select(node, resting, here, depth, facts, calls)]

    def _called(self, s: object) -> str | None:
        """The operation definition a statement calls (``op(args)``, without ``$``), as the
        interpreter finds it before the platform's operations."""
        if isinstance(s, ast.CallStatement) and isinstance(s.call, ex.Call) and \
                isinstance(s.call.func, ex.Name) and \
                s.call.func.parts[-1] in self.interpreter.operations:
            return s.call.func.parts[-1]
        return None

    def _invoke(self, s: ast.CallStatement, rest: tuple[Item, ...], node: str,
                here: str | Place | None, depth: int, during_done: bool, resting: bool,
                facts: Facts, calls: Calls) -> list[c.Action]:
        """A call of an operation definition (the interpreter's ``_invoke``): its parameters
        take the arguments' values (computed in the caller's scope), its variables their
        initial values (which may read the parameters), its clocks 0; the caller, with the
        rest of its action, waits in a frame while the operation runs from its initial
        junction."""
        call: ex.Call = s.call  # type: ignore[assignment]
        op = str(self._called(s))
        path = [f.running for f in calls.stack] + [calls.running]
        if op in path:
            chain = " → ".join([p or self.machine.name for p in path] + [op])
            raise self._refuse(f"{op} is called again while it runs ({chain}): D holds one copy "
                               "of an operation's variables, so a recursive chain of calls "
                               "is not written", call.span,
                               "write the repetition as a loop of transitions with exec")
        caller, callee = self.terms[calls.running], self.terms[op]
        scope = callee.scope
        params = scope.decl.params
        if len(params) != len(call.args):
            raise self._refuse(f"{op} takes {len(params)} argument"
                               f"{'s' if len(params) != 1 else ''}, not {len(call.args)}",
                               call.span, f"write {op}({', '.join(p.name for p in params)})")
        start = scope.initial(None)
        if start is None:
            raise self._refuse(f"operation {op} has no initial junction", scope.decl.span,
                               "add 'initial i0' (see STM2)")
        names = {p.name for p in params}
        sets = [c.Assign(tuple(callee.fields(p.name)), tuple(
                    caller.components(a, callee.sizes[p.name]) if p.name in callee.sizes
                    else [caller.value(a, callee.variables[p.name])]))
                for p, a in zip(params, call.args)]
        for x, d in scope.variables.items():
            if x in names:
                continue
            read = {n.text for n in d.value.walk() if isinstance(n, ex.Name)} \
                if d.value is not None else set()
            if read & (set(scope.variables) - names):
                raise self._refuse(f"the initial value of {x} of operation {op} reads another "
                                   "of its variables", d.span)
            sets.append(c.Assign(tuple(callee.fields(x)), tuple(callee.declared_value(x))))
        sets += [c.Assign((callee.field(k),), (ex.Num("0"),)) for k in scope.clocks]
        for a in sets:
            facts = facts.after(a.targets, a.values)
        frame = Frame(calls.running, node, resting, rest, during_done)
        inside = Calls(op, (*calls.stack, frame))
        return [*sets, *self._run((), start.key, here, depth + 1, during_done, False, facts,
                                  inside)]

    def _resume(self, items: tuple[Item, ...], node: str, calls: Calls) -> ex.Expr:
        """The mode of the rest of a cut action (the same rest at the same node: one)."""
        if calls.stack:
            return self._inner(Place(calls.later(), node, items))
        if (items, node) not in self.resumes:
            self.resumes.append((items, node))
        return ex.Num(str(len(self.index) + self.resumes.index((items, node))))

    def _inner(self, place: Place) -> ex.Expr:
        """The mode of a place inside an operation, to be numbered once all are known."""
        if place not in self.inner:
            self.inner.append(place)
        return name_expr(f"{_PLACE}{self.inner.index(place)}")

    def _cond(self, cond: ex.Expr, then: c.Action, orelse: c.Action) -> c.Action:
        self.conditionals += 1
        if self.conditionals > MAX_CONDITIONALS:
            raise self._refuse(f"its cycles unroll to more than {MAX_CONDITIONALS} "
                               "conditionals", hint="let the machine's cycles pass fewer "
                               "junctions, or end them with exec")
        return c.Cond(cond, then, orelse)

    def _select(self, key: str, resting: bool, here: str | Place | None, depth: int,
                facts: Facts, calls: Calls) -> c.Action:
        """The machine at ``key`` after its during action: its first enabled transition
        taken, else it rests at ``key`` (``here``: where the cycle began). A transition whose
        guard cannot hold given ``facts`` is not written; one whose guard must hold is the
        last choice (those after it, and resting, are never taken)."""
        terms = self.terms[calls.running]
        scope = terms.scope
        if depth > MAX_DEPTH:
            raise self._refuse(f"a cycle from {here} passes more than {MAX_DEPTH} nodes: a "
                               "loop of transitions without exec?", scope.nodes[key].span,
                               self._loop_hint())
        chain = self._ancestors(key, calls)  # a composite state's transitions before its states'
        choices: list[tuple[ast.Transition, str, ex.Expr, list[c.Action], Facts]] = []
        before, always = facts, False  # before: what holds when the choice reaches t
        for t, source in [(t, a) for a in chain for t in scope.outgoing(a)
                          if t.target is not None and (resting or not t.decl.exec)]:
            guard, bindings = terms.guard(t.decl)
            holds = before.value(guard)
            if holds is False:
                continue
            choices.append((t, source, guard, bindings, before.taken(guard)))
            if holds is True:
                always = True
                break
            before = before.refused(guard)
        place: str | Place = key if not calls.stack else Place(calls.later(), key, None)
        action: c.Action = c.Skip()  # resting (never, when a guard must hold)
        if place != here and isinstance(place, str):
            action = c.Assign((self.mode,), (ex.Num(str(self.index[key])),))
        elif place != here and not always:
            action = c.Assign((self.mode,), (self._inner(place),))
        if not always and isinstance(place, str) and key not in self.rest:
            self.rest.append(key)
        for n, (t, source, guard, bindings, after) in reversed(list(enumerate(choices))):
            leaving = chain[chain.index(source):]  # exited innermost first
            exits = [s for k in reversed(leaving) for s in scope.nodes[k].actions("exit")]
            pending: list[Item] = [("do", b) for b in bindings]
            pending += [*self._items(exits, calls), *self._items(t.decl.action or (), calls),
                        ("enter", t.target)]
            taken = _seq(self._run(tuple(pending), key, here, depth, during_done=True,
                                   resting=False, facts=after, calls=calls))
            last = always and n == len(choices) - 1
            action = taken if last else self._cond(guard, taken, action)
        return action

    def _loop_hint(self) -> str:
        """A loop guarded by open constants may close for some values: say which."""
        names = ", ".join(self.interpreter.open)
        return "mark the end of the cycle with exec" + (names and ", or give the open "
                                                        f"constants ({names}) values (--const)")

    def _ancestors(self, key: str, calls: Calls) -> list[str]:
        """The node and the composite states around it, outermost first."""
        nodes = self.terms[calls.running].scope.nodes
        out = [key]
        while nodes[out[0]].parent is not None:
            out.insert(0, nodes[out[0]].parent)  # type: ignore[arg-type]
        return out

    def _enter(self, key: str, rest: tuple[Item, ...], here: str | Place | None, depth: int,
               facts: Facts, calls: Calls) -> list[c.Action]:
        """Entering ``key``: a state's entry action, then a composite state's initial
        junction, or a simple state's during action; then, the pending steps done, its
        transitions. An operation's top-level final state returns to its caller, which goes
        on with the rest of its action in the same cycle."""
        scope = self.terms[calls.running].scope
        node = scope.nodes[key]
        if depth > MAX_DEPTH:
            raise self._refuse(f"a cycle from {here} passes more than {MAX_DEPTH} nodes: a "
                               "loop of transitions without exec?", node.span,
                               self._loop_hint())
        if node.kind == "final" and node.parent is None and calls.stack:
            f = calls.stack[-1]  # (nothing is pending in the operation: it took a transition)
            return self._run(f.items, f.node, here, depth, f.during_done, f.resting, facts,
                             Calls(f.running, calls.stack[:-1]))
        items: list[Item] = []
        if node.kind == "state":
            items += self._items(node.actions("entry"), calls)
            if node.composite:
                inner = scope.initial(key)
                if inner is None:
                    raise self._refuse(f"state {key} has no initial junction", node.span,
                                       "add 'initial i0' inside it (see STM2)")
                items.append(("enter", inner.key))
            else:
                items += self._items(node.actions("during"), calls)
        return self._run((*items, *rest), key, here, depth, during_done=True, resting=False,
                         facts=facts, calls=calls)


def cycle_process(name: str, interpreters: list[MachineInterpreter],
                  reads: dict[str, tuple[c.Type, ...]],
                  writes: dict[str, tuple[c.Type, ...]]) -> c.BasicProcess:
    """``D`` for the module's machines (see the module docstring; several run in the
    module's order each cycle, on the events read once, as
    :class:`~cyphy.semantics.machines.parallel.ModuleInterpreter` runs them): ``reads``
    are the mapped input events with their ``registerRead`` payload types (``(bool,)`` or
    ``(bool, T)``), ``writes`` the mapped calls with their parameters' types. Raises
    :class:`MachineError` with what cannot be written, ``ValueError`` naming a call the
    mapping does not map."""
    same_cycle(interpreters)
    several = len(interpreters) > 1
    cycles = [_Cycle(name, f"{name}_{it.machine.name}" if several else name, it, reads, writes)
              for it in interpreters]
    events = {f.name: f for t in cycles for f in t.event_fields()}
    starts = [t.initial() for t in cycles]
    fields = [c.SchemaField(t.mode, c.NAT) for t in cycles] + list(events.values()) + \
        [f for t in cycles for f in t.own_fields()]
    constants = list({k.name: k for t in cycles for k in t.open_constants()}.values())
    names = [f.name for f in fields]
    every = [*names, *(k.name for k in constants)]
    clash = next((n for n in every if every.count(n) > 1), None)
    if clash is not None:
        raise cycles[0]._refuse(f"two parts of D's state would both be named {clash} (an "
                                "event, a variable, a clock or an open constant of one "
                                f"name, or one named '{MODE}' or '<event>_value')",
                                hint="rename one of them")
    values = [mode for mode, _ in starts] + \
        [ex.Bool(False) if f.type == c.BOOL else ex.Num("0") for f in events.values()] + \
        [v for _, own in starts for v in own]
    read_events = list(dict.fromkeys(e for t in cycles for e in t.events))
    typed = {e for t in cycles for e in t.typed}
    p = name
    actions = [t.actions() for t in cycles]
    defs = [c.ActionDef(f"{p}Init", (), c.Assign(tuple(names), tuple(values))),
            c.ActionDef(f"{p}Read", (), read_events_action(name, read_events, typed, reads)),
            c.ActionDef(f"{p}Start", (), _seq([start for start, _ in actions])),
            c.ActionDef(f"{p}Step", (), _seq([step for _, step in actions]))]
    call: Callable[[str], c.Call] = lambda suffix: c.Call(f"{p}{suffix}")
    wait = c.Wait(name_expr("cycle"))
    main = c.Seq((call("Init"), call("Read"), call("Start"), wait,
                  c.Mu("X", c.Seq((call("Read"), call("Step"), wait, c.Call("X"))))))
    return c.BasicProcess(name, tuple(constants), c.Schema(f"{p}State", tuple(fields)),
                          c.Schema(f"{p}Local", ()), tuple(defs), main)


def is_cycle_process(process: c.BasicProcess) -> bool:
    """Whether ``D`` is this module's (it has ``<D>Start``), not the automaton's: the
    theories' prose says which construction they state."""
    return any(a.name == f"{process.name}Start" for a in process.actions)
