"""`cyphy simulate` with the d-model's state machine as the controller (issues 16 and 18): a
scenario without ``[controller]`` runs the machine's interpreter once per ``cycle × tscale``
seconds, and the mapping's operations give its calls' effects. Checked against traces
computed by hand from RoboSim's cycle semantics and against the equivalent hand-written
``[controller]`` table."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest

from cyphy.cli import main
from motors import SSPEED_TABLE

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
DCMOTOR = EXAMPLES / "dcmotor"
MARXBOT = EXAMPLES / "marxbot"



def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def _with_table(tmp_path: Path) -> Path:
    scenario = tmp_path / "sampled_stop_table.toml"
    text = (DCMOTOR / "sampled_stop.toml").read_text()
    scenario.write_text(text.replace("[unsafe]", SSPEED_TABLE + "\n[unsafe]"))
    return scenario


def test_the_machine_drives_the_motor_and_stops_it_at_the_predicted_cycle(
        capsys, monkeypatch) -> None:
    from cyphy.semantics.machines.cycle import MachineInterpreter

    trace: list[tuple] = []
    original = MachineInterpreter.cycle

    def spy(self, events):
        calls = original(self, events)
        trace.append((events.get("near"), calls))
        return calls

    monkeypatch.setattr(MachineInterpreter, "cycle", spy)
    assert main(["simulate", str(DCMOTOR), "--scenario", str(DCMOTOR / "sampled_stop.toml"),
                 "--samples", "41", "--rtol", "1e-9", "--atol", "1e-12"]) == 0
    columns = _csv(capsys.readouterr().out)
    # Hand-computed: 20 cycles of 1 × 0.1 s over the 2 s horizon. The distance falls from
    # 3.05 at 2 m/s, so range <= 1 is first sampled at t = 1.1 (cycle 11; 1.05 m at t = 1.0).
    # SSpeed: cycle 0 enters Cruise (drive(10)); each later cycle takes the exec transition
    # to Check and returns to Cruise (drive(10) again) until near, when it takes t3
    # (stop()) to Stopped, where nothing more is called.
    trace = trace[-20:]  # the earlier cycles are the Flow* compilation's exploration
    assert trace[0] == (None, (("drive", (10.0,)),))
    assert [calls for _, calls in trace[:11]] == [(("drive", (10.0,)),)] * 11
    assert all(near is None for near, _ in trace[:11])
    assert trace[11] == (True, (("stop", ()),))
    assert all(calls == () for _, calls in trace[12:])
    t, speed = columns["t"], columns["Motor_av"]
    demand = columns["Motor_e"] + speed  # e = das - av
    assert np.allclose(demand[t < 1.1 - 1e-9], 10.0) and np.allclose(demand[t > 1.1], 0.0)
    cruise = (t > 0.7) & (t <= 1.1 + 1e-9)
    assert np.all(np.abs(speed[cruise] - 10.0) < 0.5)  # near 10 rad/s before the stop
    after = (t > 1.1) & (t <= 1.35)
    assert np.all(np.diff(speed[after]) < 0) and speed[after][-1] < 3.0  # decaying
    assert abs(speed[-1]) < 1.0


def test_the_machine_and_the_hand_written_table_agree(tmp_path: Path, capsys) -> None:
    common = ["--samples", "41", "--rtol", "1e-9", "--atol", "1e-12"]
    assert main(["simulate", str(DCMOTOR), "--scenario", str(DCMOTOR / "sampled_stop.toml"),
                 *common]) == 0
    machine = _csv(capsys.readouterr().out)
    assert main(["simulate", str(DCMOTOR), "--scenario", str(_with_table(tmp_path)),
                 *common]) == 0
    table = _csv(capsys.readouterr().out)
    assert list(machine) == list(table)
    for name in machine:
        assert np.allclose(machine[name], table[name], rtol=1e-9, atol=1e-9), name


def test_the_hand_written_table_as_a_controller_object(tmp_path: Path) -> None:
    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.controller import ScenarioController
    from cyphy.verify.flowstar.scenario import load_scenario

    controller = ScenarioController(load_scenario(_with_table(tmp_path), Report()))
    assert controller.cycle({"near": True}) == (("drive", (10.0,)),)  # time 0: initial calls
    assert controller.cycle({"near": None}) == (("drive", (10.0,)),)
    assert controller.cycle({"near": True}) == (("stop", ()),)
    assert controller.cycle({"near": None}) == (("stop", ()),)  # no way back


def test_operation_effects_hold_for_any_arguments() -> None:
    """move(lv, av) solved once from the mapping: dsl, dsr with r = 0.025025 m and the
    0.06 m axis, lv = r(dsl + dsr)/2, av = r(dsl - dsr)/0.06 (computed here by hand)."""
    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.controller import CallEffects
    from cyphy.verify.flowstar.build import build_problem
    from cyphy.verify.flowstar.scenario import load_scenario

    report = Report()
    scenario = load_scenario(MARXBOT / "avoid_obstacle.toml", report)
    problem, _ = build_problem([MARXBOT], scenario, report)
    assert problem is not None and problem.machine is not None, report.diagnostics
    effects = CallEffects({}, {}, problem.operation_effects)
    r, axis, lv, av = 0.025025, 0.06, 0.07, -0.3  # arguments no state of the machine uses
    values = effects((("move", (lv, av)),))
    assert values["LMotor_das"] == pytest.approx((lv + av * axis / 2) / r, rel=1e-12)
    assert values["RMotor_das"] == pytest.approx((lv - av * axis / 2) / r, rel=1e-12)
    assert effects((("move", (lv, av)), ("stop", ()))) == {"LMotor_das": 0.0,
                                                           "RMotor_das": 0.0}
    with pytest.raises(ValueError, match="no effect the mapping determines"):
        effects((("fly", (1.0,)),))


def test_machine_option_errors_as_for_reach(tmp_path: Path, capsys) -> None:
    scenario = str(DCMOTOR / "sampled_stop.toml")
    assert main(["simulate", str(DCMOTOR), "--scenario", scenario, "--machine", "Nope"]) == 1
    err = capsys.readouterr().err
    assert "E-FLOWSTAR" in err and "no state machine 'Nope'" in err and "SSpeed" in err
    assert main(["simulate", str(DCMOTOR), "--scenario", str(_with_table(tmp_path)),
                 "--machine", "SSpeed"]) == 1
    captured = capsys.readouterr()
    assert "E-SCENARIO" in captured.err and "has a [controller]" in captured.err
    assert captured.out == ""
    assert main(["simulate", str(DCMOTOR), "--machine", "SSpeed"]) == 2
    assert main(["simulate", str(DCMOTOR), "--scenario", scenario, "--machine", "SSpeed",
                 "--samples", "3"]) == 0


def test_a_scenario_cycle_other_than_the_machines_is_reported(tmp_path: Path, capsys) -> None:
    scenario = tmp_path / "s.toml"
    text = (DCMOTOR / "sampled_stop.toml").read_text()
    scenario.write_text(text.replace("horizon = 2.0", "horizon = 2.0\ncycle = 2"))
    assert main(["simulate", str(DCMOTOR), "--scenario", str(scenario)]) == 1
    err = capsys.readouterr().err
    assert "E-FLOWSTAR" in err and "cycle = 2" in err and "cycleDef cycle == 1" in err


def test_marxbot_under_smovement_cruises_stops_at_the_obstacle_and_turns(capsys) -> None:
    assert main(["simulate", str(MARXBOT), "--scenario", str(MARXBOT / "avoid_obstacle.toml"),
                 "--samples", "26"]) == 0
    c = _csv(capsys.readouterr().out)
    t = c["t"]
    dl, dr = c["LMotor_e"] + c["LMotor_av"], c["RMotor_e"] + c["RMotor_av"]  # demands
    cruise, turn = 0.1 / 0.025025, 0.5 * 0.03 / 0.025025  # move(lv, 0), move(0, av)
    # Hand-computed: the distance (0.255 m at the start) falls at r(ωl + ωr)/2; the first
    # cycle at which it is at most 0.09 m (the obstacle event) stops the robot (t4: stop()),
    # and the next cycle enters Turning (move(0, av)).
    d = c["Proximity1_distance"]
    stop = t[np.isclose(t, np.round(t, 1)) & (d <= 0.09)][0]
    assert stop == pytest.approx(1.8)
    assert np.allclose(dl[t < stop - 1e-9], cruise) and np.allclose(dr[t < stop - 1e-9], cruise)
    at_stop = np.isclose(t, stop)
    assert dl[at_stop][0] == pytest.approx(0.0) and dr[at_stop][0] == pytest.approx(0.0)
    turning = t > stop + 0.1 + 1e-9
    assert np.allclose(dl[turning], turn) and np.allclose(dr[turning], -turn)
    assert np.all(np.abs(c["LMotor_av"][(t > 1.0) & (t < stop)] - cruise) < 0.1)
    # turning on the spot leaves the obstacle's distance as it is
    assert np.ptp(d[t >= 2.3]) < 2e-3 and d.min() > 0.05


def test_chosen_hinges_bring_their_equations_of_motion() -> None:
    """``elements`` naming a joint keeps the tree's equation of motion of that joint when
    it names only chosen joints (the marXbot's wheels: each its own); motors alone, none."""
    from cyphy import api
    from cyphy.semantics.dynamics.equations import assemble

    model = api.elaborate([MARXBOT], api.ElaborateOptions("marXbotBase")).model
    assert model is not None
    hinges = assemble(model, ["marXbotBase::Core::LHinge", "marXbotBase::Core::RHinge"])
    origins = {eq.origin for eq in hinges.equations}
    assert {"LHinge motion", "RHinge motion"} <= origins
    assert "LHinge_tau" not in hinges.inputs  # the relation LMotor.T == LHinge.tau gives it
    motors = assemble(model, ["marXbotBase::Core::LHinge::LMotor"])
    assert not any(o.endswith(" motion") for o in {eq.origin for eq in motors.equations})


def test_marxbot_with_the_hinges_dynamics_spins_the_wheels_by_the_motor_torque(capsys) -> None:
    scenario = MARXBOT / "avoid_obstacle_dynamics.toml"
    assert main(["simulate", str(MARXBOT), "--scenario", str(scenario), "--samples", "251",
                 "--rtol", "1e-9", "--atol", "1e-12"]) == 0
    c = _csv(capsys.readouterr().out)
    t = c["t"]
    # the wheel's speed integrates the motor torque through the wheel's inertia about its
    # axis: Treel.rsm's solid cylinder, izz = 0.02 kg * (1.001 * 0.05 m / 2)^2 / 2
    inertia = 0.02 * (1.001 * 0.05 / 2) ** 2 / 2
    torque, speed = c["LMotor_T"], c["LHinge_v"]
    integral = np.concatenate([[0], np.cumsum(np.diff(t) * (torque[1:] + torque[:-1]) / 2)])
    assert np.abs(speed - integral / inertia).max() < 5e-3 * np.abs(speed).max()
    # the machine's phases are those without the hinges (the travel follows the motors)
    d = c["Proximity1_distance"]
    assert t[np.isclose(t, np.round(t, 1)) & (d <= 0.09)][0] == pytest.approx(1.8)
    dl = c["LMotor_e"] + c["LMotor_av"]
    assert np.allclose(dl[t > 1.9 + 1e-9], 0.5 * 0.03 / 0.025025)


def test_marxbot_dynamics_scenario_exports_the_hinges_motion() -> None:
    """The Flow* problem of avoid_obstacle_dynamics.toml (its verdict with the real Flow*,
    SAFE in 30 s, is recorded in examples/marxbot/README.md): the hinges' speeds are states
    whose derivative is the motor torque over the wheel's inertia about its axis."""
    import sympy

    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.build import build_problem
    from cyphy.verify.flowstar.export import render
    from cyphy.verify.flowstar.scenario import load_scenario

    report = Report()
    scenario = load_scenario(MARXBOT / "avoid_obstacle_dynamics.toml", report)
    problem, _ = build_problem([MARXBOT], scenario, report)
    assert problem is not None, [d.message for d in report.diagnostics]
    assert {"LHinge_theta", "LHinge_v", "RHinge_theta", "RHinge_v"} <= set(problem.states)
    inertia = 0.02 * (1.001 * 0.05 / 2) ** 2 / 2  # Treel.rsm's wheel: izz of a cylinder
    for side in "LR":
        torque = problem.outputs[f"{side}Motor_T"]
        point = {x: 0.3 + 0.1 * k for k, x in enumerate(sorted(
            problem.rhs[f"{side}Hinge_v"].free_symbols | torque.free_symbols, key=str))}
        assert float(problem.rhs[f"{side}Hinge_v"].subs(point)) == pytest.approx(
            float((torque / inertia).subs(point)), rel=1e-12)
        assert problem.rhs[f"{side}Hinge_theta"] == sympy.Symbol(f"{side}Hinge_v", real=True)
    text = render(problem, "avoid_obstacle_dynamics")
    assert "LHinge_v'" in text and "RHinge_theta'" in text


def test_obstacle_stop_stops_for_good_under_sstop_and_turns_under_smovement(capsys) -> None:
    # obstacle_stop.toml's property: no torque above 0.002 N m once t >= 3.5. Its machine
    # SStop (marXbotStop.rsm) stops for good; the module's SMovement turns after the stop
    # (move(0, av) for PI/(av*tu) time units, t = 1.9 to 8.1): the motors still work after
    # 3.5 s, which is why the scenario, about stopping for good, names SStop.
    scenario = str(MARXBOT / "obstacle_stop.toml")
    common = ["--samples", "81"]
    assert main(["simulate", str(MARXBOT), "--scenario", scenario, *common]) == 0
    stop = _csv(capsys.readouterr().out)
    late = stop["t"] >= 3.5
    assert np.max(stop["LMotor_T"][late] ** 2) < 4e-6
    assert main(["simulate", str(MARXBOT), "--scenario", scenario, "--machine", "SMovement",
                 *common]) == 0
    turn = _csv(capsys.readouterr().out)
    demand = turn["LMotor_e"] + turn["LMotor_av"]  # the wheel speed the machine asks for
    assert np.allclose(demand[late], 0.5 * 0.06 / 2 / 0.025025)  # move(0, av): turning
    assert np.allclose(stop["LMotor_e"][late] + stop["LMotor_av"][late], 0, atol=1e-12)  # stop()
