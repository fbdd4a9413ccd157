"""Numerical simulation of a model's explicit ODEs with SciPy (``cyphy simulate``, issue 16).

Two paths, as for the equations of motion:

- **symbolic**: the ODEs ``x' = f(x, u, p)`` that :mod:`cyphy.semantics.dynamics.reduce` derived from the
  whole model (devices, relations and the kinematic tree's equations of motion), turned into
  NumPy functions with ``lambdify``; states, inputs and outputs are the model's variables;
  A tree's equations of motion arrive as named definitions (the articulated-body algorithm,
  :mod:`cyphy.semantics.dynamics.articulated`), compiled to one function that evaluates them in order;
- **numeric** (``--numeric``): the kinematic tree alone, integrated with the numeric
  articulated-body algorithm; its states are the joints' ``<J>_theta`` and ``<J>_v`` and its
  inputs their efforts ``<J>_tau``, and the other devices' equations are not part of it.

Inputs are expressions of ``t`` (``--input Motor_das=10*(t>1)`` is not accepted: no
comparisons; ``--input 'Motor_das=10*sin(t)'`` is); an input that is not given is 0. A
controller (:class:`Controller`) runs at every cycle boundary ``k·period``: it sees the events
of that instant and what it does sets inputs until the next cycle.
"""

from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Collection, Mapping, Protocol, Sequence

import numpy as np

from cyphy import codes
from cyphy.diagnostics import did_you_mean
from cyphy.limits import trajectory_refusal
from cyphy.backends.generated import definition_names
from cyphy.backends.pinocchio_tree import pinocchio_model
from cyphy.backends.stiffness import choose, finite_difference
from cyphy.backends.whole_model import annotated_efforts, system_dynamics
from cyphy.semantics.dynamics.rigid_body import forward_dynamics
from cyphy.semantics.dynamics.spatial import euler_singularity
from cyphy.semantics.dynamics.tree import EULER, coordinate_names

SIMULATE = codes.code("E-SIMULATE", codes.E, "the model cannot be simulated as asked")

Calls = tuple[tuple[str, tuple[float, ...]], ...]


class Controller(Protocol):
    """A sampled controller: once per cycle it receives the input events of that instant
    (event name → ``None`` when absent, ``True`` or the communicated value when present) and
    returns the operation calls and output events it performs in that cycle, in order
    (``(("drive", (10.0,)),)``). The scenario's ``[controller]`` table and a RoboSim state
    machine both have this shape."""

    def cycle(self, events: Mapping[str, object]) -> Calls: ...


@dataclass
class SimulationOptions:
    t_end: float = 1.0
    init: dict[str, float] = field(default_factory=dict)
    inputs: dict[str, str] = field(default_factory=dict)  # name → expression of t
    method: str | None = None  # None: the one that fits (stiffness.choose)
    rtol: float = 1e-6
    atol: float = 1e-9
    samples: int = 201  # output instants, evenly spaced over [0, t_end]
    progress: Callable[[float], None] | None = None  # called with the fraction done
    # the states that are pitches of ZYX Euler angles → what they turn ("ball joint J"):
    # the run stops with a message where one reaches ±π/2 (the angles' singularity)
    pitches: dict[str, str] = field(default_factory=dict)


@dataclass
class Trajectory:
    """``times`` and one column per name (states first, then outputs), in ``values``;
    ``events``: the output events a controller sent that reach no input of the p-model
    (observable only), as ``(time of the cycle, name, values)`` in the order sent."""

    names: list[str]
    times: np.ndarray
    values: np.ndarray  # len(times) x len(names)
    events: list[tuple[float, str, tuple[float, ...]]] = field(default_factory=list)
    method: str = ""  # the integrator that ran (solve_ivp's name)
    engine: str = ""  # what evaluated the dynamics, for the user's note
    reason: str = ""  # why that integrator (cyphy.backends.stiffness.choose), for the note

    def column(self, name: str) -> np.ndarray:
        return self.values[:, self.names.index(name)]


class SimulationError(Exception):
    """What stops a simulation (an unknown name, an input that cannot be read, the
    integrator's failure), with a hint."""

    def __init__(self, message: str, hint: str) -> None:
        super().__init__(message)
        self.message, self.hint = message, hint


