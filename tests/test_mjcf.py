"""``cyphy gen --mjcf``: MJCF that MuJoCo loads and steps, and the cross-check of the
exports: mass matrices of Pinocchio (URDF), PyBullet (URDF) and MuJoCo (MJCF) agree."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.cli import main
from robot_exports import compare, mujoco_mass, pinocchio_mass, pybullet_mass

MODELS = {"manipulator": "Manipulator", "marxbot": "marXbotBase", "dcmotor": "DCMotorBase"}


def _gen(out: Path, example: str) -> tuple[Path, Path]:
    for target in ("urdf", "mjcf"):
        assert main(["gen", str(EXAMPLES / example), f"--{target}", "-o", str(out)]) == 0
    return out / f"{MODELS[example]}.urdf", out / f"{MODELS[example]}.xml"


def _step(mjcf: Path, seconds: float = 1.0) -> tuple[float, float]:
    """Step the model from rest for ``seconds`` without controls: (largest |qvel|, largest
    rise of the total energy above its start, relative to the energy of lifting the whole
    robot by 1 m)."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(mjcf))
    model.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    start = float(data.energy.sum())
    rise, speed = 0.0, 0.0
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
        assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))
        speed = max(speed, float(np.abs(data.qvel).max(initial=0.0)))
        rise = max(rise, float(data.energy.sum()) - start)
    return speed, rise / (float(model.body_mass.sum()) * 9.81)


@pytest.mark.parametrize("example", sorted(MODELS))
def test_examples_load_step_and_agree(tmp_path: Path, example: str, capsys) -> None:
    urdf, mjcf = _gen(tmp_path, example)
    speed, rise = _step(mjcf)
    # Gravity, damping and contacts only: bodies that overlap in the model (the manipulator's
    # gripper and arm) push apart at the start, which may add a little energy, never much.
    assert speed < 10.0 and rise < 0.01
    names = pinocchio_mass(urdf, {})[0]
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = dict(zip(names, rng.uniform(-1.0, 1.0, len(names)).tolist()))
        assert compare({"pinocchio": pinocchio_mass(urdf, q), "pybullet": pybullet_mass(urdf, q),
                        "mujoco": mujoco_mass(mjcf, q)}) < 1e-9


def test_manipulator_motors_and_ranges(tmp_path: Path, capsys) -> None:
    _, mjcf = _gen(tmp_path, "manipulator")
    root = ET.parse(mjcf).getroot()
    motors = {m.get("joint"): m.get("ctrlrange") for m in root.iter("motor")}
    assert motors == {"Stand__Shoulder": "-20 20", "Arm__Slide": "-50 50",
                      "Forearm__Lift": "-30 30"}
    slide = root.find(".//joint[@name='Arm__Slide']")
    assert (slide.get("type"), slide.get("range"), slide.get("axis")) == ("slide", "0 0.3",
                                                                          "1 0 0")
    again = tmp_path / "again"
    _gen(again, "manipulator")
    assert (again / "Manipulator.xml").read_bytes() == mjcf.read_bytes()
    faulty = tmp_path / "faulty"
    assert main(["gen", str(EXAMPLES / "faulty"), "--mjcf", "-o", str(faulty)]) == 1
    assert not faulty.exists()
    assert main(["gen", str(EXAMPLES / "dcmotor"), "--mjcf", "--urdf-package", "p"]) == 2


