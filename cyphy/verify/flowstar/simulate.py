"""Concrete trajectories of a Flow* hybrid automaton (the model file cyphy wrote), to confirm
an UNSAFE verdict (SciPy ``solve_ivp`` with event detection).

Flow*'s UNSAFE on a hybrid run is not a proof: its flowpipes follow every jump whose guard
meets the enclosure, including branches no real trajectory takes (an initial set within
1e-5 of an event boundary is enough). An UNSAFE is only reported when a trajectory found
here shows it: from a point of the initial set, flows integrated to 1e-10, a jump taken when
the invariant forces it, the first jump in file order whose guard holds (the order the
exporter gives the controller's transitions), and the unsafe set entered. A trajectory is a
witness only if every decision on it is clear: each guard tested at a jump holds or fails
by a margin, and the unsafe constraints hold by a margin, so that integration error cannot
have made the choice. :func:`find_witness` searches the initial box for such a start,
deterministically and within a budget of trajectories, guided by how close each trajectory
comes to the unsafe set on the mode path Flow* flagged.
"""

from __future__ import annotations

import itertools
import math
import random
import re
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import sympy

from cyphy import expr as ex
from cyphy.translate.to_sympy import to_sympy
from cyphy.verify.flowstar.syntax import Constraint, FlowModel, parse_model

RTOL, ATOL = 1e-10, 1e-12
MARGIN = 1e-7  # relative margin a decision needs to count as clear
BUDGET = 120  # trajectories a witness search simulates at most


@dataclass(frozen=True)
class Point:
    """A state on the trajectory: when, in which mode, the values."""

    time: float
    mode: str
    values: tuple[tuple[str, float], ...]

    def text(self, names: list[str]) -> str:
        shown = dict(self.values)
        return ", ".join(f"{n} = {shown[n]:.6g}" for n in names if n in shown)


@dataclass(frozen=True)
class Witness:
    """A simulated trajectory that enters the unsafe set: its start, the states where the
    mode changed, and the first state in the unsafe set."""

    start: Point
    switches: tuple[Point, ...]
    entry: Point
    jumps: int

    def lines(self, names: list[str]) -> list[str]:
        rows = [("start", self.start), *(("jump", p) for p in self.switches),
                ("unsafe", self.entry)]
        return [f"  t = {p.time:<10.6g} {what:<6} {p.mode:<12} {p.text(names)}"
                for what, p in rows]


class _Unclear(Exception):
    """A decision on the trajectory lies within the margin of a boundary."""