class OptionError(SimulationError):
    """A command-line value that does not fit the model (reported as ``E-OPTION``: exit
    status 2)."""


# ----------------------------------------------------------------------------- inputs

def input_expression(text: str) -> Any:
    """An input's value, ``10*sin(t)``, as a SymPy expression of ``t`` (read by cyphy's own
    parser, so it accepts what RoboSim expressions accept, and nothing is evaluated)."""
    # lazy: SymPy takes about half a second to import; only an input given as an expression needs it
    import sympy

    # lazy: imports SymPy (see above)
    from cyphy.translate.to_sympy import SympyPrinter, UnsupportedNode
    # lazy: Lark and the grammar only when an input expression is parsed
    from cyphy.lang.parser import parse_text

    result = parse_text(f"const input_value: real = {text}", "<--input>")
    item = result.file.items[0] if result.file and result.file.items else None
    if result.diagnostics or item is None or getattr(item, "value", None) is None:
        raise OptionError(f"cannot read the input value '{text}'",
                              "write an expression of t, for example 10*sin(t)")
    t = sympy.Symbol("t", real=True)
    try:
        value = SympyPrinter(symbols={"t": t}).doprint(item.value)
    except (UnsupportedNode, TypeError, ValueError) as err:
        raise OptionError(f"cannot read the input value '{text}': {err}",
                              "write an expression of t, for example 10*sin(t)") from None
    unknown = sorted(str(s) for s in sympy.sympify(value).free_symbols if s != t)
    if unknown:
        raise OptionError(f"the input value '{text}' names {', '.join(unknown)}",
                              "an input may depend on t only")
    if sympy.sympify(value).has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo):
        raise OptionError(f"the input value '{text}' is not finite ({value})",
                          "write an expression with a finite value at every t")
    return value


def _input_functions(names: Sequence[str], given: Mapping[str, str]
                     ) -> list[Callable[[float], float]]:
    """One function of t per input name; ``der_X`` is the derivative of ``X``'s expression."""
    out: list[Callable[[float], float]] = []
    for name in names:
        base = name[4:] if name.startswith("der_") and name not in given else name
        if base not in given:  # without SymPy: `simulate --numeric` need not import it
            out.append(lambda _t: 0.0)
            continue
        # lazy: SymPy costs 0.6 s to import, for the inputs given only
        import sympy

        t = sympy.Symbol("t", real=True)
        expr = input_expression(given[base])
        if base != name:
            expr = sympy.diff(expr, t)
        if expr.is_Number:  # most inputs: not given (lambdify costs 10 ms each, measured)
            out.append(lambda _t, value=float(expr): value)
        else:
            out.append(_finite(name, given.get(base, ""), sympy.lambdify(t, expr, "math")))
    return out


def _check_inputs(functions: Sequence[Callable[[float], float]], grid: np.ndarray) -> None:
    """Evaluate the given inputs at the output instants before the run, so that one not
    defined there (``1/(t-0.05)`` at 0.05) is an ``E-OPTION`` naming it, whichever method
    runs: an explicit method's steps pass beside the instant and it fails on the values'
    growth instead, with no word about the input."""
    for fn in functions:
        for tt in grid:
            fn(float(tt))


def _finite(name: str, text: str, fn: Callable[[float], float]) -> Callable[[float], float]:
    """``fn`` refusing a value that is not finite (``1/(t-1)`` at 1, ``log(t)`` at 0): the
    integrator would otherwise carry a NaN into every column."""
    def checked(tt: float) -> float:
        try:
            value = fn(tt)
        except (ValueError, ZeroDivisionError, OverflowError) as err:
            raise OptionError(f"--input {name}={text} cannot be evaluated at t = {tt:g}: "
                              f"{err}", "write an expression defined at every t") from None
        if not math.isfinite(value):
            raise OptionError(f"--input {name}={text} is {value} at t = {tt:g}",
                              "write an expression with a finite value at every t")
        return value
    return checked


