"""RoboSim's cycle semantics for one state machine: an interpreter.

Each call of :meth:`MachineInterpreter.cycle` is one cycle of the machine (RoboSim,
Cavalcanti et al., "RoboSim: a simulation notation for robotics", SoSyM 2019, and the
paper's Section 2 / Fig. 3 for how a d-model drives a p-model):

1. **Inputs.** The events of the cycle are read once, at its start: ``$e`` is true when the
   event occurs in this cycle (its value, if typed, is what ``$e?x`` binds).
2. **Clocks.** Every clock advances by one cycle at the start of each cycle but the first;
   ``since(C)`` is the number of cycles since ``#C`` (or since the machine started) times
   the machine's cycle (``cycleDef cycle == k``, default 1): clocks count cycles.
3. **Run to exec.** The machine resumes where the last cycle ended. In a state it runs the
   state's ``during`` action and then takes the first enabled transition (in the order
   written; a composite state's own transitions before those of the states inside it). A
   transition is enabled when its trigger and condition hold and, for an ``exec``
   transition, when the machine has rested in its source since the previous cycle
   (``exec`` marks the end of the cycle: the transition waits for the next one). Taking a
   transition runs the exit actions (innermost first), the transition's action, and the
   target's entry action (a composite target continues at its initial junction).
   Junctions are passed through in the same cycle. The cycle ends when no transition is
   enabled (the machine rests in its state), or at an ``exec`` statement inside an action
   (the rest of the action, and the entry of the target, run at the start of the next
   cycle); ``wait(n)`` is ``n`` such ends.
4. **Outputs.** The operation calls (``$op(args)``), output events (``$e!v``, ``$e``) and
   assignments to platform variables (``speed = v``, ``$speed = v``: reads give the last
   value written, at first the interface's, else 0) of the cycle are returned in order;
   the caller writes them to the platform through the mapping (an output event or a
   variable it does not map is observable only), then waits ``cycle × tscale`` seconds.

**Operation definitions** (``operation op(x: real) { … }``, called as ``op(e)`` without
``$``) run inline, in the caller's cycle: the call binds the parameters to the arguments'
values, gives the operation's variables their initial values and its clocks 0, and runs the
operation's own machine from its initial junction under the same rules (its ``exec``
transitions and statements end the caller's cycle too, and the next cycle resumes inside
the operation); when it enters one of its top-level final states the call returns and the
caller goes on with the rest of its action, in the same cycle. Operations see their own
constants, parameters, variables and clocks, and the cycle's input events; their platform
calls and output events are the cycle's like the caller's. Calls nest (an operation may
call another) up to :data:`MAX_DEPTH`.

Simplifications (documented in the README): when two transitions are enabled at once the
first written is taken (RoboSim leaves the choice open; ``cyphy check --consistency``
reports such junctions, STM7); a junction with no enabled transition makes the machine wait
there for the next cycle instead of deadlocking (also reported by STM7); ``during`` actions
run to completion; final states of the machine end nothing (the machine just rests
there); an operation that never reaches a final state never returns; vectors are NumPy
arrays indexed from 1.
"""

from __future__ import annotations

from typing import Any, Mapping

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.records import record
from cyphy.semantics.machines import scalars
from cyphy.model.evaluate import MATH_FUNCTIONS, EvalError, evaluate
from cyphy.model.machines import Machine, MachineTransition

MACHINE = codes.code("E-MACHINE", codes.E, "the state machine cannot be run")

Output = tuple[str, tuple[float, ...]]
MAX_STEPS = 10_000
"""Steps (statements, nodes passed) in one cycle before the machine is taken to loop."""
MAX_DEPTH = 32
"""Nested operation calls before the machine is taken to recurse without end."""


class MachineError(Exception):
    """The machine cannot go on (a constant without value, an expression with no value, a
    loop without ``exec``), with the span of what is at fault."""

    def __init__(self, message: str, span: Span, hint: str = "") -> None:
        super().__init__(message)
        self.message, self.span, self.hint = message, span, hint


@record(frozen=True, slots=False)
class _Exec:
    """A cycle boundary inside an action (``exec``, or one cycle of ``wait``)."""


@record(frozen=True, slots=False)
class _Enter:
    key: str


@record(frozen=True, slots=False)
class _Stmt:
    statement: ast.Statement


