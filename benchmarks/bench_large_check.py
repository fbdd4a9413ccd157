"""``cyphy check`` on one very large model, as a newcomer meets it (issue 29): a tree of
90,198 links written by :mod:`synthetic`, checked by the command in a process of its own, with
its wall and CPU time and peak memory (the child's maximum resident set size). The issue's
target is 60 s and 1.5 GB (10^9 bytes); the report measured 292 s and 3.6 GB for a 20 MB
model of that many links. Progress lines (``CYPHY_PROGRESS=1``) are timed too: the longest gap
between two says how long the progress line stood still.

The tree is ``tree_model(N, 3, lean=True)`` by default: links with a pose, a mass, a box and a
revolute joint per child, each at a place of its own, 27.5 MB at 90,198 links (larger than
the report's 20 MB). ``--full`` gives every link an IR sensor and every joint a speed-control
motor (56.3 MB), and, as cousins share places there, V5 warns about most links.

Measured on a quiet machine (2026-11-27, 2 cores, load below 1), cold: the default tree
52.3 and 53.8 s (earlier states of the same changes 54.1-57.5 s, once 64.2 s) and 1.37 GiB
(1.47 GB), the progress line still for at most 1.9 s: met, narrowly. ``--full``: 118.6 s and 2.58 GiB (2.77 GB), still for at most 2.3 s. The
history (docs/limits.md): 422 s / 6.10 GiB before the syntax tree was built during the parse,
382 s / 2.37 GiB with lark-cython (shared machine), 143 s / 2.36 GiB (``--full``) and 70 s /
1.35 GiB (the lean tree, then with coincident links) before cyphy's own lexer.

    python3 benchmarks/bench_large_check.py [--links N [N ...]] [--full] [--warm [--repeat K]]
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from synthetic import tree_model, write_model  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, nargs="+", default=[90_198], metavar="N",
                        help="one size, or several: then the growth exponents are fitted")
    parser.add_argument("--warm", action="store_true",
                        help="check a second time, with the parse cache the first run wrote")
    parser.add_argument("--repeat", type=int, default=1, metavar="K",
                        help="with --warm: K warm runs (the machine is shared: one run's time "
                             "says little)")
    parser.add_argument("--full", action="store_true",
                        help="an IR sensor on every link and a motor on every joint: 56.3 MB at"
                             " 90,198 links (by default 27.5 MB: a pose, a mass, a box, a joint)")
    args = parser.parse_args()
    #: kind -> (links, CPU s, peak GiB, wall s), one per run
    measured: dict[str, list[tuple[int, float, float, float]]] = {}
    code = 0
    for links in args.links:
        runs = _size(links, args.warm, args.repeat, not args.full)
        for kind, (_status, seconds, peak, _gap, _last, cpu) in runs:
            measured.setdefault(kind, []).append((links, cpu, peak, seconds))
        code = code or runs[0][1][0]
    if len(args.links) > 1:
        for kind, rows in measured.items():
            print(f"{kind}: CPU time grows as N^{_exponent([(r[0], r[1]) for r in rows]):.2f}, "
                  f"peak memory as N^{_exponent([(r[0], r[2]) for r in rows]):.2f} "
                  f"({min(args.links)}-{max(args.links)} links)")
    links = args.links[-1]
    _, _, peak, seconds = measured["cold"][-1]
    met = links >= 90_198 and seconds <= 60 and peak * 2**30 <= 1.5e9
    print(f"target (90,198 links cold: 60 s, 1.5 GB): {'met' if met else 'NOT met'}")
    return code or (0 if met else 1)


def _size(links: int, warm: bool, repeat: int, lean: bool = True
          ) -> list[tuple[str, tuple[int, float, float, float, str, float]]]:
    """A model of ``links`` links checked cold, then (``warm``) ``repeat`` times warm."""
    with tempfile.TemporaryDirectory(prefix="cyphy-bench-") as folder:
        path = write_model(Path(folder), tree_model(links, 3, lean=lean))
        size = path.stat().st_size
        env = {**os.environ, "PYTHONPATH": str(ROOT), "CYPHY_PROGRESS": "1",
               "CYPHY_CACHE_DIR": str(Path(folder) / "cache")}
        runs = [("cold", _check(path, env))]
        if warm:
            runs.extend(("warm", _check(path, env)) for _ in range(max(repeat, 1)))
    for kind, (code, seconds, peak, gap, last, cpu) in runs:
        print(f"{links} links ({size / 1e6:.1f} MB), {kind}: exit {code}, {seconds:.1f} s "
              f"({cpu:.1f} s of CPU), peak {peak:.2f} GiB ({peak * 2**30 / 1e9:.2f} GB), "
              f"progress still for at most {gap:.1f} "
              f"s; last line: {last}", flush=True)
    return runs


def _exponent(points: list[tuple[int, float]]) -> float:
    """The least-squares slope of log(value) against log(links): the k of value ~ N^k (1 is
    linear). Repeated runs of one size all count."""
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(v) for _, v in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return (sum((x - mx) * (y - my) for x, y in zip(xs, ys))
            / sum((x - mx) ** 2 for x in xs))


def _check(path: Path, env: dict[str, str]) -> tuple[int, float, float, float, str, float]:
    """One ``cyphy check`` in a child process: (exit code, seconds, peak GiB, longest still
    progress in seconds, last line of its output, CPU seconds: on a shared machine the wall
    time varies with the load, the CPU time much less)."""
    started = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "cyphy", "check", str(path)],
                            stderr=subprocess.PIPE, text=True, env=env)
    stamps = [started]
    last = ""
    assert proc.stderr is not None
    for line in proc.stderr:  # one line per stage: when each arrived
        stamps.append(time.perf_counter())
        last = line.rstrip()
    _, status, usage = os.wait4(proc.pid, 0)  # this child's own peak, not all children's
    proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.perf_counter() - started
    stamps.append(time.perf_counter())
    gap = max(b - a for a, b in zip(stamps, stamps[1:]))
    return (proc.returncode, seconds, usage.ru_maxrss / 2**20, gap, last,  # KiB -> GiB
            usage.ru_utime + usage.ru_stime)


if __name__ == "__main__":
    sys.exit(main())