def check_names(options: SimulationOptions, states: Sequence[str], inputs: Sequence[str]
                ) -> None:
    """Refuse ``--init`` and ``--input`` names that are not the model's states and inputs
    (an unknown one would be ignored and the run silently start from zero), each with the
    likely intent: a state given as an input, a misspelling. ``der_X`` inputs take ``X``."""

    valid = set(inputs) | {n[4:] for n in inputs if n.startswith("der_")}
    for name in sorted(set(options.init) - set(states)):
        hint = (f"{name} is an input: give it with --input {name}=EXPR" if name in valid
                else did_you_mean(name, states) or "the states are: " + ", ".join(states))
        raise OptionError(f"--init {name}: not a state of the model", hint)
    for name in sorted(set(options.inputs) - valid):
        if name in states:
            raise OptionError(f"--input {name}: {name} is a state, which the equations "
                              "determine", f"give its initial value with --init {name}=VALUE")
        raise OptionError(f"--input {name}: not an input of the model",
                          did_you_mean(name, valid) or "the inputs are: " +
                          (", ".join(sorted(valid)) or "none"))
    for name, value in options.init.items():
        if not math.isfinite(value):
            raise OptionError(f"--init {name}={value}: not a finite number",
                              "give a finite initial value")


def check_memory(samples: int, columns: int) -> None:
    """Refuse, before integrating, a run whose trajectory would not fit in memory
    (:func:`cyphy.limits.trajectory_refusal`)."""
    refusal = trajectory_refusal(samples, columns)
    if refusal:
        raise OptionError(*refusal)


# ----------------------------------------------------------------------------- symbolic path

