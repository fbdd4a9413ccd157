"""Issue 27, items 1: the equations are right or refused. A structural analysis (a matching of
equations to unknowns, a variable and its derivatives one column) runs before any reduction,
for `solve`, `simulate`, `reach` and the axiomatic Isabelle dialect alike: an equation left
over is E-OVERDETERMINED, in the user's file, naming what it competes with; never a
reduction that silently drops an equation of motion."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest

from cyphy import api
from cyphy.cli import main

MOTOR = dict(J=0.01, b=0.1, Ke=0.01, Kt=0.01, R=1.0, L=0.5, Kp=100.0, Ki=200.0, Kd=1.0)

# The arm: a SpeedControlMotor in the shoulder tied to the joint by its torque and,
# as the library's comment used to suggest, by its speed too; a free elbow.
ARM = """\
import physmod::math::*
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor

pmodel Arm {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Shoulder = Revolute {
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Upper
            aref Drive = SpeedControlMotor {
                relation Drive.T == Shoulder.tau
                %SPEED%
            }
        }
    }
    local link Upper {
        pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 1.0 inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 } } }
        jref Elbow = Revolute {
            pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Fore
        }
    }
    local link Fore {
        pose { x = 1.0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 0.5 inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 } } }
    }
}
"""


def _consts() -> list[str]:
    return [a for k, v in MOTOR.items() for a in ("--const", f"{k}={v}")]


def _arm(tmp_path: Path, speed: str) -> Path:
    (tmp_path / "arm.rsm").write_text(ARM.replace("%SPEED%", speed))
    return tmp_path / "arm.rsm"


def test_a_speed_relation_on_a_torque_driven_motor_is_overdetermined(tmp_path: Path,
                                                                       capsys) -> None:
    """Why, bullet 1: `Drive.av == Shoulder.v` adds an equation and no unknown. Before, solve
    took the rotor's equation for Shoulder_v' and dropped the joint's equation of motion,
    and simulate exited 0 with the arm held under gravity."""
    path = _arm(tmp_path, "relation Drive.av == Shoulder.v")
    for command in ("solve", "simulate"):
        assert main([command, str(path), *_consts()]) == 1, command
        captured = capsys.readouterr()
        assert captured.out == "", command  # no partial output
        assert "E-OVERDETERMINED" in captured.err and "Traceback" not in captured.err
    result = api.solve([path], api.SolveOptions(consts=MOTOR))
    (d,) = [d for d in result.report.diagnostics if d.code.id == "E-OVERDETERMINED"]
    # at the relation the user wrote (line 13), not in the library
    assert d.span.file == str(path) and d.span.line == 13
    assert "Drive_av" in d.message and "Shoulder_v" in d.message
    # what it competes with: the rotor's equation and the joint's derivative(v) == a, each
    # located in the library and at the element of the user's file that brings it in
    assert any("Drive_J * derivative(Drive_av) == Drive_T" in n and f"{path}:11" in n
               for n in d.notes)
    assert any("derivative(Shoulder_v) == Shoulder_a" in n and f"{path}:8" in n
               for n in d.notes)
    assert "M.T == J.tau" in d.hint
    assert not result.reduced.rhs  # nothing reduced, nothing dropped


def test_the_torque_alone_drives_the_arm_under_gravity(tmp_path: Path, capsys) -> None:
    """The same arm without the speed relation: solved, and the shoulder moves under gravity
    (held horizontal, the arm falls: the motor's rotor speed is its own)."""
    path = _arm(tmp_path, "")
    assert main(["simulate", str(path), *_consts(), "--t-end", "0.3", "--samples", "4"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    columns = {name: np.array([float(r[k]) for r in rows[1:]]) for k, name in
               enumerate(rows[0])}
    assert abs(columns["Shoulder_theta"][-1]) > 0.05  # gravity turns it


def test_two_joints_forced_to_one_speed_are_refused(tmp_path: Path) -> None:
    """An index-2 constraint (two bodies forced to the same speed) would need its constraint
    effort as an unknown: cyphy refuses it rather than dropping an equation of motion."""
    text = ARM.replace("%SPEED%", "").replace(
        "            flexibly connected to Fore\n",
        "            flexibly connected to Fore\n            relation Elbow.v == Shoulder.v\n")
    (tmp_path / "arm.rsm").write_text(text)
    result = api.solve([tmp_path], api.SolveOptions(consts=MOTOR))
    (d,) = [d for d in result.report.diagnostics if d.code.id == "E-OVERDETERMINED"]
    assert d.span.file == str(tmp_path / "arm.rsm") and d.span.line == 24
    assert "derivative(Elbow_v) == Elbow_a" in d.message
    assert "derivative(Shoulder_v) == Shoulder_a" in d.message


def test_a_prescribed_motion_does_not_make_an_effort_unknown(tmp_path: Path) -> None:
    """Only the speed relation (no torque relation): the joint's effort would be whatever
    keeps it at the motor's speed; cyphy gives accelerations from efforts, never the converse,
    so it is refused as over-determined instead of solving the effort from the motion."""
    path = _arm(tmp_path, "relation Drive.av == Shoulder.v").read_text()
    (tmp_path / "arm.rsm").write_text(path.replace("relation Drive.T == Shoulder.tau", ""))
    result = api.solve([tmp_path], api.SolveOptions(consts=MOTOR))
    assert [d.code.id for d in result.report.diagnostics] == ["E-OVERDETERMINED"]


TORQUE_HUB = """\
import physmod::math::*
import physmod::joints::Revolute
import physmod::actuators::TorqueControlMotor

pmodel Wheel {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Hub = Revolute {
            instantiation AXIS = (|0, 0, 1|)
            flexibly connected to Disc
            aref Drive = TorqueControlMotor {
                relation Drive.TorqueOut == Hub.tau
            }
        }
    }
    local link Disc {
        def { inertial information { mass 1.0 inertia matrix { ixx 0.05 ixy 0 ixz 0 iyy 0.05 iyz 0 izz 0.025 } } }
    }
}
"""


def test_a_torque_control_motor_drives_its_joint(tmp_path: Path, capsys) -> None:
    """Why, bullet 2: before, `E-REDUCE: no equation determines Hub_tau` pointed into the
    library while the definitions printed Hub_tau = Drive_TorqueIn (a variable solved
    without states was not counted as known). A disc of izz 0.025 about the vertical axis
    under a constant torque 0.5: v = 20 t, theta = 10 t² (no gravity torque about z)."""
    (tmp_path / "hub.rsm").write_text(TORQUE_HUB)
    assert main(["solve", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    assert "Hub_v' = Hub_qdd" in captured.out and captured.err == ""
    assert main(["simulate", str(tmp_path), "--input", "Drive_TorqueIn=0.5", "--t-end", "1",
                 "--samples", "5", "--rtol", "1e-10", "--atol", "1e-12"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    columns = {name: np.array([float(r[k]) for r in rows[1:]]) for k, name in
               enumerate(rows[0])}
    t = columns["t"]
    assert np.allclose(columns["Hub_v"], 20 * t, atol=1e-8)
    assert np.allclose(columns["Hub_theta"], 10 * t ** 2, atol=1e-8)


def test_an_underdetermined_variable_is_named(tmp_path: Path) -> None:
    """A speed relation on a LinearSpeedControlMotor is what determines its speed; without it
    the motor's lv is free: E-UNDERDETERMINED names it."""
    text = """\
import physmod::actuators::LinearSpeedControlMotor
pmodel P { local link L { def { inertial information { mass 1 } } aref M = LinearSpeedControlMotor { } } }
"""
    (tmp_path / "m.rsm").write_text(text)
    result = api.solve([tmp_path], api.SolveOptions())
    codes = {d.code.id for d in result.report.diagnostics}
    assert codes == {"E-UNDERDETERMINED"}
    assert any("M_lv" in d.message for d in result.report.diagnostics)


def test_the_axiomatic_dialect_refuses_an_overdetermined_robot(tmp_path: Path) -> None:
    """The mapping tests' two-wheeled robot with the speed relation on its left motor: the
    axiomatic Isabelle dialect's Evolve uses the same analysis."""
    mappings = Path(__file__).resolve().parent / "mappings"
    for name in ("Robot.rsm", "RobotSoftware.rsm", "Good.rsm"):
        text = (mappings / name).read_text().replace(
            "relation LMotor.T == LHinge.tau",
            "relation LMotor.T == LHinge.tau relation LMotor.av == LHinge.v")
        (tmp_path / name).write_text(text)
    generated = api.generate_isabelle(sorted(tmp_path.glob("*.rsm")), api.SemanticsGenOptions(
        dialect="axiomatic", elements=()))
    errors = [d for d in generated.report.diagnostics if d.severity.value == "ERROR"]
    assert [d.code.id for d in errors] == ["E-OVERDETERMINED"] and generated.files == {}
    assert errors[0].span.file == str(tmp_path / "Robot.rsm")
    assert "LMotor_av == LHinge_v" in errors[0].message


def test_reach_refuses_the_speed_relation_on_the_dc_motor_bench(tmp_path: Path) -> None:
    """`cyphy reach` / `gen --flowstar` builds its problem from the same analysis: the motor
    bench of examples/dcmotor with the speed relation added, and the shaft among the
    scenario's elements, is E-OVERDETERMINED at the relation (it was reduced before, the
    flywheel's equation of motion dropped)."""
    from conftest import EXAMPLES

    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.build import build_problem
    from cyphy.verify.flowstar.scenario import load_scenario

    for source in (EXAMPLES / "dcmotor").glob("*.rsm"):
        text = source.read_text().replace("relation Motor.T == Shaft.tau",
                                          "relation Motor.T == Shaft.tau\n"
                                          "\t\t\t\trelation Motor.av == Shaft.v")
        (tmp_path / source.name).write_text(text)
    scenario = (EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text().replace(
        '"DCMotorBase::Bench::Shaft::Motor"', '"DCMotorBase::Bench::Shaft"')
    (tmp_path / "s.toml").write_text(scenario)
    report = Report()
    loaded = load_scenario(tmp_path / "s.toml", report)
    assert loaded is not None
    build_problem([tmp_path], loaded, report)
    errors = [d for d in report.diagnostics if d.code.id == "E-OVERDETERMINED"]
    assert len(errors) == 1 and "Motor_av == Shaft_v" in errors[0].message
    assert errors[0].span.file == str(tmp_path / "DCMotorBase.rsm")
