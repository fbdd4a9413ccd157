"""Start-up budget: the processor time of whole ``cyphy`` processes (user + system of the child,
interpreter start and imports included) against the budget of issue 24, with an empty cache
and a warm one.

    python3 benchmarks/bench_startup.py [--runs N] [--cold-runs N] [--root TREE]

Runs the code of this source tree (``python3 -P -m cyphy`` with the tree on ``PYTHONPATH``,
``-P`` so that the current folder does not come first), not an installed copy. Bytecode is
cached in a temporary folder (``PYTHONPYCACHEPREFIX``) and each command runs once unmeasured
first, as an installed copy has its ``.pyc`` files: with ``PYTHONDONTWRITEBYTECODE`` set,
every run would compile cyphy's modules again (a third of ``check``'s time on the machine
measured).

cyphy keeps parsed files, derived equations of motion and compiled templates in a cache
(``CYPHY_CACHE_DIR``, docs/commands/index.md): each command is measured first with an empty
cache (``--cold-runs`` runs, each in a fresh folder: what a first run after installing or
changing cyphy costs), then warm (``--runs`` runs, median, the cache filled by the first
ones: every later run). The budget applies to the warm median; exit status 1 when one is
over.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: (arguments, budget in seconds of processor time).
COMMANDS: tuple[tuple[tuple[str, ...], float], ...] = (
    (("--help",), 0.15),
    (("check", "examples/marxbot"), 0.25),
    (("gen", "examples/marxbot", "--isabelle"), 0.30),
    (("gen", "examples/marxbot", "--sdf"), 0.25),
)


def processor_time(args: tuple[str, ...], out: Path, pycache: Path, cache: Path,
                   root: Path = ROOT) -> float:
    """One run's user + system time, in seconds; generators write into ``out``, bytecode
    goes to ``pycache``, cyphy's cache to ``cache``."""
    argv = list(args) + (["-o", str(out)] if args[0] == "gen" else [])
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONPYCACHEPREFIX=str(pycache),
               CYPHY_CACHE_DIR=str(cache))
    for name in ("PYTHONDONTWRITEBYTECODE", "CYPHY_NO_CACHE"):
        env.pop(name, None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-P", "-m", "cyphy", *argv], cwd=ROOT, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="warm runs (default 7)")
    parser.add_argument("--cold-runs", type=int, default=3,
                        help="runs with an empty cache, each in a fresh folder (default 3)")
    parser.add_argument("--root", type=Path, default=ROOT,
                        help="the source tree whose code runs (default: this one), e.g. a "
                        "worktree of main to compare; the examples are this tree's")
    options = parser.parse_args()
    runs, root = options.runs, options.root.resolve()
    if runs < 1 or options.cold_runs < 1:
        parser.error("--runs and --cold-runs take at least 1")
    print(f"{root}: load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}; processor "
          "time of whole processes: empty cache median (min-max) of "
          f"{options.cold_runs}, warm median (min-max) of {runs}")
    over = 0
    with tempfile.TemporaryDirectory() as tmp:
        out, pycache = Path(tmp) / "out", Path(tmp) / "pycache"
        out.mkdir()
        for k, (args, budget) in enumerate(COMMANDS):
            # warm-up: writes the bytecode (its cache folder is not used again)
            processor_time(args, out, pycache, Path(tmp) / f"warm-up-{k}", root)
            cold = []
            for i in range(options.cold_runs):
                cache = Path(tmp) / f"cache-{k}-{i}"  # empty: a fresh folder each time
                cold.append(processor_time(args, out, pycache, cache, root))
            times = [processor_time(args, out, pycache, cache, root) for _ in range(runs)]
            median = statistics.median(times)
            verdict = "ok" if median <= budget else "OVER"
            over += median > budget
            print(f"cyphy {' '.join(args):<34} empty cache {statistics.median(cold):.3f} s "
                  f"({min(cold):.3f}-{max(cold):.3f})  warm {median:.3f} s "
                  f"({min(times):.3f}-{max(times):.3f})  budget {budget:.2f} s {verdict}")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
