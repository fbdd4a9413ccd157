"""``cyphy reach`` with the real Flow*: verdict time against the horizon (issue 28).

Two controllers of the motor bench of ``examples/dcmotor`` (property: the motor never
reaches 20 rad/s; SAFE):

- **final**: the example's machine, whose Stopped state no transition leaves: once
  stopped, the mode flows to the horizon without jumps;
- **periodic**: a two-state controller (cruise ↔ coast on the range finder's event) whose
  obstacle never comes near, so the automaton jumps at every cycle to the horizon.

Each case times the whole ``cyphy reach`` process (falsification search, Flow* runs, the
verdict). A case that takes longer than ``--timeout`` seconds is reported as such.
The cost against the number of independent motors is ``bench_reach.py --sizes 1,2,4,8``.

Run: ``python benchmarks/bench_reach_horizon.py [--horizons 1,2,4,8,16] [--flowstar PATH]``.
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
sys.path.insert(0, str(ROOT / "tests"))
from flowstar_scenarios import CRUISE_COAST, sampled_stop  # noqa: E402

EXAMPLE = ROOT / "examples" / "dcmotor"


def scenario(kind: str, horizon: float, folder: Path) -> Path:
    """The example's scenario with the horizon (and, periodic, the controller) changed."""
    edits = [("horizon = 2.0", f"horizon = {horizon}")]
    if kind == "periodic":
        edits += [('Range_distance = "-2"', 'Range_distance = "0"'),
                  ("[unsafe]", CRUISE_COAST.strip() + "\n\n[unsafe]")]
    return sampled_stop(folder, f"{kind}_{horizon:g}", *edits)


def reach_time(path: Path, binary: str, out: Path, timeout: float) -> tuple[float, str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    started = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "cyphy", "reach", str(EXAMPLE),
                               "--scenario", str(path), "-o", str(out), "--flowstar-bin",
                               binary], capture_output=True, text=True, env=env,
                              check=False, timeout=timeout)
    except subprocess.TimeoutExpired:
        return time.perf_counter() - started, f"(no verdict within {timeout:g} s)"
    text = done.stdout or done.stderr
    line = text.splitlines()[0] if text else ""
    scope = " (for every horizon)" if "for every horizon" in line else \
        " (up to the horizon)" if line.startswith("SAFE") else ""
    return time.perf_counter() - started, line.split(":")[0] + scope


def main() -> int:
    from conftest import flowstar_binary

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--horizons", default="1,2,4,8,16")
    parser.add_argument("--kinds", default="final,periodic")
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--flowstar", default=None)
    args = parser.parse_args()
    binary = args.flowstar or (str(flowstar_binary()) if flowstar_binary() else None)
    if binary is None:
        print("no Flow* binary: build it with .ci/install or give --flowstar")
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        for kind in args.kinds.split(","):
            for h in (float(x) for x in args.horizons.split(",")):
                path = scenario(kind, h, Path(tmp))
                seconds, line = reach_time(path, binary, Path(tmp) / "out", args.timeout)
                print(f"{kind:<9} horizon {h:>4g} s: {seconds:7.1f} s  {line}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
