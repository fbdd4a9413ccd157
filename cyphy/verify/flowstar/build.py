"""Building the automaton's :class:`~cyphy.verify.flowstar.problem.Problem`: the model
elaborated with the scenario's constants, its equations assembled and reduced to explicit
ODEs, and the scenario's controller, environment, events and property translated to SymPy
over the automaton's variables (see :mod:`cyphy.verify.flowstar.export` for the automaton).
Every refusal is an ``E-FLOWSTAR`` diagnostic at the scenario's line.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import sympy

from cyphy import expr as ex
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.lang import ast
from cyphy.pipeline.elaborate import ElaborateOptions, elaborate
from cyphy.semantics.dynamics.equations import (AssemblyError, Equation, assemble,
                                                input_event_predicate, mapping_operation)
from cyphy.semantics.dynamics.obstacles import report_obstacles
from cyphy.semantics.dynamics.reduce import reduce_system
from cyphy.translate.to_sympy import UnsupportedNode, to_sympy
from cyphy.verify.flowstar.constraints import dnf
from cyphy.verify.flowstar.first_cycle import settle, unreadable
from cyphy.verify.flowstar.limits import MAX_JUMPS
from cyphy.verify.flowstar.machine import machine_controller
from cyphy.verify.flowstar.mapping_vectors import per_component
from cyphy.verify.flowstar.printer import FUNCTIONS, NotExpressible, valid_name
from cyphy.verify.flowstar.problem import CLOCK, TIMER, Problem, symbol
from cyphy.verify.flowstar.scenario import EXPORT, Scenario
from cyphy.verify.flowstar.time_functions import replace_time_functions
from cyphy.verify.flowstar.typed_events import (ValueRefused, machine_events, not_one_number,
                                                solve_value, typed_event)

if TYPE_CHECKING:
    from cyphy.verify.flowstar.typed_events import TypedEvent


def build_problem(paths: Sequence[str | Path], scenario: Scenario, report: Report,
                  search_paths: tuple[str, ...] = (), sampled: bool = False
                  ) -> tuple[Problem | None, dict[str, str]]:
    """The model elaborated with the scenario's constants, reduced, and the scenario's
    controller, environment and property translated; None (with diagnostics) when any of
    it cannot be done. Also returns the source texts for rendering diagnostics.

    ``sampled``: the problem is for ``simulate``, whose controller is the machine's
    interpreter, so a machine reading typed input events is run, not compiled (see
    :func:`cyphy.verify.flowstar.machine.machine_controller`): the problem then has no
    modes, its inputs are those every operation the machine may call sets, its events those
    the machine reads, and each typed event's value (``Problem.event_values``) is what the
    mapping's equations give its parameter."""
    result = elaborate(paths, ElaborateOptions(scenario.model, dict(scenario.consts),
                                               search_paths,
                                               default_inertial=scenario.default_inertial,
                                               strict_consts=False))  # call arguments too
    for d in result.report.diagnostics:
        report.add(d)
    sources = dict(result.check.sources)
    sources[scenario.path] = scenario.text
    if result.model is None:
        return None, sources
    machine = None
    if not scenario.states:  # no [controller]: the d-model's state machine is the controller

        machine = machine_controller(result.check, result.model.name, scenario, report,
                                     sampled)
        if machine is None:
            return None, sources
    try:
        return _Builder(result, scenario, report, machine).build(), sources
    except _Stop:
        return None, sources


class _Stop(Exception):
    """An error was reported: stop building."""


