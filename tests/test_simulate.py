"""`cyphy simulate`: trajectories of the reduced ODEs and of the kinematic tree, checked
against closed forms and independent integrations (not against cyphy's own output)."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import numpy as np
import pytest

from cyphy.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def test_dcmotor_csv_and_plot(tmp_path: Path, capsys) -> None:
    png = tmp_path / "dc.png"
    assert main(["simulate", str(EXAMPLES / "dcmotor"), "--t-end", "3", "--input",
                 "Motor_das=10", "--plot", str(png), "--plot-var", "Motor_av",
                 "--rtol", "1e-9", "--atol", "1e-12"]) == 0
    columns = _csv(capsys.readouterr().out)
    assert list(columns)[:1] == ["t"] and columns["t"][-1] == pytest.approx(3.0)
    # PI speed control: the motor settles at the demanded 10 rad/s
    assert columns["Motor_av"][-1] == pytest.approx(10.0, abs=0.05)
    # the shaft integrates the motor torque through the flywheel's 0.001 kg m²
    t, torque, speed = columns["t"], columns["Motor_T"], columns["Shaft_v"]
    integral = np.concatenate([[0], np.cumsum(np.diff(t) * (torque[1:] + torque[:-1]) / 2)])
    assert np.abs(speed - integral / 0.001).max() < 1e-2 * np.abs(speed).max()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_pendulum_json_matches_an_independent_integration(tmp_path: Path, capsys) -> None:
    from scipy.integrate import solve_ivp

    from tests.test_dynamics import PENDULUM

    (tmp_path / "p.rsm").write_text(PENDULUM)
    assert main(["simulate", str(tmp_path), "--t-end", "2", "--init", "Hinge_theta=1.0",
                 "--format", "json", "--rtol", "1e-11", "--atol", "1e-12", "--samples",
                 "21", "--method", "DOP853"]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = solve_ivp(lambda _t, x: [x[1], -2 * 9.81 * 0.5 * np.sin(x[0]) / 0.51], (0, 2),
                    [1.0, 0.0], t_eval=np.linspace(0, 2, 21), rtol=1e-12, atol=1e-12,
                    method="DOP853")
    assert np.abs(np.array(out["columns"]["Hinge_theta"]) - ref.y[0]).max() < 1e-6


def test_numeric_path_agrees_with_the_symbolic_one(tmp_path: Path, capsys) -> None:
    from tests.test_dynamics import PENDULUM

    (tmp_path / "p.rsm").write_text(PENDULUM)
    common = ["--t-end", "1", "--init", "Hinge_theta=0.5", "--input", "Hinge_tau=0.2*t",
              "--rtol", "1e-10", "--atol", "1e-12", "--samples", "11"]
    assert main(["simulate", str(tmp_path), *common]) == 0
    symbolic = _csv(capsys.readouterr().out)
    assert main(["simulate", str(tmp_path), "--numeric", *common]) == 0
    numeric = _csv(capsys.readouterr().out)
    assert np.abs(numeric["Hinge_theta"] - symbolic["Hinge_theta"]).max() < 1e-7
    assert set(numeric) == {"t", "Hinge_theta", "Hinge_v"}


@pytest.mark.parametrize("args, text", [
    (["--init", "Nope=1"], "not a state"),
    (["--input", "Hinge_tau=foo(t"], "cannot read the input value"),
    (["--input", "Hinge_tau=x*t"], "names x"),
])
def test_bad_options_are_diagnosed(tmp_path: Path, capsys, args, text) -> None:
    from tests.test_dynamics import PENDULUM

    (tmp_path / "p.rsm").write_text(PENDULUM)
    assert main(["simulate", str(tmp_path), *args]) == 2  # values of the command line
    captured = capsys.readouterr()
    assert text in captured.err and "E-OPTION" in captured.err and captured.out == ""


# ----------------------------------------------------------------------------- scenarios

def test_scenario_controller_stops_the_motor_at_the_sampled_event(capsys) -> None:
    folder = EXAMPLES / "dcmotor"
    assert main(["simulate", str(folder), "--scenario", str(folder / "sampled_stop.toml"),
                 "--samples", "21"]) == 0
    columns = _csv(capsys.readouterr().out)
    t, speed, distance = columns["t"], columns["Motor_av"], columns["Range_distance"]
    assert t[-1] == pytest.approx(2.0)  # the scenario's horizon
    # distance from 3.05 (the [init] midpoint) at -2 m/s: 1.05 at t = 1.0, 0.85 at t = 1.1,
    # so the event `near` (range <= 1) is first sampled at t = 1.1
    assert distance[np.isclose(t, 1.0)][0] == pytest.approx(1.05)
    assert speed[np.isclose(t, 1.1)][0] == pytest.approx(10.0, abs=0.5)  # cruising
    demand = columns["Motor_e"] + speed  # e = das - av: the demanded speed
    assert np.allclose(demand[t < 1.1 - 1e-9], 10.0) and np.allclose(demand[t > 1.1], 0.0)
    assert abs(speed[-1]) < 1.0  # stopped


MOTOR = ["R=1", "L=0.1", "Kt=0.05", "Ke=0.05", "b=0.01", "J=0.01", "Kp=2", "Ki=5", "Kd=0"]


def test_marxbot_needs_its_motor_constants_then_simulates(tmp_path: Path, capsys) -> None:
    folder = str(EXAMPLES / "marxbot")
    assert main(["simulate", folder, "--model", "marXbotBase", "--samples", "3"]) == 1
    err = capsys.readouterr().err
    assert "E-SIMULATE" in err and "--const SpeedControlMotor::J=VALUE" in err
    consts = [a for c in MOTOR for a in ("--const", f"SpeedControlMotor::{c}")]
    png = tmp_path / "m.png"
    assert main(["simulate", folder, "--model", "marXbotBase", "--samples", "11", "--t-end",
                 "0.2", "--input", "LMotor_das=5", *consts, "--plot", str(png),
                 "--plot-var", "LHinge_v"]) == 0
    columns = _csv(capsys.readouterr().out)
    # the left wheel turns (its motor drives it), the right one has no demand and stays
    assert columns["LHinge_v"][-1] > 1.0 and np.allclose(columns["RHinge_v"], 0.0)
    assert png.stat().st_size > 1000


def test_a_controller_object_replaces_the_scenario_table() -> None:
    from cyphy import api

    class StopAfterFive:
        """Drives for five cycles, then stops, whatever the events say."""

        def __init__(self) -> None:
            self.cycles, self.seen = 0, []

        def cycle(self, events):
            self.seen.append(dict(events))
            self.cycles += 1
            return (("drive", (10.0,)),) if self.cycles <= 5 else (("stop", ()),)

    folder = EXAMPLES / "dcmotor"
    controller = StopAfterFive()
    result = api.simulate([folder], api.SimulateOptions(
        scenario=str(folder / "sampled_stop.toml"), controller=controller))
    assert not result.report.has_errors and result.trajectory is not None
    t = result.trajectory.times
    demand = result.trajectory.column("Motor_e") + result.trajectory.column("Motor_av")
    assert np.allclose(demand[t < 0.5 - 1e-9], 10.0) and np.allclose(demand[t > 0.5], 0.0)
    assert controller.cycles == 20 and set(controller.seen[0]) == {"near"}


def test_output_is_byte_identical_across_runs(capsys) -> None:
    args = ["simulate", str(EXAMPLES / "dcmotor"), "--input", "Motor_das=10", "--samples", "7"]
    assert main(args) == 0
    first = capsys.readouterr().out
    assert main(args) == 0
    assert capsys.readouterr().out == first


def test_a_machine_that_does_not_run_is_named(tmp_path: Path, capsys) -> None:
    """Without ``--scenario`` the d-model's machine cannot run (its cycle needs the scenario's
    tscale and initial values): the run is the p-model alone, its inputs 0 unless given, and
    stderr names the machine left out rather than leave a flat trajectory unexplained. With
    the scenario it runs and no such line appears; a p-model without a d-model has none."""
    out = tmp_path / "a.csv"
    assert main(["simulate", str(EXAMPLES / "dcmotor"), "--t-end", "0.5", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "the d-model's machine SSpeed is not run" in err and "--scenario" in err, err
    assert max(abs(v) for v in _csv(out.read_text())["Motor_av"]) == 0.0  # nothing drives it
    assert main(["simulate", str(EXAMPLES / "dcmotor"), "--scenario",
                 str(EXAMPLES / "dcmotor" / "sampled_stop.toml"), "-o", str(out)]) == 0
    assert "not run" not in capsys.readouterr().err
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / "DCMotorBase.rsm").write_text((EXAMPLES / "dcmotor" / "DCMotorBase.rsm").read_text())
    assert main(["simulate", str(alone), "--t-end", "0.5", "-o", str(out)]) == 0
    assert "not run" not in capsys.readouterr().err
