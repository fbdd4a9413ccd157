"""``cyphy reach`` with the real Flow* on the marXbot scenarios whose verdicts the tests do not
run (each takes about a minute): each must be SAFE within 5 minutes on 2 cores.

- ``examples/marxbot/obstacle_stop.toml`` (the machine ``SStop``),
- ``examples/marxbot/avoid_obstacle_dynamics.toml`` (``SMovement`` with the hinges' dynamics),
- ``examples/marxbot/corpus_smovement.toml`` (RoboTool's marXbot from ``../shared/corpus``
  under its own ``SMovement``, SDF's default inertials; left out when the corpus is absent).

Run: ``python benchmarks/bench_marxbot_reach.py [--only NAME] [--flowstar PATH]``.
Exit status 0 when every verdict is SAFE within the target.
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

MARXBOT = ROOT / "examples" / "marxbot"
CORPUS = ROOT.parent / "shared" / "corpus" / "pmodel-examples" / "marXbot"
TARGET = 300.0  # seconds, the whole command
CASES = {"obstacle_stop": MARXBOT, "avoid_obstacle_dynamics": MARXBOT,
         "corpus_smovement": CORPUS}


def main() -> int:
    from conftest import flowstar_binary

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=sorted(CASES))
    parser.add_argument("--flowstar", default=None)
    args = parser.parse_args()
    binary = args.flowstar or (str(flowstar_binary()) if flowstar_binary() else None)
    if binary is None:
        print("no Flow* binary: build it with .ci/install or give --flowstar")
        return 2
    ok = True
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    with tempfile.TemporaryDirectory() as tmp:
        for name, models in CASES.items():
            if args.only not in (None, name):
                continue
            if not models.is_dir():
                print(f"{name}: skipped ({models} is absent)")
                continue
            started = time.perf_counter()
            done = subprocess.run(
                [sys.executable, "-m", "cyphy", "reach", str(models), "--scenario",
                 str(MARXBOT / f"{name}.toml"), "-o", str(Path(tmp) / name), "-q",
                 "--flowstar-bin", binary], capture_output=True, text=True, env=env,
                check=False)
            elapsed = time.perf_counter() - started
            line = (done.stdout or done.stderr or "\n").splitlines()[0]
            ok = ok and line.startswith("SAFE") and elapsed <= TARGET
            print(f"{name}: {elapsed:6.1f} s (target {TARGET:g} s)   {line[:120]}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
