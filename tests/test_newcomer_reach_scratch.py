"""The newcomer's path (issue 29): `reach` runs Flow* in process groups of its own, kills
them on SIGINT or SIGTERM, removes its scratch, and writes its model into a temporary folder
(kept with --keep), never beside the inputs. A stand-in Flow* (a script) shows what happens
to the processes: it starts a child and sleeps, as Flow* runs long and may start gnuplot."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT, sigint_as_at_a_terminal

SAFE = ("Computation completed: 3 flowpipe(s) computed.\n"
        "Result of the safety verification on the computed flowpipes: SAFE\n")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # a zombie is dead: its parent (cyphy, gone) no longer reaps it, init will
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.exists() and stat.read_text().split(") ")[1].startswith("Z"))


def _ours(tmp: Path) -> list[Path]:
    """cyphy's scratch in the temporary folder (lark keeps a grammar cache there too)."""
    return [p for p in tmp.iterdir() if p.name.startswith("cyphy-")]


def _slow_flowstar(tmp_path: Path) -> tuple[Path, Path]:
    """A Flow* that records its pid and its child's (a `sleep 300`) in ``pids/`` and waits."""
    pids = tmp_path / "pids"
    pids.mkdir()
    script = tmp_path / "flowstar"
    script.write_text(f"#!{sys.executable}\nimport os, subprocess, sys, time\n"
                      "sys.stdin.read()\n"
                      "child = subprocess.Popen(['sleep', '300'])\n"
                      f"open(os.path.join({str(pids)!r}, str(os.getpid())), 'w')"
                      ".write(str(child.pid))\n"
                      "time.sleep(300)\n")
    script.chmod(0o755)
    return script, pids


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupt_kills_every_flowstar_and_removes_the_scratch(signum: int,
                                                                   tmp_path: Path) -> None:
    binary, pids = _slow_flowstar(tmp_path)
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "TMPDIR": str(scratch)}
    # --split 2 --jobs 2: two Flow* runs at once, in worker threads
    cyphy = subprocess.Popen(
        [sys.executable, "-m", "cyphy", "reach", str(EXAMPLES / "dcmotor"), "--scenario",
         str(EXAMPLES / "dcmotor" / "sampled_stop.toml"), "--flowstar-bin", str(binary),
         "--split", "2", "--jobs", "2"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
        preexec_fn=sigint_as_at_a_terminal)
    try:
        deadline = time.monotonic() + 120
        while len(list(pids.iterdir())) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        started = {int(p.name): int(p.read_text()) for p in pids.iterdir()}
        assert len(started) == 2, cyphy.stderr.read() if cyphy.poll() is not None else ""
        assert all(_alive(p) for p in [*started, *started.values()])
        cyphy.send_signal(signum)
        code = cyphy.wait(timeout=30)
    finally:
        if cyphy.poll() is None:
            cyphy.kill()
    assert code == 128 + signum
    deadline = time.monotonic() + 10
    while any(_alive(p) for p in [*started, *started.values()]) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [p for p in [*started, *started.values()] if _alive(p)]
    assert not _ours(scratch)  # the runs' scratch folders and the model's: removed
    time.sleep(1)
    assert len(list(pids.iterdir())) == 2  # no run started after the interrupt


def _fast_flowstar(tmp_path: Path) -> Path:
    script = tmp_path / "flowstar"
    script.write_text(f"#!/bin/sh\ncat >/dev/null\nprintf '{SAFE}'\n")
    script.chmod(0o755)
    return script


def test_reach_writes_nothing_beside_its_inputs(tmp_path: Path) -> None:
    models = tmp_path / "dcmotor"
    shutil.copytree(EXAMPLES / "dcmotor", models)
    before = sorted(p.name for p in models.iterdir())
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "TMPDIR": str(scratch)}
    argv = [sys.executable, "-m", "cyphy", "reach", str(models), "--scenario",
            str(models / "sampled_stop.toml"), "--flowstar-bin", str(_fast_flowstar(tmp_path))]
    done = subprocess.run(argv, capture_output=True, text=True, env=env, cwd=models,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("SAFE:") and "model" not in done.stdout.splitlines()[0]
    assert sorted(p.name for p in models.iterdir()) == before
    assert not _ours(scratch)
    # --keep keeps the temporary folder and says where it is
    done = subprocess.run(argv + ["--keep"], capture_output=True, text=True, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    (kept,) = _ours(scratch)
    assert f"; model {kept / 'sampled_stop.model'})" in done.stdout.splitlines()[0]
    assert "hybrid reachability" in (kept / "sampled_stop.model").read_text()
    assert sorted(p.name for p in models.iterdir()) == before
