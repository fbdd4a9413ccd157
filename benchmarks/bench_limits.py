"""Hostile index ranges: time and peak memory of `cyphy check` (issue 20).

Targets: a link indexed over ``[0, 1000000000)`` is refused (IX1) in under 10 s (the start of a process and the parse included); a link indexed
over ``[0, 100000)`` (10^5 elements, the default --max-copies) checks with a peak resident
memory under 1 GB. Each case runs as its own process, as a user runs it; the peak is that
process's (``ru_maxrss`` of the child).

Run: ``python benchmarks/bench_limits.py``.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MODEL = """package h
pmodel M {{
	local link L {{
		index i : [0, {n})
		pose {{ x = i y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
		def {{ }}
		local body B {{ def {{ box(length = 0.1, width = 0.1, height = 0.1)
			inertial information {{ mass 1.0 }} }} }}
	}}
}}
"""
CASES = ((1_000_000_000, 10.0, None), (100_000, None, 1024.0))


def run(n: int) -> tuple[int, float, float]:
    """Exit status, seconds and peak MB of `cyphy check` on a link indexed over [0, n)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "m.rsm"
        path.write_text(MODEL.format(n=n))
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        start = time.monotonic()
        done = subprocess.run([sys.executable, "-m", "cyphy", "-q", "check", str(path)],
                              capture_output=True, text=True, cwd=ROOT,
                              env={**os.environ, "PYTHONPATH": str(ROOT),
                                   "CYPHY_NO_CACHE": "1"})
        seconds = time.monotonic() - start
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return done.returncode, seconds, max(peak, before) / 1024.0


def main() -> int:
    failed = False
    for n, max_s, max_mb in CASES:
        code, seconds, mb = run(n)
        ok = (max_s is None or seconds <= max_s) and (max_mb is None or mb <= max_mb)
        failed |= not ok
        limits = ", ".join(x for x in (f"< {max_s:g} s" if max_s else "",
                                       f"< {max_mb:g} MB" if max_mb else "") if x)
        print(f"[0, {n}): exit {code}, {seconds:.1f} s, peak {mb:.0f} MB "
              f"(target {limits}) {'ok' if ok else 'MISSED'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