class Automaton:
    """A parsed hybrid model compiled to NumPy functions."""

    def __init__(self, text: str) -> None:
        model: FlowModel = parse_model(text)
        if model.kind != "hybrid":
            raise ValueError("only hybrid models are simulated")
        self.model = model
        self.variables = model.variables
        self.params = {k: float(v) for k, v in model.params.items()}
        syms = [sympy.Symbol(v, real=True) for v in self.variables]
        self._syms = syms
        self.horizon = float(model.settings["time"])
        self.max_jumps = int(model.settings["max jumps"])
        self.flows = {name: sympy.lambdify(syms, [self._sympy(mode.flow[v]) if v in mode.flow
                                                  else 0 for v in self.variables], "numpy")
                      for name, mode in model.modes.items()}
        self.invariants = {name: [self._constraint(c) for c in mode.invariant]
                           for name, mode in model.modes.items()}
        self.jumps = [(j.source, j.target, [self._constraint(c) for c in j.guard],
                       {v: self._function(r) for v, r in j.resets.items()})
                      for j in model.jumps]
        self.unsafe = {m: [self._constraint(c) for c in cons]
                       for m, cons in (model.unsafe or {}).items()}
        steps = model.settings.get("fixed steps") or \
            (model.settings.get("adaptive steps") or ("0.01", "0.01"))[1]
        self.step = float(steps)  # Flow*'s step: the trajectory is sampled at an eighth

    def _sympy(self, e: ex.Expr) -> Any:
        names = {n.text: sympy.Symbol(n.text, real=True) for n in e.walk()
                 if isinstance(n, ex.Name)}
        value = to_sympy(e, symbols=names)
        return value.xreplace({sympy.Symbol(k, real=True): sympy.Float(v)
                               for k, v in self.params.items()})

    def _function(self, e: ex.Expr) -> Callable[..., Any]:
        return sympy.lambdify(self._syms, self._sympy(e), "numpy")

    def _bound(self, b: str) -> float:
        return self.params[b] if b in self.params else float(b)

    def _constraint(self, c: Constraint) -> tuple[Callable[..., Any], str, tuple[float, ...]]:
        return self._function(c.lhs), c.rel, tuple(self._bound(b) for b in c.bounds)

    # ----- deciding constraints with a margin
    @staticmethod
    def _status(value: Any, rel: str, bounds: tuple[float, ...]) -> Any:
        """+1 where the constraint clearly holds, -1 where it clearly fails, 0 in between
        (element-wise for arrays)."""
        v = np.asarray(value, dtype=float)
        scale = MARGIN * (1.0 + np.abs(v) + max(abs(b) for b in bounds))
        if rel == "=":  # only reachable exactly, as the timer reaches the sampling instant
            return np.where(np.abs(v - bounds[0]) <= 1e-3 * scale, 1, -1)
        if rel == "in":
            lo, hi = bounds
            return np.minimum(Automaton._status(v, ">=", (lo,)),
                              Automaton._status(v, "<=", (hi,)))
        d = bounds[0] - v if rel == "<=" else v - bounds[0]
        return np.where(d > scale, 1, np.where(d < -scale, -1, 0))

    def _conjunction(self, cons: list, x: Any) -> Any:
        status = np.ones(np.shape(x)[1:] or (), dtype=int)
        for f, rel, bounds in cons:
            value = np.broadcast_to(np.asarray(f(*x), dtype=float), status.shape)
            status = np.minimum(status, self._status(value, rel, bounds))
        return status

    # ----- one trajectory
    def run(self, start: dict[str, float]) -> Witness | None:
        """The trajectory from ``start``; a witness when it clearly enters the unsafe set,
        None when it does not or when a decision on it is unclear."""
        try:
            return self._run(start)
        except _Unclear:
            return None

    def _run(self, start: dict[str, float]) -> Witness | None:
        mode = self.model.initial_mode
        first = self._point(0.0, mode, [start[v] for v in self.variables])
        switches: list[Point] = []
        step = self.step
        previous = mode
        for mode, sol, begin, end, jumps in self._segments(start, strict=True):
            if mode != previous:
                switches.append(self._point(begin, mode, sol.y[:, 0]))
                previous = mode
            entry = self._entry(mode, sol, begin, end, step)
            if entry is not None:
                return Witness(first, tuple(switches), entry, jumps)
        return None

    def sample(self, start: dict[str, float], times: Any) -> dict[str, Any]:
        """The values of every variable at ``times`` (NaN after the path ends); at a jump
        whose guard is on its boundary the first such jump in file order is taken."""
        out = {v: np.full(len(times), np.nan) for v in self.variables}
        for _, sol, begin, end, _ in self._segments(start, strict=False):
            inside = (times >= begin) & (times <= end)
            if not inside.any():
                continue
            values = sol.sol(times[inside])
            for k, v in enumerate(self.variables):
                out[v][inside] = values[k]
        return out

    def _segments(self, start: dict[str, float], strict: bool) -> Any:
        """The flows of the trajectory from ``start``, one per mode visit: (mode, solution,
        start time, end time, jumps so far)."""
        # lazy: SciPy's integrators (0.5-1 s to import): only a witness is integrated
        from scipy.integrate import solve_ivp

        mode = self.model.initial_mode
        x = np.array([start[v] for v in self.variables], dtype=float)
        now, jumps = 0.0, 0
        while True:
            events = []
            for f, rel, (b, *_) in self.invariants[mode]:
                if rel != "<=":
                    raise _Unclear  # cyphy writes upper-bound invariants only
                ev = (lambda t, y, f=f, b=b: float(f(*y)) - b)
                ev.terminal, ev.direction = True, 1
                events.append(ev)
            flow = self.flows[mode]
            sol = solve_ivp(lambda t, y: np.asarray(flow(*y), dtype=float), (now, self.horizon),
                            x, method="DOP853", rtol=RTOL, atol=ATOL, events=events,
                            dense_output=True)
            end = float(sol.t[-1])
            yield mode, sol, now, end, jumps
            now, x = end, sol.y[:, -1]
            if now >= self.horizon - 1e-12 or jumps >= self.max_jumps:
                return
            taken = self._jump(mode, x, strict)
            if taken is None:
                return  # no guard holds: the path ends, as in Flow*
            target, resets = taken
            new = x.copy()
            for v, f in resets.items():
                new[self.variables.index(v)] = float(f(*x))
            x, jumps, mode = new, jumps + 1, target

    def _entry(self, mode: str, sol: Any, start: float, end: float, step: float
               ) -> Point | None:
        cons = self.unsafe.get(mode)
        if not cons:  # cyphy lists every mode; an empty list would be everything
            return None
        samples = np.unique(np.concatenate([np.arange(start, end, step / 8), [end]]))
        states = sol.sol(samples)
        status = self._conjunction(cons, states)
        inside = np.nonzero(status == 1)[0]
        if inside.size:
            k = int(inside[0])
            return self._point(float(samples[k]), mode, states[:, k])
        return None

    def _jump(self, mode: str, x: Any, strict: bool) -> tuple[str, dict[str, Any]] | None:
        for source, target, guard, resets in self.jumps:
            if source != mode:
                continue
            status = int(self._conjunction(guard, x.reshape(-1, 1))[0])
            if status == 0 and strict:
                raise _Unclear  # this jump's guard is on its boundary here
            if status >= 0:
                return target, resets
        return None

    def _point(self, time: float, mode: str, x: Any) -> Point:
        return Point(time, mode, tuple((v, float(x[k])) for k, v in enumerate(self.variables)))

    def starts(self) -> list[dict[str, float]]:
        """The first points tried, in order: the initial box's centre, its corners (of at
        most 6 uncertain coordinates; seeded ones beyond), and 9 points along each uncertain
        coordinate through the centre."""
        box, wide = self.box(), self.uncertain()
        centre = {v: (lo + hi) / 2 for v, (lo, hi) in box.items()}
        points = [centre]
        corners = list(itertools.product((0, 1), repeat=len(wide))) if len(wide) <= 6 else \
            [tuple(random.Random(k).randint(0, 1) for _ in wide) for k in range(64)]
        for corner in corners:
            points.append({**centre, **{v: box[v][side] for v, side in zip(wide, corner)}})
        for v in wide:
            lo, hi = box[v]
            points += [{**centre, v: lo + (hi - lo) * k / 8} for k in range(9)]
        return points

    def box(self) -> dict[str, tuple[float, float]]:
        return {v: (float(lo), float(hi)) for v, (lo, hi) in
                ((v, self.model.init.get(v, ("0", "0"))) for v in self.variables)}

    def uncertain(self) -> list[str]:
        return [v for v, (lo, hi) in self.box().items() if hi > lo]

    # ----- how far a trajectory stays from the unsafe set
    def measure(self, start: dict[str, float], paths: list[list[str]] = ()
                ) -> tuple[float, float]:
        """(robustness, guided score) of the trajectory from ``start`` (first jump in file
        order on a guard's boundary). The robustness is the least, over the samples of every
        flow, of the largest relative violation of an unsafe constraint: negative inside
        the unsafe set. The guided score is that robustness on the flow that ends one of
        Flow*'s unsafe ``paths`` when the trajectory follows that path's modes, and worse
        (1 + the share of the path not followed + the robustness if positive) when it
        departs from it: it draws the search to the branch Flow* flagged."""
        try:
            flows = [(mode, self._robustness(mode, sol, begin, end))
                     for mode, sol, begin, end, _ in self._segments(start, strict=False)]
        except (_Unclear, ValueError, ArithmeticError):
            return math.inf, math.inf
        rho = min((r for _, r in flows), default=math.inf)
        if not paths:
            return rho, rho
        modes, guided = [m for m, _ in flows], math.inf
        for path in paths:
            same = next((k for k, (a, b) in enumerate(zip(modes, path)) if a != b),
                        min(len(modes), len(path)))
            if same == len(path):
                guided = min(guided, flows[len(path) - 1][1])
            else:
                guided = min(guided, 1 + (len(path) - same) / len(path) + max(rho, 0.0))
        return rho, guided

    def _robustness(self, mode: str, sol: Any, start: float, end: float) -> float:
        cons = self.unsafe.get(mode)
        if not cons:
            return math.inf
        samples = np.unique(np.concatenate([np.arange(start, end, self.step / 8), [end]]))
        states = sol.sol(samples)
        worst = np.full(samples.shape, -np.inf)
        for f, rel, bounds in cons:
            v = np.broadcast_to(np.asarray(f(*states), dtype=float), samples.shape)
            scale = 1.0 + max(abs(b) for b in bounds)
            if rel == "<=":
                d = v - bounds[0]
            elif rel == ">=":
                d = bounds[0] - v
            elif rel == "in":
                d = np.maximum(bounds[0] - v, v - bounds[1])
            else:
                d = np.abs(v - bounds[0])
            worst = np.maximum(worst, d / scale)
        value = float(np.min(worst))
        return value if math.isfinite(value) else math.inf


