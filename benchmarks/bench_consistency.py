"""Consistency benchmark (``cyphy check --consistency``): the marXbot mapping, and mappings of
N operations that all drive the same two motors (C5 compares every pair: N(N-1)/2 pairs).

In-process, after a warm-up. The time of the consistency checks is that of
``api.check(consistency=True)`` minus that of ``api.check()`` on the same files (medians).

Target: the marXbot mapping's checks (C1-C5, 2 operations and 1 input event) take a median
under 100 ms. Exit status 0 when it holds, 1 otherwise.

Run: ``python benchmarks/bench_consistency.py [--sizes 2,4,8,16] [--runs 5]``.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from cyphy import api  # noqa: E402

TARGET_MS = 100.0
ROBOT = ROOT / "tests" / "mappings"


def _median_ms(paths: list[str], consistency: bool, runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        api.check(paths, api.CheckOptions(consistency=consistency))
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def _consistency_ms(paths: list[str], runs: int) -> float:
    return _median_ms(paths, True, runs) - _median_ms(paths, False, runs)


def _operations(folder: Path, n: int) -> Path:
    """A d-model with operations op0 … op{n-1}(v: real) and a mapping that gives each the
    marXbot's differential drive, scaled by its index."""
    for name in ("Robot.rsm",):
        shutil.copy(ROBOT / name, folder / name)
    ops = "\n".join(f"\top{i}(lv: real, av: real)" for i in range(n))
    (folder / "Software.rsm").write_text(
        "package robotSoftware\ninterface DriveI {\n" + ops + "\n}\n"
        "module RobotSoftware {\n\tcycleDef cycle == 1\n"
        "\trobotic platform RobotPlatform { provides DriveI }\n}\n")
    members = "\n".join(
        f"\toperation op{i} {{\n\t\tvar dsl: real, dsr: real\n"
        "\t\tequation Base::LHinge::LMotor.das == dsl\n"
        "\t\tequation Base::RHinge::RMotor.das == dsr\n"
        f"\t\tequation lv == {i + 1}*0.025*(dsl + dsr)/2\n"
        "\t\tequation av == 0.025*(dsl - dsr)/0.12\n\t}" for i in range(n))
    mapping = folder / "Mapping.rsm"
    mapping.write_text("import consistencyRobot::*\nimport robotSoftware::*\n"
                       "map M dmodel RobotSoftware to pmodel Robot {\n" + members + "\n}\n")
    return mapping


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="2,4,8,16")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    marxbot = [str(ROOT / "examples" / "marxbot" / "Mapping.rsm")]
    _median_ms(marxbot, True, 1)  # warm-up: grammar, library, Z3
    ms = _consistency_ms(marxbot, args.runs)
    print(f"marXbot mapping: consistency checks {ms:.1f} ms (target < {TARGET_MS:.0f} ms)")
    for n in (int(s) for s in args.sizes.split(",")):
        with tempfile.TemporaryDirectory() as folder:
            mapping = _operations(Path(folder), n)
            result = api.check([str(mapping)], api.CheckOptions(consistency=True))
            conflicts = sum(1 for d in result.report.diagnostics if d.code.id == "C5")
            print(f"{n:>3} operations: {_consistency_ms([str(mapping)], args.runs):8.1f} ms, "
                  f"{conflicts} C5 warnings ({n * (n - 1) // 2} pairs)")
    return 0 if ms < TARGET_MS else 1


if __name__ == "__main__":
    sys.exit(main())
