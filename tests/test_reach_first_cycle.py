"""``reach`` and ``gen --flowstar`` for a machine whose first cycle reads its input events (no
``exec`` before the first read): the held-out rover with one ``exec`` taken out (``from
Ahead to Turn condition $near``), so its drive machine enters ``Ahead`` and, when something
is already near at time 0, turns in the same cycle. Before, reach refused it ("the first
cycle of SDrive depends on its inputs").

The verdicts are known by reasoning, and each agrees with ``simulate``'s trajectory (the
machine's interpreter, not the automaton): the obstacle approaches at 1 m/s, so ``near``
(range <= 0.5) holds from the start for 0.3 m and never within 1 s for 5 m. Near from the
start, the right wheel is demanded -spin (-4 rad/s) from time 0 and turns backwards at once;
otherwise +cruise (8 rad/s), which it passes 1 rad/s towards within 0.06 s. So ``RMotor_av
>= 1`` is unsafe exactly when the rover may start ahead, ``RMotor_av <= -1`` when it may
start turning. Were the first cycle's calls taken at the end of the first cycle (as the
automaton did for a first cycle that reads nothing), the near rover would cruise for 0.1 s
and pass 1 rad/s (1.43 at 0.1 s): its SAFE shows the turn acts from time 0.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest

from conftest import flowstar_binary, needs_flowstar
from test_dmodel_first_cycle import _rover
from cyphy.cli import main


def _scenario(tmp_path: Path, distance: str, unsafe: str) -> tuple[Path, Path]:
    """The rover (first cycle reading ``near``) and its scenario over 1 s with the obstacle
    starting ``distance`` away (a number or an interval) and the unsafe set ``unsafe``."""
    folder, scenario = _rover(tmp_path / "rover", distance)  # type: ignore[arg-type]
    text = scenario.read_text().replace("horizon = 2.0", "horizon = 1.0")
    scenario.write_text(text.replace('"Pan_av >= 1.5"', f'"{unsafe}"'))
    return folder, scenario


def _simulated(folder: Path, scenario: Path, distance: float) -> dict[str, np.ndarray]:
    """``simulate`` over 1 s (the interpreter runs the machine) from ``distance``."""
    text = re.sub(r"\nRange_distance = [^\n]*\n", f"\nRange_distance = {distance}\n",
                  scenario.read_text(), count=1)
    point = scenario.with_name("point.toml")
    point.write_text(text)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["simulate", str(folder), "--scenario", str(point), "--t-end", "1",
                     "--samples", "201", "--format", "json", "-q"]) == 0
    doc = json.loads(out.getvalue())
    return {k: np.array(v) for k, v in doc["columns"].items()}


def _reach(folder: Path, scenario: Path, capsys: pytest.CaptureFixture[str],
           out_dir: Path) -> tuple[int, str]:
    capsys.readouterr()
    code = main(["reach", str(folder), "--scenario", str(scenario), "--jobs", "1",
                 "--timeout", "240", "-o", str(out_dir)])
    return code, capsys.readouterr().out


@pytest.mark.parametrize("distance, unsafe, verdict, mode", [
    ("0.3", "RMotor_av >= 1", "SAFE", "Turn_Left"),
    ("0.3", "RMotor_av <= -1", "UNSAFE", "Turn_Left"),
    ("5.0", "RMotor_av >= 1", "UNSAFE", "Ahead_Left"),
    ("5.0", "RMotor_av <= -1", "SAFE", "Ahead_Left"),
])
@needs_flowstar
def test_a_point_start_is_decided_exactly(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                          distance: str, unsafe: str, verdict: str,
                                          mode: str) -> None:
    folder, scenario = _scenario(tmp_path, distance, unsafe)
    # simulate's trajectory agrees with the verdict reasoned above
    right = _simulated(folder, scenario, float(distance))["RMotor_av"]
    near = float(distance) <= 0.5
    assert (right[1:].max() < 0 < -right[1:].min()) if near else \
        (right[1:].min() > 0 and right.max() > 5)
    crossed = bool(np.any(right >= 1) if ">=" in unsafe else np.any(right <= -1))
    assert crossed == (verdict == "UNSAFE")

    code, out = _reach(folder, scenario, capsys, tmp_path / "out")
    assert (code, out.split(":")[0]) == ({"SAFE": 0, "UNSAFE": 1}[verdict], verdict), out
    assert f"the first cycle reads near at the initial state: on the initial set it ends " \
        f"in {mode} (exact)" in out
    model = (tmp_path / "out" / "bump.model").read_text()
    assert f" init\n {{\n  {mode}\n" in model and "cyphy_first_cycle" not in model
    if verdict == "UNSAFE":  # the witness starts in that mode, at time 0
        assert re.search(rf"t = 0 +start +{mode} ", out), out


@needs_flowstar
def test_an_interval_start_over_both_modes_is_proved_with_a_start_mode(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """From [0.3, 0.7] the first cycle may turn (<= 0.5) or go ahead: the automaton starts
    in a mode of its own that jumps at time 0 to each. The wheel stays below 12 rad/s
    either way: the demand is at most +8 (cruise) and the PI motor's step response
    overshoots by 29% at most (-5.2 for -4 from rest), so below 10.4; simulate's peak is
    8.0 (from 0.7 m, which turns at 0.3 s)."""
    folder, scenario = _scenario(tmp_path, "[0.3, 0.7]", "RMotor_av >= 12")
    for d in (0.3, 0.5, 0.51, 0.7):
        assert _simulated(folder, scenario, d)["RMotor_av"].max() < 12
    code, out = _reach(folder, scenario, capsys, tmp_path / "out")
    assert (code, out.split(":")[0]) == (0, "SAFE"), out
    assert "the first cycle reads near, which the initial set does not decide: the " \
        "automaton starts in each of Ahead_Left, Turn_Left where its guard may hold at time " \
        "0 (an over-approximation of the first cycle)" in out
    model = (tmp_path / "out" / "bump.model").read_text()
    assert " init\n {\n  cyphy_first_cycle\n" in model
    assert "cyphy_first_cycle -> Ahead_Left\n  guard { timer = 0  Range_distance >= 0.5 }" \
        in model
    assert "cyphy_first_cycle -> Turn_Left\n  guard { timer = 0  Range_distance <= 0.5 }" \
        in model
    # Flow* took both jumps: the 100 steps of 1 s along each start, and the branches the
    # later samples of near open (a SAFE without the jumps would be one flowpipe); the run
    # is the part of the automaton the wheel needs, as reach ran it
    binary = flowstar_binary()
    assert binary is not None
    run_model = (tmp_path / "out" / "runs" / "bump.001.model").read_text()
    assert " init\n {\n  cyphy_first_cycle\n" in run_model
    with tempfile.TemporaryDirectory() as scratch:
        run = subprocess.run([str(binary)], input=run_model.encode(), capture_output=True,
                             cwd=scratch, timeout=240)
    found = re.search(rb"Computation completed: (\d+) flowpipe", run.stdout)
    assert found and int(found.group(1)) > 1 + 2 * 100, run.stdout[-500:]


@needs_flowstar
def test_an_interval_start_finds_the_witness_on_the_side_that_goes_ahead(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder, scenario = _scenario(tmp_path, "[0.3, 0.7]", "RMotor_av >= 1")
    assert _simulated(folder, scenario, 0.7)["RMotor_av"].max() > 1
    assert _simulated(folder, scenario, 0.3)["RMotor_av"].max() < 1
    code, out = _reach(folder, scenario, capsys, tmp_path / "out")
    assert (code, out.split(":")[0]) == (1, "UNSAFE"), out
    start = re.search(r"t = 0 +start +cyphy_first_cycle .*Range_distance = ([0-9.]+)", out)
    jump = re.search(r"t = 0 +jump +(\w+) ", out)
    assert start and jump and jump.group(1) == "Ahead_Left", out
    assert float(start.group(1)) > 0.5  # a start the first cycle takes ahead


@pytest.mark.parametrize("distance, start", [
    ("0.5", "Turn_Left"),  # on the boundary: near holds (range <= 0.5), as simulate reads it
    ("[0.3, 0.45]", "Turn_Left"),
    ("[0.55, 0.7]", "Ahead_Left"),
    ("[0.3, 0.7]", "cyphy_first_cycle"),
])
def test_gen_flowstar_starts_where_the_initial_set_decides(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], distance: str, start: str) -> None:
    folder, scenario = _scenario(tmp_path, distance, "RMotor_av >= 12")
    assert main(["gen", str(folder), "--flowstar", "--scenario", str(scenario), "-o",
                 str(tmp_path / "gen"), "-q"]) == 0
    model = (tmp_path / "gen" / "bump.model").read_text()
    assert f" init\n {{\n  {start}\n" in model
    assert ("cyphy_first_cycle" in model) == (start == "cyphy_first_cycle")


@pytest.mark.parametrize("low, high, starts", [
    (-2.0, -1.5, ["B"]),  # x^2 <= 1 nowhere: the first cycle goes to B (exact)
    (-0.5, 0.5, ["A"]),  # everywhere: A (exact)
    (-1.2, 0.0, ["A", "B"]),  # both: the start mode
    (1.0, 1.0, ["A"]),  # a point on the boundary: it holds (<=), as simulate reads it
    (1.0000001, 3.0, ["B"]),  # just past the boundary: interval arithmetic excludes A
])
def test_the_first_cycle_is_decided_on_the_box(low: float, high: float,
                                               starts: list[str]) -> None:
    """``settle`` on a problem whose first cycle reads ``e`` (``x^2 <= 1``): to A when it
    holds, to B otherwise. The oracle: the predicate on 10001 points of the box, and the
    bounds worked out by hand where sampling cannot tell (a boundary point)."""
    import sympy

    from cyphy.diagnostics import Span
    from cyphy.verify.flowstar.first_cycle import settle, start_modes
    from cyphy.verify.flowstar.problem import Problem
    from cyphy.verify.flowstar.scenario import Scenario, Transition

    x = sympy.Symbol("x", real=True)
    span = Span("s.toml", 1, 1, 1, 2)
    scenario = Scenario("s.toml", "", 1.0, 0.1, init={"x": (low, high)}, initial="B",
                        states={"A": (), "B": ()},
                        first=[Transition("", "A", "e", False, span),
                               Transition("", "B", "e", True, span)])
    p = Problem("P", scenario, ["x"], {"x": sympy.Integer(0)}, [], {},
                {"A": {}, "B": {}}, {"e": x ** 2 <= 1}, x >= 5)
    settled = settle(p)
    assert start_modes(settled) == starts
    assert bool(settled.scenario.first) == (len(starts) > 1)
    assert settled.first_events == ("e",)
    sampled = {"A" if v * v <= 1 else "B" for v in np.linspace(low, high, 10001)}
    assert sampled <= set(starts)  # never a mode left out that a start reaches
    if low < high:
        assert sampled == set(starts)


def test_the_start_mode_needs_one_more_jump(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    """1 s of 0.1 s cycles: 10 cycles and one more jump (spec §5), and one at time 0 out of
    the start mode when the box does not decide the first cycle."""
    folder, scenario = _scenario(tmp_path, "[0.3, 0.7]", "RMotor_av >= 12")
    scenario.write_text(scenario.read_text().replace("max_jumps = 40", "max_jumps = 11"))
    capsys.readouterr()
    assert main(["gen", str(folder), "--flowstar", "--scenario", str(scenario), "-o",
                 str(tmp_path / "gen")]) == 1
    assert "max_jumps = 11 is too small: the horizon of 1 s is 10 cycles of 0.1 s (cycle × " \
        "tscale), with a jump at time 0 out of the first cycle, so Flow* needs at least 12 " \
        "jumps" in capsys.readouterr().err
    scenario.write_text(scenario.read_text().replace("max_jumps = 11", "max_jumps = 12"))
    assert main(["gen", str(folder), "--flowstar", "--scenario", str(scenario), "-o",
                 str(tmp_path / "gen"), "-q"]) == 0
    assert "max jumps 12" in (tmp_path / "gen" / "bump.model").read_text()


def test_a_first_cycle_event_over_an_actuator_input_cannot_be_decided() -> None:
    """An event whose predicate (through the outputs it reads) depends on an actuator
    input: nothing sets the input before the first cycle's calls, so ``reach`` refuses the
    machine rather than pick a value; an event over states only is decidable."""
    import sympy

    from cyphy.diagnostics import Span
    from cyphy.verify.flowstar.first_cycle import unreadable
    from cyphy.verify.flowstar.problem import Problem
    from cyphy.verify.flowstar.scenario import Scenario, Transition

    x, u = sympy.Symbol("x", real=True), sympy.Symbol("u", real=True)
    span = Span("s.toml", 1, 1, 1, 2)
    first = [Transition("", "A", "e", False, span), Transition("", "B", "e", True, span)]
    scenario = Scenario("s.toml", "", 1.0, 0.1, init={"x": (0.0, 0.0)}, initial="B",
                        states={"A": (), "B": ()}, first=first)
    p = Problem("P", scenario, ["x"], {"x": u - x}, ["u"], {}, {"A": {"u": 1}, "B": {"u": 2}},
                {"e": x + 2 * u <= 1, "f": x <= 1}, x >= 5)
    assert unreadable(p) == ("e", ["u"])
    first[0] = Transition("", "A", "f", False, span)
    first[1] = Transition("", "B", "f", True, span)
    assert unreadable(p) is None