class _Found(Exception):
    """A witness: ends the search (raised through SciPy's minimiser too)."""

    def __init__(self, witness: Witness) -> None:
        self.witness = witness


class _Exhausted(Exception):
    """The search's budget of trajectories is spent."""


class _Search:
    """The deterministic search of :func:`find_witness`, within ``budget`` trajectories."""

    def __init__(self, automaton: Automaton, paths: list[list[str]], budget: int) -> None:
        self.a, self.paths, self.budget = automaton, paths, budget
        self.box = automaton.box()
        self.wide = automaton.uncertain()
        self.centre = {v: (lo + hi) / 2 for v, (lo, hi) in self.box.items()}
        self.seen: dict[tuple[float, ...], tuple[float, float]] = {}

    def point(self, x: Any) -> dict[str, float]:
        out = dict(self.centre)
        for v, value in zip(self.wide, x):
            lo, hi = self.box[v]
            out[v] = min(max(float(value), lo), hi)
        return out

    def key(self, start: dict[str, float]) -> tuple[float, ...]:
        return tuple(start[v] for v in self.wide)

    def score(self, start: dict[str, float]) -> float:
        """The guided score of ``start``; raises _Found on a witness, _Exhausted when the
        budget is spent."""
        key = self.key(start)
        if key in self.seen:
            return self.seen[key][1]
        if len(self.seen) >= self.budget:
            raise _Exhausted
        rho, guided = self.a.measure(start, self.paths)
        self.seen[key] = (rho, guided)
        if rho < 0:
            witness = self.a.run(start)
            if witness is not None:
                raise _Found(witness)
        return guided

    def best(self, count: int) -> list[tuple[float, ...]]:
        ranked = sorted(self.seen.items(), key=lambda kv: (kv[1][1], kv[1][0], kv[0]))
        return [k for k, _ in ranked[:count]]

    def run(self) -> Witness | None:
        try:
            for start in self.a.starts():
                self.score(start)
            if self.wide:
                self.refine()
                self.optimise()
        except _Found as found:
            return found.witness
        except _Exhausted:
            pass
        return None

    def refine(self) -> None:
        """Grids around the best points so far, halving their spacing each level: for up
        to 3 uncertain coordinates every point of the 3^d grid, beyond that the 2d points
        along the axes. Uses up to half of the budget."""
        stop = len(self.seen) + (self.budget - len(self.seen)) // 2
        widths = [self.box[v][1] - self.box[v][0] for v in self.wide]
        steps = (itertools.product((-1, 0, 1), repeat=len(self.wide)) if len(self.wide) <= 3
                 else [tuple(s if i == k else 0 for i in range(len(self.wide)))
                       for k in range(len(self.wide)) for s in (-1, 1)])
        steps = [s for s in steps if any(s)]
        for level in range(1, 40):
            h = [w / (8 * 2 ** level) for w in widths]
            for centre in self.best(3):
                for s in steps:
                    if len(self.seen) >= stop:
                        return
                    self.score(self.point([c + k * d for c, k, d in zip(centre, s, h)]))

    def optimise(self) -> None:
        """Nelder-Mead on the guided score from the best point, within the budget left."""
        # lazy: SciPy's optimisers: only a search its first samples did not end uses them
        from scipy.optimize import minimize

        left = self.budget - len(self.seen)
        if left <= 0:
            return
        lows = np.array([self.box[v][0] for v in self.wide])
        highs = np.array([self.box[v][1] for v in self.wide])
        x0 = np.array(self.best(1)[0])
        simplex = [x0] + [np.clip(x0 + np.eye(len(x0))[k] * (highs - lows)[k] / 16, lows,
                                  highs) for k in range(len(x0))]
        minimize(lambda x: self.score(self.point(x)), x0, method="Nelder-Mead",
                 bounds=list(zip(lows, highs)),
                 options={"maxfev": left, "initial_simplex": np.array(simplex),
                          "xatol": 1e-12 * float(np.max(highs - lows)), "fatol": 0.0})


