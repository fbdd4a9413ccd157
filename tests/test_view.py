"""``cyphy view``: the picture shows the bodies where they are (pixels at their projected
centres are not background), at the joint positions asked for (forward kinematics checked
against Pinocchio), with V5's coincident elements in red; byte-identical, nothing on errors."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES
from cyphy import api
from cyphy.cli import main


def _pixels(png: bytes) -> np.ndarray:
    import matplotlib.image

    return matplotlib.image.imread(io.BytesIO(png), format="png")[:, :, :3]


def _not_background(image: np.ndarray, centre: tuple[float, float]) -> bool:
    """Most of the 5 x 5 pixels around ``centre`` differ from the white background."""
    column, row = (round(v) for v in centre)
    patch = image[row - 2:row + 3, column - 2:column + 3]
    return bool((np.abs(patch - 1.0).max(axis=2) > 0.1).mean() > 0.8)


@pytest.mark.parametrize("example, bodies", [
    ("manipulator", {"Stand__Foot", "Stand__Column", "Arm__Beam", "Forearm__Tube",
                     "Gripper__Palm", "Gripper__Finger_0", "Gripper__Finger_1"}),
    ("marxbot", None)])
def test_bodies_show_where_projected(example: str, bodies: set[str] | None) -> None:
    generated, picture = api.view([EXAMPLES / example])
    assert picture is not None and len(generated.files) == 1
    image = _pixels(picture.png)
    assert image.shape[:2] == (800, 1000)
    if bodies is not None:
        assert set(picture.centres) == bodies
    assert len(picture.centres) >= 5
    for name, centre in picture.centres.items():
        assert _not_background(image, centre), name
    for corner in ((5, 5), (5, 994), (794, 5), (794, 994)):
        assert np.allclose(image[corner], 1.0)  # the background is white
    again = api.view([EXAMPLES / example])[1]
    assert again.png == picture.png  # byte-identical


def test_set_moves_the_links_as_pinocchio_does(tmp_path: Path) -> None:
    """--set Shoulder=π/2 turns the arm to +y: the bodies show where they have moved, and
    the forward kinematics agrees with Pinocchio on the URDF."""
    import pinocchio
    from cyphy.semantics.sdf.robot_tree import moved

    request = api.ViewRequest(positions={"Shoulder": math.pi / 2, "Arm::Slide": 0.2,
                                         "Manipulator::Forearm::Lift": 0.1})
    turned = api.view([EXAMPLES / "manipulator"], request)[1]
    image = _pixels(turned.png)
    for name, centre in turned.centres.items():
        assert _not_background(image, centre), name
    generated, robot, _ = api.robot([EXAMPLES / "manipulator"], api.TreeGenOptions(), "urdf")
    q = {"Stand__Shoulder": math.pi / 2, "Arm__Slide": 0.2, "Forearm__Lift": 0.1}
    motion = moved(robot, q)
    urdf = tmp_path / "m.urdf"
    urdf.write_text(api.generate_urdf([EXAMPLES / "manipulator"]).files["Manipulator.urdf"])
    model = pinocchio.buildModelFromUrdf(str(urdf))
    data = model.createData()
    config = pinocchio.neutral(model)
    for name, value in q.items():
        config[model.joints[model.getJointId(name)].idx_q] = value
    pinocchio.forwardKinematics(model, data, config)
    for joint in robot.joints():
        ours = motion[joint.child].compose(joint.frame)  # the child's URDF frame, moved
        theirs = data.oMi[model.getJointId(joint.name)]
        assert np.allclose(ours.position, theirs.translation, atol=1e-12), joint.name
        assert np.allclose(ours.rotation, theirs.rotation, atol=1e-12), joint.name


TWINS = """\
pmodel Twins {
  local link Left {
    def { inertial information { mass 1.0 } }
    local body Block { def { box(length = 0.2, width = 0.2, height = 0.2) } }
  }
  local link Right {
    def { inertial information { mass 1.0 } }
    local body Block { def { box(length = 0.2, width = 0.2, height = 0.2) } }
    fixed to Left
  }
  local link Other {
    pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1.0 } }
    local body Block { def { box(length = 0.2, width = 0.2, height = 0.2) } }
    fixed to Left
  }
}
"""


def test_coincident_links_are_red(tmp_path: Path) -> None:
    model = tmp_path / "Twins.rsm"
    model.write_text(TWINS)
    generated, picture = api.view([model])
    assert "V5" in [d.code.id for d in generated.report.diagnostics]
    image = _pixels(picture.png)

    def reddish(centre: tuple[float, float]) -> bool:
        """Most pixels around the centre (the link frame's lines cross it) are red."""
        column, row = (round(v) for v in centre)
        patch = image[row - 10:row + 11, column - 10:column + 11]
        r, g, b = patch[..., 0], patch[..., 1], patch[..., 2]
        return bool(((r > 0.4) & (r > 2 * g) & (r > 2 * b)).mean() > 0.6)

    assert reddish(picture.centres["Right__Block"]) and reddish(picture.centres["Left__Block"])
    assert not reddish(picture.centres["Other__Block"])


def test_cli_writes_the_picture_or_nothing(tmp_path: Path, capsys) -> None:
    out = tmp_path / "pictures" / "arm.png"
    assert main(["view", str(EXAMPLES / "manipulator"), "-o", str(out), "--view", "top",
                 "--set", "Shoulder=0.5"]) == 0
    assert out.read_bytes().startswith(b"\x89PNG")
    assert main(["view", str(EXAMPLES / "faulty"), "-o", str(tmp_path / "f.png")]) == 1
    assert not (tmp_path / "f.png").exists()
    assert main(["view", str(EXAMPLES / "manipulator"), "-o", str(tmp_path / "g.png"),
                 "--set", "Elbow=1"]) == 1
    err = capsys.readouterr().err
    assert "E-VIEW-JOINT" in err and "Manipulator::Stand::Shoulder" in err
    assert not (tmp_path / "g.png").exists()
    assert main(["view", str(EXAMPLES / "manipulator"), "--set", "Shoulder"]) == 2
    assert main(["view", str(EXAMPLES / "manipulator"), "-o", "x.jpg"]) == 2