_Step = _Exec | _Enter | _Stmt


@record(frozen=True, slots=False)
class Frame:
    """A caller suspended in an operation call: what it runs (``None``: the machine, else
    the operation's name), where it is, the rest of its action after the call, its
    variables and clocks, and whether its ``during`` action had run in the cycle of the call
    (it has not in a later cycle)."""

    running: str | None
    node: str
    resting: bool
    pending: tuple[_Step, ...]
    variables: tuple[tuple[str, Any], ...]
    clocks: tuple[tuple[str, int], ...]
    during_done: bool = False


@record(frozen=True, slots=False)
class Configuration:
    """Everything the next cycles depend on, hashable: where the machine is, the rest of an
    action interrupted by ``exec``, the variables and the clocks' cycle counts, and the
    operation calls under way (``running``: the operation now running, ``stack``: its
    callers, outermost first)."""

    node: str
    resting: bool  # rested in ``node`` since the last cycle ended: exec transitions enabled
    pending: tuple[_Step, ...]
    variables: tuple[tuple[str, Any], ...]
    clocks: tuple[tuple[str, int], ...]
    running: str | None = None
    stack: tuple[Frame, ...] = ()
    platform: tuple[tuple[str, Any], ...] = ()  # the platform variables' last values


def _frozen(v: Any) -> Any:
    return tuple(v.ravel().tolist()) if scalars.is_vector(v) else v


