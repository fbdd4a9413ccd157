"""A ``cyphy reach`` killed with SIGKILL leaves no Flow* running: each run asks the kernel
(Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``) to kill it when its parent goes, since a
killed cyphy cannot kill its runs' process groups as it does on SIGINT and SIGTERM
(``test_newcomer_reach_scratch.py``). Before, Flow* ran on to its end, orphaned."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT, flowstar_binary, needs_flowstar
from test_newcomer_reach_scratch import _alive, _slow_flowstar

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="the parent-death signal is Linux's")


def _children(pid: int) -> dict[int, str]:
    """The processes whose parent is ``pid``, with their command names (``/proc``)."""
    out = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        name, rest = text[text.index("(") + 1:text.rindex(")")], text[text.rindex(")") + 2:]
        if int(rest.split()[1]) == pid:
            out[int(stat.parent.name)] = name
    return out


def _kill_and_wait(cyphy: subprocess.Popen, runs: list[int]) -> list[int]:
    """SIGKILL cyphy; the runs still alive 5 s later."""
    cyphy.kill()
    cyphy.wait(timeout=30)
    deadline = time.monotonic() + 5
    while any(_alive(p) for p in runs) and time.monotonic() < deadline:
        time.sleep(0.05)
    return [p for p in runs if _alive(p)]


def test_killed_reach_takes_its_flowstar_runs_with_it(tmp_path: Path) -> None:
    """Two runs at once (``--split 2 --jobs 2``: in worker threads), a stand-in Flow*
    that waits."""
    binary, pids = _slow_flowstar(tmp_path)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "TMPDIR": str(tmp_path)}
    cyphy = subprocess.Popen(
        [sys.executable, "-m", "cyphy", "reach", str(EXAMPLES / "dcmotor"), "--scenario",
         str(EXAMPLES / "dcmotor" / "sampled_stop.toml"), "--flowstar-bin", str(binary),
         "--split", "2", "--jobs", "2"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    started: dict[int, int] = {}
    try:
        deadline = time.monotonic() + 120
        while len(list(pids.iterdir())) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        started = {int(p.name): int(p.read_text()) for p in pids.iterdir()}
        assert len(started) == 2 and all(_alive(p) for p in started)
        assert set(started) <= set(_children(cyphy.pid))
        assert _kill_and_wait(cyphy, list(started)) == []
    finally:
        if cyphy.poll() is None:
            cyphy.kill()
        for pid in [*started, *started.values()]:  # the stand-in's own child outlives it
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


@needs_flowstar
def test_killed_reach_takes_the_real_flowstar_with_it(tmp_path: Path) -> None:
    """The real Flow* on the motor example with a step of 1e-5 s (minutes of work)."""
    scenario = tmp_path / "long.toml"
    scenario.write_text((EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text()
                        .replace("step = 0.01", "step = 0.00001")
                        .replace("max_jumps = 25", "max_jumps = 40"))
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cyphy = subprocess.Popen(
        [sys.executable, "-m", "cyphy", "reach", str(EXAMPLES / "dcmotor"), "--scenario",
         str(scenario), "--flowstar-bin", str(flowstar_binary()), "--jobs", "1"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    runs: list[int] = []
    try:
        deadline = time.monotonic() + 180  # the simulation search comes first
        while not runs and cyphy.poll() is None and time.monotonic() < deadline:
            runs = [p for p, name in _children(cyphy.pid).items() if name == "flowstar"]
            time.sleep(0.1)
        assert runs, "no Flow* run started"
        time.sleep(0.5)
        assert all(_alive(p) for p in runs)
        assert _kill_and_wait(cyphy, runs) == []
    finally:
        if cyphy.poll() is None:
            cyphy.kill()
        for pid in runs:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
