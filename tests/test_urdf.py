"""``cyphy gen --urdf``: URDF 1.0 that check_urdf, PyBullet and Pinocchio accept, with the
model's geometry re-expressed in URDF's joint frames (checked against the SDF's poses)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.cli import main
from robot_exports import check_urdf, pinocchio_mass, pybullet_mass

MODELS = {"manipulator": "Manipulator", "marxbot": "marXbotBase", "dcmotor": "DCMotorBase"}


def _gen(tmp_path: Path, example: str, *extra: str) -> Path:
    out = tmp_path / example
    assert main(["gen", str(EXAMPLES / example), "--urdf", "-o", str(out), *extra]) == 0
    return out / f"{MODELS[example]}.urdf"


@pytest.mark.parametrize("example", sorted(MODELS))
def test_examples_pass_check_urdf_and_load(tmp_path: Path, example: str, capsys) -> None:
    urdf = _gen(tmp_path, example)
    assert check_urdf(urdf) == ""
    names, M = pinocchio_mass(urdf, {})
    bullet_names, _ = pybullet_mass(urdf, {})
    assert names and sorted(names) == sorted(bullet_names)
    assert np.all(np.linalg.eigvalsh(M) > 0)


def test_manipulator_frames_match_the_sdf(tmp_path: Path, capsys) -> None:
    """Forward kinematics of the URDF at q = 0 (Pinocchio) puts every link's centre of mass
    where the SDF (model frame) puts it, and the joint axes point the model's way."""
    import pinocchio

    urdf = _gen(tmp_path, "manipulator")
    model = pinocchio.buildModelFromUrdf(str(urdf))
    data = model.createData()
    pinocchio.forwardKinematics(model, data, pinocchio.neutral(model))
    arm = model.getJointId("Stand__Shoulder")  # the shoulder: on the column, at z 0.41
    assert np.allclose(data.oMi[arm].translation, [0, 0, 0.41])
    sdf = ET.fromstring(api.generate_sdf([EXAMPLES / "manipulator"]).files[
        "Manipulator.sdf"])
    com = {}
    for link in sdf.iter("link"):
        pose = [float(v) for v in link.find("pose").text.split()]
        inertial = [float(v) for v in link.find("inertial/pose").text.split()]
        assert pose[3:] == [0, 0, 0] and inertial[3:] == [0, 0, 0]
        com[link.get("name")] = np.array(pose[:3]) + inertial[:3]
    child = {j.find("child").text: j.get("name") for j in sdf.iter("joint")}
    for link, joint in child.items():
        i = model.getJointId(joint)
        assert np.allclose(data.oMi[i].act(model.inertias[i].lever), com[link]), link
    assert np.allclose(model.inertias[0].lever, com["Stand"])  # the root, fixed to the world
    lift = ET.parse(urdf).getroot().find("joint[@name='Forearm__Lift']")
    assert lift.get("type") == "prismatic" and lift.find("axis").get("xyz") == "0 0 -1"
    limit = lift.find("limit")
    assert (limit.get("lower"), limit.get("upper"), limit.get("effort")) == ("0", "0.15", "30")


def test_byte_identical_and_errors_write_nothing(tmp_path: Path, capsys) -> None:
    first = _gen(tmp_path / "a", "marxbot").read_bytes()
    assert _gen(tmp_path / "b", "marxbot").read_bytes() == first
    out = tmp_path / "faulty"
    assert main(["gen", str(EXAMPLES / "faulty"), "--urdf", "-o", str(out)]) == 1
    assert not out.exists()
    assert main(["gen", str(EXAMPLES / "dcmotor"), "--urdf", "--short-names"]) == 2
    assert "--short-names is an option of --sdf, not of --urdf" in capsys.readouterr().err


LOOP = """
pmodel Loop {
  local link A {
    def { inertial information { mass 1.0 } }
    local body Cube { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref J1 = Revolute { flexibly connected to B
      annotation Revolute { axis = Axis { xyz = (|0,0,1|) } } }
    jref J2 = Revolute { flexibly connected to C
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } } }
  }
  local link B {
    pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1.0 } }
    local body Cube { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref J3 = Revolute { flexibly connected to C
      annotation Revolute { axis = Axis { xyz = (|1,0,0|) } } }
  }
  local link C {
    pose { x = 1 y = 1 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1.0 } }
    local body Ball { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      def { sphere(radius = 0.1) } }
  }
  local link Free {
    pose { x = 3 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 2.0 } }
    local body Part { def { mesh { shape "../outside.stl" scaling 1 } } }
  }
}
"""