class MachineInterpreter:
    """One machine under RoboSim's cycle semantics; the sampled-controller hook of
    ``cyphy simulate`` (``cycle`` and ``reset``)."""

    def __init__(self, machine: Machine, constants: Mapping[str, object] | None = None,
                 functions: Mapping[str, Any] | None = None,
                 operations: Mapping[str, Machine] | None = None,
                 open_constants: Mapping[str, ast.VarDecl] | None = None) -> None:
        self.machine = machine
        self.operations = dict(operations or {})
        #: constants left without a value (only :mod:`cyphy.semantics.circus.dmodel_cycle`
        #: asks for them: it writes them as the theory's open constants); running the machine
        #: raises where it needs one, as do those computed from them
        self.open: dict[str, ast.VarDecl] = dict(open_constants or {})
        self.unknown: set[str] = set(self.open)  # and those computed from them
        self.open_origins: dict[str, str] = {}  # a package's open constant → pkg::name (caller)
        self.observable: frozenset[str] = frozenset()
        """Output events the platform mapping does not map (set by the caller): they reach
        no input of the p-model, so a simulation records them and the Flow* automaton
        leaves them out."""
        self.functions = {**MATH_FUNCTIONS, **(functions or {}), "since": lambda c: c}
        self.constants = self._constants(machine, dict(constants or {}))
        self.op_constants = {name: self._constants(op, dict(constants or {}))
                             for name, op in self.operations.items()}
        self.period = self._period()
        self._reads: dict[int, tuple[Any, Any]] = {}  # id(node) → (node, what it reads)
        start = machine.initial(None)
        if start is None:
            raise MachineError(f"machine {machine.name} has no initial junction",
                               machine.decl.span, "add 'initial i0' (see STM2)")
        self._start = start.key
        self.reset()

    # ----- set-up
    def _constants(self, machine: Machine, given: dict[str, object]) -> dict[str, object]:
        """The machine's (or operation's) constants; an operation's parameters are bound
        at each call instead."""
        values: dict[str, object] = dict(given)
        params = {p.name for p in machine.decl.params}
        unknown = self.unknown  # open, or computed from an open one: left out
        for name, decl in machine.constants.items():
            if name in params or name in unknown:
                continue
            if name in given:
                values[name] = _given(name, decl, given[name])
            elif decl.value is not None and unknown & {n.text for n in decl.value.walk()
                                                       if isinstance(n, ex.Name)}:
                unknown.add(name)
            elif decl.value is not None:
                values[name] = self._value(decl.value, values)
            else:
                raise MachineError(
                    f"the constant {name} of {machine.name} has no value", decl.span,
                    f"give it one in the machine, or in the scenario's [consts] ({name} = …)")
        return values

    def _value(self, e: ex.Expr, env: Mapping[str, object]) -> object:
        try:
            return evaluate(e, env, self.functions)
        except EvalError as err:
            raise MachineError(err.message, err.span, err.hint) from None

    def _period(self) -> float:
        cycle = self.machine.cycle
        if cycle is None:
            return 1.0
        value = self._value(cycle, self.constants)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value <= 0:
            raise MachineError(f"the cycle of {self.machine.name} is not a positive number",
                               cycle.span)
        return float(value)

    def _initial_value(self, decl: ast.VarDecl, constants: Mapping[str, object]) -> object:
        if decl.value is not None:
            if self.unknown & {n.text for n in decl.value.walk() if isinstance(n, ex.Name)}:
                return None  # from an open constant: D writes it as its expression
            return self._value(decl.value, constants)
        t = decl.type
        if isinstance(t, ast.PrimitiveType) and t.name == "boolean":
            return False
        if isinstance(t, ast.VectorType) and t.size is not None:
            size = self._value(t.size, constants)
            return scalars.zeros(int(size))
        return 0.0

    def reset(self) -> None:
        """Back to the start: variables at their initial values, clocks at 0, the machine
        before its initial junction (its first cycle leaves it)."""
        self.variables: dict[str, object] = {
            n: self._initial_value(d, self.constants)
            for n, d in self.machine.variables.items()}
        self.clocks: dict[str, int] = {c: 0 for c in self.machine.clocks}
        self.node = self._start
        self.resting = False
        self.pending: list[_Step] = []
        self.running: str | None = None
        self.stack: list[Frame] = []
        self.during_done = False
        self.cycles = 0
        self.platform_values: dict[str, object] = {
            n: self._initial_value(d, {}) for m in [self.machine, *self.operations.values()]
            for n, d in m.platform.written.items()}

    @property
    def current(self) -> Machine:
        """The machine now running: the machine, or the operation it has called."""
        return self.machine if self.running is None else self.operations[self.running]

    # ----- configurations (the Flow* compilation explores them)
    def configuration(self) -> Configuration:
        return Configuration(self.node, self.resting, tuple(self.pending),
                             _frozen_vars(self.variables), tuple(sorted(self.clocks.items())),
                             self.running,
                             tuple(Frame(f.running, f.node, f.resting, f.pending, f.variables,
                                         f.clocks) for f in self.stack),
                             _frozen_vars(self.platform_values))

    def restore(self, c: Configuration, cycles: int = 1) -> None:
        self.node, self.resting, self.pending = c.node, c.resting, list(c.pending)
        self.variables = _thawed_vars(c.variables)
        self.clocks = dict(c.clocks)
        self.running, self.stack = c.running, list(c.stack)
        self.platform_values.update(_thawed_vars(c.platform))
        self.cycles = cycles

    def saturate(self, caps: Mapping[str | None, Mapping[str, int]]) -> None:
        """Clock counts at most ``caps[running][clock]`` (None: the machine's clocks), in
        the running machine and in every suspended caller (the Flow* compilation)."""
        def capped(running: str | None, clocks: Mapping[str, int]) -> dict[str, int]:
            limit = caps.get(running, {})
            return {c: min(n, limit[c]) if c in limit else n for c, n in clocks.items()}

        self.clocks = capped(self.running, self.clocks)
        self.stack = [Frame(f.running, f.node, f.resting, f.pending, f.variables,
                            tuple(sorted(capped(f.running, dict(f.clocks)).items())),
                            f.during_done) for f in self.stack]

    # ----- one cycle
    def cycle(self, events: Mapping[str, object]) -> tuple[Output, ...]:
        """Run one cycle with the given input events (name → None when absent, True or the
        event's value when present) and return the calls and output events, in order."""
        if self.cycles > 0:
            for c in self.clocks:
                self.clocks[c] += 1
            self.stack = [Frame(f.running, f.node, f.resting, f.pending, f.variables,
                                tuple((c, n + 1) for c, n in f.clocks)) for f in self.stack]
        self.cycles += 1
        self.events = {name: v for name, v in events.items() if v is not None and not (
            v is False and self._untyped(name)) and name not in self.machine.unconnected}
        self.outputs: list[Output] = []
        steps = 0
        self.during_done = False
        while True:
            steps += 1
            if steps > MAX_STEPS:
                raise MachineError(f"machine {self.current.name} took {MAX_STEPS} steps "
                                   "without ending its cycle: a loop of transitions without "
                                   "exec?", self.current.nodes[self.node].span,
                                   "mark the end of the cycle with exec")
            if self.pending:
                step = self.pending.pop(0)
                if isinstance(step, _Exec):
                    self.resting = False
                    return tuple(self.outputs)
                if isinstance(step, _Stmt):
                    self._execute(step.statement)
                else:
                    self._arrive(step.key)
                    self.during_done = True
                    node = self.current.nodes[step.key]
                    if node.kind == "final" and node.parent is None and self.stack:
                        self._return()
                continue
            if not self.during_done:
                self._during()
                self.during_done = True
                continue
            taken = self._select()
            if taken is None:
                self.resting = True
                return tuple(self.outputs)
            self._take(taken)
            self.resting = False

    def _untyped(self, name: str) -> bool:
        decl = self.machine.platform.input_events.get(name) or next(
            (op.platform.input_events[name] for op in self.operations.values()
             if name in op.platform.input_events), None)
        return decl is None or decl.type is None

    def _ancestors(self, key: str) -> list[str]:
        """The node and the composite states around it, outermost first."""
        out = [key]
        parent = self.current.nodes[key].parent
        while parent is not None:
            out.insert(0, parent)
            parent = self.current.nodes[parent].parent
        return out

    def _during(self) -> None:
        node = self.current.nodes[self.node]
        if node.kind != "state":
            return
        for key in self._ancestors(self.node):
            for s in self.current.nodes[key].actions("during"):
                self.pending.append(_Stmt(s))

    def _select(self) -> tuple[MachineTransition, str, dict[str, object]] | None:
        """The transition to take (with the node it leaves and the bindings of ``$e?x``)."""
        for key in self._ancestors(self.node):
            for t in self.current.outgoing(key):
                if t.target is None:
                    continue
                if t.decl.exec and not self.resting:
                    continue
                bindings = self._bindings(t.decl)
                if all(self._truth(e, bindings) for e in (t.decl.trigger, t.decl.condition)
                       if e is not None):
                    return t, key, bindings
        return None

    def _bindings(self, t: ast.Transition) -> dict[str, object]:
        if id(t) not in self._reads:  # walked once (a compile runs hundreds of cycles)
            self._reads[id(t)] = (t, [
                (node.binding, node.name[-1]) for e in (t.trigger, t.condition)
                for node in (e.walk() if e is not None else ())
                if isinstance(node, ex.PlatformRef) and node.binding is not None])
        return {b: self.events[name] for b, name in self._reads[id(t)][1] if name in self.events}

    def _take(self, chosen: tuple[MachineTransition, str, dict[str, object]]) -> None:
        t, source, bindings = chosen
        self.variables.update(bindings)
        leaving = self._ancestors(self.node)
        leaving = leaving[leaving.index(source):]
        steps: list[_Step] = []
        for key in reversed(leaving):
            steps += [_Stmt(s) for s in self.current.nodes[key].actions("exit")]
        for s in t.decl.action or ():
            steps += self._expand(s)
        steps.append(_Enter(t.target))  # type: ignore[arg-type]
        self.pending = steps + self.pending

    def _expand(self, s: ast.Statement) -> list[_Step]:
        if isinstance(s, ast.ExecStatement):
            return [_Exec()]
        if isinstance(s, ast.WaitStatement):
            n = self._number(s.cycles)
            if n < 0 or n != int(n):
                raise MachineError(f"wait({n:g}): the number of cycles must be a natural "
                                   "number", s.span)
            return [_Exec()] * int(n)
        return [_Stmt(s)]

    def _arrive(self, key: str) -> None:
        """Enter a node: a state's entry action runs (then the state's own during action and
        transitions, or the initial junction of a composite state); a junction is left in the
        same cycle."""
        node = self.current.nodes[key]
        self.node = key
        if node.kind != "state":
            return
        steps: list[_Step] = []
        for s in node.actions("entry"):
            steps += self._expand(s)
        if node.composite:
            inner = self.current.initial(key)
            if inner is None:
                raise MachineError(f"state {key} has no initial junction", node.span,
                                   "add 'initial i0' inside it (see STM2)")
            steps.append(_Enter(inner.key))
        else:
            steps += [_Stmt(s) for s in node.actions("during")]
        self.pending = steps + self.pending

    # ----- statements and expressions
    def _execute(self, s: ast.Statement) -> None:
        if isinstance(s, ast.Assign):
            self._assign(s.target, self._eval(s.value))
        elif isinstance(s, ast.ClockReset):
            self.clocks[s.clock] = 0
        elif isinstance(s, ast.SendStatement):
            value = self._eval(s.value)
            name = s.event.name[-1] if isinstance(s.event, ex.PlatformRef) else "?"
            self.outputs.append((name, _floats(value, s.span)))
        elif isinstance(s, ast.CallStatement):
            self._call(s)
        elif isinstance(s, (ast.ExecStatement, ast.WaitStatement)):
            self.pending = self._expand(s) + self.pending

    def _call(self, s: ast.CallStatement) -> None:
        call = s.call
        if isinstance(call, ex.PlatformRef):  # `$e` alone: an output event without value
            self.outputs.append((call.name[-1], ()))
            return
        if not isinstance(call, ex.Call):
            raise MachineError("this statement does nothing", s.span)
        func = call.func
        name = func.name[-1] if isinstance(func, ex.PlatformRef) else \
            func.parts[-1] if isinstance(func, ex.Name) else None
        platform = self.current.platform
        if isinstance(func, ex.Name) and name in self.operations:
            self._invoke(name, call)
        elif name is not None and name in platform.operations:
            args = tuple(float(_floats(self._eval(a), a.span)[0]) for a in call.args)
            self.outputs.append((name, args))
        elif name is not None and name in platform.output_events:
            self.outputs.append((name, tuple(v for a in call.args
                                             for v in _floats(self._eval(a), a.span))))
        else:
            raise MachineError(f"'{name}' is neither an operation of {self.current.name}'s "
                               "platform nor an operation definition it can call", s.span,
                               "call an operation of the output context (STM3), or define "
                               f"'operation {name}(…) {{ … }}'")

    def _invoke(self, name: str, call: ex.Call) -> None:
        """Call an operation definition: suspend the caller (the rest of its action stays
        pending in its frame) and start the operation at its initial junction."""
        op = self.operations[name]
        params = op.decl.params
        if len(params) != len(call.args):
            raise MachineError(f"{name} takes {len(params)} argument"
                               f"{'s' if len(params) != 1 else ''}, not {len(call.args)}",
                               call.span, f"write {name}({', '.join(p.name for p in params)})")
        if len(self.stack) >= MAX_DEPTH:
            raise MachineError(f"more than {MAX_DEPTH} operation calls are under way: "
                               f"{name} calls itself without end?", call.span)
        start = op.initial(None)
        if start is None:
            raise MachineError(f"operation {name} has no initial junction", op.decl.span,
                               "add 'initial i0' (see STM2)")
        args = {p.name: self._eval(a) for p, a in zip(params, call.args)}
        self.stack.append(Frame(self.running, self.node, self.resting, tuple(self.pending),
                                _frozen_vars(self.variables),
                                tuple(sorted(self.clocks.items())), self.during_done))
        constants = self.op_constants[name]
        variables = {n: self._initial_value(d, {**constants, **args})
                     for n, d in op.variables.items()}
        variables.update(args)
        self.running, self.node, self.resting, self.pending = name, start.key, False, []
        self.variables = variables
        self.clocks = {c: 0 for c in op.clocks}

    def _return(self) -> None:
        """The running operation entered a final state: its caller goes on where it
        stopped (its ``during`` action is not run again in the cycle of the call)."""
        f = self.stack.pop()
        self.running, self.node, self.resting = f.running, f.node, f.resting
        self.pending = list(f.pending)
        self.variables = _thawed_vars(f.variables)
        self.clocks = dict(f.clocks)
        self.during_done = f.during_done

    def _assign(self, target: ex.Expr, value: object) -> None:
        name = target.name[-1] if isinstance(target, ex.PlatformRef) else target.text \
            if isinstance(target, ex.Name) and target.text not in self.variables else None
        if name in self.current.platform.written:
            # a platform variable (``speed`` or ``$speed``): an output of the cycle, in
            # program order like a call (the mapping's ``variable`` effect), read back later
            self.platform_values[name] = value
            self.outputs.append((name, _floats(value, target.span)))
            return
        if isinstance(target, ex.Name):
            self.variables[target.text] = value
            return
        if isinstance(target, ex.Index) and isinstance(target.base, ex.Name) and \
                len(target.args) == 1:
            name = target.base.text
            if name not in self.variables and name in self.current.platform.written:
                raise MachineError(f"one entry of the platform variable {name} cannot be "
                                   "written alone", target.span, f"assign all of {name}")
            vector = scalars.array(self.variables.get(name, ()), dtype=float)
            i = int(self._number(target.args[0])) - 1
            if not 0 <= i < vector.size:
                raise MachineError(f"index {i + 1} is outside {name} (size {vector.size})",
                                   target.span)
            vector[i] = float(_floats(value, target.span)[0])
            self.variables[name] = vector
            return
        raise MachineError("only a variable or one entry of a vector can be assigned",
                           target.span)

    def _env(self, bindings: Mapping[str, object] | None = None) -> dict[str, object]:
        env: dict[str, object] = dict(
            self.constants if self.running is None else self.op_constants[self.running])
        for n, v in self.platform_values.items():
            if n in self.current.platform.written:
                env[n] = env["$" + n] = v
        env.update(self.variables)
        env.update({c: n * self.period for c, n in self.clocks.items()})
        for name in [*self.machine.platform.input_events,
                     *self.current.platform.input_events]:
            env["$" + name] = name in self.events
        if bindings:
            env.update(bindings)
        return env

    def _eval(self, e: ex.Expr, bindings: Mapping[str, object] | None = None) -> object:
        def platform(node: ex.Expr) -> ex.Expr | None:
            if isinstance(node, ex.PlatformRef):
                return ex.Name(("$" + node.name[-1],), span=node.span)
            return None

        if id(e) not in self._reads:  # its $-form, once (the node is kept: its id stays)
            self._reads[id(e)] = (e, ex.transform(e, platform))
        try:
            return evaluate(self._reads[id(e)][1], self._env(bindings), self.functions)
        except EvalError as err:
            raise MachineError(err.message, err.span, err.hint) from None

    def _truth(self, e: ex.Expr, bindings: Mapping[str, object]) -> bool:
        value = self._eval(e, bindings)
        if not scalars.is_truth(value):
            raise MachineError("a condition must be true or false", e.span)
        return bool(value)

    def _number(self, e: ex.Expr) -> float:
        value = self._eval(e)
        if not scalars.is_number(value):
            raise MachineError("a number is needed here", e.span)
        return float(value)

    # ----- what callers read
    @property
    def parts(self) -> tuple["MachineInterpreter", ...]:
        """The machines run (a module's several: :mod:`~cyphy.semantics.machines.parallel`)."""
        return (self,)

    @property
    def state(self) -> str:
        """The node the machine rests in (a state, or a junction it is stuck at)."""
        return self.node