def simulate_reduced(reduced: Any, options: SimulationOptions,
                     controller: Controller | None = None,
                     effects: Callable[[Calls], dict[str, float]] | None = None,
                     period: float | None = None,
                     events: Callable[[float, Mapping[str, float]], Mapping[str, object]]
                     | None = None, observable: Collection[str] = (), tree: Any = None
                     ) -> Trajectory:
    """Integrate the reduced ODEs (:class:`cyphy.semantics.dynamics.reduce.Reduced`);
    ``tree``, the model's kinematic tree, is evaluated by Pinocchio when the ODEs use its
    accelerations (:mod:`cyphy.backends.whole_model`).

    With a ``controller``, the run is cut at every ``period``: ``events(t, values)`` gives the
    input events at that instant, the controller's calls go through ``effects`` to input
    values that hold until the next cycle (they override ``options.inputs``); the output
    events named in ``observable`` have no effect and are recorded in the trajectory's
    ``events``."""
    import sympy  # lazy: SymPy only for the reduced equations, not for the kinematic-tree path

    states = list(reduced.states)
    inputs = list(reduced.inputs)
    check_names(options, states, inputs)
    check_memory(options.samples, len(states) + len(reduced.outputs))
    symbol = {n: sympy.Symbol(n, real=True) for n in [*states, *inputs]}
    t = sympy.Symbol("t", real=True)
    outputs = sorted(reduced.outputs)
    args = [symbol[n] for n in states] + [symbol[n] for n in inputs] + [t]
    rhs_expr = [reduced.rhs[s] for s in states]
    definitions = getattr(reduced, "definitions", [])  # a Flow* problem has none
    known = {str(a) for a in args} | {n for n, _ in definitions}
    leftover = sorted(({str(s) for e in rhs_expr for s in sympy.sympify(e).free_symbols} |
                       definition_names(definitions)) - known)
    if leftover:
        raise SimulationError(f"constants without a value: {', '.join(leftover)}",
                              "give them values with --const NAME=VALUE")
    out_exprs = [reduced.outputs[o] for o in outputs]
    out_ok = [not ({str(s) for s in sympy.sympify(e).free_symbols} - known)
              for e in out_exprs]
    outputs = [o for o, ok in zip(outputs, out_ok) if ok]
    out_exprs = [e for e, ok in zip(out_exprs, out_ok) if ok]

    dynamics = system_dynamics(states, inputs, rhs_expr, out_exprs, definitions, tree)
    rhs, out_fn = dynamics.rhs, dynamics.outputs
    given = _input_functions(inputs, options.inputs)
    held: dict[str, float] = {}
    # most inputs are not given (a chain's parent twists: 120 of 130 at 20 links): 0 once
    varying = [k for k, name in enumerate(inputs)
               if name in options.inputs or name[4:] in options.inputs]

    def u(tt: float) -> list[float]:
        if not held:
            values = [0.0] * len(inputs)
            for k in varying:
                values[k] = given[k](tt)
            return values
        return [held[n] if n in held else f(tt) for n, f in zip(inputs, given)]

    guarded = [(states.index(n), what) for n, what in sorted(options.pitches.items())
               if n in states]

    def f(tt: float, x: np.ndarray) -> np.ndarray:
        for k, what in guarded:
            _pitch_guard(what, float(x[k]), tt)
        return np.asarray(rhs(*x, *u(tt), tt), dtype=float).reshape(-1)

    x0 = np.array([float(options.init.get(s, 0.0)) for s in states])

    def observe(times: np.ndarray, xs: np.ndarray) -> np.ndarray:
        rows = []
        for k, tt in enumerate(times):
            x = xs[:, k]
            ys = out_fn(*x, *u(tt), tt) if outputs else []
            rows.append([*x, *(float(np.asarray(y, dtype=float)) for y in ys)])
        return np.array(rows, dtype=float).reshape(len(times), len(states) + len(outputs))

    grid = np.linspace(0.0, options.t_end, max(options.samples, 2))
    _check_inputs([given[k] for k in varying], grid)
    # stiffness detected on central differences at the start (2n evaluations, cheaper than
    # building the analytic Jacobian), which only a stiff method then gets
    choice = choose(options.method, lambda: _jacobian_at_start(f, None, x0),
                    options.t_end, dynamics.make_jacobian is not None)
    method, engine = choice.method, dynamics.engine
    jac = None
    if method in STIFF and dynamics.make_jacobian is not None:
        analytic = dynamics.make_jacobian()

        def jac(tt: float, x: np.ndarray) -> np.ndarray:
            return analytic(*x, *u(tt), tt)
    if controller is None or period is None:
        times, xs = _integrate(f, x0, grid, options, method=method, jac=jac)
        return _finite_trajectory(Trajectory([*states, *outputs], times, observe(times, xs),
                                             method=method, engine=engine,
                                             reason=choice.reason))
    all_t, all_rows = [], []
    sent: list[tuple[float, str, tuple[float, ...]]] = []
    start, x, k = 0.0, x0, 0
    while start < options.t_end - 1e-12:
        stop = min((k + 1) * period, options.t_end)
        values = dict(zip(states, x))
        values.update(zip(inputs, u(start)))
        calls = controller.cycle(events(start, values) if events else {})
        sent += [(start, name, tuple(args)) for name, args in calls if name in observable]
        calls = tuple(c for c in calls if c[0] not in observable)
        held.update((effects or (lambda _c: {}))(calls))
        inside = grid[(grid >= start) & (grid < stop)]
        local = np.unique(np.concatenate([[start], inside, [stop]]))
        times, xs = _integrate(f, x, local, options, offset=(start, options.t_end),
                               method=method, jac=jac)
        keep = np.isin(times, inside) | (times == start) | \
            ((times == stop) & (stop >= options.t_end))
        all_t.append(times[keep])
        all_rows.append(observe(times[keep], xs[:, keep]))
        x, start, k = xs[:, -1], stop, k + 1
    times = np.concatenate(all_t)
    rows = np.vstack(all_rows)
    order = np.unique(times, return_index=True)[1]
    return _finite_trajectory(Trajectory([*states, *outputs], times[order], rows[order], sent,
                                         method, engine, choice.reason))


#: The implicit (stiff-capable) methods of solve_ivp: those that take a Jacobian.
STIFF = ("LSODA", "BDF", "Radau")


def _jacobian_at_start(f: Callable[[float, np.ndarray], np.ndarray],
                       jac: Callable[[float, np.ndarray], np.ndarray] | None,
                       x0: np.ndarray) -> np.ndarray | None:
    """The state Jacobian at the start, for :func:`cyphy.backends.stiffness.choose`:
    analytic when there is one, else central differences (once, to detect stiffness)."""
    if not len(x0):
        return None
    if jac is not None:
        return jac(0.0, x0)
    return finite_difference(lambda x: f(0.0, x), x0)