class _Builder:
    def __init__(self, elaborated: Any, scenario: Scenario, report: Report,
                 machine: Any = None) -> None:
        self.elaborated, self.model = elaborated, elaborated.model
        self.s, self.report, self.machine = scenario, report, machine
        self.ports = _ports(self.model)
        self.call_effects: dict[str, dict[str, Any]] = {}
        # a machine run by its interpreter alone (typed input events): no automaton's modes
        self.uncompiled = machine is not None and not scenario.states
        self.typed: dict[str, TypedEvent] = {}

    def fail(self, message: str, span: Span, hint: str = "") -> _Stop:
        self.report.report(EXPORT, message, span, hint)
        return _Stop()

    def build(self) -> Problem:
        s = self.s
        self._check_elements()
        try:
            system = assemble(self.model, list(s.elements) or None)
        except AssemblyError as err:
            raise self.fail(err.message, err.span, err.hint) from None
        self._environment(system)
        effects, frame = self._effects()
        operation_effects: dict[str, tuple[tuple[Any, ...], dict[str, Any]]] = {}
        if self.uncompiled:  # the inputs are those the operations the machine may call set
            operation_effects = self._operation_effects(None)
            frame = sorted({u for _, solved in operation_effects.values() for u in solved})
        free = sorted(system.inputs - set(frame))
        if free:
            raise self.fail(
                f"nothing gives the input{'s' if len(free) > 1 else ''} {', '.join(free)}: "
                "the controller's calls do not set them and the environment does not say how "
                "they evolve", s.span("environment"),
                "add them to [environment] (a derivative, or { value = NUMBER }), or restrict "
                "the model with 'elements'")
        event_exprs = self._event_expressions()
        unsafe_exprs = [(self.expression(text, span), span) for text, span in
                        ((t, s.span("unsafe", t.split()[0])) for t in s.unsafe)]
        probes = self._probes(system, [e for e, _ in event_exprs.values()] +
                              [e for t in self.typed.values() for e in t.equations] +
                              [e for e, _ in unsafe_exprs])
        reduced = reduce_system(system)
        if reduced.obstacles:
            report_obstacles(reduced, self.report)
            raise self.fail(f"the equations of {self.model.name} cannot be reduced to explicit "
                            "ODEs (see the diagnostics above)", s.span("elements"),
                            "restrict the model to the elements that matter with 'elements', "
                            "as for `cyphy solve --element`")
        zero = {sympy.Symbol(f"der_{u}", real=True): 0 for u in frame}
        states = [x for x in reduced.states if x not in probes]
        rhs = {x: sympy.expand(reduced.rhs[x].xreplace(zero)) for x in states}
        rhs, auxiliary = replace_time_functions(rhs, symbol(CLOCK), {*reduced.states, *frame})
        for a in auxiliary:  # functions of time as states of their own (linear ODEs)
            states.append(a.name)
            rhs[a.name] = a.rhs
            s.init[a.name] = a.initial
        outputs = {n: sympy.expand(v.xreplace(zero)) for n, v in reduced.outputs.items()}
        outputs.update({name: sympy.expand(reduced.rhs[probe].xreplace(zero))
                        for probe, name in probes.items() if name not in states})
        inputs = [u for u in frame if u in system.inputs]
        known = {symbol(n) for n in [*states, *inputs, TIMER, CLOCK]}
        for x, f in rhs.items():
            extra = f.free_symbols - known
            if extra:
                raise self.fail(f"the ODE of {x} needs {', '.join(sorted(map(str, extra)))}, "
                                "which has no value", s.span("consts"),
                                "give the constants values in [consts] (qualified names "
                                "allowed), or the missing inputs in [environment]")
        self._check_names([*states, *inputs, *s.states])
        scope = _Scope(states, inputs, outputs)
        values = {name: scope.value(self, t) for name, t in self.typed.items()}
        events = {name: scope.predicate(self, e, span, f"event {name}",
                                        values[name][1] if name in values else None)
                  for name, (e, span) in event_exprs.items()}
        unsafe = self._unsafe(scope, unsafe_exprs)
        problem = Problem(self.model.name, s, states, rhs, inputs, outputs,
                          effects, events, unsafe, {v: k for k, v in self.ports.items()} |
                          {a.name: a.meaning for a in auxiliary},
                          dict(self.call_effects), self.machine,
                          operation_effects if self.uncompiled else
                          self._operation_effects(frame) if self.machine else {},
                          {name: v for name, (v, _) in values.items()})
        problem = self._first_cycle(problem)
        self._check_init(problem)
        start = 1 if problem.scenario.first else 0  # the start mode's jump at time 0
        cycles = problem.required_jumps - 1 - start
        if problem.required_jumps > MAX_JUMPS:
            raise self.fail(
                f"the horizon of {s.horizon:g} s is {cycles} cycles of "
                f"{s.period:g} s: more jumps than Flow* can count ({MAX_JUMPS}, a C int)",
                s.span("horizon"), "shorten the horizon or lengthen the cycle")
        if s.settings.max_jumps is not None and s.settings.max_jumps < problem.required_jumps:
            raise self.fail(
                f"max_jumps = {s.settings.max_jumps} is too small: the horizon of "
                f"{s.horizon:g} s is {cycles} cycles of {s.period:g} s (cycle × tscale)"
                f"{', with a jump at time 0 out of the first cycle' if start else ''}, so "
                f"Flow* needs at least {problem.required_jumps} jumps; "
                "with fewer it stops early and still reports "
                "SAFE", s.span("flowstar", "max_jumps"),
                f"remove max_jumps (the default is {problem.required_jumps}) or raise it")
        return problem

    # ----- names
    def _check_elements(self) -> None:
        qualified = {e.name for e in [*self.model.joints, *self.model.unconnected,
                                      *self.model.sensors, *self.model.actuators]}
        for q in self.s.elements:
            if not any(n == q or n.startswith(q + "::") for n in qualified):
                raise self.fail(f"'{q}' names no element of {self.model.name}",
                                self.s.span("elements", q.split("::")[-1]),
                                did_you_mean(q, qualified) or "qualified names start with "
                                f"the p-model: {self.model.name}::…")

    def mangled(self, name: str, span: Span) -> str:
        """A scenario's variable name (mangled, or qualified with ``::``) as mangled."""
        if "::" not in name:
            return name
        key = name if name.startswith(self.model.name + "::") else \
            f"{self.model.name}::{name}"
        if key in self.ports:
            return self.ports[key]
        raise self.fail(f"'{name}' names no port of {self.model.name}", span,
                        did_you_mean(key, self.ports) or "write the mangled name "
                        "(LMotor_av) or the qualified one (Model::Link::Joint::Motor::av)")

    def _check_names(self, names: list[str]) -> None:
        for n in [*names, TIMER, CLOCK]:
            if not valid_name(n):
                raise self.fail(f"'{n}' cannot be a Flow* name (a reserved word, or a "
                                "character Flow* names do not allow)", self.s.span("controller"),
                                "rename the state or the element")
        taken = [n for n in names if n in (TIMER, CLOCK)]
        if taken:
            raise self.fail(f"'{taken[0]}' is the automaton's own clock; a model variable or "
                            "controller state cannot be called that", self.s.span("controller"))

    def expression(self, text: str, span: Span) -> ex.Expr:
        # lazy: the parser loads Lark, which a model read from the parse cache does not need
        from cyphy.lang.parser import parse_text

        parsed = parse_text(f"const scenario_value: real = {text}", span.file)
        item: Any = parsed.file.items[0] if parsed.file and parsed.file.items else None
        if parsed.diagnostics or item is None or item.value is None:
            raise self.fail(f"cannot read the expression '{text}'", span,
                            "write it in the notation: LMotor_av >= 0.5, -0.1*(a + b)")
        for node in item.value.walk():
            if isinstance(node, ex.Num) and not math.isfinite(float(node.text)):
                raise self.fail(f"'{node.text}' in '{text}' is not a finite number", span,
                                "write a number a double can hold")

        def rename(node: ex.Expr) -> ex.Expr | None:
            if isinstance(node, ex.Name) and len(node.parts) > 1:
                return ex.Name((self.mangled(node.text, span),))
            return None

        return ex.transform(item.value, rename)

    # ----- the environment: sensor inputs as states or constants
    def _environment(self, system: Any) -> None:
        for env in self.s.environment.values():
            name = self.mangled(env.name, env.span)
            if name not in system.inputs:
                inputs = sorted(system.inputs)
                raise self.fail(f"'{env.name}' is not an input of the model's equations",
                                env.span, did_you_mean(name, inputs) or
                                f"inputs: {', '.join(inputs) or '(none)'}")
            var = ex.Name((name,), span=env.span)
            if env.derivative is not None:
                value = self.expression(env.derivative, env.span)
                self._known_names(value, system, env.span)
                eq = ex.BinOp("==", ex.Derivative(var, span=env.span), value, span=env.span)
            else:
                eq = ex.BinOp("==", var, self._constant(env.value, system.variables.get(name)),
                              span=env.span)
            system.equations.append(Equation(eq, "environment", env.span))
            system.inputs.discard(name)

    @staticmethod
    def _constant(value: float, type_: Any) -> ex.Expr:
        """``{ value = v }`` for an input of that type: a number, or a vector of fixed size
        with every entry v (a joint's parent twist on a base fixed to the world: 0)."""
        number = ex.Num(repr(value))
        if isinstance(type_, ast.VectorType) and isinstance(type_.size, ex.Num):
            return ex.Vector(((number,) * int(float(type_.size.text)),))
        return number

    def _known_names(self, e: ex.Expr, system: Any, span: Span) -> None:
        known = set(system.variables) | set(system.parameters) | {CLOCK}
        functions = {id(n.func) for n in e.walk() if isinstance(n, ex.Call)}
        for node in e.walk():
            if isinstance(node, ex.Call) and (
                    not isinstance(node.func, ex.Name) or node.func.text not in FUNCTIONS
                    or len(node.args) != 1):
                name = node.func.text if isinstance(node.func, ex.Name) else "?"
                raise self.fail(f"'{name}' is not a function Flow* has", span,
                                "Flow* knows exp, sin, cos, log and sqrt, of one argument")
            if isinstance(node, ex.Name) and id(node) not in functions and \
                    node.text not in known:
                raise self.fail(f"'{node.text}' is not a variable of the model's equations",
                                span, did_you_mean(node.text, known))

    # ----- calls: Rule 5's OpCall, the mapping's equations solved for the actuator inputs
    def _effects(self) -> tuple[dict[str, dict[str, Any]], list[str]]:
        check = self.elaborated.check
        cache: dict[str, dict[str, Any]] = {}
        effects: dict[str, dict[str, Any]] = {}
        frame: list[str] = []
        for state, calls in self.s.states.items():
            effects[state] = {}
            span = self.s.span("controller", "states", state, "calls")
            for text in calls:
                if text not in cache:
                    try:
                        mapping, call, params = mapping_operation(
                            check.workspace, check.resolution, self.model, text)
                        system = assemble(self.model, list(self.s.elements) or None, mapping,
                                          call, params)
                    except AssemblyError as err:
                        raise self.fail(f"state {state}: {err.message}", span, err.hint) \
                            from None
                    op = call.func.text if isinstance(call.func, ex.Name) else ""
                    eqs = [eq.expr for eq in system.equations if eq.origin == f"mapping {op}"]
                    cache[text] = self._solve_call(text, op, eqs, system, span, to_sympy)
                    self.call_effects[text] = cache[text]
                # the calls are made in the cycle's order and each call's update persists
                # (the theory's ReceiveFromDModel takes them in sequence): a later call to
                # the same input (a during action's, then the next state's entry) wins
                for u, v in cache[text].items():
                    effects[state].pop(u, None)
                    effects[state][u] = v
                    if u not in frame:
                        frame.append(u)
        return effects, sorted(frame)

    def _solve_call(self, text: str, op: str, eqs: list[ex.Expr], system: Any, span: Span,
                    to_sympy: Any) -> dict[str, Any]:
        solved = self._solve_equations(eqs, op, system, to_sympy)
        if solved is None:
            frame = ", ".join(self._frame(eqs, system))
            raise self.fail(f"the call {text} does not determine "
                            f"{frame or 'any actuator input'} uniquely",
                            span, "the mapping's equations of the operation must fix each "
                            "actuator input it constrains")
        for u, v in solved.items():
            if v.is_number and not (v.is_finite and math.isfinite(float(v))):
                raise self.fail(f"the call {text} sets {u} beyond what a double holds", span,
                                "give the call finite arguments")
            if not v.is_number:
                raise self.fail(f"the call {text} leaves {u} = {v}, not a number", span,
                                "give the call numbers, or names defined in [consts]")
        return solved

    @staticmethod
    def _frame(eqs: list[ex.Expr], system: Any) -> list[str]:
        """The actuator inputs the equations name."""
        return sorted({n.text for e in eqs for n in e.walk() if isinstance(n, ex.Name)
                       and system.kinds.get(n.text) == "input"})

    def _operation_effects(self, frame: list[str] | None
                           ) -> dict[str, tuple[tuple[Any, ...], dict[str, Any]]]:
        """Each operation the machine may call (and output event it may send) that the
        mapping defines, solved once for the actuator inputs with its arguments as symbols
        (``move(lv, av)`` → ``LMotor_das = (lv + 0.03*av)/0.025025``, …): the simulator
        evaluates it for whatever arguments a cycle computes. An operation whose equations do
        not fix its inputs uniquely, or set inputs the export's frame lacks (``None``: no
        frame, the machine is not compiled), is left out (a call of it is then reported)."""
        check = self.elaborated.check
        out: dict[str, tuple[tuple[Any, ...], dict[str, Any]]] = {}
        it = self.machine
        names = {name for part in it.parts for m in [part.machine, *part.operations.values()]
                 for name in [*m.platform.operations, *m.platform.output_events,
                              *m.platform.written]}
        for op in sorted(names - set(it.observable)):
            try:
                params = mapping_operation(check.workspace, check.resolution, self.model,
                                           f"{op}()")[2]
                args = tuple(f"cyphy_arg_{p}" for p in params)
                mapping, call, params = mapping_operation(
                    check.workspace, check.resolution, self.model, f"{op}({', '.join(args)})")
                system = assemble(self.model, list(self.s.elements) or None, mapping, call,
                                  params)
            except AssemblyError:
                continue
            eqs = [eq.expr for eq in system.equations if eq.origin == f"mapping {op}"]
            solved = self._solve_equations(eqs, op, system, to_sympy, frozenset(args))
            if solved is not None and (frame is None or set(solved) <= set(frame)):
                out[op] = (tuple(symbol(a) for a in args), solved)
        return out

    def _solve_equations(self, eqs: list[ex.Expr], op: str, system: Any, to_sympy: Any,
                         free: frozenset[str] = frozenset()) -> dict[str, Any] | None:
        """The actuator inputs an operation's equations constrain, solved (values in the
        symbols ``free`` only); None when they are not determined uniquely."""
        values = {symbol(n): sympy.Rational(repr(float(v))) for n, v in
                  system.parameters.items() if isinstance(v, (int, float))
                  and not isinstance(v, bool)}
        values.update({symbol(n): sympy.Rational(repr(float(v))) for n, v in
                       self.s.consts.items() if isinstance(v, (int, float))
                       and not isinstance(v, bool) and "::" not in n})
        frame = self._frame(eqs, system)
        split = per_component(eqs, system, op)  # a vector local as its components
        if split is None:
            return None
        eqs, locals_ = split
        relations = []
        for e in eqs:
            rel = to_sympy(e)
            relations.append(sympy.expand(rel.lhs - rel.rhs).xreplace(values))
        unknowns = [symbol(n) for n in [*frame, *locals_]]
        solutions = sympy.solve(relations, unknowns, dict=True) if unknowns else []
        if len(solutions) != 1 or any(symbol(u) not in solutions[0] for u in frame):
            return None
        out = {u: sympy.nsimplify(solutions[0][symbol(u)]) for u in frame}
        if free and any({str(x) for x in v.free_symbols} - set(free) for v in out.values()):
            return None
        return out

    # ----- events and the unsafe set
    def _mapping(self) -> Any:
        check = self.elaborated.check
        for f in check.workspace.user_files():
            for item in f.items:
                if isinstance(item, ast.PlatformMapping) and item.pmodel[-1] == self.model.name:
                    return item
        raise self.fail(f"no platform mapping of {self.model.name} among the files",
                        self.s.span("controller"), "name the mapping file (or its folder) too")

    def _event_expressions(self) -> dict[str, tuple[ex.Expr, Span]]:
        """Each input event a transition names (a machine run uncompiled: each it reads),
        as its mapping predicate (mangled names); a typed event of an uncompiled machine
        also gets its value's equations (``self.typed``)."""
        wanted = machine_events(self.machine) if self.uncompiled else \
            [(name, t.span, None) for t in [*self.s.first, *self.s.transitions]
             for name, _ in t.literals]
        if not wanted:
            return {}
        mapping = self._mapping()
        available = {e.name: e for e in mapping.events if e.direction == "input"}
        out: dict[str, tuple[ex.Expr, Span]] = {}
        for name, span, type_ in wanted:
            if name in out:
                continue
            event = available.get(name)
            if event is None:
                raise self.fail(f"mapping {mapping.name} has no input event '{name}'",
                                span, did_you_mean(name, available) or
                                f"input events: {', '.join(sorted(available)) or '(none)'}")
            if self.uncompiled and event.param is not None:
                refused = not_one_number(name, type_)
                if refused is not None:
                    raise self.fail(refused.message, span, refused.hint)
                self.typed[name] = typed_event(self.model, mapping, event)
                pred = self.typed[name].predicate
            else:
                pred = input_event_predicate(self.model, mapping, event)
            # no predicate: the event occurs every cycle (PMap12's warning; the theory's
            # Rule 4 with ``true``)
            out[name] = (ex.Bool(True) if pred is None else pred, span)
        return out

    def _probes(self, system: Any, exprs: list[ex.Expr]) -> dict[str, str]:
        """For each model variable the predicates mention, a probe state ``p' = v``: the
        reducer then gives ``v`` as a function of the states (it solves only what some
        derivative needs), and the probe is dropped afterwards."""
        names = sorted({n.text for e in exprs for n in e.walk() if isinstance(n, ex.Name)
                        and n.text in system.variables})
        probes = {}
        for k, name in enumerate(names):
            probe = f"cyphy_probe{k + 1}"
            system.variables[probe] = ast.PrimitiveType("real")
            system.kinds[probe] = "local"
            system.equations.append(Equation(ex.BinOp(
                "==", ex.Derivative(ex.Name((probe,))), ex.Name((name,))), "probe",
                Span.unknown(self.s.path)))
            probes[probe] = name
        return probes

    def _unsafe(self, scope: "_Scope", exprs: list[tuple[ex.Expr, Span]]) -> Any:
        parts = [scope.predicate(self, e, span, "the unsafe set") for e, span in exprs]
        unsafe = sympy.And(*parts)
        try:
            conjunctions = dnf(unsafe, scope.variables)
        except NotExpressible as err:
            raise self.fail(str(err), self.s.span("unsafe"), "") from None
        if not conjunctions:
            raise self.fail("the unsafe set is empty (its constraints contradict each other)",
                            self.s.span("unsafe"), "nothing to check: write the negation of "
                            "the property")
        return unsafe

    def _first_cycle(self, p: Problem) -> Problem:
        """``p`` with its first cycle decided on the initial box
        (:func:`cyphy.verify.flowstar.first_cycle.settle`); refused when an event the first
        cycle reads has a predicate over an actuator input, which has no value before the
        first cycle's calls."""
        if not self.s.first:
            return p
        found = unreadable(p)
        if found is not None:
            event, inputs = found
            raise self.fail(
                f"the first cycle of the machine reads the input event {event}, whose "
                f"predicate reads the actuator input{'s' if len(inputs) > 1 else ''} "
                f"{', '.join(inputs)}: nothing sets {'them' if len(inputs) > 1 else 'it'} "
                "before the first cycle's calls, so which way the first cycle goes cannot be "
                "decided", self.s.first[0].span,
                "let the first cycle end (exec) before reading the event, or map the event "
                "to a predicate over sensor and state variables")
        return settle(p)

    def _check_init(self, p: Problem) -> None:
        given = {self.mangled(n, self.s.span("init", n)): n for n in self.s.init}
        expected = set(p.states) | set(p.held_inputs)
        for name, written in given.items():
            if name not in expected:
                raise self.fail(f"'{written}' is not a state variable of the automaton",
                                self.s.span("init", written.split("::")[-1]),
                                did_you_mean(name, expected) or
                                f"state variables: {', '.join(sorted(expected))}")
        starts = list(dict.fromkeys(t.target for t in p.scenario.first)) or \
            [p.scenario.initial]
        unset = [u for u in p.held_inputs if u not in given
                 and not all(u in p.effects.get(m, {}) for m in starts)]
        if unset:
            where = f"the initial state {starts[0]} calls" if len(starts) == 1 else \
                f"a state the first cycle may end in ({', '.join(starts)}) calls"
            raise self.fail(
                f"nothing gives the held actuator input{'s' if len(unset) > 1 else ''} "
                f"{', '.join(unset)} a value at time 0: {where} "
                "nothing that sets it", self.s.span("controller", "initial"),
                "give its value at time 0 in [init] (" + ", ".join(f"{u} = 0" for u in unset)
                + "), or a call in the initial state that sets it")
        missing = [x for x in p.states if x not in given]
        if missing:
            raise self.fail(f"[init] gives no initial interval for {', '.join(missing)}",
                            self.s.span("init"), "every state variable needs one (a number "
                            "or [low, high]): " + ", ".join(f"{x} = 0" for x in missing))


