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

Refused (``W-SEMANTICS-DMODEL``, with the reason): operation definitions, vector variables
and open constants, an ``int`` or ``nat`` event value or call argument computed from the
state (D holds numbers as reals), ``wait(n)`` with ``n`` not a constant, a name bound by
``$e?x`` outside a conjunct of its guard, machines of one module with different cycles, and
a cycle that passes more than :data:`MAX_DEPTH` nodes (a loop without ``exec``).
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel import MODE, literal, read_events_action
from cyphy.semantics.circus.path_facts import Facts
from cyphy.semantics.circus.values import held_type, type_of, value_expr
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter
from cyphy.semantics.machines.parallel import same_cycle

#: Nodes passed in one cycle before the unrolling is taken to loop.
MAX_DEPTH = 32
#: Conditionals in one ``D`` before it is called too large to write.
MAX_CONDITIONALS = 2000
_SCALARS = (c.REAL, c.INT, c.NAT, c.BOOL)
_CONNECTIVES = ("/\\", "\\/", "=>", "<=>")


def _name(text: str) -> ex.Name:
    return ex.Name((text,))


def _seq(actions: list[c.Action]) -> c.Action:
    actions = [a for a in actions if not isinstance(a, c.Skip)]
    if not actions:
        return c.Skip()
    return actions[0] if len(actions) == 1 else c.Seq(tuple(actions))


#: A pending step of the interpreter: ``("stmt", statement)``, ``("do", action)`` (a binding
#: already translated), ``("end", None)`` (exec: the cycle ends) or ``("enter", node)``.
_Item = tuple[str, object]