def _given(name: str, decl: ast.VarDecl, value: object) -> object:
    """A value given for a machine's constant (``--const``, ``[consts]``), of its declared
    type: a truth value for a ``boolean`` (``fast=true`` would be sent as 1.0), a number
    for a ``real``, a whole number for an ``int`` (at least 0 for a ``nat``: ``count=2.5``
    would run a model its type rules out)."""
    t = decl.type
    wrong = scalars.misfit(t.name if isinstance(t, ast.PrimitiveType) else "", value)
    if wrong is not None:
        shown = str(value).lower() if scalars.is_truth(value) else repr(value)
        raise MachineError(f"the constant {name} is {wrong[0]}, not {shown}", decl.span,
                           f"give {name} {wrong[1]}")
    return value


def _frozen_vars(variables: Mapping[str, object]) -> tuple[tuple[str, Any], ...]:
    return tuple((n, _frozen(v)) for n, v in sorted(variables.items()))


def _thawed_vars(variables: tuple[tuple[str, Any], ...]) -> dict[str, object]:
    return {n: scalars.array(v) if isinstance(v, tuple) else v for n, v in variables}


def _floats(value: object, span: Span) -> tuple[float, ...]:
    if scalars.is_truth(value):
        return (1.0 if value else 0.0,)
    if scalars.is_number(value):
        return (float(value),)
    if scalars.is_vector(value):
        return tuple(float(x) for x in value.ravel())
    raise MachineError(f"{value!r} cannot be sent to the platform as numbers", span)
