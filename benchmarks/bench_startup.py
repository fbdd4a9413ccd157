"""Start-up budget: the processor time of whole ``cyphy`` processes (user + system of the child,
interpreter start and imports included), median of 7 runs, against the budget of issue 24.

    python3 benchmarks/bench_startup.py [--runs N] [--root TREE]

Runs the code of this source tree (``python3 -m cyphy`` with the tree on ``PYTHONPATH``), not
an installed copy. Bytecode is cached in a temporary folder (``PYTHONPYCACHEPREFIX``) and each
command runs once unmeasured first, as an installed copy has its ``.pyc`` files: with
``PYTHONDONTWRITEBYTECODE`` set, every run would compile cyphy's modules again (a third of
``check``'s time on the machine measured). Exit status 1 when a median is over its budget.
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


def processor_time(args: tuple[str, ...], out: Path, pycache: Path, root: Path = ROOT) -> float:
    """One run's user + system time, in seconds; generators write into ``out``, bytecode
    goes to ``pycache``."""
    argv = list(args) + (["-o", str(out)] if args[0] == "gen" else [])
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONPYCACHEPREFIX=str(pycache))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "cyphy", *argv], cwd=ROOT, env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--root", type=Path, default=ROOT,
                        help="the source tree whose code runs (default: this one), e.g. a "
                        "worktree of main to compare; the examples are this tree's")
    options = parser.parse_args()
    runs, root = options.runs, options.root.resolve()
    print(f"{root}: load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    over = 0
    with tempfile.TemporaryDirectory() as tmp:
        out, pycache = Path(tmp) / "out", Path(tmp) / "pycache"
        out.mkdir()
        for args, budget in COMMANDS:
            processor_time(args, out, pycache, root)  # warm-up: writes the bytecode
            times = [processor_time(args, out, pycache, root) for _ in range(runs)]
            median = statistics.median(times)
            verdict = "ok" if median <= budget else "OVER"
            over += median > budget
            print(f"cyphy {' '.join(args):<38} median {median:.3f} s  budget {budget:.2f} s  "
                  f"{verdict}  (min {min(times):.3f}, max {max(times):.3f})")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
