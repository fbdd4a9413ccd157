"""The same robot in every command (issue 32): `show` on joints of several coordinates,
`--const` honoured everywhere, joint damping and limits in the equations, orientation
coordinates near their singularity, solve's JSON closed under its names.

Oracles: Pinocchio (its model built with its own joints, tests/test_dynamics_joints.py) and
MuJoCo on cyphy's own MJCF export; the printed equations are read back by the parser and
evaluated by SymPy, never through cyphy's dynamics."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy

from cyphy.cli import main
from cyphy.semantics.dynamics import rigid_body as dynamics

pin = pytest.importorskip("pinocchio")
from test_dynamics_joints import MULTI, _elaborated, pinocchio_model  # noqa: E402


def _write(folder: Path, text: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "m.rsm").write_text(text)
    return folder


def _parse(text: str):
    from cyphy.lang.parser import parse_text

    result = parse_text(f"const e: real = {text}", "<show>")
    assert not result.diagnostics, (text, result.diagnostics)
    return result.file.items[0].value


def _evaluate_show(motion: list[dict], values: dict[str, object]) -> dict[str, object]:
    """The per-body equations `show --format json` printed, read back by the parser and
    evaluated by SymPy: forward (``A``, ``dA``, ``G``, ``X``, ``V``, ``dV``) root to leaves,
    then the wrenches leaves to root, then the efforts."""
    from cyphy.translate.to_sympy import to_sympy

    known: dict[str, object] = dict(values)
    split = [[e.split(" == ", 1) for e in body["equations"]] for body in motion]

    def run(pairs):
        for left, right in pairs:
            value = to_sympy(_parse(right), symbols=dict(known))
            value = sympy.Matrix(value).evalf() if isinstance(value, sympy.MatrixBase) \
                else sympy.Float(sympy.sympify(value).evalf())
            known[left] = value

    for pairs in split:
        run([p for p in pairs if not p[0].endswith(("_F", "_tau"))])
    for pairs in reversed(split):
        run([p for p in pairs if p[0].endswith("_F")])
    for pairs in split:
        run([p for p in pairs if p[0].endswith("_tau")])
    return known


def test_show_on_ball_and_universal_joints_gives_pinocchio_efforts(tmp_path: Path,
                                                                   capsys) -> None:
    """`show` (text and JSON) on a ball–universal chain: the printed Newton–Euler equations,
    evaluated at random states, give the efforts of Pinocchio's RNEA."""
    folder = _write(tmp_path / "multi", MULTI)
    assert main(["show", str(folder)]) == 0
    text = capsys.readouterr().out
    assert "Wrist_dV == Wrist_X * Shoulder_dV + ad(Wrist_V) * Wrist_A * Wrist_v + " \
           "Wrist_A * Wrist_a + Wrist_dA" in text
    assert main(["show", str(folder), "--format", "json"]) == 0
    motion = json.loads(capsys.readouterr().out)["motion"]
    assert [b["kind"] for b in motion] == ["spherical", "universal"]
    model = _elaborated(folder)
    tree = dynamics.kinematic_tree(model)
    robot = pinocchio_model(model, tree.names, False)
    rng = np.random.default_rng(32)
    for _ in range(2):
        q, qd, qdd = (rng.uniform(-1.2, 1.2, tree.dof) for _ in range(3))
        values: dict[str, object] = {}
        for joint, k in zip(tree.joints, tree.offsets):
            for port, x in (("theta", q), ("v", qd), ("a", qdd)):
                values[f"{joint.prefix}_{port}"] = sympy.Matrix(x[k:k + joint.dof])
        known = _evaluate_show(motion, values)
        ours = np.concatenate([np.array(known[f"{p}_tau"], dtype=float).ravel()
                               for p in tree.prefixes])
        reference = pin.rnea(robot, robot.createData(), q, qd, qdd)
        assert np.abs(ours - reference).max() <= 1e-9 * np.abs(reference).max()


# ----------------------------------------------------------------------------- --const

