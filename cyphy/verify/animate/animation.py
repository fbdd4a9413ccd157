"""The animation: the composition run from ``Init`` to ``t_end``, sampled on a uniform grid,
with every event the two processes exchanged."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from cyphy.diagnostics import did_you_mean
from cyphy.limits import trajectory_refusal
from cyphy.verify.animate import ax_evolve
from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.evolve import OdeSystem, build
from cyphy.verify.animate.executor import (MAX_EVENTS_PER_INSTANT, Evolving, Proc, Runner,
                                           synchronise)
from cyphy.verify.animate.model import TheoryModel
from cyphy.verify.animate.reader import read_model
from cyphy.verify.animate.terms import Unsupported, evaluate, evaluate_hol, op_name


@dataclass
class Animation:
    """Trajectories (``columns[0]`` is t) and events ``(t, channel, value)``."""

    columns: list[str]
    rows: list[list[float]]
    events: list[tuple[float, str, Any]]
    composition: str
    undetermined: list[str] = field(default_factory=list)
    differential: list[str] = field(default_factory=list)  # the states Evolve integrates
    held: list[str] = field(default_factory=list)  # axiomatic world inputs kept at 0


class _Constants:
    """The theory's constants, ``--const`` winning, then the axioms ``name = value``."""

    def __init__(self, model: TheoryModel, given: dict[str, float],
                 scenario: dict[str, float] | None = None) -> None:
        self.model = model
        self.values = dict(model.values)
        known = sorted(set(model.values) | set(model.open_constants))
        # a scenario's values set the constants the theory has (tscale only when open); its
        # other keys (call arguments, another model's names) are not the theory's business
        for name, value in (scenario or {}).items():
            if name in model.open_constants or (name in model.values and name != "tscale"):
                self.values[name] = value
        for name, value in given.items():
            if name not in known:
                raise AnimateError("E-ANIMATE-OPTION", f"--const {name}: the theory has no "
                                   "constant of that name", hint=did_you_mean(name, known),
                                   status=2)
            self.values[name] = value
        for name in model.truths & set(self.values):  # a Boolean one: given as 0 or 1
            if self.values[name] not in (0, 1):
                raise AnimateError("E-ANIMATE-OPTION", f"--const {name}: a Boolean constant "
                                   "takes true or false (1 or 0)", status=2)
            self.values[name] = bool(self.values[name])
        # an int or nat one: a whole number (judged here, not by the interpreter's
        # scalars.misfit: the animator shares no code with what it is checked against)
        for name, kind in model.wholes.items():
            if name in self.values:
                value = self.values[name]
                if not float(value).is_integer() or (kind == "nat" and value < 0):
                    where = f"--const {name}={value:g}" if name in given else \
                        f"the scenario's [consts] {name} = {value:g}"
                    raise AnimateError("E-ANIMATE-OPTION", f"{where}: the constant is "
                                       f"declared {kind}", hint="give a whole "
                                       "number" + (" of at least 0" if kind == "nat" else ""),
                                       status=2)
                self.values[name] = int(value)
        for tree, line in model.axioms:
            if (getattr(tree, "data", "") == "binop" and op_name(tree.children[1]) == "="
                    and getattr(tree.children[0], "data", "") == "name"):
                name = str(tree.children[0].children[0])
                if name not in self.values:
                    try:
                        self.values[name] = evaluate_hol(tree.children[2], self.get)
                    except (KeyError, Unsupported):
                        pass
        for tree, line in model.axioms:
            try:
                holds = evaluate_hol(tree, self.get)
            except (KeyError, Unsupported):
                continue  # over a constant without a value: nothing to check
            if holds is False:
                raise AnimateError("E-ANIMATE-CONST", "the constants' values contradict an "
                                   "axiom of the theory", path=model.path, line=line, status=2)

    def get(self, name: str) -> Any:
        """The value (KeyError for a constant without one: Evolve keeps it a symbol)."""
        return self.values[name]

    def need(self, name: str) -> Any:
        """The value, where running needs it now (a condition, a call, the cycle)."""
        if name in self.values:
            return self.values[name]
        line = self.model.open_constants.get(name, 0)
        if name in self.model.open_constants:
            raise AnimateError("E-ANIMATE-CONST", f"the constant {name} has no value in the "
                               "theory and running needs it", path=self.model.path, line=line,
                               hint=f"give it with --const {name}=VALUE", status=1)
        raise AnimateError("E-ANIMATE-READ", f"{name} is neither a constant of the theory nor "
                           "a bound name", path=self.model.path, status=2)


