"""The newcomer's path (issue 29): every command-line value is validated before it can be
ignored, crash, or fill a table with NaN. Each case was accepted (exit 0) or crashed (exit 70)
before: now exit 2 with a message naming the option and the value."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT

ENV = {**os.environ, "PYTHONPATH": str(ROOT)}
DC = str(EXAMPLES / "dcmotor")
SIM = ["simulate", DC, "--t-end", "0.2", "--samples", "5"]


def _cyphy(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "cyphy", *args], capture_output=True,
                          text=True, cwd=ROOT, env=ENV, timeout=300)


@pytest.mark.parametrize("argv, message", [
    ([*SIM, "--const", "NoSuchConst=1"], "--const NoSuchConst: the model has no constant"),
    (["show", str(EXAMPLES / "marxbot"), "--const", "Treel::HEIGT=1"],
     "did you mean 'Treel::HEIGHT'?"),
    ([*SIM, "--input", "Motor_av=10"], "--input Motor_av: Motor_av is a state"),
    ([*SIM, "--input", "Motr_das=1"], "did you mean 'Motor_das'?"),
    ([*SIM, "--init", "Motor_das=1"], "Motor_das is an input: give it with --input"),
    ([*SIM, "--init", "Motor_avv=1"], "did you mean 'Motor_av' or"),
    ([*SIM, "--input", "Motor_das=1/0"], "the input value '1/0' is not finite"),
    ([*SIM, "--input", "Motor_das=1/(t-0.05)"], "cannot be evaluated at t = 0.05"),
    ([*SIM, "--input", "Motor_das=log(t)"], "--input Motor_das=log(t)"),
    ([*SIM, "--gravity", "nan,0,0"], "'nan,0,0' is not three finite numbers"),
    (["solve", DC, "--gravity", "0,inf,0"], "is not three finite numbers"),
    ([*SIM, "--init", "Motor_av=inf"], "--init Motor_av=inf: not a finite number"),
    ([*SIM, "--t-end", "inf"], "--t-end: not a finite number"),
    ([*SIM, "--rtol", "nan"], "--rtol: not a finite number"),
    (["simulate", DC, "--samples", "100000000"], "give at most --samples"),
    (["simulate", DC, "--numeric", "--init", "Nope_theta=1"], "not a state of the model"),
    (["view", str(EXAMPLES / "manipulator"), "--set", "Shoulder=nan"], "--set Shoulder=nan"),
    (["view", str(EXAMPLES / "manipulator"), "--set", "Shoulder=1e300"],
     "--set Shoulder=1e300"),
    (["view", str(EXAMPLES / "manipulator"), "--elevation", "nan"], "not a finite number"),
    (["reach", DC, "--scenario", "x.toml", "--timeout", "nan"], "--timeout: not a finite number"),
])
def test_bad_values_exit_2_with_a_message(argv: list[str], message: str, tmp_path: Path
                                          ) -> None:
    if argv[0] == "view":
        argv = [*argv, "-o", str(tmp_path / "v.png")]
    done = _cyphy(*argv)
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert message in done.stderr
    assert "Traceback" not in done.stderr and "internal error" not in done.stderr
    assert "nan" not in done.stdout.lower()  # no table of NaN
    assert not (tmp_path / "v.png").exists()


def test_the_memory_budget_is_refused_before_integrating() -> None:
    """11.6 GB in 2 minutes before: refused at once, with the most samples that fit."""
    import time

    started = time.perf_counter()
    done = _cyphy("simulate", DC, "--samples", "20000000")  # fits one column, not 14
    assert done.returncode == 2 and "give at most --samples" in done.stderr, done.stderr
    assert time.perf_counter() - started < 60


def test_a_correct_const_and_input_still_run() -> None:
    done = _cyphy(*SIM, "--input", "Motor_das=10*sin(t)", "--init", "Motor_av=1")
    assert done.returncode == 0, done.stderr
    rows = [r.split(",") for r in done.stdout.splitlines()]
    assert rows[0][:2] == ["t", "Motor_av"] and float(rows[1][1]) == 1.0


def test_simulate_needs_no_unsafe_set(tmp_path: Path) -> None:
    scenario = tmp_path / "no_unsafe.toml"
    text = (EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text()
    start = text.index("[unsafe]")
    end = text.find("\n[", start + 1)
    scenario.write_text(text[:start] + (text[end + 1:] if end >= 0 else ""))
    assert "[unsafe]" not in scenario.read_text()
    done = _cyphy("simulate", DC, "--scenario", str(scenario), "--samples", "5")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("t,Motor_av")
    # reach checks the unsafe set: it still needs one
    done = _cyphy("reach", DC, "--scenario", str(scenario), "--flowstar-bin", sys.executable)
    assert done.returncode == 2 and "needs an [unsafe] set" in done.stderr
