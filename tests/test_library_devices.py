"""Issue 27, item 2: every actuator and sensor of the built-in library on a joint, through
`cyphy solve` and `cyphy simulate`: each drives (or reads) a one-joint pendulum, and the
trajectory `simulate` writes is compared, value by value, with an independent integration
(SciPy, tight tolerances) of the equations derived by hand below, never with cyphy's own.

The pendulum: a hinge about y at the origin, a bob of 2 kg at 0.5 m below it with iyy 0.01,
so the moment of inertia about the hinge is I = 0.01 + 2·0.5² = 0.51 kg m² and gravity's
torque −2·9.81·0.5·sin θ: I·θ'' = τ − 9.81·sin θ."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from cyphy.cli import main

INERTIA, GRAVITY_TORQUE = 0.51, 9.81  # I and m·g·l of the pendulum

PENDULUM = """\
import physmod::math::*
import physmod::joints::{joint}
import physmod::actuators::*
import physmod::sensors::*

pmodel P {{
    local link Base {{
        def {{ inertial information {{ mass 1.0 inertia matrix {{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
        jref Hinge = {joint} {{
            instantiation AXIS = {axis}
            flexibly connected to Bob
            {devices}
        }}
    }}
    local link Bob {{
        pose {{ x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0 }}
        def {{ inertial information {{ mass 2.0 inertia matrix {{ ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 }} }} }}
    }}
}}
"""

TIMES = np.linspace(0, 1.5, 16)


def simulate(tmp_path: Path, capsys, devices: str, *args: str, joint: str = "Revolute",
             axis: str = "(|0, 1, 0|)") -> dict[str, np.ndarray]:
    (tmp_path / "p.rsm").write_text(PENDULUM.format(joint=joint, axis=axis, devices=devices))
    const = [a for k, a in enumerate(args) if a == "--const" or k and args[k - 1] == "--const"]
    assert main(["solve", str(tmp_path), *const]) == 0, capsys.readouterr().err
    capsys.readouterr()
    assert main(["simulate", str(tmp_path), *args, "--t-end", "1.5", "--samples", "16",
                 "--rtol", "1e-11", "--atol", "1e-12", "--method", "DOP853"]) == 0, \
        capsys.readouterr().err
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    return {name: np.array([float(r[k]) for r in rows[1:]]) for k, name in enumerate(rows[0])}


def reference(f: Callable[[float, np.ndarray], list[float]], x0: list[float]) -> np.ndarray:
    return solve_ivp(f, (0, 1.5), x0, t_eval=TIMES, rtol=1e-12, atol=1e-13,
                     method="DOP853").y


def consts(**values: float) -> list[str]:
    return [a for k, v in values.items() for a in ("--const", f"{k}={v}")]


def close(ours: np.ndarray, theirs: np.ndarray) -> bool:
    return bool(np.abs(ours - theirs).max() <= 1e-6 * max(1.0, np.abs(theirs).max()))


def free_swing(theta0: float) -> np.ndarray:
    """θ and θ' of the undriven pendulum released at rest from θ0."""
    return reference(lambda _t, x: [x[1], -GRAVITY_TORQUE * math.sin(x[0]) / INERTIA],
                     [theta0, 0.0])


# ------------------------------------------------------------------------------ actuators

def test_speed_control_motor_drives_the_pendulum(tmp_path: Path, capsys) -> None:
    """T == tau: the motor's rotor (J) follows the PID's current, the pendulum gets T.
    T = Kt·i − b·av, J·av' = T, e = das − av (e' = −av' for a constant demand),
    V = Kp·e + Ki·∫e + Kd·e', L·i' = V − R·i − Ke·av, I·θ'' = T − 9.81·sin θ."""
    k = dict(J=0.01, b=0.1, Ke=0.05, Kt=0.05, R=1.0, L=0.1, Kp=2.0, Ki=5.0, Kd=0.01)
    das = 2.0
    out = simulate(tmp_path, capsys, "aref Drive = SpeedControlMotor { relation Drive.T == "
                   "Hinge.tau }", *consts(**k), "--input", f"Drive_das={das}", "--init",
                   "Hinge_theta=0.3")

    def f(_t: float, x: np.ndarray) -> list[float]:
        theta, v, av, i, z = x
        torque = k["Kt"] * i - k["b"] * av
        dav = torque / k["J"]
        e = das - av
        voltage = k["Kp"] * e + k["Ki"] * z + k["Kd"] * (-dav)
        di = (voltage - k["R"] * i - k["Ke"] * av) / k["L"]
        return [v, (torque - GRAVITY_TORQUE * math.sin(theta)) / INERTIA, dav, di, e]

    theta, v, av, i, _ = reference(f, [0.3, 0, 0, 0, 0])
    assert close(out["Hinge_theta"], theta) and close(out["Hinge_v"], v)
    assert close(out["Drive_av"], av) and close(out["Drive_i"], i)
    assert close(out["Drive_T"], k["Kt"] * i - k["b"] * av)


def test_linear_speed_control_motor_lifts_a_vertical_slider(tmp_path: Path, capsys) -> None:
    """On a prismatic joint along z (the bob's 2 kg against gravity), tied by force and
    speed (the linear motor has no mass of its own: its speed is the joint's).
    F = Kf·i − b·v, 2·v' = F − 2·9.81, e = dls − v, e' = −v', V = Kp·e + Ki·∫e + Kd·e',
    L·i' = V − R·i − Ke·v."""
    k = dict(b=0.1, Ke=5.0, Kf=5.0, R=1.0, L=0.05, Kp=20.0, Ki=50.0, Kd=0.01)
    dls = 0.5
    out = simulate(tmp_path, capsys, "aref Drive = LinearSpeedControlMotor { relation "
                   "Drive.F == Hinge.tau relation Drive.lv == Hinge.v }", *consts(**k),
                   "--input", f"Drive_dls={dls}", joint="Prismatic", axis="(|0, 0, 1|)")

    def f(_t: float, x: np.ndarray) -> list[float]:
        _, v, i, z = x
        force = k["Kf"] * i - k["b"] * v
        dv = force / 2.0 - 9.81
        e = dls - v
        voltage = k["Kp"] * e + k["Ki"] * z + k["Kd"] * (-dv)
        return [v, dv, (voltage - k["R"] * i - k["Ke"] * v) / k["L"], e]

    x, v, i, _ = reference(f, [0, 0, 0, 0])
    assert close(out["Hinge_theta"], x) and close(out["Hinge_v"], v)
    assert close(out["Drive_i"], i) and close(out["Drive_x"], x)
    assert abs(v[-1] - dls) < 0.05  # it settles at the demanded speed, against gravity


def test_torque_control_motor_drives_the_pendulum(tmp_path: Path, capsys) -> None:
    """TorqueOut == TorqueIn == tau: I·θ'' = 0.5·sin(3t) − 9.81·sin θ."""
    out = simulate(tmp_path, capsys, "aref Drive = TorqueControlMotor { relation "
                   "Drive.TorqueOut == Hinge.tau }", "--input", "Drive_TorqueIn=0.5*sin(3*t)",
                   "--init", "Hinge_theta=0.2")
    theta, v = reference(lambda t, x: [x[1], (0.5 * math.sin(3 * t) - GRAVITY_TORQUE *
                                              math.sin(x[0])) / INERTIA], [0.2, 0.0])
    assert close(out["Hinge_theta"], theta) and close(out["Hinge_v"], v)


# -------------------------------------------------------------------------------- sensors

def test_ir_reads_the_distance_the_swing_sets(tmp_path: Path, capsys) -> None:
    """distance = 1 + 0.5·sin θ, voltage = a/(distance + b) + c."""
    out = simulate(tmp_path, capsys, "sref Range = IR { relation Range.distance == 1 + 0.5 * "
                   "sin(Hinge.theta) }", *consts(a=1.0, b=0.1, c=0.2), "--init",
                   "Hinge_theta=1")
    theta, _ = free_swing(1.0)
    distance = 1 + 0.5 * np.sin(theta)
    assert close(out["Range_distance"], distance)
    assert close(out["Range_voltage"], 1.0 / (distance + 0.1) + 0.2)


def test_sonar_reads_the_bob_height(tmp_path: Path, capsys) -> None:
    """The bob's height above a floor 2 m below the hinge: 2 − 0.5·cos θ."""
    out = simulate(tmp_path, capsys, "sref Echo = Sonar { relation Echo.distance == 2 - 0.5 * "
                   "cos(Hinge.theta) }", "--init", "Hinge_theta=1")
    theta, _ = free_swing(1.0)
    assert close(out["Echo_range"], 2 - 0.5 * np.cos(theta))


def test_gyroscope_reads_the_swing_rate(tmp_path: Path, capsys) -> None:
    out = simulate(tmp_path, capsys, "sref Gyro = Gyroscope { relation Gyro.angularVelocity "
                   "== (|0, Hinge.v, 0|) }", "--init", "Hinge_theta=1")
    _, v = free_swing(1.0)
    assert close(out["Gyro_measuredAngularVelocity_2"], v)
    assert close(out["Gyro_measuredAngularVelocity_1"], 0 * v)


def test_accelerometer_reads_the_bob_acceleration(tmp_path: Path, capsys) -> None:
    """Tangential 0.5·θ'' and centripetal 0.5·θ'² of the bob (θ'' from the equation of
    motion: −9.81·sin θ / 0.51)."""
    out = simulate(tmp_path, capsys, "sref Acc = Accelerometer { relation Acc.acceleration == "
                   "(|0.5 * Hinge.a, 0, 0.5 * Hinge.v * Hinge.v|) }", "--init", "Hinge_theta=1")
    theta, v = free_swing(1.0)
    assert close(out["Acc_measuredAcceleration_1"],
                 0.5 * -GRAVITY_TORQUE * np.sin(theta) / INERTIA)
    assert close(out["Acc_measuredAcceleration_3"], 0.5 * v ** 2)


def test_gps_reads_the_bob_position_and_velocity(tmp_path: Path, capsys) -> None:
    """The bob at (−0.5·sin θ, 0, −0.5·cos θ) (a turn θ about y of (0, 0, −0.5))."""
    out = simulate(tmp_path, capsys, "sref Fix = GPS { relation Fix.position == (|-0.5 * "
                   "sin(Hinge.theta), 0, -0.5 * cos(Hinge.theta)|) relation Fix.velocity == "
                   "(|-0.5 * cos(Hinge.theta) * Hinge.v, 0, 0.5 * sin(Hinge.theta) * Hinge.v|) }",
                   "--init", "Hinge_theta=1")
    theta, v = free_swing(1.0)
    assert close(out["Fix_measuredPosition_1"], -0.5 * np.sin(theta))
    assert close(out["Fix_measuredPosition_3"], -0.5 * np.cos(theta))
    assert close(out["Fix_measuredVelocity_1"], -0.5 * np.cos(theta) * v)
    assert close(out["Fix_measuredVelocity_3"], 0.5 * np.sin(theta) * v)


def test_devices_without_a_numeric_quantity_leave_the_pendulum_alone(tmp_path: Path,
                                                                      capsys) -> None:
    """Camera (images), Lidar (sequences) and LED (booleans) have nothing a joint moves or
    reads: carried by the hinge they change nothing, and solve still gives their identity
    equations."""
    devices = "sref Cam = Camera { } sref Scan = Lidar { } aref Lamp = LED { }"
    out = simulate(tmp_path, capsys, devices, "--init", "Hinge_theta=1")
    theta, v = free_swing(1.0)
    assert close(out["Hinge_theta"], theta) and close(out["Hinge_v"], v)
    assert main(["solve", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "Lamp_lit = Lamp_on" in text and "Scan_ranges = Scan_distances" in text


@pytest.mark.parametrize("device", ["SpeedControlMotor", "LinearSpeedControlMotor",
                                    "TorqueControlMotor", "LED", "IR", "Accelerometer",
                                    "Gyroscope", "Camera", "GPS", "Sonar", "Lidar"])
def test_every_library_device_is_covered(device: str) -> None:
    """The library's devices are the ones above (a new one needs a test here)."""
    from cyphy.lang.workspace import LIBRARY_ROOT

    text = "".join((LIBRARY_ROOT / "physmod" / f).read_text()
                   for f in ("actuators.rsm", "sensors.rsm"))
    assert f"actuator {device} " in text or f"sensor {device} " in text
    declared = {line.split()[1] for line in text.splitlines()
                if line.startswith(("actuator ", "sensor "))}
    assert declared == {"SpeedControlMotor", "LinearSpeedControlMotor", "TorqueControlMotor",
                        "LED", "IR", "Accelerometer", "Gyroscope", "Camera", "GPS", "Sonar",
                        "Lidar"}