class _Cycle:
    """The translation of one machine (see the module docstring)."""

    def __init__(self, name: str, own: str, interpreter: MachineInterpreter,
                 reads: dict[str, tuple[c.Type, ...]],
                 writes: dict[str, tuple[c.Type, ...]]) -> None:
        """``name`` is D's (its events' fields ``<D>_e``), ``own`` prefixes the machine's
        mode, variables and clocks (``<D>``, or ``<D>_<machine>`` beside others)."""
        self.interpreter = interpreter
        self.machine = m = interpreter.machine
        self.writes = writes
        self.name = name
        self.prefix = own
        self.mode = f"{own}_{MODE}"
        self.index = {key: i for i, key in enumerate(m.nodes)}
        # an event the mapping does not map, or the module does not connect, never occurs
        self.events = [e for e in m.platform.input_events
                       if e in reads and e not in m.unconnected]
        self.typed = {e: reads[e][1] for e in self.events if len(reads[e]) == 2}
        self.conditionals = 0
        self.rest: list[str] = []  # nodes the machine may rest in, in the order found
        #: the rests of actions cut by exec (pending steps, and the node), in the order found
        self.resumes: list[tuple[tuple[_Item, ...], str]] = []
        self._refuse_unsupported()

    # ----- what the translation refuses
    def _refuse(self, message: str, span: object = None, hint: str = "") -> MachineError:
        return MachineError(message, span or self.machine.decl.span,  # type: ignore[arg-type]
                            hint or "the theory's D for typed events is written for machines "
                            "of states, junctions, variables, clocks, and calls made in one "
                            "cycle")

    def _refuse_unsupported(self) -> None:
        m = self.machine
        if self.interpreter.operations:
            names = ", ".join(sorted(self.interpreter.operations))
            raise self._refuse(f"it calls the operation definition{'s' if ',' in names else ''}"
                               f" {names}: D for typed events does not run operation "
                               "definitions")
        for name, decl in [*m.variables.items(), *self.interpreter.open.items()]:
            if type_of(decl.type) not in _SCALARS:
                what = "variable" if name in m.variables else "open constant (no value)"
                raise self._refuse(f"{what} {name} is not a number or a Boolean", decl.span)
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
        """The machine's variables and clocks (its mode is :attr:`mode`)."""
        p = self.prefix
        return [c.SchemaField(f"{p}_{x}", held_type(d.type))
                for x, d in self.machine.variables.items()] + \
            [c.SchemaField(f"{p}_{k}", c.REAL) for k in self.machine.clocks]

    def open_name(self, name: str) -> str:
        """The theory's constant for an open constant: the machine's own is named as its
        variables are, one declared outside it (a package's) once for all of D's machines."""
        own = name in self.machine.constants
        return f"{self.prefix if own else self.name}_{name.replace('::', '_')}"

    def open_constants(self) -> list[c.Constant]:
        """The machine's open constants (no value, none given): parameters of the theory,
        held as D holds numbers (:func:`~cyphy.semantics.circus.values.held_type`)."""
        m = self.machine.name
        return [c.Constant(self.open_name(n), held_type(d.type), None,
                           f"{m}::{n}" if n in self.machine.constants else n)
                for n, d in self.interpreter.open.items()]

    def initial(self) -> tuple[ex.Expr, list[ex.Expr]]:
        """The mode's initial value (the initial junction) and the own fields'."""
        it = self.interpreter
        it.reset()
        values = [_constant(it.variables[x], held_type(d.type)) if it.variables[x] is not None
                  else self._predicate(d.value, {}) if held_type(d.type) == c.BOOL
                  else self._expr(d.value)  # from an open constant
                  for x, d in self.machine.variables.items()]
        return ex.Num(str(self.index[it.node])), values + [ex.Num("0")] * len(self.machine.clocks)

    # ----- one cycle
    def start(self) -> c.Action:
        it = self.interpreter
        it.reset()
        _, values = self.initial()  # Start runs right after Init: the initial values hold
        fields = [f"{self.prefix}_{x}" for x in [*self.machine.variables, *self.machine.clocks]]
        facts = Facts()
        for f, v in zip(fields, values):
            facts = facts.assigned(f, v)
        return _seq(self._run((), it.node, it.node, 0, during_done=False, resting=False,
                              facts=facts))

    def step(self) -> c.Action:
        clocks = [c.Assign((f"{self.prefix}_{k}",),
                           (ex.BinOp("+", _name(f"{self.prefix}_{k}"), ex.Num("1")),))
                  for k in self.machine.clocks]
        branches: list[tuple[int, c.Action]] = []
        nodes_done: set[str] = set()
        resumes_done = 0
        while len(nodes_done) < len(self.rest) or resumes_done < len(self.resumes):
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
        cases: c.Action = c.Skip()
        for number, body in sorted(branches, key=lambda nb: nb[0], reverse=True):
            cases = self._cond(ex.BinOp("==", _name(self.mode), ex.Num(str(number))),
                               body, cases)
        return _seq([*clocks, cases])

    def _items(self, statements: tuple[ast.Statement, ...] | list[ast.Statement]
               ) -> list[_Item]:
        """Statements as the interpreter's pending steps: ``exec`` ends the cycle, and
        ``wait(n)`` is ``n`` such ends."""
        out: list[_Item] = []
        for st in statements:
            if isinstance(st, ast.ExecStatement):
                out.append(("end", None))
            elif isinstance(st, ast.WaitStatement):
                out += [("end", None)] * self._cycles(st)
            else:
                out.append(("stmt", st))
        return out

    def _cycles(self, st: ast.WaitStatement) -> int:
        try:
            n = self.interpreter._value(st.cycles, self.interpreter.constants)
        except MachineError:
            n = None
        if isinstance(n, bool) or not isinstance(n, (int, float)) or n < 0 or n != int(n):
            raise self._refuse("wait(n) is written in D only with n a constant natural "
                               "number", st.span)
        return int(n)

    def _run(self, items: tuple[_Item, ...], node: str, here: str | None, depth: int,
             during_done: bool, resting: bool, facts: Facts) -> list[c.Action]:
        """The interpreter's loop from ``node`` with ``items`` pending (its cycle's step 3):
        the pending steps in order (an ``end`` cuts the cycle: the rest resumes in the next
        one, a mode of its own), then the during action unless a state was entered, then the
        transitions (``here``: the node the cycle began resting in, None when it resumed;
        ``facts``: what is known of D's state on the way here)."""
        out: list[c.Action] = []
        for n, (kind, item) in enumerate(items):
            if kind == "end":
                resume = self._resume(items[n + 1:], node)
                return [*out, c.Assign((self.mode,), (ex.Num(str(resume)),))]
            if kind == "do":
                out.append(item)  # type: ignore[arg-type]
                facts = facts.forgotten(item.targets)  # type: ignore[attr-defined]
            elif kind == "stmt":
                out.append(self._statement(item))  # type: ignore[arg-type]
                if isinstance(out[-1], c.Assign):  # it tells its field (a clock reset: 0)
                    facts = facts.assigned(out[-1].targets[0], out[-1].values[0])
            else:
                key = str(item)
                return [*out, *self._enter(key, items[n + 1:], here, depth + 1, facts)]
        if not during_done:
            during = [st for k in self._ancestors(node)
                      for st in self.machine.nodes[k].actions("during")] \
                if self.machine.nodes[node].kind == "state" else []
            return [*out, *self._run(tuple(self._items(during)), node, here, depth, True,
                                     resting, facts)]
        return [*out, self._select(node, resting, here, depth, facts)]

    def _resume(self, items: tuple[_Item, ...], node: str) -> int:
        """The mode of the rest of a cut action (the same rest at the same node: one)."""
        if (items, node) not in self.resumes:
            self.resumes.append((items, node))
        return len(self.index) + self.resumes.index((items, node))

    def _cond(self, cond: ex.Expr, then: c.Action, orelse: c.Action) -> c.Action:
        self.conditionals += 1
        if self.conditionals > MAX_CONDITIONALS:
            raise self._refuse(f"its cycles unroll to more than {MAX_CONDITIONALS} "
                               "conditionals", hint="let the machine's cycles pass fewer "
                               "junctions, or end them with exec")
        return c.Cond(cond, then, orelse)

    def _select(self, key: str, resting: bool, here: str | None, depth: int,
                facts: Facts) -> c.Action:
        """The machine at ``key`` after its during action: its first enabled transition
        taken, else it rests at ``key`` (``here``: where the cycle began). A transition whose
        guard cannot hold given ``facts`` is not written; one whose guard must hold is the
        last choice (those after it, and resting, are never taken)."""
        if depth > MAX_DEPTH:
            raise self._refuse(f"a cycle from {here} passes more than {MAX_DEPTH} nodes: a "
                               "loop of transitions without exec?",
                               self.machine.nodes[key].span,
                               self._loop_hint())
        chain = self._ancestors(key)  # a composite state's transitions before its states'
        choices: list[tuple[ast.Transition, str, ex.Expr, list[c.Action], Facts]] = []
        before, always = facts, False  # before: what holds when the choice reaches t
        for t, source in [(t, a) for a in chain for t in self.machine.outgoing(a)
                          if t.target is not None and (resting or not t.decl.exec)]:
            guard, bindings = self._guard(t.decl)
            holds = before.value(guard)
            if holds is False:
                continue
            choices.append((t, source, guard, bindings, before.taken(guard)))
            if holds is True:
                always = True
                break
            before = before.refused(guard)
        action: c.Action = c.Skip() if key == here else \
            c.Assign((self.mode,), (ex.Num(str(self.index[key])),))
        if not always and key not in self.rest:
            self.rest.append(key)
        for n, (t, source, guard, bindings, after) in reversed(list(enumerate(choices))):
            leaving = chain[chain.index(source):]  # exited innermost first
            exits = [s for k in reversed(leaving)
                     for s in self.machine.nodes[k].actions("exit")]
            pending: list[_Item] = [("do", b) for b in bindings]
            pending += [*self._items(exits), *self._items(t.decl.action or ()),
                        ("enter", t.target)]
            taken = _seq(self._run(tuple(pending), key, here, depth, during_done=True,
                                   resting=False, facts=after))
            last = always and n == len(choices) - 1
            action = taken if last else self._cond(guard, taken, action)
        return action

    def _loop_hint(self) -> str:
        """A loop guarded by open constants may close for some values: say which."""
        names = ", ".join(self.interpreter.open)
        return "mark the end of the cycle with exec" + (names and ", or give the open "
                                                        f"constants ({names}) values (--const)")

    def _ancestors(self, key: str) -> list[str]:
        """The node and the composite states around it, outermost first."""
        out = [key]
        while self.machine.nodes[out[0]].parent is not None:
            out.insert(0, self.machine.nodes[out[0]].parent)  # type: ignore[arg-type]
        return out

    def _enter(self, key: str, rest: tuple[_Item, ...], here: str | None, depth: int,
               facts: Facts) -> list[c.Action]:
        """Entering ``key``: a state's entry action, then a composite state's initial
        junction, or a simple state's during action; then, the pending steps done, its
        transitions."""
        node = self.machine.nodes[key]
        if depth > MAX_DEPTH:
            raise self._refuse(f"a cycle from {here} passes more than {MAX_DEPTH} nodes: a "
                               "loop of transitions without exec?", node.span,
                               self._loop_hint())
        items: list[_Item] = []
        if node.kind == "state":
            items += self._items(node.actions("entry"))
            if node.composite:
                inner = self.machine.initial(key)
                if inner is None:
                    raise self._refuse(f"state {key} has no initial junction", node.span,
                                       "add 'initial i0' inside it (see STM2)")
                items.append(("enter", inner.key))
            else:
                items += self._items(node.actions("during"))
        return self._run((*items, *rest), key, here, depth, during_done=True, resting=False,
                         facts=facts)

    # ----- guards and expressions
    def _guard(self, t: ast.Transition) -> tuple[ex.Expr, list[c.Action]]:
        """The guard over D's state and the assignments of the names ``$e?x`` binds."""
        parts = [e for e in (t.trigger, t.condition) if e is not None]
        bound: dict[str, str] = {}
        bindings: list[c.Action] = []
        for part in parts:
            top = set(map(id, ex.conjuncts(part)))
            for n in part.walk():
                if isinstance(n, ex.PlatformRef) and n.binding is not None:
                    event = n.name[-1]
                    if id(n) not in top:
                        raise self._refuse(f"transition {t.name} binds {n.binding} from "
                                           f"${event} outside a conjunct of its guard: the "
                                           "value is bound only when the event occurs", n.span,
                                           f"write the guard as ${event}?{n.binding} /\\ …")
                    if event in self.typed:
                        bound[n.binding] = f"{self.name}_{event}_value"
                        bindings.append(c.Assign((f"{self.prefix}_{n.binding}",),
                                                 (_name(bound[n.binding]),)))
                    elif event in self.events:  # (an event not mapped never occurs)
                        raise self._refuse(f"transition {t.name} binds {n.binding} from the "
                                           f"untyped event {event}", n.span)
        if not parts:
            return ex.Bool(True), bindings
        guard = ex.conjunction([self._predicate(p, bound) for p in parts])
        return guard, bindings

    def _predicate(self, e: ex.Expr, bound: dict[str, str]) -> ex.Expr:
        """A condition as a predicate: Z has no Boolean-valued terms in predicate position,
        so an event and a Boolean variable are compared with true."""
        if isinstance(e, ex.BinOp) and e.op in _CONNECTIVES:
            return ex.BinOp(e.op, self._predicate(e.left, bound),
                            self._predicate(e.right, bound))
        if isinstance(e, ex.UnaryOp) and e.op == "not":
            return ex.UnaryOp("not", self._predicate(e.operand, bound))
        if isinstance(e, ex.PlatformRef):
            event = e.name[-1]
            if event not in self.events:  # not mapped: it never occurs
                return ex.Bool(False)
            return ex.BinOp("==", _name(f"{self.name}_{event}"), ex.Bool(True))
        if isinstance(e, ex.Bool):
            return e
        declared = {**self.interpreter.open, **self.machine.variables}
        if isinstance(e, ex.Name) and e.text in declared and \
                type_of(declared[e.text].type) == c.BOOL:
            return ex.BinOp("==", self._expr(e, bound), ex.Bool(True))
        return self._expr(e, bound)

    def _expr(self, e: ex.Expr, bound: dict[str, str] | None = None) -> ex.Expr:
        """A value over D's state: variables and clocks are D's, constants their values."""
        p, bound = self.prefix, bound or {}
        period = self.interpreter.period
        constants = self.interpreter.constants

        def rewrite(n: ex.Expr) -> ex.Expr | None:
            if isinstance(n, ex.Call) and isinstance(n.func, ex.Name) and \
                    n.func.text == "since" and len(n.args) == 1 and \
                    isinstance(n.args[0], ex.Name) and n.args[0].text in self.machine.clocks:
                count = _name(f"{p}_{n.args[0].text}")
                return count if period == 1 else ex.BinOp("*", count, value_expr(period))
            if isinstance(n, ex.PlatformRef):
                raise self._refuse(f"${n.text} is used as a value", n.span,
                                   "test events in guards only")
            if isinstance(n, ex.Name):
                if n.text in bound:
                    return _name(bound[n.text])
                if n.text in self.machine.variables:
                    return _name(f"{p}_{n.text}")
                value = constants.get(n.text)
                if isinstance(value, (bool, int, float)):
                    return _constant(value, c.REAL)
                if n.text in self.interpreter.open:
                    return _name(self.open_name(n.text))
                decl = self.machine.constants.get(n.text)
                if decl is not None and decl.value is not None:  # computed from an open one
                    return self._expr(decl.value)
                if n.text == "since" or n.text in self.machine.clocks:
                    return None  # since(C) is rewritten at the call (bottom-up)
                raise self._refuse(f"'{n.text}' has no value in the machine", n.span)
            return None

        out = ex.transform(e, rewrite)
        left = next((n for n in out.walk() if isinstance(n, ex.Name) and (
            n.text == "since" or n.text in self.machine.clocks)), None)
        if left is not None:
            raise self._refuse(f"'{left.text}' is used outside since(C)", left.span)
        return out

    # ----- statements
    def _statement(self, s: ast.Statement) -> c.Action:
        p = self.prefix
        if isinstance(s, ast.Assign):
            if not isinstance(s.target, ex.Name) or s.target.text not in self.machine.variables:
                raise self._refuse("only a variable of the machine can be assigned", s.span)
            decl = self.machine.variables[s.target.text]
            value = self._predicate(s.value, {}) if held_type(decl.type) == c.BOOL \
                else self._expr(s.value)
            return c.Assign((f"{p}_{s.target.text}",), (value,))
        if isinstance(s, ast.ClockReset):
            return c.Assign((f"{p}_{s.clock}",), (ex.Num("0"),))
        if isinstance(s, ast.SkipStatement):
            return c.Skip()
        if isinstance(s, ast.SendStatement):
            name = s.event.name[-1] if isinstance(s.event, ex.PlatformRef) else "?"
            return self._send(name, (s.value,), s)
        if isinstance(s, ast.CallStatement):
            call = s.call
            if isinstance(call, ex.PlatformRef):
                return self._send(call.name[-1], (), s)
            if isinstance(call, ex.Call) and isinstance(call.func, ex.PlatformRef):
                return self._send(call.func.name[-1], call.args, s)
            platform = self.machine.platform  # `move(0, av)`: RoboTool's call without `$`
            if isinstance(call, ex.Call) and isinstance(call.func, ex.Name) and \
                    call.func.parts[-1] in {**platform.operations, **platform.output_events}:
                return self._send(call.func.parts[-1], call.args, s)
            raise self._refuse("this call is not a call of the platform", s.span)
        raise self._refuse("this statement is not written in D", s.span)

    def _send(self, name: str, args: tuple[ex.Expr, ...], s: ast.Statement) -> c.Action:
        types = self.writes.get(name)
        if types is None and name in self.interpreter.observable:
            return c.Skip()  # an output event the mapping does not map: observable only
        if types is None or len(types) != len(args):
            raise ValueError(name)
        values = tuple(c.Out(self._argument(a, t)) for a, t in zip(args, types))
        return c.Prefix(c.Comm("registerWrite", name, values), c.Skip())

    def _argument(self, a: ex.Expr, type_: c.Type) -> ex.Expr:
        """A constant argument as the automaton's ``D`` writes it (a literal of the
        parameter's type), any other as an expression over the state."""
        translated = self._expr(a)
        if not any(isinstance(n, ex.Name) for n in translated.walk()):
            try:
                value = self.interpreter._value(a, self.interpreter.constants)
            except MachineError:
                value = None
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                return literal(float(value), type_)
        if type_ in (c.INT, c.NAT):
            raise self._refuse(f"an argument of {'int' if type_ == c.INT else 'nat'} type is "
                               "computed from the machine's state, which D holds as reals: "
                               "the conversion is not written", a.span)
        return translated