def _finite_trajectory(trajectory: Trajectory) -> Trajectory:
    """The trajectory, or an error naming where it stops being finite: a table of NaN is
    no result."""
    rows = trajectory.values
    bad = ~np.isfinite(rows)
    if bad.any():
        k, j = np.argwhere(bad)[0]
        raise SimulationError(f"{trajectory.names[j]} is {rows[k, j]} at t = "
                              f"{trajectory.times[k]:g}: the trajectory is not finite from "
                              "there", "check the inputs and initial values, or try "
                              "another --method")
    return trajectory


def euler_pitches(tree: Any) -> dict[str, str]:
    """The coordinates that are pitches of ZYX Euler angles (a ball joint's second, a
    floating base's ``pitch``), with what they turn, for ``simulate``'s guard."""

    return {coordinate_names(j, "theta")[-2]:
            f"{'floating base' if j.kind == 'floating' else 'ball joint'} {j.name}"
            for j in tree.joints if j.kind in EULER}


#: How close to ±π/2 (in ``|cos(pitch)|``) ZYX Euler angles may come: ``q̈ = B⁻¹·w`` loses
#: about ``1e-16/|cos(pitch)|`` of its relative accuracy (rigid_body.subspace_factors), 1e-7
#: here, and the rates of yaw and roll grow as ``1/|cos(pitch)|``.
PITCH_GUARD = 1e-9


def _pitch_guard(what: str, pitch: float, t: float) -> None:
    if abs(math.cos(pitch)) < PITCH_GUARD:
        raise SimulationError(
            f"the {what} reached pitch {pitch:.12g} rad at t = {t:g} s, where its ZYX Euler "
            "angles are singular (yaw and roll turn about one axis; their rates are "
            "unbounded)", "turn the joint frame (its pose) so that the motion stays away from "
            "pitch ±π/2")