CONST_PENDULUM = """
import physmod::joints::*

pmodel P {
    const M2: real = 2.0
    const L: real
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref J = Revolute {
            instantiation AXIS = (|1, 0, 0|)
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0 y = 0 z = L roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass M2 inertia matrix { ixx 0.5 ixy 0 ixz 0 iyy 0.5 iyz 0 izz 0.5 } } }
    }
}
"""


def _pendulum_qdd(mass: float, length: float, theta: float) -> float:
    """By hand: a body of ``mass`` (inertia 0.5 about x at its centre) hanging ``length``
    below a hinge about x: ``(0.5 + m·L²)·θ̈ = −m·g·L·sin θ``."""
    return -mass * 9.81 * length * np.sin(theta) / (0.5 + mass * length ** 2)


def test_const_overrides_a_declared_value_in_show_solve_and_simulate(tmp_path: Path,
                                                                     capsys) -> None:
    folder = _write(tmp_path / "p", CONST_PENDULUM)
    given = ["--const", "L=-0.5", "--const", "M2=5.0"]
    assert main(["show", str(folder), "--format", "json", *given]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert [link["inertial"]["mass"] for link in shown["links"]] == [1, 5]
    assert shown["motion"][0]["mass"] == 5
    assert main(["solve", str(folder), "--format", "json", *given]) == 0
    out = json.loads(capsys.readouterr().out)
    from test_articulated import _evaluate

    scope = _evaluate(out, {"J_theta": 0.1, "J_v": 0.0, "J_tau": 0.0})
    assert scope["J_qdd"] == pytest.approx(_pendulum_qdd(5.0, 0.5, 0.1), rel=1e-12)
    assert main(["simulate", str(folder), *given, "--init", "J_theta=0.1", "--t-end", "0.01",
                 "--samples", "2", "--rtol", "1e-10", "--atol", "1e-12"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header, last = lines[0].split(","), lines[-1].split(",")
    speed = float(last[header.index("J_v")])
    assert speed == pytest.approx(_pendulum_qdd(5.0, 0.5, 0.1) * 0.01, rel=1e-3)


@pytest.mark.parametrize("command", [["show"], ["solve"], ["simulate", "--t-end", "0.01"],
                                     ["gen", "--urdf"], ["view"]])
def test_const_naming_no_constant_is_an_error(tmp_path: Path, capsys, command) -> None:
    folder = _write(tmp_path / "p", CONST_PENDULUM)
    extra = ["-o", str(tmp_path / "out")] if command[0] == "gen" else \
        ["-o", str(tmp_path / "v.png")] if command[0] == "view" else []
    code = main([*command, str(folder), *extra, "--const", "L=-0.5", "--const", "Lx=3"])
    captured = capsys.readouterr()
    assert code == 1
    assert captured.out == ""
    assert "E-CONST-NAME" in captured.err and "--const Lx" in captured.err
    assert "did you mean 'L'?" in captured.err
    assert not (tmp_path / "out").exists() and not (tmp_path / "v.png").exists()


# ----------------------------------------------------------------------------- damping, limits

LIMITED = """
import physmod::joints::*
import physmod::sdf::annotations::*

pmodel P {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref J = Revolute {
            annotation Revolute { axis = Axis { xyz = (|0, 1, 0|)
                dynamics = Dynamics { DYNAMICS }
                limit = Limit { lower = -1 upper = 1 } } }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 2.0 inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.02 iyz 0 izz 0.03 } } }
    }
}
"""


def _mujoco_run(mjcf: Path, times: list[float], qpos0: float = 0.0) -> dict[float, tuple]:
    """MuJoCo's RK4 at 0.1 ms on cyphy's MJCF export: (position, rate) at ``times``."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.timestep = 1e-4
    data = mujoco.MjData(model)
    data.qpos[0] = qpos0
    out = {}
    for step in range(round(max(times) / 1e-4) + 1):
        t = step * 1e-4
        for s in times:
            if abs(t - s) < 1e-9:
                out[s] = (float(data.qpos[0]), float(data.qvel[0]))
        mujoco.mj_step(model, data)
    return out


def _simulated(folder: Path, t_end: float, samples: int, numeric: bool = False,
               init: dict[str, float] | None = None):
    from cyphy import api
    from cyphy.backends.simulate import SimulationOptions

    settings = SimulationOptions(t_end=t_end, samples=samples, rtol=1e-10, atol=1e-10,
                                 init=init or {})
    result = api.simulate([folder], api.SimulateOptions(simulation=settings,
                                                        numeric=numeric))
    assert result.trajectory is not None, result.report.diagnostics
    return result.trajectory


@pytest.mark.parametrize("numeric", [False, True])
def test_damped_limited_pendulum_stops_at_its_limit_as_in_mujoco(tmp_path: Path,
                                                                 numeric: bool) -> None:
    """A pendulum released horizontally, damped (0.5 N·m·s/rad) and limited to ±1 rad:
    `simulate` (symbolic and numeric paths) follows MuJoCo (RK4) on cyphy's own MJCF export
    until the stop, then both rest against the limit (the two contact models differ: a
    few milliradians of penetration)."""
    folder = _write(tmp_path / "p", LIMITED.replace("DYNAMICS", "damping = 0.5"))
    assert main(["gen", "--mjcf", str(folder), "-o", str(tmp_path / "mjcf")]) == 0
    reference = _mujoco_run(tmp_path / "mjcf" / "P.xml", [0.1, 0.2, 0.3, 1.0, 2.0])
    trajectory = _simulated(folder, 2.0, 21, numeric)
    theta, speed = trajectory.column("J_theta"), trajectory.column("J_v")
    for k, t in ((1, 0.1), (2, 0.2), (3, 0.3)):  # before the stop: the same motion
        assert theta[k] == pytest.approx(reference[t][0], rel=1e-5)
        assert speed[k] == pytest.approx(reference[t][1], rel=1e-5)
    assert reference[0.3][0] < 1.0 < reference[1.0][0]  # MuJoCo reached the limit
    assert theta.max() < 1.03  # it stops there: without the limit it swings to 2.46 rad
    for t, k in ((1.0, 10), (2.0, 20)):  # and rests against the limit in both
        assert abs(theta[k] - 1.0) < 5e-3 and abs(reference[t][0] - 1.0) < 5e-3
        assert abs(speed[k]) < 1e-3 and abs(reference[t][1]) < 1e-3


def test_spring_and_damping_follow_mujoco_and_are_in_the_written_out_equations(
        tmp_path: Path) -> None:
    """A spring (stiffness 3 N·m/rad about 0.2 rad) and damping within the limits: the
    whole motion agrees with MuJoCo, and the written-out equation (Flow*, theories) has
    ``J_tau == M·J_a + h + 0.5·J_v + 3·(J_theta − 0.2)``."""
    from cyphy import api
    from cyphy.lang.notation import to_notation
    from cyphy.semantics.dynamics.rigid_body import motion_equations

    folder = _write(tmp_path / "p", LIMITED.replace(
        "DYNAMICS", "damping = 0.5 spring_stiffness = 3 spring_reference = 0.2")
        .replace("lower = -1 upper = 1", "lower = -10 upper = 10")
        .replace("x = 0.5 y = 0 z = 0", "x = 0 y = 0 z = 0.5"))  # standing: it would fall
    assert main(["gen", "--mjcf", str(folder), "-o", str(tmp_path / "mjcf")]) == 0
    text = (tmp_path / "mjcf" / "P.xml").read_text()
    assert 'stiffness="3"' in text and 'springref="0.2"' in text
    times = [0.5, 1.0, 2.0]
    reference = _mujoco_run(tmp_path / "mjcf" / "P.xml", times, qpos0=0.1)
    trajectory = _simulated(folder, 2.0, 5, init={"J_theta": 0.1})
    for k, t in ((1, 0.5), (2, 1.0), (4, 2.0)):
        assert trajectory.column("J_theta")[k] == pytest.approx(reference[t][0], abs=1e-6)
    model = api.elaborate([folder]).model
    [(equation, _)] = motion_equations(model)
    printed = to_notation(equation)
    assert "0.5 * J_v" in printed and "3.0 * J_theta" in printed, printed
