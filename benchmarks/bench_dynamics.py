"""Equations-of-motion benchmark (issue 16), on synthetic robot arms
(``synthetic.chain_model(n, bent=True)``: ``n`` links, each 0.1 m along x and z from its
parent, ``n - 1`` revolute joints about z, y, x in turn, each driven by a PID speed-controlled
DC motor), so that every joint's equation of motion couples all the others.

Targets:
* ``cyphy solve`` (``api.solve``: assemble the model's equations, derive the explicit
  accelerations as the articulated-body algorithm's named definitions, reduce the whole
  model, motors included, with SymPy) of a 10-link arm ≤ 1 s;
* linear cost: solve of a 100-link arm / solve of a 10-link arm ≤ 15 (10 times the links);
  7 and 30 links are measured too;
* numeric path, 100 links: elaborate, build the tree and evaluate the numeric
  articulated-body algorithm at 100 states ≤ 10 s, and time(100 links) / time(10 links) of
  those evaluations ≤ 15;
* ``api.simulate`` of 1 s of a 10-link arm, whole model (solve's ODEs compiled): ≤ 1 s; the
  tree alone (``numeric``) is measured too.

In-process, after a warm-up (imports, grammar, library); medians of ``--runs`` runs (the
100-link solve: one run), SymPy's cache cleared before each solve (a second solve of the same
model finds its expressions cached and takes a third of the time).
Exit status 0 when every target holds, 1 otherwise.

Run: ``python benchmarks/bench_dynamics.py [--runs 3]``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402
from sympy.core.cache import clear_cache  # noqa: E402

from cyphy import api  # noqa: E402
from cyphy.backends.simulate import SimulationOptions  # noqa: E402
from cyphy.semantics.dynamics import rigid_body as dynamics  # noqa: E402
from synthetic import chain_model, write_model  # noqa: E402
from timing import median_time  # noqa: E402

#: The motors' constants (the library leaves them open): a small DC motor, P control.
MOTOR = {f"SpeedControlMotor::{k}": v for k, v in dict(
    J=0.01, b=0.001, Ke=0.01, Kt=0.01, R=1.0, L=0.5, Kp=1.0, Ki=0.0, Kd=0.0).items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="cyphy-bench-dynamics-"))
    folders = {}
    for n in (7, 10, 30, 100):
        folders[n] = tmp / f"arm{n}"
        write_model(folders[n], chain_model(n, sensors_per_link=0, bent=True))
    ok = True
    api.solve([folders[7]])  # warm-up: grammar, library, SymPy

    def solve(n: int) -> None:
        clear_cache()  # as a fresh `cyphy solve` finds it: nothing of an earlier run cached
        result = api.solve([folders[n]], api.SolveOptions(closed_form=False))
        assert result.reduced is not None and not result.reduced.obstacles
        assert len(result.reduced.definitions) > 0

    solved = {}
    for n in (7, 10, 30, 100):
        api.elaborate([folders[n]])  # parsed and elaborated once (cyphy caches the parse)
        solved[n] = median_time(lambda: solve(n), args.runs if n < 100 else 1)
        print(f"solve (derive + reduce), {n}-link arm: {solved[n]:.3f} s"
              + (" (target <= 1 s)" if n == 10 else ""))
    ratio = solved[100] / solved[10]
    ok &= solved[10] <= 1.0 and ratio <= 15.0
    print(f"solve, 100 links / 10 links: {ratio:.1f} (target <= 15; linear is 11)")

    rng = np.random.default_rng(0)

    def numeric(n: int) -> float:
        model = api.elaborate([folders[n]]).model
        tree = dynamics.kinematic_tree(model)
        states = rng.uniform(-1, 1, (100, 3, len(tree)))
        start = time.perf_counter()
        for q, qd, tau in states:
            dynamics.forward_dynamics(tree, q, qd, tau)
        return time.perf_counter() - start

    whole = median_time(lambda: numeric(100), args.runs)
    aba = {n: statistics.median(numeric(n) for _ in range(args.runs)) for n in (10, 100)}
    ratio = aba[100] / aba[10]
    ok &= whole <= 10.0 and ratio <= 15.0
    print(f"numeric, 100-link arm (elaborate, tree, 100 ABA): {whole:.3f} s (target <= 10 s)")
    print(f"ABA x100: 10 links {aba[10] * 1000:.1f} ms, 100 links {aba[100] * 1000:.1f} ms, "
          f"ratio {ratio:.1f} (target <= 15)")

    def simulate(tree_only: bool) -> None:
        result = api.simulate([folders[10]], api.SimulateOptions(
            consts=MOTOR, numeric=tree_only,
            simulation=SimulationOptions(t_end=1.0, init={"J0_v": 1.0})))
        assert result.trajectory is not None and result.numeric == tree_only

    t = median_time(lambda: simulate(False), args.runs)
    ok &= t <= 1.0
    print(f"simulate 1 s of a 10-link arm, whole model: {t:.3f} s (target <= 1 s)")
    t = median_time(lambda: simulate(True), args.runs)
    print(f"simulate 1 s of a 10-link arm, tree alone (--numeric): {t:.3f} s")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