def _integrate(f: Callable[[float, np.ndarray], np.ndarray], x0: np.ndarray,
               times: np.ndarray, options: SimulationOptions,
               offset: tuple[float, float] | None = None, method: str = "LSODA",
               jac: Callable[[float, np.ndarray], np.ndarray] | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
    # lazy: SciPy takes a quarter second to import; only integration needs it
    from scipy.integrate import solve_ivp

    if len(x0) == 0:
        return times, np.zeros((0, len(times)))
    total = offset[1] if offset else times[-1]
    last = [time.monotonic()]

    def tracked(tt: float, x: np.ndarray) -> np.ndarray:
        if options.progress is not None and time.monotonic() - last[0] > 1.0:
            last[0] = time.monotonic()
            options.progress(min(tt / total, 1.0) if total > 0 else 1.0)
        return f(tt, x)

    extra = {"jac": jac} if jac is not None and method in STIFF else {}
    solution = solve_ivp(tracked, (times[0], times[-1]), x0, method=method,
                         t_eval=times, rtol=options.rtol, atol=options.atol, **extra)
    if not solution.success:
        raise SimulationError(f"the integrator stopped at t = {solution.t[-1]:g}: "
                              f"{solution.message}",
                              "try another --method (BDF, Radau) or looser tolerances")
    return solution.t, solution.y


# ----------------------------------------------------------------------------- numeric path

def simulate_tree(tree: Any, options: SimulationOptions) -> Trajectory:
    """Integrate a kinematic tree alone with the articulated-body algorithm: states the
    coordinates ``<J>_theta`` (``<J>_theta_1`` … for a joint of several, ``<Root>_x`` … for
    a floating base) then their rates (``<J>_v``, ``<Root>_vx`` …), in tree order; inputs the
    joint efforts ``<J>_tau`` (a floating base has none).

    The accelerations come from Pinocchio's compiled ABA when it is installed
    (:mod:`cyphy.backends.pinocchio_tree`), else from cyphy's NumPy ABA, which the tests check
    against Pinocchio, MuJoCo and the symbolic path; a stiff method gets Pinocchio's analytic
    Jacobian when the tree has only revolute and prismatic joints (else the method's finite
    differences)."""

    n = tree.dof
    thetas, speeds = list(tree.coordinates("theta")), list(tree.coordinates("v"))
    states = [*thetas, *speeds]
    efforts = list(tree.coordinates("tau"))
    check_names(options, states, efforts)
    check_memory(options.samples, len(states))
    slots = np.array([k for j, start in zip(tree.joints, tree.offsets) if j.kind != "floating"
                      for k in range(start, start + j.dof)], dtype=int)
    given = _input_functions(efforts, options.inputs)
    constant = all(name not in options.inputs for name in efforts)
    zero = np.zeros(n)
    compiled_tree = pinocchio_model(tree)
    euler = any(j.kind in EULER for j in tree.joints)

    def accelerations(q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        if compiled_tree is None:
            return forward_dynamics(tree, q, qd, tau)
        if euler:  # Pinocchio divides by cos(pitch) without a word: refuse as the NumPy ABA
            euler_singularity(tree, q)
        return compiled_tree.forward_dynamics(q, qd, tau)

    def efforts_at(tt: float) -> np.ndarray:
        if constant:
            return zero
        tau = np.zeros(n)
        tau[slots] = [g(tt) for g in given]
        return tau

    annotated = annotated_efforts(tree)

    def f(tt: float, x: np.ndarray) -> np.ndarray:
        tau = efforts_at(tt)
        if annotated is not None:
            tau = tau + annotated(x[:n], x[n:])
        return np.concatenate([x[n:], accelerations(x[:n], x[n:], tau)])

    jac = None
    # the analytic Jacobian is of the ABA alone: annotated damping, springs and stops make
    # the efforts depend on the state too, so then the method's finite differences
    if compiled_tree is not None and compiled_tree.derivatives and annotated is None:
        def jac(tt: float, x: np.ndarray) -> np.ndarray:
            return compiled_tree.jacobian(x[:n], x[n:], efforts_at(tt))

    x0 = np.array([float(options.init.get(s, 0.0)) for s in states])
    # the NumPy ABA once: its diagnostic for a massless subtree (a singular mass matrix),
    # where Pinocchio would return NaN
    forward_dynamics(tree, x0[:n], x0[n:], efforts_at(0.0))
    grid = np.linspace(0.0, options.t_end, max(options.samples, 2))
    _check_inputs([g for name, g in zip(efforts, given) if name in options.inputs], grid)
    choice = choose(options.method, lambda: _jacobian_at_start(f, jac, x0),
                    options.t_end, jac is not None)
    method = choice.method
    times, xs = _integrate(f, x0, grid, options, method=method, jac=jac)
    engine = "Pinocchio's articulated-body algorithm" if compiled_tree is not None else \
        "cyphy's NumPy articulated-body algorithm (Pinocchio, the pip package pin, is not " \
        "installed: it is about 100 times faster)"
    return _finite_trajectory(Trajectory(states, times, xs.T.copy(), method=method,
                                         engine=engine, reason=choice.reason))


# ----------------------------------------------------------------------------- output

def to_csv(trajectory: Trajectory) -> str:
    """``t`` then one column per name; values as Python prints floats (round-trip exact)."""
    lines = [",".join(["t", *trajectory.names])]
    for tt, row in zip(trajectory.times, trajectory.values):
        lines.append(",".join(repr(float(v)) for v in [tt, *row]))
    return "\n".join(lines) + "\n"


def to_json(trajectory: Trajectory) -> str:
    return json.dumps({"t": [float(v) for v in trajectory.times],
                       "columns": {n: [float(v) for v in trajectory.column(n)]
                                   for n in trajectory.names},
                       "events": [{"t": float(t), "name": name,
                                   "values": [float(v) for v in values]}
                                  for t, name, values in trajectory.events]},
                      indent=1) + "\n"


def plot(trajectory: Trajectory, names: Sequence[str] = ()) -> bytes:
    """A PNG of the chosen columns over time (all states when none is chosen; at most 8), as
    bytes: the caller writes it atomically, where it checked it could before the run."""
    from cyphy.backends.plotting import line_plot  # lazy: matplotlib behind it

    chosen = list(names) or trajectory.names[:8]
    missing = [n for n in chosen if n not in trajectory.names]
    if missing:
        raise SimulationError(f"--plot-var names {', '.join(missing)}, which is not simulated",
                              "choose among: " + ", ".join(trajectory.names))
    return line_plot(trajectory.times, [(name, trajectory.column(name)) for name in chosen])


def progress_to_stderr(fraction: float) -> None:
    sys.stderr.write(f"cyphy simulate: {100 * fraction:5.1f}%\r")
    sys.stderr.flush()