def test_loops_cut_and_forests_split(tmp_path: Path) -> None:
    model = tmp_path / "m" / "Loop.rsm"
    model.parent.mkdir()
    model.write_text("import physmod::joints::Revolute\nimport physmod::sdf::annotations::*\n"
                     + LOOP)
    (tmp_path / "outside.stl").write_text("solid x\nendsolid x\n")
    result = api.generate_urdf([model], api.TreeGenOptions(output=str(tmp_path / "out")))
    codes = [d.code.id for d in result.report.diagnostics]
    assert codes.count("W-SDF-CUT") == 1 and [d.code.id for d in result.report.diagnostics
                                                       if "outside the model's folder"
                                                       in d.message] == ["V2"]
    assert "W-SDF-SENSOR" not in codes
    assert sorted(result.files) == ["Loop.names.json", "Loop__A.urdf", "Loop__Free.urdf"]
    (cut,) = [d for d in result.report.diagnostics if d.code.id == "W-SDF-CUT"]
    assert "joint Loop::B::J3" in cut.message and "left out for URDF" in cut.message
    for name in ("Loop__A.urdf", "Loop__Free.urdf"):
        (tmp_path / "out").mkdir(exist_ok=True)
        (tmp_path / "out" / name).write_text(result.files[name])
        assert check_urdf(tmp_path / "out" / name) == ""
    free = ET.fromstring(result.files["Loop__Free.urdf"])
    # The mesh path is relative to the output folder: ../m is the model folder.
    assert free.find("link/visual/geometry/mesh").get("filename") == "../outside.stl"
    tree = ET.fromstring(result.files["Loop__A.urdf"])
    assert [j.get("name") for j in tree.iter("joint")] == ["A__J1", "A__J2"]
    assert [j.get("type") for j in tree.iter("joint")] == ["continuous"] * 2
    packaged = api.generate_urdf([model], api.TreeGenOptions(package="loop"))
    mesh = ET.fromstring(packaged.files["Loop__Free.urdf"]).find(".//mesh")
    assert mesh.get("filename") == "package://loop/../outside.stl"



def _corpus_models() -> list[tuple[str, str]]:
    if not CORPUS.is_dir():
        return []
    from test_conformance_elaboration import EXAMPLES as CORPUS_EXAMPLES, read_expected

    return [(e, read_expected(s).model) for e in CORPUS_EXAMPLES
            for s in sorted((CORPUS / e / "expected").glob("*.sdf"))]


@needs_corpus
def test_corpus_urdf_passes_check_urdf(tmp_path: Path) -> None:
    """Every corpus model we accept (trees, and forests and loops made trees) gives URDF
    that check_urdf accepts and Pinocchio builds."""
    import pinocchio
    from test_conformance_elaboration import _consts, _model_files

    written = 0
    for example, name in _corpus_models():
        result = api.generate_urdf(_model_files(CORPUS / example), api.TreeGenOptions(
            model=name, consts=_consts(example, name), output=str(tmp_path)))
        if result.report.has_errors:
            assert not result.files
            continue
        for file, text in result.files.items():
            if file.endswith(".urdf"):
                path = tmp_path / example.replace("/", "_") / file
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(text)  # type: ignore[arg-type]
                assert check_urdf(path) == "", (example, name, check_urdf(path))
                pinocchio.buildModelFromUrdf(str(path))
                written += 1
    assert written > 150


MULTI_AXIS = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Multi {
  local link Base {
    def { inertial information { mass 1.0 } }
    local body B { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref Shoulder = Revolute { pose { x = 0 y = 0 z = 0.1 roll = 0 pitch = 0 yaw = 0 }
      annotation Ball { } flexibly connected to Upper }
  }
  local link Upper {
    pose { x = 0 y = 0 z = 0.1 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.5 } }
    local body U { pose { x = 0 y = 0 z = 0.2 roll = 0 pitch = 0 yaw = 0 }
      def { cylinder(radius = 0.02, length = 0.4) } }
    jref Wrist = Revolute { pose { x = 0 y = 0 z = 0.4 roll = 0 pitch = 0 yaw = 0 }
      annotation Universal { axis = Axis { xyz = (|1,0,0|) } axis2 = Axis { xyz = (|0,1,0|) } }
      flexibly connected to Hand }
  }
  local link Hand {
    pose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.2 } }
    local body H { def { sphere(radius = 0.05) } }
  }
}
"""


def test_ball_and_universal_joints(tmp_path: Path) -> None:
    """URDF: a ball joint as three revolute joints, a universal joint as two, through
    massless links (W-URDF-JOINT each); MJCF keeps them (a ball, two hinges in one body)."""
    import mujoco
    import pinocchio

    model_file = tmp_path / "Multi.rsm"
    model_file.write_text(MULTI_AXIS)
    options = api.TreeGenOptions(output=str(tmp_path))
    urdf = api.generate_urdf([model_file], options)
    assert [d.code.id for d in urdf.report.diagnostics].count("W-URDF-JOINT") == 2
    (tmp_path / "Multi.urdf").write_text(urdf.files["Multi.urdf"])  # type: ignore[arg-type]
    assert check_urdf(tmp_path / "Multi.urdf") == ""
    robot = ET.parse(tmp_path / "Multi.urdf").getroot()
    axes = [(j.get("name"), j.find("axis").get("xyz")) for j in robot.iter("joint")]
    # the ball joint's yaw, pitch and roll (ZYX), the coordinates of solve and simulate
    assert axes == [("Base__Shoulder", "0 0 1"), ("Base__Shoulder__2", "0 1 0"),
                    ("Base__Shoulder__3", "1 0 0"), ("Upper__Wrist", "1 0 0"),
                    ("Upper__Wrist__2", "0 1 0")]
    assert pinocchio.buildModelFromUrdf(str(tmp_path / "Multi.urdf")).nv == 5
    mjcf = api.generate_mjcf([model_file], api.TreeGenOptions(output=str(tmp_path),
                                                               free_base=True))
    (tmp_path / "Multi.xml").write_text(mjcf.files["Multi.xml"])  # type: ignore[arg-type]
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "Multi.xml"))
    assert model.nv == 6 + 3 + 2  # free base, ball, two hinges
    assert sorted(int(t) for t in model.jnt_type) == sorted(int(t) for t in (
        mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_BALL, mujoco.mjtJoint.mjJNT_HINGE,
        mujoco.mjtJoint.mjJNT_HINGE))