def animate(folder: str | Path, t_end: float, inputs: dict[str, str] | None = None,
            consts: dict[str, float] | None = None, samples: int = 201,
            scenario_consts: dict[str, float] | None = None,
            scenario_rates: dict[str, tuple[str, float]] | None = None) -> Animation:
    """Run the session in ``folder`` for ``t_end`` seconds (see the module docstring);
    ``scenario_consts`` (a scenario's [consts], theory names) yield to ``consts``."""
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and t_end > 0):
        raise AnimateError("E-ANIMATE-OPTION", f"--t-end {t_end}: the time must be a finite "
                           "number above 0", status=2)
    if samples < 2:
        raise AnimateError("E-ANIMATE-OPTION", "--samples must be at least 2", status=2)
    refusal = trajectory_refusal(samples, 1)  # simulate's budget, for the smallest table
    if refusal:
        raise AnimateError("E-ANIMATE-OPTION", f"{refusal[0]} ({refusal[1]})", status=2)
    model = read_model(Path(folder))
    for name, (rate, _start) in sorted((scenario_rates or {}).items()):
        if model.dialect != "axiomatic":  # the utp dialect takes an input's value, not rate
            raise AnimateError("E-ANIMATE-SCENARIO", f"the scenario's {name}' = {rate} "
                               "depends on the state: give " + name + " as a function of t "
                               f"and the state with --input {name}=EXPR", status=2)
    animator = _Animator(model, t_end, inputs or {}, consts or {}, samples,
                         scenario_consts or {}, scenario_rates or {})
    try:
        return animator.run()
    except (ZeroDivisionError, OverflowError, ValueError) as err:  # math on the values
        raise AnimateError("E-ANIMATE-VALUE", f"a value is undefined at t = {animator.t:.6g} "
                           f"({err})", status=1,
                           hint="an input or constant makes an equation divide by zero or "
                           "leave its domain") from None


