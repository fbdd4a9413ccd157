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
have made the choice.
"""

from __future__ import annotations

import itertools
import random
import re
from dataclasses import dataclass
from typing import Any, Callable

from cyphy import expr as ex
from cyphy.flowstar.syntax import Constraint, FlowModel, parse_model

RTOL, ATOL = 1e-10, 1e-12
MARGIN = 1e-7  # relative margin a decision needs to count as clear


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
        import sympy

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

    def _sympy(self, e: ex.Expr) -> Any:
        import sympy

        from cyphy.backends.sympy import to_sympy

        names = {n.text: sympy.Symbol(n.text, real=True) for n in e.walk()
                 if isinstance(n, ex.Name)}
        value = to_sympy(e, symbols=names)
        return value.xreplace({sympy.Symbol(k, real=True): sympy.Float(v)
                               for k, v in self.params.items()})

    def _function(self, e: ex.Expr) -> Callable[..., Any]:
        import sympy

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
        import numpy as np

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
        import numpy as np

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
        steps = self.model.settings.get("fixed steps") or \
            (self.model.settings.get("adaptive steps") or ("0.01", "0.01"))[1]
        step = float(steps)
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
        import numpy as np

        out = {v: np.full(len(times), np.nan) for v in self.variables}
        for _, sol, begin, end, _ in self._segments(start, strict=False):
            inside = (times >= begin) & (times <= end)
            values = sol.sol(times[inside])
            for k, v in enumerate(self.variables):
                out[v][inside] = values[k]
        return out

    def _segments(self, start: dict[str, float], strict: bool) -> Any:
        """The flows of the trajectory from ``start``, one per mode visit: (mode, solution,
        start time, end time, jumps so far)."""
        import numpy as np
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
        import numpy as np

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

    def starts(self, count: int = 40, seed: int = 0) -> list[dict[str, float]]:
        """Points of the initial box to try: its centre, corners (of at most 5 uncertain
        coordinates), points spread along each uncertain coordinate, then seeded random
        points: deterministic, so the verdict is the same on every run."""
        box = {v: (float(lo), float(hi)) for v, (lo, hi) in
               ((v, self.model.init.get(v, ("0", "0"))) for v in self.variables)}
        wide = [v for v, (lo, hi) in box.items() if hi > lo]
        centre = {v: (lo + hi) / 2 for v, (lo, hi) in box.items()}
        points = [centre]
        for corner in itertools.product((0, 1), repeat=min(len(wide), 5)):
            p = dict(centre)
            for v, side in zip(wide, corner):
                p[v] = box[v][side]
            points.append(p)
        for v in wide:
            for k in range(1, 8):
                p = dict(centre)
                p[v] = box[v][0] + (box[v][1] - box[v][0]) * k / 8
                points.append(p)
        rng = random.Random(seed)
        while len(points) < count:
            points.append({v: rng.uniform(lo, hi) if hi > lo else lo
                           for v, (lo, hi) in box.items()})
        return points[:max(count, 1 + 2 ** min(len(wide), 5))]


def find_witness(text: str, count: int = 40) -> Witness | None:
    """A trajectory of the model from its initial set that clearly enters the unsafe set,
    trying :meth:`Automaton.starts` in order; None when none of them does."""
    automaton = Automaton(text)
    for start in automaton.starts(count):
        witness = automaton.run(start)
        if witness is not None:
            return witness
    return None


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
