"""``cyphy reach`` with the real Flow*: N independent motors cost N runs of one motor.

Each case writes the motors of ``motors.py`` (the unsafe set: some motor reaches 20 rad/s,
one disjunct per motor) and times the whole ``cyphy reach`` process (elaboration, reduction,
the Flow* runs in parallel, the verdict). The decomposition gives each disjunct only its own
motor and the range finder, so 8 motors are 8 small runs, not one run whose cost grows with
the square of the dimension (141 s for 8 motors without it).

Target (issue 17): 8 motors in at most 4 × the time of one, on 2 cores. Exit status 0 when it
holds (and every verdict is SAFE).

Run: ``python benchmarks/bench_reach.py [--sizes 1,8] [--flowstar PATH]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))

from motors import write_motors  # noqa: E402


def reach_time(n: int, binary: str, folder: Path) -> tuple[float, str]:
    scenario = write_motors(folder / f"m{n}", n)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "cyphy", "reach", str(folder / f"m{n}"),
                           "--scenario", str(scenario), "-o", str(folder / f"out{n}"),
                           "--flowstar-bin", binary], capture_output=True, text=True,
                          env=env, check=False)
    elapsed = time.perf_counter() - started
    line = (done.stdout or done.stderr).splitlines()[0] if (done.stdout or done.stderr) else ""
    return elapsed, line


def main() -> int:
    from conftest import flowstar_binary

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1,8")
    parser.add_argument("--flowstar", default=None)
    args = parser.parse_args()
    binary = args.flowstar or (str(flowstar_binary()) if flowstar_binary() else None)
    if binary is None:
        print("no Flow* binary: build it with .ci/install or give --flowstar")
        return 2
    sizes = [int(s) for s in args.sizes.split(",")]
    times = {}
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            elapsed, line = reach_time(n, binary, Path(tmp))
            times[n] = elapsed
            ok = ok and line.startswith("SAFE")
            print(f"{n:3d} motor{'s' if n > 1 else ' '}: {elapsed:6.1f} s   {line[:110]}")
    if 1 in times and 8 in times:
        ratio = times[8] / times[1]
        print(f"8 motors / 1 motor: {ratio:.2f} (target <= 4)")
        ok = ok and ratio <= 4
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