class _Animator:
    def __init__(self, model: TheoryModel, t_end: float, inputs: dict[str, str],
                 consts: dict[str, float], samples: int,
                 scenario_consts: dict[str, float],
                 scenario_rates: dict[str, tuple[str, float]]) -> None:
        import sympy  # lazy: the inputs and Evolve are symbolic
        self.model = model
        self.t_end = t_end
        self.constants = _Constants(model, consts, scenario_consts)
        d, p = model.processes
        self.d = Proc(d.name, dict.fromkeys(d.fields), [(model.definitions[d.main].tree, {})])
        self.p = Proc(p.name, dict.fromkeys(p.fields), [(model.definitions[p.main].tree, {})])
        self.t_sym = sympy.Symbol("t")
        self.inputs = self._inputs(inputs)
        # the axiomatic dialect's world rates a scenario gives over the state: (rate, start)
        exprs = self._inputs({k: rate for k, (rate, _start) in scenario_rates.items()})
        self.rates = {k: (e, scenario_rates[k][1]) for k, e in exprs.items()}
        if model.dialect == "axiomatic":  # a world input is what the theory gives a rate
            clash = sorted(x for x in {**self.inputs, **self.rates}
                           if x + "_rate" not in self.p.state)
            if clash:
                raise AnimateError("E-ANIMATE-OPTION", f"--input {clash[0]}: the theory "
                                   "evolves it from the value its actions give (a state, not "
                                   "a world input)", status=2)
        self.runner = Runner(model, self.constants.need, self._settle, self._choose)
        p_defs = [df for df in model.definitions.values() if df.name != d.main]
        self.ties = ax_evolve.ties(p_defs) if model.dialect == "axiomatic" else {}
        self.systems: dict[frozenset[str], OdeSystem] = {}
        self.evolve_tree = next((df.tree.children[0] for df in model.definitions.values()
                                 if df.tree.data == "evolution"), None)
        self.t = 0.0
        self.grid = [t_end * k / (samples - 1) for k in range(samples)]
        self.rows: dict[int, dict[str, float]] = {}
        self.events: list[tuple[float, str, Any]] = []
        self.undetermined: set[str] = set()
        self.held: set[str] = set()  # axiomatic world inputs without --input: at 0, still

    def _inputs(self, given: dict[str, str]) -> dict[str, Any]:
        import sympy  # lazy: as above
        from sympy.parsing.sympy_parser import parse_expr  # lazy: with sympy
        fields = sorted(self.p.state)
        out: dict[str, Any] = {}
        names = {f: sympy.Symbol(f) for f in fields}
        names["t"] = self.t_sym
        for fn in ("sin", "cos", "tan", "exp", "sqrt", "log", "atan", "Abs", "pi",
                   "Piecewise", "Min", "Max"):
            names[fn] = getattr(sympy, fn)
        for name, text in given.items():
            if name not in self.p.state:
                raise AnimateError("E-ANIMATE-OPTION", f"--input {name}: not a state variable "
                                   f"of {self.p.name}", hint=did_you_mean(name, fields), status=2)
            try:
                expr = parse_expr(text, local_dict=names, global_dict={"Integer": sympy.Integer,
                                  "Float": sympy.Float, "Rational": sympy.Rational,
                                  "Symbol": sympy.Symbol})
                expr = sympy.sympify(expr)
            except Exception as err:  # noqa: BLE001 — any parse failure is the user's input
                raise AnimateError("E-ANIMATE-OPTION", f"--input {name}={text}: cannot read "
                                   f"the expression ({type(err).__name__})", status=2) from None
            stray = sorted(str(s) for s in expr.free_symbols if str(s) not in names)
            if stray:
                raise AnimateError("E-ANIMATE-OPTION", f"--input {name}={text}: {stray[0]} is "
                                   "neither t nor a state variable",
                                   hint=did_you_mean(stray[0], fields), status=2)
            if expr.is_number and not expr.is_finite:
                raise AnimateError("E-ANIMATE-OPTION", f"--input {name}={text}: not a finite "
                                   "value", status=2)
            out[name] = expr
        return out

    # Evolve -------------------------------------------------------------------------
    def _system(self) -> OdeSystem:
        if self.evolve_tree is None:
            raise AnimateError("E-ANIMATE-EVOLVE", "the p-model has no Evolve", status=1,
                               path=self.model.path)
        if self.model.dialect == "axiomatic":
            return self._explicit()
        primed = {str(n.children[0]) for n in self.evolve_tree.iter_subtrees()
                  if n.data == "state_derivative"}
        differential = [f for f in self.p.state if f in primed and f in self.p.assigned]
        key = frozenset(differential)
        if key not in self.systems:
            clash = sorted(set(self.inputs) & key)
            if clash:
                raise AnimateError("E-ANIMATE-OPTION", f"--input {clash[0]}: the theory "
                                   "evolves it from the value its actions give (a state, not "
                                   "a world input)", status=2)
            try:
                self.systems[key] = build(self.evolve_tree, differential, set(self.p.state),
                                          self.inputs, self.constants.get, self.t_sym)
            except Unsupported as err:
                evolve = next(df for df in self.model.definitions.values()
                              if df.tree.data == "evolution")
                raise AnimateError("E-ANIMATE-UNSUPPORTED", f"{evolve.name}: animate does not "
                                   f"run {err}", path=evolve.path, line=evolve.line,
                                   status=2) from None
            self.undetermined |= set(self.systems[key].undetermined)
        return self.systems[key]

    def _explicit(self) -> OdeSystem:
        """The axiomatic dialect's explicit ODE under the values given so far."""
        key = frozenset(x for x, v in self.p.state.items() if v is not None)
        if key not in self.systems:
            where = next(df for df in self.model.definitions.values()
                         if df.tree.data == "evolution")
            self.systems[key] = ax_evolve.explicit(self.evolve_tree, self.p.state,
                                                   self.constants.get, self.t_sym, where)
            self.undetermined |= set(self.systems[key].undetermined)
        return self.systems[key]

    def _choose(self, frame: list[str], proc: Proc) -> list[float]:
        """The axiomatic dialect's world rates (any values): an input's rate from its
        ``--input`` expression now; an input not given keeps still (rate 0). The frame
        holds 0 while its rates are computed (the chain rule reads no rate of a rate)."""
        out = []
        for x in frame:
            if self.p.state.get(x) is None:
                self.p.state[x] = 0.0
        for x in frame:
            base = x[:-len("_rate")] if x.endswith("_rate") else None
            if base is None or proc is not self.p:
                raise AnimateError("E-ANIMATE-UNSUPPORTED", f"a choice of {x}, which is not "
                                   "a world input's rate", path=self.model.path, status=2)
            if base in self.rates and base not in self.inputs:
                out.append(self._now(self.rates[base][0]))
                continue
            if base not in self.inputs:
                self.held.add(base)
                out.append(0.0)
                continue
            if self.p.state.get(base) is None:
                self._settle(base, proc)
            system = self._system()
            out.append(ax_evolve.input_rate(self.inputs[base], self.t_sym, self.t,
                                            self.p.state, system, self._y(system)))
        return out

    def _now(self, expr: Any) -> float:
        """A scenario's rate over the state, at the current state."""
        import sympy  # lazy: as above
        subs = {sympy.Symbol(k): v for k, v in self.p.state.items() if v is not None}
        subs[self.t_sym] = self.t
        value = sympy.sympify(expr).subs(subs)
        if value.free_symbols:
            raise AnimateError("E-ANIMATE-OPEN", f"a scenario rate reads "
                               f"{sorted(map(str, value.free_symbols))[0]}, which has no "
                               "value yet", status=1)
        return float(value)

    def _ax_settle(self, name: str) -> Any:
        """An axiomatic p-model value read before any action gives it: a world input's
        ``--input`` value now (from then on it moves at its chosen rate), or the value the
        main action re-establishes it to (an output's definition, ``Range_range :=
        Range_distance``)."""
        import sympy  # lazy: as above
        if name in self.inputs:
            subs = {sympy.Symbol(k): v for k, v in self.p.state.items() if v is not None}
            subs[self.t_sym] = self.t
            value = sympy.sympify(self.inputs[name]).subs(subs)
            if value.free_symbols:
                raise AnimateError("E-ANIMATE-OPEN", f"--input {name}: reads "
                                   f"{sorted(map(str, value.free_symbols))[0]}, which has no "
                                   "value yet", status=1)
            self.p.state[name] = float(value)
            return self.p.state[name]
        if name in self.rates:
            self.p.state[name] = float(self.rates[name][1])
            return self.p.state[name]
        if name in self.ties:
            return self.runner.value(self.ties[name], self.p, {})
        if name + "_rate" in self.p.state:  # a world input the theory leaves arbitrary
            self.held.add(name)
            self.p.state[name] = 0.0
            return 0.0
        raise AnimateError("E-ANIMATE-OPEN", f"{self.p.name} reads {name} before anything "
                           "gives it a value", status=1, path=self.model.path,
                           hint="a world input is given with --input NAME=EXPR")

    def _y(self, system: OdeSystem) -> list[float]:
        return [float(self.p.state[x]) for x in system.states]

    def _settle(self, name: str, proc: Proc) -> Any:
        """An unset p-model state read by an action: Evolve's value for it now (the theory
        leaves it free until the first Evolve; this is the one of its values consistent with
        the equations). The d-model's state has no equations: reading it unset is an error."""
        # by name: a branch of an interleaving or a choice runs on a copy of P
        if proc.name == self.p.name and self.model.dialect == "axiomatic":
            return self._ax_settle(name)
        if proc.name == self.p.name:
            system = self._system()
            if name in system.algebraic:
                return float(system.algebraic[name](self.t, self._y(system)))
        raise AnimateError("E-ANIMATE-OPEN", f"{proc.name} reads {name} before anything gives "
                           "it a value", status=1, path=self.model.path,
                           hint="a world input is given with --input NAME=EXPR")

    def _evolve(self, ev: Evolving) -> None:
        from scipy.integrate import solve_ivp  # lazy: SciPy loads when time first passes
        system = self._system()
        y0 = self._y(system)
        guard = self._condition(ev, system)
        if guard(self.t, y0) >= 0:
            return
        if self.t_end - self.t <= 1e-12 * max(1.0, self.t_end):  # rounding: LSODA refuses
            for k, tk in enumerate(self.grid):
                if k not in self.rows and tk >= self.t - 1e-12:
                    self.rows[k] = self._sample(system, tk, y0)
            self.t = self.t_end
            return
        guard.terminal = True  # type: ignore[attr-defined]
        guard.direction = 1  # type: ignore[attr-defined]
        sol = solve_ivp(system.rates, (self.t, self.t_end), y0, method="LSODA", rtol=1e-9,
                        atol=1e-11, events=[guard], dense_output=True)
        if not sol.success:
            raise AnimateError("E-ANIMATE-INTEGRATE", f"the integrator failed at t = "
                               f"{sol.t[-1]:.6g}: {sol.message}", status=1)
        t1 = float(sol.t[-1])
        # An instant where the evolution stops (a tock) is sampled by the next one, after
        # the cycle's calls, as t = 0 is and as simulate samples it: inputs such as a motor's
        # demand, and what depends on them, take their new values there. The end is
        # sampled here.
        last = t1 >= self.t_end - 1e-12 * max(1.0, self.t_end)
        for k, tk in enumerate(self.grid):
            if k not in self.rows and self.t - 1e-12 <= tk and \
                    (tk < t1 - 1e-9 * max(1.0, t1) or last):
                self.rows[k] = self._sample(system, tk,
                                            list(sol.sol(min(max(tk, self.t), t1))))
        for x, v in zip(system.states, sol.y[:, -1]):
            self.p.state[x] = float(v)
        yend = list(sol.y[:, -1])
        for x, f in system.algebraic.items():
            if x in self.p.state and x not in system.states:
                self.p.state[x] = float(f(t1, yend))
        self.t = t1

    def _condition(self, ev: Evolving, system: OdeSystem) -> Any:
        import sympy  # lazy: as above
        node = ev.until
        if node.data != "binop" or op_name(node.children[1]) not in ("\\<ge>", ">", "\\<le>",
                                                                     "<"):
            raise AnimateError("E-ANIMATE-UNSUPPORTED", "an interrupt condition that is not a "
                               "comparison", path=self.model.path, status=2)

        def state(x: str) -> Any:
            value = system.expression(x)
            if value is None:
                raise AnimateError("E-ANIMATE-OPEN", f"the interrupt reads {x}, which Evolve "
                                   "does not determine", status=1)
            return value

        def name(x: str) -> Any:
            return ev.env[x] if x in ev.env else self.constants.need(x)

        lhs = evaluate(node.children[0], state, state, name)
        rhs = evaluate(node.children[2], state, state, name)
        g = (lhs - rhs) if op_name(node.children[1]) in ("\\<ge>", ">") else (rhs - lhs)
        f = sympy.lambdify((system.t, system.y), g, modules="math")

        def guard(t: float, y: Any) -> float:
            return float(f(t, list(y)))
        return guard

    def _sample(self, system: OdeSystem, t: float, y: list[float]) -> dict[str, float]:
        row = {"t": t}
        for x, v in zip(system.states, y):
            row[x] = float(v)
        for x, f in system.algebraic.items():
            if x in self.p.state and x not in row:
                row[x] = float(f(t, y))
        for x, v in self.d.state.items():
            if v is not None:
                row[x] = float(v)
        return row

    # the composition ----------------------------------------------------------------
    def run(self) -> Animation:
        d_next = self.runner.run(self.d)
        p_next = self.runner.run(self.p)
        at_instant = 0
        while self.t < self.t_end:
            if isinstance(d_next, Evolving):
                raise AnimateError("E-ANIMATE-UNSUPPORTED", "the d-model process evolves: "
                                   "only the p-model's Evolve is run", status=2)
            if isinstance(p_next, Evolving):
                before = self.t
                self._evolve(p_next)
                at_instant = 0 if self.t > before else at_instant
                p_next = self.runner.run(p_next.proc)
                continue
            if d_next is None or p_next is None:
                break  # a process ended: nothing more happens
            got = synchronise(d_next, p_next, self.model.channels)
            if got is None:
                offered = sorted({o.channel for o in d_next + p_next})
                raise AnimateError("E-ANIMATE-DEADLOCK", f"deadlock at t = {self.t:.6g}: D "
                                   f"and P agree on no event (offered: "
                                   f"{', '.join(offered) or 'none'})", status=1)
            channel, value, d_after, p_after = got
            self.events.append((self.t, channel, value))
            at_instant += 1
            if at_instant > MAX_EVENTS_PER_INSTANT:
                raise AnimateError("E-ANIMATE-LIVELOCK", f"more than {MAX_EVENTS_PER_INSTANT}"
                                   f" events at t = {self.t:.6g} without time passing",
                                   status=1)
            if d_after is not None:
                self.d = d_after
                d_next = self.runner.run(self.d)
            if p_after is not None:
                self.p = p_after
                p_next = self.runner.run(self.p)
        return self._result()

    def _result(self) -> Animation:
        if len(self.rows) < len(self.grid):
            missing = min(k for k in range(len(self.grid)) if k not in self.rows)
            raise AnimateError("E-ANIMATE-STOPPED", f"the run stopped at t = {self.t:.6g}, "
                               f"before {self.grid[missing]:.6g} (a process ended)", status=1)
        names = [x for x in list(self.p.state) + list(self.d.state)
                 if all(x in self.rows[k] for k in self.rows)]
        rows = [[self.rows[k]["t"]] + [self.rows[k][x] for x in names]
                for k in range(len(self.grid))]
        for row in rows:
            if not all(math.isfinite(v) for v in row):
                raise AnimateError("E-ANIMATE-VALUE", f"a value is not finite at t = "
                                   f"{row[0]:.6g}", status=1)
        differential = [x for x in names if any(x in s.states for s in self.systems.values())]
        if self.model.dialect == "axiomatic":  # left out: what never got a value
            self.undetermined = {x for x in self.undetermined if self.p.state.get(x) is None}
            self.held = {x for x in self.held if self.p.state.get(x) is not None}
        return Animation(["t"] + names, rows, self.events, self.model.composition,
                         sorted(self.undetermined), differential, sorted(self.held))