class _Scope:
    """The names a predicate may use: states, actuator inputs, the clocks, and algebraic
    variables (replaced by their solutions)."""

    def __init__(self, states: list[str], inputs: list[str], outputs: dict[str, Any]) -> None:
        self.names = {n: symbol(n) for n in [*states, *inputs, TIMER, CLOCK]}
        self.variables = set(self.names.values())
        self.outputs = {symbol(n): v for n, v in outputs.items()}

    def in_states(self, value: Any) -> Any:
        for _ in range(8):  # outputs may be written in terms of other outputs
            replaced = value.xreplace(self.outputs)
            if replaced == value:
                break
            value = replaced
        return value

    def value(self, b: _Builder, t: "TypedEvent") -> tuple[Any, dict[Any, Any]]:
        """The typed event's value over the states and inputs, and the substitution of its
        parameter and solved locals for the predicate (:func:`typed_events.solve_value`)."""
        consts = {n: v for n, v in b.s.consts.items() if isinstance(v, (int, float))
                  and not isinstance(v, bool) and "::" not in n}
        try:
            return solve_value(t, self.names, self.variables, self.in_states, consts)
        except ValueRefused as err:
            raise b.fail(err.message, t.span, err.hint) from None

    def predicate(self, b: _Builder, e: ex.Expr, span: Span, what: str,
                  given: dict[Any, Any] | None = None) -> Any:

        try:
            value = to_sympy(e, symbols=self.names)
        except UnsupportedNode as err:
            raise b.fail(f"{what}: {err}", span) from None
        value = self.in_states(value.xreplace(given or {}))
        if value.has(sympy.zoo, sympy.oo, -sympy.oo, sympy.nan):
            raise b.fail(f"{what} is undefined (a division by zero, or an infinite value)",
                         span, "write a comparison of finite polynomials")
        unknown = value.free_symbols - self.variables
        if unknown:
            names = sorted(map(str, unknown))
            raise b.fail(f"{what} uses {', '.join(names)}, which the automaton does not "
                         "have (not a state, input or output of the reduced equations)", span,
                         did_you_mean(names[0], [str(v) for v in self.names]) or
                         "restrict or extend 'elements' so the equations define it")
        return value


def _ports(model: Any) -> dict[str, str]:
    """Qualified port name (``Model::Link::Joint::Motor::av``) → mangled (``LMotor_av``)."""
    out = {}
    for e in [*model.joints, *model.unconnected, *model.sensors, *model.actuators]:
        if e.device is not None:
            for p in e.device.ports:
                out["::".join(e.qname + (p.name,))] = p.mangled
    return out

