"""Well-formedness benchmark: every condition on the synthetic 10,000-link model.

Target (issue 4): all checks in under 3 s, measured as the time of ``cyphy check`` with the
conditions minus the time without them (parsing and name resolution are the front end's).
Run: ``python benchmarks/bench_wellformed.py [N]``.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from cyphy import api  # noqa: E402
from synthetic import chain_model, write_model  # noqa: E402

TARGET_S = 3.0


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    with tempfile.TemporaryDirectory() as tmp:
        path = write_model(Path(tmp), chain_model(n))
        api.check([path])  # warm-up (grammar, library)
        start = time.perf_counter()
        front = api.check([path], api.CheckOptions(wellformedness=False))
        front_s = time.perf_counter() - start
        start = time.perf_counter()
        full = api.check([path])
        full_s = time.perf_counter() - start
    rules = full_s - front_s
    print(f"{n} links: front end {front_s:.2f} s, with every condition {full_s:.2f} s, "
          f"conditions alone {rules:.2f} s (target < {TARGET_S:.0f} s); "
          f"{len(full.report.diagnostics)} diagnostics")
    assert not front.report.has_errors
    return 0 if rules < TARGET_S else 1


if __name__ == "__main__":
    sys.exit(main())
