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
    assert code == 2  # a usage error (E-OPTION), reported once
    assert captured.out == ""
    assert captured.err.count("--const Lx") == 1, captured.err
    assert "E-OPTION" in captured.err and "did you mean 'L'?" in captured.err
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
    from cyphy.semantics.dynamics.motion import motion_equations

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


# ----------------------------------------------------------------------------- near pitch ±π/2

def _rates(angles):
    """By hand, for ZYX Euler angles (yaw, pitch, roll), ``R = Rz·Ry·Rx``: the matrix that
    turns their rates into the angular velocity in the turned frame."""
    _, p, r = angles
    return np.array([[-np.sin(p), 0.0, 1.0],
                     [np.cos(p) * np.sin(r), np.cos(r), 0.0],
                     [np.cos(p) * np.cos(r), -np.sin(r), 0.0]])


def _rates_derivative(angles, speeds):
    """``d/dt(E)·(ẏ, ṗ, ṙ)``, differentiated by hand."""
    _, p, r = angles
    dy, dp, dr = speeds
    sp, cp, sr, cr = np.sin(p), np.cos(p), np.sin(r), np.cos(r)
    return np.array([-cp * dp * dy,
                     -sr * dr * dp + dy * (-sp * dp * sr + cp * cr * dr),
                     -cr * dr * dp + dy * (-sp * dp * cr - cp * sr * dr)])


def _quaternion(angles):
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_euler("ZYX", angles).as_quat()
    return np.array([w, x, y, z])


def _euler_accelerations(angles, speeds, angular_acceleration):
    """MuJoCo's angular acceleration (turned frame) as the angles' accelerations:
    ``q̈ = E⁻¹·(ω̇ − Ė·q̇)``."""
    return np.linalg.solve(_rates(angles), angular_acceleration
                           - _rates_derivative(angles, speeds))


DELTAS = (1e-4, 1e-6, 1e-8)