def find_witness(text: str, paths: list[list[str]] = (), budget: int = BUDGET
                 ) -> Witness | None:
    """A trajectory of the model from its initial set that clearly enters the unsafe set,
    or None. Deterministic, within ``budget`` simulated trajectories: the centre, corners
    and lines of points of :meth:`Automaton.starts`; then grids refined around the best
    points so far (by :meth:`Automaton.measure`'s score, guided by Flow*'s unsafe
    ``paths``); then Nelder-Mead (SciPy) on that score from the best point. A start whose
    trajectory enters the unsafe set is confirmed by :meth:`Automaton.run` (every decision
    clear) before it counts."""
    return _Search(Automaton(text), list(paths), budget).run()


_PATH = re.compile(r"computation path\s*\{\s*([^;{}]*);", re.S)


def unsafe_paths(counterexample: str) -> list[list[str]]:
    """The mode paths of the flowpipes Flow*'s counterexample file calls unsafe (each
    ``mode (jump, [time]) -> mode …``), as lists of modes."""
    out: list[list[str]] = []
    for section in re.split(r"Unknown flowpipes:", counterexample):
        head = section.split("Unsafe flowpipes:")
        for part in head[1:]:
            for m in _PATH.finditer(part):
                modes = [re.sub(r"\(.*", "", step).strip() for step in m.group(1).split("->")]
                if modes not in out:
                    out.append(modes)
    return out
