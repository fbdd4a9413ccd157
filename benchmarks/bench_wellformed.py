"""Well-formedness benchmark: every condition on the synthetic 10,000-link model.

Target (issue 4): all checks in under 3 s. The file is parsed and resolved once (the front
end, timed for information); then every condition (``check_wellformed``, what ``cyphy check``
adds to the front end) runs on that workspace ``--runs`` times, each run with a fresh context
(nothing is shared between runs), and the median is compared with the target. Timing the
conditions directly, rather than ``check`` with them minus ``check`` without them, keeps the
front end's noise (a minute of parsing on a loaded machine) out of a number of a few seconds.
``check_wellformed`` pauses the garbage collector and then moves what the run built to the
oldest generation; a young collection after the run is timed with it, and the previous run's
garbage is collected, untimed, before each run (a ``cyphy check`` process has none).
One more run times each rule, in registry order on one context (the value checks share one
elaboration, which the first of them pays), and the slowest are printed.

Run: ``python benchmarks/bench_wellformed.py [N] [--runs R]``.
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from cyphy import api  # noqa: E402
from cyphy.diagnostics import Report  # noqa: E402
from cyphy.wellformed import RULES, WFContext, check_wellformed  # noqa: E402
from synthetic import chain_model, write_model  # noqa: E402

TARGET_S = 3.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("links", nargs="?", type=int, default=10_000)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = write_model(Path(tmp), chain_model(args.links))
        start = time.perf_counter()
        front = api.check([path], api.CheckOptions(wellformedness=False))
        front_s = time.perf_counter() - start
    assert not front.report.has_errors and front.resolution is not None
    times, diagnostics = [], 0
    for _ in range(args.runs):
        report = Report()
        gc.collect()  # untimed: the previous run's garbage, which a fresh process has not
        start = time.perf_counter()
        check_wellformed(WFContext(front.workspace, front.resolution, report))
        gc.collect(0)  # the collection the run defers (the rules pause the collector)
        times.append(time.perf_counter() - start)
        diagnostics = len(report.diagnostics)
    ctx = WFContext(front.workspace, front.resolution, Report())
    per_rule = {}
    gc.disable()  # as check_wellformed does
    for rule in RULES.values():
        start = time.perf_counter()
        rule.check(ctx)
        per_rule[rule.id] = time.perf_counter() - start
    gc.enable()
    median = statistics.median(times)
    slowest = sorted(per_rule.items(), key=lambda kv: -kv[1])[:6]
    print(f"{args.links} links: front end (parse + resolve) {front_s:.2f} s; every condition: "
          f"median {median:.2f} s, min {min(times):.2f} s over {len(times)} runs "
          f"(target < {TARGET_S:.0f} s); {diagnostics} diagnostics; load average "
          f"{os.getloadavg()[0]:.1f}")
    print(f"one run rule by rule: {sum(per_rule.values()):.2f} s; slowest: "
          + ", ".join(f"{k} {v:.2f} s" for k, v in slowest))
    return 0 if median < TARGET_S else 1


if __name__ == "__main__":
    sys.exit(main())