FOUR_BAR = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Bar {
  local link Ground {
    def { inertial information { mass 1.0 } }
    local body G { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref A = Revolute { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } } flexibly connected to Crank }
    jref D = Revolute { pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } } flexibly connected to Rocker }
  }
  local link Crank {
    def { inertial information { mass 0.5 } }
    local body C { pose { x = 0 y = 0 z = 0.25 roll = 0 pitch = 0 yaw = 0 }
      def { box(length = 0.02, width = 0.02, height = 0.5) } }
    jref B = Revolute { pose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } } flexibly connected to Coupler }
  }
  local link Coupler {
    pose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.5 } }
    local body K { pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      def { box(length = 1, width = 0.02, height = 0.02) } }
    jref C = Revolute { pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } } flexibly connected to Rocker }
  }
  local link Rocker {
    pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.5 } }
    local body R { pose { x = 0 y = 0 z = 0.25 roll = 0 pitch = 0 yaw = 0 }
      def { box(length = 0.02, width = 0.02, height = 0.5) } }
  }
}
"""


def test_a_closed_chain_becomes_an_equality_constraint(tmp_path: Path) -> None:
    """The four-bar's coupler-rocker joint is cut (W-SDF-CUT) and closed again by a connect
    at its origin: stepping keeps the two bodies together there."""
    import mujoco

    model_file = tmp_path / "Bar.rsm"
    model_file.write_text(FOUR_BAR)
    result = api.generate_mjcf([model_file], api.TreeGenOptions(output=str(tmp_path)))
    assert [d.code.id for d in result.report.diagnostics].count("W-SDF-CUT") == 1
    (tmp_path / "Bar.xml").write_text(result.files["Bar.xml"])  # type: ignore[arg-type]
    (connect,) = ET.parse(tmp_path / "Bar.xml").getroot().iter("connect")
    # joint C: 1 m along the coupler (in its frame), where the rocker's top is
    assert (connect.get("body1"), connect.get("body2"), connect.get("anchor")) == \
        ("Coupler", "Rocker", "1 0 0")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "Bar.xml"))
    data = mujoco.MjData(model)
    data.qvel[:] = 1.0
    for _ in range(1000):
        mujoco.mj_step(model, data)
    assert np.all(np.isfinite(data.qpos))
    body1 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, connect.get("body1"))
    body2 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, connect.get("body2"))
    anchor = np.array([float(v) for v in connect.get("anchor").split()])
    on1 = data.xpos[body1] + data.xmat[body1].reshape(3, 3) @ anchor
    # the same material point of body 2 (where it was at the start)
    data0 = mujoco.MjData(model)
    mujoco.mj_forward(model, data0)
    start = data0.xpos[body1] + data0.xmat[body1].reshape(3, 3) @ anchor
    local2 = data0.xmat[body2].reshape(3, 3).T @ (start - data0.xpos[body2])
    on2 = data.xpos[body2] + data.xmat[body2].reshape(3, 3) @ local2
    assert np.linalg.norm(on1 - on2) < 1e-2


# ------------------------------------------------------------------ Hypothesis: random trees

def _pose(values: tuple[float, ...]) -> str:
    return "pose { " + " ".join(f"{k} = {v!r}" for k, v in zip(
        ("x", "y", "z", "roll", "pitch", "yaw"), values)) + " }"


poses = st.tuples(*[st.floats(-0.5, 0.5)] * 3, *[st.floats(-3.0, 3.0)] * 3)
links = st.tuples(
    poses,  # the link's pose
    st.tuples(*[st.floats(0.02, 0.5)] * 3),  # the box whose inertia the link has
    st.floats(0.1, 5.0),  # mass
    poses,  # the inertial frame in the link
    st.tuples(*[st.floats(-3.0, 3.0)] * 3),  # the inertia's principal axes (roll pitch yaw)
    st.sampled_from(["Revolute", "Prismatic"]),
    st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: math.hypot(*v) > 0.1),  # axis
    poses,  # the joint's pose in its parent link
)


def _tree_model(parents: list[int], specs: list) -> str:  # type: ignore[type-arg]
    from cyphy.model.poses import Pose

    text = ["import physmod::joints::Revolute", "import physmod::joints::Prismatic",
            "import physmod::sdf::annotations::*", "pmodel Random {"]
    for i, (pose, box, mass, com, axes, _, _, _) in enumerate(specs):
        a, b, c = box
        principal = np.diag([mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12,
                             mass * (a * a + b * b) / 12])
        r = np.array(Pose.from_xyz_rpy(0, 0, 0, *axes).rotation)
        full = r @ principal @ r.T
        inertia = " ".join(f"{k} {float(full[i_, j_])!r}" for k, (i_, j_) in zip(
            ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
            ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))))
        text.append(f"  local link L{i} {{ {_pose(pose)}")
        text.append(f"    def {{ inertial information {{ mass {mass!r} inertia matrix "
                    f"{{ {inertia} }} {_pose(com)} }} }}")
        text.append(f"    local body B {{ def {{ box(length = {a!r}, width = {b!r}, "
                    f"height = {c!r}) }} }}")
        for k, parent in enumerate(parents, start=1):
            if parent == i:
                _, _, _, _, _, kind, axis, jpose = specs[k]
                text.append(f"    jref J{k} = {kind} {{ {_pose(jpose)} annotation {kind} {{ "
                            f"axis = Axis {{ xyz = (|{axis[0]!r}, {axis[1]!r}, {axis[2]!r}|) "
                            f"}} }} flexibly connected to L{k} }}")
        text.append("  }")
    text.append("}")
    return "\n".join(text) + "\n"


@settings(max_examples=15, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(st.lists(links, min_size=2, max_size=5).flatmap(
    lambda specs: st.tuples(st.just(specs), st.tuples(
        *[st.integers(0, i) for i in range(len(specs) - 1)]))),
    st.lists(st.floats(-2.0, 2.0), min_size=4, max_size=4))
def test_random_trees_mass_matrices_agree(tmp_path_factory, tree, q_values) -> None:
    """Chains and trees of 2-5 links with rotated inertials, tilted joints and random axes:
    the three tools' mass matrices agree to 1e-9 (relative to the largest entry)."""
    specs, parents = tree
    folder = tmp_path_factory.mktemp("random")
    (folder / "Random.rsm").write_text(_tree_model(list(parents), specs))
    options = api.TreeGenOptions(output=str(folder))
    urdf_result = api.generate_urdf([folder / "Random.rsm"], options)
    mjcf_result = api.generate_mjcf([folder / "Random.rsm"], options)
    assert urdf_result.files, [str(d) for d in urdf_result.report.diagnostics]
    for result in (urdf_result, mjcf_result):
        for name, text in result.files.items():
            (folder / name).write_text(text)  # type: ignore[arg-type]
    urdf, mjcf = folder / "Random.urdf", folder / "Random.xml"
    names = pinocchio_mass(urdf, {})[0]
    assert len(names) == len(specs) - 1
    q = dict(zip(names, q_values))
    assert compare({"pinocchio": pinocchio_mass(urdf, q), "pybullet": pybullet_mass(urdf, q),
                    "mujoco": mujoco_mass(mjcf, q)}) < 1e-9


@needs_corpus
def test_corpus_mjcf_loads_and_steps(tmp_path: Path) -> None:
    """Every corpus model we accept gives MJCF that MuJoCo loads and steps for 1 s with
    finite, bounded velocities."""
    import mujoco
    from test_conformance_elaboration import _consts, _model_files
    from test_urdf import _corpus_models

    loaded = 0
    for example, name in _corpus_models():
        out = tmp_path / example.replace("/", "_")
        result = api.generate_mjcf(_model_files(CORPUS / example), api.TreeGenOptions(
            model=name, consts=_consts(example, name), output=str(out)))
        if result.report.has_errors:
            assert not result.files
            continue
        out.mkdir(parents=True, exist_ok=True)
        (out / f"{name}.xml").write_text(result.files[f"{name}.xml"])  # type: ignore[arg-type]
        model = mujoco.MjModel.from_xml_path(str(out / f"{name}.xml"))
        data = mujoco.MjData(model)
        for _ in range(1000):
            mujoco.mj_step(model, data)
        assert np.all(np.isfinite(data.qpos)), (example, name)
        assert float(np.abs(data.qvel).max(initial=0.0)) < 1e3, (example, name)
        loaded += 1
    assert loaded > 150
