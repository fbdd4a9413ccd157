"""Elaboration benchmark: the marXbot base module, and synthetic chains of 10 … 10000 links.

In-process, after a warm-up (grammar tables, the library parse and lazy imports are per
process). The check (parse, resolve, well-formedness: ``api.check``) and the elaboration are
timed separately: the files are checked once, then the elaboration of the checked workspace
(``cyphy.model.elaborate.elaborate``) is timed alone. If that function is not available, the
whole ``api.elaborate`` and ``api.check`` alone are timed and subtracted.

Targets:
* marXbot base module (``marXbotBase``): elaboration, excluding parsing, median < 10 ms;
* scaling: elaboration time(10000 links) / time(1000 links) ≤ 12 (near linear).

Uses the corpus marXbot folder when ../shared/corpus is present, our own examples/marxbot
otherwise. Exit status 0 when both targets hold, 1 otherwise.

Run: ``python benchmarks/bench_elaborate.py [--sizes 10,100,1000,10000] [--runs 30]``.
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from cyphy import api  # noqa: E402
from cyphy.diagnostics import Report  # noqa: E402
from synthetic import chain_model, write_model  # noqa: E402

MARXBOT_TARGET_MS = 10.0
SCALING_TARGET = 12.0
MARXBOT_MODEL = "marXbotBase"


def _elaborate_checked() -> Callable | None:  # type: ignore[type-arg]
    try:
        from cyphy.model.elaborate import elaborate
    except ImportError:
        return None
    return elaborate


def _ms(seconds: float) -> float:
    return seconds * 1000.0


def _timed(fn: Callable[[], object]) -> tuple[float, object]:
    gc.collect()  # start every run from the same heap state (the collector stays enabled)
    start = time.perf_counter()
    value = fn()
    return _ms(time.perf_counter() - start), value


class Bench:
    """Times check and elaboration of one set of files."""

    def __init__(self, files: list[Path], model: str | None) -> None:
        self.files = files
        self.model = model
        self.run = _elaborate_checked()
        self.method = "check once, then elaborate the checked workspace" if self.run else \
            "api.elaborate − api.check"

    def check(self) -> tuple[float, api.CheckResult]:
        ms, result = _timed(lambda: api.check(self.files))
        return ms, result  # type: ignore[return-value]

    def elaborate(self, checked: api.CheckResult) -> tuple[float, object]:
        if self.run is not None:
            assert checked.resolution is not None
            return _timed(lambda: self.run(checked.workspace, checked.resolution, Report(),
                                           self.model, {}))
        whole, result = _timed(lambda: api.elaborate(
            self.files, api.ElaborateOptions(model=self.model)))
        check_ms, _ = self.check()
        return max(whole - check_ms, 0.0), result.model  # type: ignore[attr-defined]


def _errors(checked: api.CheckResult) -> list[str]:
    return [f"{d.code.id}: {d.message}" for d in checked.report.diagnostics
            if d.severity.name == "ERROR"]


def bench_marxbot(runs: int) -> tuple[float, list[str]]:
    corpus = ROOT.parent / "shared" / "corpus" / "pmodel-examples" / "marXbot"
    folder = corpus if corpus.is_dir() else ROOT / "examples" / "marxbot"
    files = sorted(p for p in folder.iterdir() if p.suffix in (".pm", ".rst", ".rsm"))
    bench = Bench(files, MARXBOT_MODEL)
    check_ms, checked = bench.check()  # warm-up
    _, model = bench.elaborate(checked)  # warm-up
    check_times = [bench.check()[0] for _ in range(max(3, runs // 10))]
    checked = bench.check()[1]
    times = [bench.elaborate(checked)[0] for _ in range(runs)]
    _, model = bench.elaborate(checked)
    median = statistics.median(times)
    counts = _counts(model)
    errors = _errors(checked)
    note = f"; {len(errors)} check errors ({errors[0]}, …)" if errors else ""
    lines = [
        f"marXbot base module ({MARXBOT_MODEL} from {folder}; {bench.method})",
        f"  check (parse, resolve, well-formedness): median {statistics.median(check_times):8.1f}"
        f" ms over {len(check_times)} runs{note}",
        f"  elaboration:                              median {median:8.2f} ms, min "
        f"{min(times):.2f} ms over {runs} runs (target < {MARXBOT_TARGET_MS:.0f} ms); {counts}",
    ]
    return median, lines


def _counts(model: object) -> str:
    if model is None:
        return "no model"
    m = model
    return (f"{len(m.links)} links, {len(m.bodies)} bodies, {len(m.joints)} joints, "  # type: ignore[attr-defined]
            f"{len(m.fixed)} fixed, {len(m.sensors)} sensors, "  # type: ignore[attr-defined]
            f"{len(m.actuators)} actuators")  # type: ignore[attr-defined]


def bench_chains(sizes: list[int]) -> tuple[dict[int, float], list[str]]:
    elaboration: dict[int, float] = {}
    lines = ["synthetic chains (benchmarks/synthetic.py chain_model)",
             f"  {'N':>6} {'runs':>5} {'check ms':>12} {'elaborate ms':>13} {'ms/link':>9}  "
             "elements"]
    with tempfile.TemporaryDirectory(prefix="cyphy-bench-") as tmp:
        warm = Bench([write_model(Path(tmp) / "warm", chain_model(3))], None)
        warm.elaborate(warm.check()[1])
        for n in sizes:
            bench = Bench([write_model(Path(tmp) / f"chain{n}", chain_model(n))], None)
            runs = 5 if n <= 100 else 3  # medians: one run of a large model is noisy
            check_ms, checked = bench.check()  # checking once is enough: it is not measured
            check_times, elab_times = [check_ms], []
            errors = _errors(checked)
            model = None
            for _ in range(runs):
                elab_ms, model = bench.elaborate(checked)
                elab_times.append(elab_ms)
            elab = statistics.median(elab_times)
            elaboration[n] = elab
            lines.append(f"  {n:>6} {runs:>5} {statistics.median(check_times):>12.1f} "
                         f"{elab:>13.1f} {elab / n:>9.3f}  {_counts(model)}"
                         + (f"; {len(errors)} check errors" if errors else ""))
            print(lines[-1], file=sys.stderr, flush=True)  # progress: large sizes take long
    return elaboration, lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="10,100,1000,10000",
                        help="comma-separated chain lengths (default 10,100,1000,10000)")
    parser.add_argument("--runs", type=int, default=30, help="marXbot elaboration runs")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s]

    marxbot_ms, lines = bench_marxbot(args.runs)
    print("\n".join(lines), flush=True)
    chains, chain_lines = bench_chains(sizes)
    print("\n".join(chain_lines))

    ok_marxbot = marxbot_ms < MARXBOT_TARGET_MS
    print(f"target 1: marXbot elaboration {marxbot_ms:.2f} ms < {MARXBOT_TARGET_MS:.0f} ms: "
          f"{'OK' if ok_marxbot else 'FAILED'}")
    if 1000 in chains and 10000 in chains:
        ratio = chains[10000] / chains[1000] if chains[1000] > 0 else float("inf")
        ok_scaling = ratio <= SCALING_TARGET
        print(f"target 2: elaboration time(10000)/time(1000) = {ratio:.1f} ≤ "
              f"{SCALING_TARGET:.0f}: {'OK' if ok_scaling else 'FAILED'}")
    else:
        ok_scaling = False
        print("target 2: not measured (needs sizes 1000 and 10000): FAILED")
    return 0 if ok_marxbot and ok_scaling else 1


if __name__ == "__main__":
    sys.exit(main())