@pytest.mark.parametrize("delta", DELTAS)
def test_free_body_at_rest_near_pitch_half_pi_falls_freely(tmp_path: Path, capsys,
                                                           delta: float) -> None:
    """A free body at rest, its pitch ``δ`` from π/2: it falls with ``g`` and does not turn
    (by hand), in solve's definitions and in the numeric algorithm (the issue: ``z̈ = −10.3``
    at 1e-7, angular accelerations of −57 rad/s² at 1e-8)."""
    from test_dynamics_joints import FREE, _definitions_at

    folder = _write(tmp_path / "free", FREE)
    assert main(["solve", str(folder), "--floating-base", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    values = {n: 0.0 for n in out["states"]}
    values["Body_pitch"] = np.pi / 2 - delta
    scope = _definitions_at(out, values)
    expected = np.array([0.0, 0.0, -9.81, 0.0, 0.0, 0.0])
    ours = np.array([scope[f"Body_qdd_{k}"] for k in range(1, 7)])
    assert np.abs(ours - expected).max() <= 1e-6 * 9.81
    tree = dynamics.kinematic_tree(_elaborated(folder), floating_base=True)
    q = np.zeros(6)
    q[4] = np.pi / 2 - delta
    numeric = dynamics.forward_dynamics(tree, q, np.zeros(6), np.zeros(6))
    assert np.abs(numeric - expected).max() <= 1e-6 * 9.81


def _mujoco_accelerations(mjcf: Path, qpos, qvel):
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    data.qvel[:] = qvel
    mujoco.mj_forward(model, data)
    return data.qacc.copy()


@pytest.mark.parametrize("delta", DELTAS)
def test_moving_free_body_near_pitch_half_pi_agrees_with_mujoco(tmp_path: Path, capsys,
                                                                delta: float) -> None:
    """A free body turning and moving, pitch ``δ`` from π/2: solve's definitions and the
    numeric algorithm against MuJoCo's free joint (quaternion) on cyphy's MJCF export, its
    angular acceleration turned into the angles' by hand, to 1e-6 relative (an inertia
    inside the triangle inequality: on its boundary, MuJoCo's ``balanceinertia`` changes it)."""
    from test_dynamics_joints import FREE, _definitions_at

    folder = _write(tmp_path / "free", FREE.replace("izz 0.3", "izz 0.25"))
    assert main(["gen", "--mjcf", "--mjcf-free-base", str(folder), "-o",
                 str(tmp_path / "mjcf")]) == 0
    capsys.readouterr()
    assert main(["solve", str(folder), "--floating-base", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rng = np.random.default_rng(int(-np.log10(delta)))
    position = rng.uniform(-1, 1, 3)
    angles = np.array([rng.uniform(-2, 2), np.pi / 2 - delta, rng.uniform(-2, 2)])
    velocity, speeds = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
    qacc = _mujoco_accelerations(tmp_path / "mjcf" / "Free.xml",
                                 [*(position + [0, 0, 1]), *_quaternion(angles)],
                                 [*velocity, *(_rates(angles) @ speeds)])
    reference = np.concatenate([qacc[:3], _euler_accelerations(angles, speeds, qacc[3:])])
    names = ("x", "y", "z", "yaw", "pitch", "roll")
    values = dict(zip([f"Body_{n}" for n in names], [*position, *angles]))
    values.update(zip([f"Body_v{n}" for n in names], [*velocity, *speeds]))
    scope = _definitions_at(out, values)
    ours = np.array([scope[f"Body_qdd_{k}"] for k in range(1, 7)])
    scale = np.abs(reference).max()
    assert np.abs(ours - reference).max() <= 1e-6 * scale, (ours, reference)
    tree = dynamics.kinematic_tree(_elaborated(folder), floating_base=True)
    numeric = dynamics.forward_dynamics(tree, [*position, *angles], [*velocity, *speeds],
                                        np.zeros(6))
    assert np.abs(numeric - reference).max() <= 1e-6 * scale


@pytest.mark.parametrize("delta", DELTAS)
def test_ball_joint_near_pitch_half_pi_agrees_with_mujoco(tmp_path: Path, capsys,
                                                          delta: float) -> None:
    """The ball–universal chain, the ball joint's pitch ``δ`` from π/2, moving: solve's
    definitions and the numeric algorithm against MuJoCo's ball joint (quaternion) on
    cyphy's MJCF export (the universal joint as its two hinges), to 1e-6 relative."""
    from test_dynamics_joints import _definitions_at

    folder = _write(tmp_path / "multi", MULTI)
    assert main(["gen", "--mjcf", str(folder), "-o", str(tmp_path / "mjcf")]) == 0
    capsys.readouterr()
    assert main(["solve", str(folder), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rng = np.random.default_rng(int(-np.log10(delta)))
    angles = np.array([rng.uniform(-2, 2), np.pi / 2 - delta, rng.uniform(-2, 2)])
    speeds, wrist, wrist_speeds = (rng.uniform(-1, 1, n) for n in (3, 2, 2))
    qacc = _mujoco_accelerations(tmp_path / "mjcf" / "Multi.xml",
                                 [*_quaternion(angles), *wrist],
                                 [*(_rates(angles) @ speeds), *wrist_speeds])
    reference = np.concatenate([_euler_accelerations(angles, speeds, qacc[:3]), qacc[3:]])
    values = {f"Shoulder_theta_{k + 1}": x for k, x in enumerate(angles)}
    values.update({f"Shoulder_v_{k + 1}": x for k, x in enumerate(speeds)})
    values.update({f"Wrist_theta_{k + 1}": x for k, x in enumerate(wrist)})
    values.update({f"Wrist_v_{k + 1}": x for k, x in enumerate(wrist_speeds)})
    values.update({n: 0.0 for n in out["inputs"]})  # the efforts
    scope = _definitions_at(out, values)
    ours = np.array([scope[f"{j}_qdd_{k}"] for j, n in (("Shoulder", 3), ("Wrist", 2))
                     for k in range(1, n + 1)])
    scale = np.abs(reference).max()
    assert np.abs(ours - reference).max() <= 1e-6 * scale, (ours, reference)
    tree = dynamics.kinematic_tree(_elaborated(folder))
    numeric = dynamics.forward_dynamics(tree, [*angles, *wrist], [*speeds, *wrist_speeds],
                                        np.zeros(5))
    assert np.abs(numeric - reference).max() <= 1e-6 * scale


# ----------------------------------------------------------------------------- names

_FUNCTIONS = {"cos", "sin", "Piecewise", "True", "False"}


def _undefined(out: dict) -> set[str]:
    """The names solve's JSON uses (in its ODEs, outputs and definitions) that it defines
    nowhere (not a state, input, parameter, definition or output)."""
    import re

    defined = {*out["states"], *out["inputs"], *out["parameters"], *out["outputs"],
               *(d["name"] for d in out["definitions"])}
    used: set[str] = set()
    for text in [*out["odes"].values(), *out["outputs"].values(),
                 *(d["value"] for d in out["definitions"])]:
        used |= set(re.findall(r"(?<![0-9.eE])[A-Za-z_][A-Za-z0-9_]*", text))
    return used - defined - _FUNCTIONS


@pytest.mark.parametrize("model,options", [("multi", ()), ("multi", ("--floating-base",)),
                                           ("manipulator", ())])
def test_every_name_in_solve_json_is_defined(tmp_path: Path, capsys, model: str,
                                             options: tuple[str, ...]) -> None:
    """The issue: ``"J1_fV_1": "J1_pV_1"`` with ``J1_pV_1`` defined nowhere (a joint's
    parent-twist input that only an output reads)."""
    folder = _write(tmp_path / "multi", MULTI) if model == "multi" else \
        Path(__file__).resolve().parent.parent / "examples" / "manipulator"
    assert main(["solve", str(folder), "--format", "json", *options]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outputs"] and not _undefined(out)


def test_exports_name_every_joint_and_the_urdf_ball_has_solves_coordinates(
        tmp_path: Path) -> None:
    """Every link, body and joint name of the URDF and MJCF exports is in names.json; the
    URDF's three revolute joints of the ball joint are its yaw, pitch and roll (coordinates
    ``[1]``…``[3]``), so Pinocchio's mass matrix of the URDF at cyphy's coordinates is
    cyphy's."""
    import re

    from robot_exports import pinocchio_mass

    folder = _write(tmp_path / "multi", MULTI)
    for target, extra in (("urdf", ()), ("mjcf", ()), ("mjcf", ("--mjcf-free-base",))):
        out = tmp_path / f"{target}{len(extra)}"
        assert main(["gen", f"--{target}", str(folder), "-o", str(out), *extra]) == 0
        [table_file] = out.glob("*.names.json")
        table = json.loads(table_file.read_text())
        assert len(set(table.values())) == len(table)  # it inverts
        for path in out.glob("*.urdf" if target == "urdf" else "*.xml"):
            text = path.read_text()
            named = set(re.findall(r'<(?:link|body|joint|freejoint) name="([^"]+)"', text))
            assert named <= set(table), named - set(table)
    table = json.loads((tmp_path / "urdf0" / "Multi.names.json").read_text())
    exported = {qualified: name for name, qualified in table.items()}
    tree = dynamics.kinematic_tree(_elaborated(folder))
    coordinates = [exported[f"{j.name}[{k}]" if k > 1 else j.name]
                   for j in tree.joints for k in range(1, j.dof + 1)]
    rng = np.random.default_rng(5)
    for _ in range(3):
        q = rng.uniform(-1.2, 1.2, tree.dof)
        names, m = pinocchio_mass(tmp_path / "urdf0" / "Multi.urdf", dict(zip(coordinates, q)))
        order = [names.index(n) for n in coordinates]
        ours = dynamics.mass_matrix(tree, q)
        assert np.abs(m[np.ix_(order, order)] - ours).max() <= 1e-9 * np.abs(ours).max()


def test_simulate_of_a_free_body_at_rest_near_pitch_half_pi_falls(tmp_path: Path) -> None:
    """The issue: at pitch π/2 − 1e-6 at rest, `simulate` ran past 600 s. Now it falls
    (z = −g·t²/2, by hand) without turning, in both paths."""
    from test_dynamics_joints import FREE

    folder = _write(tmp_path / "free", FREE)
    from cyphy import api
    from cyphy.backends.simulate import SimulationOptions

    pitch = np.pi / 2 - 1e-6
    for numeric in (False, True):
        settings = SimulationOptions(t_end=1.0, samples=3, init={"Body_pitch": pitch})
        result = api.simulate([folder], api.SimulateOptions(
            simulation=settings, numeric=numeric, floating_base=True))
        assert result.trajectory is not None, result.report.diagnostics
        z = result.trajectory.column("Body_z")
        assert z[-1] == pytest.approx(-9.81 / 2, rel=1e-6)
        assert np.abs(result.trajectory.column("Body_pitch") - pitch).max() < 1e-9


@pytest.mark.parametrize("command", [
    ["check"], ["show"], ["show", "--format", "json"], ["solve"], ["solve", "--floating-base"],
    ["simulate", "--t-end", "0.05", "--samples", "3"],
    ["simulate", "--t-end", "0.05", "--samples", "3", "--numeric", "--floating-base"],
    ["gen", "--sdf"], ["gen", "--urdf"], ["gen", "--mjcf"], ["gen", "--mjcf", "--mjcf-free-base"],
    ["view"]])
def test_every_command_takes_ball_and_universal_joints(tmp_path: Path, capsys,
                                                       command: list[str]) -> None:
    """The issue: `show` exited 70 on a ball or universal joint while the other commands
    worked. Each command on the ball–universal chain succeeds and prints no traceback."""
    folder = _write(tmp_path / "multi", MULTI)
    extra = ["-o", str(tmp_path / "out")] if command[0] == "gen" else \
        ["-o", str(tmp_path / "v.png")] if command[0] == "view" else []
    assert main([*command, str(folder), *extra]) == 0
    captured = capsys.readouterr()
    assert "internal error" not in captured.err and "Traceback" not in captured.err
    assert captured.out or extra or command == ["check"]