def _constant(value: object, type_: c.Type) -> ex.Expr:
    if isinstance(value, bool) or type_ == c.BOOL:
        return ex.Bool(bool(value))
    return literal(float(value), type_)  # type: ignore[arg-type]


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
    defs = [c.ActionDef(f"{p}Init", (), c.Assign(tuple(names), tuple(values))),
            c.ActionDef(f"{p}Read", (), read_events_action(name, read_events, typed, reads)),
            c.ActionDef(f"{p}Start", (), _seq([t.start() for t in cycles])),
            c.ActionDef(f"{p}Step", (), _seq([t.step() for t in cycles]))]
    call: Callable[[str], c.Call] = lambda suffix: c.Call(f"{p}{suffix}")
    wait = c.Wait(_name("cycle"))
    main = c.Seq((call("Init"), call("Read"), call("Start"), wait,
                  c.Mu("X", c.Seq((call("Read"), call("Step"), wait, c.Call("X"))))))
    return c.BasicProcess(name, tuple(constants), c.Schema(f"{p}State", tuple(fields)),
                          c.Schema(f"{p}Local", ()), tuple(defs), main)


def is_cycle_process(process: c.BasicProcess) -> bool:
    """Whether ``D`` is this module's (it has ``<D>Start``), not the automaton's: the
    theories' prose says which construction they state."""
    return any(a.name == f"{process.name}Start" for a in process.actions)
