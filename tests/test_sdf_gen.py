"""``cyphy gen --sdf``: exact XML for the cases sdf.md decides, the CLI's files and options,
and the validity gate (libsdformat 12 strict + ``ign sdf -k`` checks + tree lints, PyBullet)
on every SDF these tests generate."""

from __future__ import annotations

import json
import math
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from cyphy import api
from cyphy.backends.robot_formats.sdf_xml import number, xyz_rpy
from cyphy.cli import main
from cyphy.model.poses import Pose

pytest_plugins = ["sdf_tools.fixtures"]

HEADER = """package t
import physmod::sdf::annotations::*
import physmod::math::*
import physmod::joints::Revolute
"""


def generate(tmp_path: Path, body: str, **options: object) -> tuple[api.Generated, str]:
    """Generate SDF for a model (``HEADER`` + ``body``); return the result and the SDF text."""
    path = tmp_path / "m.rsm"
    path.write_text(HEADER + textwrap.dedent(body))
    result = api.generate_sdf([path], api.SdfGenOptions(**options))  # type: ignore[arg-type]
    errors = [f"{d.code.id}: {d.message}" for d in result.report.diagnostics
              if d.severity.name == "ERROR"]
    assert not errors, errors
    sdf = next(v for k, v in result.files.items() if k.endswith(".sdf"))
    (tmp_path / "out.sdf").write_text(sdf)  # type: ignore[arg-type]
    return result, sdf  # type: ignore[return-value]


def fragment(sdf: str, path: str) -> str:
    """The element at ``path`` (ElementTree syntax, from ``<model>``), re-indented."""
    element = ET.fromstring(sdf.split("\n", 1)[1]).find("model/" + path)
    assert element is not None, path
    element.tail = None
    ET.indent(element, space="  ")
    return ET.tostring(element, encoding="unicode")


def codes(result: api.Generated) -> list[str]:
    return [d.code.id for d in result.report.diagnostics]


def valid(sdf_checker: Path, pybullet_loader, path: Path, joints: int | None = None) -> None:
    from sdf_tools import check_sdf

    assert check_sdf([path]) == {path: []}
    assert pybullet_loader(path, expect_joints=joints) is None


# --------------------------------------------------------------------------- exact fragments


def test_inertial_combined_from_bodies(tmp_path, sdf_checker, pybullet_loader) -> None:
    """Rule 4: box 3 kg at x=0.1 (0.2×0.1×0.1), ball 1 kg at x=−0.2 (r 0.1): mass 4, centre
    (3·0.1 − 0.2)/4 = 0.025; ixx = 3·0.02/12 + 0.4·0.01 = 0.009; iyy = izz = 3·0.05/12 +
    3·0.075² + 0.004 + 0.225² = 0.084."""
    _, sdf = generate(tmp_path, """
        pmodel M {
        \tlocal link L {
        \t\tdef {}
        \t\tlocal body A {
        \t\t\tpose { x = 0.1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
        \t\t\tdef { box(length = 0.2, width = 0.1, height = 0.1) inertial information { mass 3 } }
        \t\t}
        \t\tlocal body S {
        \t\t\tpose { x = -0.2 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
        \t\t\tdef { sphere(radius = 0.1) inertial information { mass 1 } }
        \t\t}
        \t}
        }
        """)
    assert fragment(sdf, "link[@name='L']/inertial") == textwrap.dedent("""\
        <inertial>
          <pose>0.025 0 0 0 0 0</pose>
          <mass>4</mass>
          <inertia>
            <ixx>0.009</ixx>
            <ixy>0</ixy>
            <ixz>0</ixz>
            <iyy>0.084</iyy>
            <iyz>0</iyz>
            <izz>0.084</izz>
          </inertia>
        </inertial>""")
    assert fragment(sdf, "link[@name='L']/collision[@name='L__S_collision']") == \
        textwrap.dedent("""\
        <collision name="L__S_collision">
          <pose>-0.2 0 0 0 0 0</pose>
          <geometry>
            <sphere>
              <radius>0.1</radius>
            </sphere>
          </geometry>
        </collision>""")
    assert "<!-- link M::L -->" in sdf and "<!-- body M::L::A -->" in sdf
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 0)


TWO_LINKS = """
    pmodel M {
    \tlocal link L {
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t\tJOINT
    \t}
    \tlocal link U {
    \t\tpose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = PI/2 }
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t}
    }
"""


def test_revolute_joint_with_annotation(tmp_path, sdf_checker, pybullet_loader) -> None:
    """Type from the template, pose relative to the child (U is 0.5 up and turned by π/2; the
    joint sits 0.2 up in L: in U's frame it is 0.3 down and turned back), limits given and the
    rest of the template's defaults."""
    joint = ("local joint J { pose { x = 0 y = 0 z = 0.2 roll = 0 pitch = 0 yaw = 0 } "
             "def { annotation Revolute { axis = Axis { xyz = (|1,0,0|) "
             "limit = Limit { lower = -1.5 upper = 1.5 } } } } flexibly connected to U }")
    result, sdf = generate(tmp_path, TWO_LINKS.replace("JOINT", joint))
    assert fragment(sdf, "joint") == textwrap.dedent("""\
        <joint name="L__J" type="revolute">
          <pose>0 0 -0.3 0 0 -1.5707963267948966</pose>
          <parent>L</parent>
          <child>U</child>
          <axis>
            <xyz>1 0 0</xyz>
            <initial_position>0</initial_position>
            <use_parent_model_frame>false</use_parent_model_frame>
            <dynamics>
              <damping>0</damping>
              <friction>0</friction>
              <spring_reference>0</spring_reference>
              <spring_stiffness>0</spring_stiffness>
            </dynamics>
            <limit>
              <lower>-1.5</lower>
              <upper>1.5</upper>
              <effort>-1</effort>
              <velocity>-1</velocity>
              <stiffness>100000000</stiffness>
              <dissipation>1</dissipation>
            </limit>
          </axis>
        </joint>""")
    assert "<!-- joint M::L::J from M::L to M::U -->" in sdf
    assert "W-SDF-JOINT" not in codes(result) and "W-SDF-AXIS" not in codes(result)
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 1)


def test_joint_with_only_an_axis_constant(tmp_path, sdf_checker, pybullet_loader) -> None:
    """No annotation: a revolute joint (warning), its axis from AXIS, limits ±1e16."""
    joint = ("local joint J { def { const AXIS: vector(real, 3) = (|0, 1, 0|) } "
             "flexibly connected to U }")
    result, sdf = generate(tmp_path, TWO_LINKS.replace("JOINT", joint))
    assert fragment(sdf, "joint/axis") == textwrap.dedent("""\
        <axis>
          <xyz>0 1 0</xyz>
          <initial_position>0</initial_position>
          <use_parent_model_frame>false</use_parent_model_frame>
          <dynamics>
            <damping>0</damping>
            <friction>0</friction>
            <spring_reference>0</spring_reference>
            <spring_stiffness>0</spring_stiffness>
          </dynamics>
          <limit>
            <lower>-1e+16</lower>
            <upper>1e+16</upper>
            <effort>-1</effort>
            <velocity>-1</velocity>
            <stiffness>100000000</stiffness>
            <dissipation>1</dissipation>
          </limit>
        </axis>""")
    assert ET.fromstring(sdf.split("\n", 1)[1]).find("model/joint").get("type") == "revolute"
    assert "W-SDF-JOINT" in codes(result) and "W-SDF-AXIS" not in codes(result)
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 1)


def test_library_joint_takes_its_axis_from_the_instantiation(tmp_path) -> None:
    """``jref K = Revolute { instantiation AXIS = … }``: the library joint's own annotation
    reads the jref's AXIS."""
    joint = "jref K = Revolute { instantiation AXIS = (|0, 0, -1|) flexibly connected to U }"
    result, sdf = generate(tmp_path, TWO_LINKS.replace("JOINT", joint))
    assert "<xyz>0 0 -1</xyz>" in fragment(sdf, "joint/axis")
    assert not [c for c in codes(result) if c.startswith("W-SDF")]


def test_fixed_connection_between_two_parts(tmp_path, sdf_checker, pybullet_loader) -> None:
    _, sdf = generate(tmp_path, """
        pmodel PP {
        \tpart a = B {
        \t\tlink L1 fixed to L1 in b
        \t}
        \tpart b = B {
        \t\tpose { x = 0 y = 0 z = 0.1 roll = 0 pitch = 0 yaw = 0 }
        \t}
        }
        pmodel B {
        \tlocal link L1 {
        \t\tdef {}
        \t\tlocal body Box { def { box(length = 0.1, width = 0.2, height = 0.05) inertial information { mass 2 } } }
        \t}
        }
        """, model="PP")
    assert fragment(sdf, "joint") == textwrap.dedent("""\
        <joint name="a__L1__fixed__b__L1" type="fixed">
          <pose>0 0 0 0 0 0</pose>
          <parent>a__L1</parent>
          <child>b__L1</child>
        </joint>""")
    assert "<!-- fixed joint PP::a::L1::fixedJoint::PP::b::L1 from PP::a::L1 to PP::b::L1 -->" \
        in sdf
    assert fragment(sdf, "link[@name='b__L1']/pose") == "<pose>0 0 0.1 0 0 0</pose>"
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 1)


RING = """
    pmodel M {
    \tlocal link L {
    \t\tdef { inertial information { mass 1 } }
    \t\tlocal body C { def { cylinder(radius = 0.1, length = 0.02) } }
    \t\tSENSOR
    \t}
    }
"""


def test_indexed_sensors_with_trigonometric_positions(tmp_path, sdf_checker,
                                                       pybullet_loader) -> None:
    """sin and cos are evaluated (RoboTool prints 0): four sensors on a circle of 0.1 m."""
    sensor = ("local sensor Ring { index i : [0, 4) pose { x = (0.1*cos(i*PI/2))m "
              "y = (0.1*sin(i*PI/2))m z = 0 roll = 0 pitch = 0 yaw = i*PI/2 } "
              "def { annotation Sonar { sonar = SonarDetails { max = 2.0 } } } }")
    _, sdf = generate(tmp_path, RING.replace("SENSOR", sensor))
    poses = [fragment(sdf, f"link/sensor[@name='L__Ring_{i}']/pose") for i in range(4)]
    assert poses == [
        "<pose>0.1 0 0 0 0 0</pose>",
        "<pose>0 0.1 0 0 0 1.5707963267948966</pose>",
        "<pose>-0.1 0 0 0 0 3.141592653589793</pose>",
        "<pose>0 -0.1 0 0 0 -1.5707963267948968</pose>",
    ]
    assert "<!-- sensor M::L::Ring::3 -->" in sdf
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 0)


def test_sensor_template_with_defaults(tmp_path, sdf_checker, pybullet_loader) -> None:
    """An empty Sonar annotation: SensorBase's and SonarDetails's defaults are written."""
    sensor = "local sensor S { def { annotation Sonar {} } }"
    _, sdf = generate(tmp_path, RING.replace("SENSOR", sensor))
    assert fragment(sdf, "link/sensor") == textwrap.dedent("""\
        <sensor name="L__S" type="sonar">
          <pose>0 0 0 0 0 0</pose>
          <always_on>false</always_on>
          <update_rate>0</update_rate>
          <visualize>false</visualize>
          <topic>__default__</topic>
          <sonar>
            <geometry>cone</geometry>
            <min>0</min>
            <max>1</max>
            <radius>0.5</radius>
          </sonar>
        </sensor>""")
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 0)


def test_actuator(tmp_path, sdf_checker, pybullet_loader) -> None:
    """A Light actuator is a <light> with a type; an unannotated one is a comment only."""
    actuator = ("local actuator Lamp { pose { x = 0 y = 0 z = 0.05 roll = 0 pitch = 0 yaw = 0 }"
                " def { annotation Light { cast_shadows = true } } } "
                "local actuator Motor { def { input u: real } }")
    result, sdf = generate(tmp_path, RING.replace("SENSOR", actuator))
    assert fragment(sdf, "link/light") == textwrap.dedent("""\
        <light name="L__Lamp" type="point">
          <pose>0 0 0.05 0 0 0</pose>
          <cast_shadows>true</cast_shadows>
          <diffuse>1 1 1 1</diffuse>
          <specular>0.1 0.1 0.1 1</specular>
          <direction>0 0 -1</direction>
        </light>""")
    assert "<!-- actuator M::L::Lamp -->" in sdf and "<!-- actuator M::L::Motor -->" in sdf
    assert "W-SDF-ACTUATOR" not in codes(result)
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 0)


def test_unannotated_sensor_is_a_wellformed_comment(tmp_path, sdf_checker) -> None:
    from sdf_tools import check_sdf

    sensor = "local sensor S { def { output d: real } }"
    result, sdf = generate(tmp_path, RING.replace("SENSOR", sensor))
    assert "W-SDF-SENSOR" in codes(result)
    assert "<sensor" not in sdf and "<!-- sensor M::L::S: has no annotation" in sdf
    assert check_sdf([tmp_path / "out.sdf"]) == {tmp_path / "out.sdf": []}


# --------------------------------------------------------------------------- printing


def test_numbers_print_as_given() -> None:
    assert [number(v) for v in (0.1 + 0.2, -0.0, 3.0, 7, 1e16, -1.2e-17, 2.5e-05, True)] == \
        ["0.3", "0", "3", "7", "1e+16", "0", "2.5e-05", "true"]


def test_rpy_matches_pose_to_xyz_rpy() -> None:
    """The written-out conversion agrees with SciPy's (``Pose.to_xyz_rpy``), gimbal lock
    included."""
    import random

    rng = random.Random(5)
    cases = [(rng.uniform(-3, 3), rng.uniform(-1.5, 1.5), rng.uniform(-3, 3)) for _ in range(200)]
    cases += [(0.3, math.pi / 2, 0.2), (0.3, -math.pi / 2, 0.2), (0, 0, math.pi)]
    for r, p, y in cases:
        pose = Pose.from_xyz_rpy(1, 2, 3, r, p, y)
        ours = Pose.from_xyz_rpy(*xyz_rpy(pose))
        assert ours.isclose(pose, 1e-9)
        assert xyz_rpy(pose)[3:] == pytest.approx(pose.to_xyz_rpy()[3:], abs=2e-7)


# --------------------------------------------------------------------------- CLI and files

MARXBOT = [str(EXAMPLES / "marxbot" / "marXbotBase.rsm"), str(EXAMPLES / "marxbot" / "Treel.rsm")]


def test_marxbot_passes_both_checks(tmp_path, sdf_checker, pybullet_loader, capsys) -> None:
    assert main(["gen", *MARXBOT, "--sdf", "-o", str(tmp_path)]) == 0
    sdf = tmp_path / "marXbotBase.sdf"
    names = json.loads((tmp_path / "marXbotBase.names.json").read_text())
    assert names["LTreel__Wheel"] == "marXbotBase::LTreel::Wheel"
    assert names["Core__Proximity_3"] == "marXbotBase::Core::Proximity::3"
    assert names["Core__Frame_collision"] == names["Core__Frame_visual"] == \
        "marXbotBase::Core::Frame"
    root = ET.parse(sdf).getroot()
    assert len(root.findall("model/link")) == 5 and len(root.findall("model/joint")) == 4
    assert len(root.findall("model/link/sensor")) == 36  # 24 + 8 + 4 rays; Acc, Gyro comments
    valid(sdf_checker, pybullet_loader, sdf, 4)


def test_outputs_are_byte_identical(tmp_path) -> None:
    for run in ("a", "b"):
        assert main(["gen", *MARXBOT, "--sdf", "-o", str(tmp_path / run)]) == 0
    for name in ("marXbotBase.sdf", "marXbotBase.names.json"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_short_names_and_their_table(tmp_path, sdf_checker) -> None:
    from sdf_tools import check_sdf

    assert main(["gen", *MARXBOT, "--sdf", "--short-names", "-o", str(tmp_path)]) == 0
    root = ET.parse(tmp_path / "marXbotBase.sdf").getroot()
    links = [link.get("name") for link in root.findall("model/link")]
    assert links == ["1-Track", "2-Wheel", "3-Track", "4-Wheel", "5-Core"]
    names = json.loads((tmp_path / "marXbotBase.names.json").read_text())
    assert names["2-Wheel"] == "marXbotBase::LTreel::Wheel"
    assert names["1--UpperRun_collision"] == "marXbotBase::LTreel::Track::UpperRun"
    assert names["Proximity_3"] == "marXbotBase::Core::Proximity::3"
    assert check_sdf([tmp_path / "marXbotBase.sdf"]) == {tmp_path / "marXbotBase.sdf": []}


def test_coppeliasim_target_turns_sensors(tmp_path) -> None:
    assert main(["gen", *MARXBOT, "--sdf", "--target", "coppeliasim", "-o", str(tmp_path)]) == 0
    root = ET.parse(tmp_path / "marXbotBase.sdf").getroot()
    pose = root.find("model/link/sensor[@name='Proximity_0']/pose").text
    assert [float(v) for v in pose.split()] == pytest.approx(
        [0.085, 0, 0, 0, 1.57079632679, 0])


def test_model_pose_option(tmp_path) -> None:
    assert main(["gen", *MARXBOT, "--sdf", "--pose", "1,2,0.5,0,0,1.5", "-o",
                 str(tmp_path)]) == 0
    root = ET.parse(tmp_path / "marXbotBase.sdf").getroot()
    assert root.find("model/pose").text == "1 2 0.5 0 0 1.5"
    with pytest.raises(SystemExit) as exit_:
        main(["gen", *MARXBOT, "--sdf", "--pose", "1,2", "-o", str(tmp_path)])
    assert exit_.value.code == 2


def test_gazebo_model_folder(tmp_path, sdf_checker) -> None:
    from sdf_tools import check_sdf

    folder = tmp_path / "marxbot_base"
    assert main(["gen", *MARXBOT, "--sdf", "--gazebo-model", str(folder)]) == 0
    assert (folder / "model.sdf").is_file()
    config = ET.parse(folder / "model.config").getroot()
    assert config.findtext("name") == "marXbotBase"
    assert config.find("sdf").text == "model.sdf" and config.find("sdf").get("version") == "1.6"
    assert check_sdf([folder / "model.sdf"]) == {folder / "model.sdf": []}


def test_model_with_errors_writes_nothing(tmp_path, capsys) -> None:
    model = tmp_path / "bad.rsm"
    model.write_text(HEADER + "pmodel M { local link L { def {} local body B { def { "
                     "box(length = 0.1, width = Nope, height = 0.1) } } } }\n")
    out = tmp_path / "out"
    assert main(["gen", str(model), "--sdf", "-o", str(out)]) == 1
    assert not out.exists() or not any(out.iterdir())
    assert "nothing written" in capsys.readouterr().err


def test_missing_constant_lists_every_one(tmp_path, capsys) -> None:
    model = tmp_path / "open.rsm"
    model.write_text(HEADER + "pmodel M { const A: real, B: real local link L { def {} "
                     "local body X { def { box(length = A, width = B, height = 0.1) } } } }\n")
    assert main(["gen", str(model), "--sdf", "-o", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "E-CONST" in err and "M::A" in err and "M::B" in err
    assert main(["gen", str(model), "--sdf", "-o", str(tmp_path / "o"), "--const", "A=0.2",
                 "--const", "B=0.1"]) == 0
    size = ET.parse(tmp_path / "o" / "M.sdf").getroot().find("model/link/collision/geometry/box")
    assert size.findtext("size") == "0.2 0.1 0.1"


def test_default_folder_is_sdf_gen_beside_the_model(tmp_path) -> None:
    model = tmp_path / "m.rsm"
    model.write_text(HEADER + "pmodel M { local link L { def { inertial information { mass 1 "
                     "} } local body X { def { sphere(radius = 0.1) } } } }\n")
    assert main(["gen", str(model), "--sdf"]) == 0
    assert (tmp_path / "sdf-gen" / "M.sdf").is_file()


@pytest.mark.parametrize("example", ["manipulator"])
def test_examples_pass_both_checks(example, tmp_path, sdf_checker, pybullet_loader) -> None:
    folder = ROOT / "examples" / example
    assert main(["gen", str(folder), "--sdf", "-o", str(tmp_path)]) == 0
    sdfs = sorted(tmp_path.glob("*.sdf"))
    assert len(sdfs) == 1
    root = ET.parse(sdfs[0]).getroot()
    joints = root.findall("model/joint")
    assert sorted(j.get("type") for j in joints) == ["prismatic", "prismatic", "revolute"]
    valid(sdf_checker, pybullet_loader, sdfs[0], 3)


# --------------------------------------------------------------------------- trees of links

FOREST = """
    pmodel F {
    \tlocal link A {
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t\tlocal joint J { def { annotation Revolute { axis = Axis { xyz = (|0,0,1|) limit = Limit { lower = -1 upper = 1 } } } } flexibly connected to B }
    \t}
    \tlocal link B {
    \t\tpose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t}
    \tlocal link C {
    \t\tpose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    \t\tdef { inertial information { mass 2 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t}
    }
"""


def test_a_forest_is_one_model_with_a_warning(tmp_path) -> None:
    result, sdf = generate(tmp_path, FOREST)
    (tree,) = [d for d in result.report.diagnostics if d.code.id == "W-SDF-TREE"]
    assert "2 links have no parent joint (F::A, F::C)" in tree.message
    assert "--split-trees" in (tree.hint or "")
    assert [m.get("name") for m in ET.fromstring(sdf.split("\n", 1)[1]).iter("model")] == ["F"]


def test_split_trees_writes_a_world_of_one_model_per_tree(tmp_path, sdf_checker,
                                                           pybullet_loader) -> None:
    result, sdf = generate(tmp_path, FOREST, split_trees=True)
    assert "W-SDF-TREE" not in codes(result)
    world = ET.fromstring(sdf.split("\n", 1)[1]).find("world")
    assert world is not None and world.get("name") == "F"
    models = {m.get("name"): m for m in world.findall("model")}
    assert list(models) == ["F__A", "F__C"]
    assert [link.get("name") for link in models["F__A"].findall("link")] == ["A", "B"]
    assert [j.get("name") for j in models["F__A"].findall("joint")] == ["A__J"]
    assert [link.get("name") for link in models["F__C"].findall("link")] == ["C"]
    assert models["F__C"].find("joint") is None
    for m in models.values():  # each tree keeps the model's own elements and pose
        assert m.findtext("self_collide") == "true" and m.findtext("pose") == "0 0 0 0 0 0"
    assert models["F__C"].find("link/pose").text == "1 0 0 0 0 0"
    assert json.loads(result.files["F.names.json"])["F__C"] == "F"
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 1)


def test_split_trees_leaves_one_tree_as_it_was(tmp_path) -> None:
    joint = "local joint J { def { annotation Revolute { axis = Axis { xyz = (|1,0,0|) } } } flexibly connected to U }"
    _, plain = generate(tmp_path, TWO_LINKS.replace("JOINT", joint))
    _, split = generate(tmp_path, TWO_LINKS.replace("JOINT", joint), split_trees=True)
    assert split == plain


def test_links_joined_in_a_cycle_are_not_a_tree(tmp_path) -> None:
    cycle = FOREST.replace("\t\tpose { x = 0 y = 0 z = 0.5", "\t\tlocal joint K { def { annotation Revolute { axis = Axis { xyz = (|0,0,1|) limit = Limit { lower = -1 upper = 1 } } } } flexibly connected to A }\n\t\tpose { x = 0 y = 0 z = 0.5")
    result, _ = generate(tmp_path, cycle, split_trees=True)
    (tree,) = [d for d in result.report.diagnostics if d.code.id == "W-SDF-TREE"]
    assert "2 links are joined in a cycle that no root reaches (F::A, F::B)" in tree.message
    assert "no parent joint" not in tree.message  # C is a tree of its own once split


def test_split_trees_and_gazebo_model_exclude_each_other(tmp_path, capsys) -> None:
    model = EXAMPLES / "manipulator"
    with pytest.raises(SystemExit) as exit_:
        main(["gen", str(model), "--sdf", "--split-trees", "--gazebo-model", str(tmp_path / "g")])
    assert exit_.value.code == 2 and "--split-trees and --target pybullet write a world" in \
        capsys.readouterr().err
    assert not (tmp_path / "g").exists()


LOOPED = """
    pmodel P {
    \tlocal link A {
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t\tlocal joint J { def { annotation Revolute { axis = Axis { xyz = (|0,0,1|) limit = Limit { lower = -1 upper = 1 } } } } flexibly connected to C }
    \t}
    \tlocal link B {
    \t\tpose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t\tfixed to C
    \t}
    \tlocal link C {
    \t\tpose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    \t\tdef { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
    \t}
    }
"""


def test_pybullet_target_turns_a_fixed_connection_into_a_moved_link_round(
        tmp_path, sdf_checker, pybullet_loader) -> None:
    """C has two parents, joint J from A and B's fixed connection; B has none. The fixed
    connection carries no motion, so written from C to B the links are one tree that J
    moves, as cyphy's dynamics has it (B rides on C): nothing is cut (it used to be, with
    B a second tree fixed to the world, which welded C to the world through B)."""
    result, plain = generate(tmp_path, LOOPED)
    assert "W-SDF-TREE" in codes(result) and "W-SDF-CUT" not in codes(result)
    result, sdf = generate(tmp_path, LOOPED, target="pybullet")
    assert "W-SDF-CUT" not in codes(result) and "W-SDF-TREE" not in codes(result)
    (model,) = ET.fromstring(sdf.split("\n", 1)[1]).iter("model")
    assert model.get("name") == "P"
    joints = {j.get("name"): (j.findtext("parent"), j.findtext("child"))
              for j in model.findall("joint")}
    assert joints == {"A__J": ("A", "C"), "B__fixed__C": ("C", "B")}
    assert "turned round for PyBullet (from P::C) to make a tree" in sdf
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 2)


def test_pybullet_target_cuts_a_fixed_connection_between_two_moved_links(
        tmp_path, sdf_checker, pybullet_loader) -> None:
    """With B moved by a joint K of its own, C fixed to B closes a chain of moving joints
    (A-J-C-B-K-A): a genuine loop, cut at the fixed connection (W-SDF-CUT)."""
    moved = LOOPED.replace(
        "flexibly connected to C }\n", "flexibly connected to C }\n"
        "\t\tlocal joint K { def { annotation Revolute { axis = Axis { xyz = (|0,0,1|) "
        "limit = Limit { lower = -1 upper = 1 } } } } flexibly connected to B }\n", 1)
    result, sdf = generate(tmp_path, moved, target="pybullet")
    (cut,) = [d for d in result.report.diagnostics if d.code.id == "W-SDF-CUT"]
    assert "fixed connection from P::B to P::C closes a kinematic loop" in cut.message
    assert cut.span.line == 15 and "W-SDF-TREE" not in codes(result)  # `fixed to C`
    (model,) = ET.fromstring(sdf.split("\n", 1)[1]).iter("model")
    assert [j.get("name") for j in model.findall("joint")] == ["A__J", "A__K"]
    assert "closes a loop: left out for PyBullet" in sdf
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 2)


def test_pybullet_target_cuts_a_cycle_at_its_first_link(tmp_path) -> None:
    cycle = FOREST.replace("\t\tpose { x = 0 y = 0 z = 0.5", "\t\tlocal joint K { def { annotation Revolute { axis = Axis { xyz = (|0,0,1|) limit = Limit { lower = -1 upper = 1 } } } } flexibly connected to A }\n\t\tpose { x = 0 y = 0 z = 0.5")
    result, sdf = generate(tmp_path, cycle, target="pybullet")
    (cut,) = [d for d in result.report.diagnostics if d.code.id == "W-SDF-CUT"]
    assert "joint F::B::K from F::B to F::A" in cut.message
    assert "W-SDF-TREE" not in codes(result)
    world = ET.fromstring(sdf.split("\n", 1)[1]).find("world")
    assert [j.get("name") for j in world.iter("joint")] == ["A__J"]


def test_pybullet_target_writes_a_gearbox_as_a_revolute_joint(tmp_path, sdf_checker,
                                                               pybullet_loader) -> None:
    joint = ("local joint G { def { annotation Gearbox { gearbox_ratio = 0.5 "
             "axis = Axis { xyz = (|1,0,0|) } axis2 = Axis { xyz = (|0,1,0|) } } } "
             "flexibly connected to U }")
    result, sdf = generate(tmp_path, TWO_LINKS.replace("JOINT", joint))
    assert fragment(sdf, "joint").startswith('<joint name="L__G" type="gearbox">')
    assert fragment(sdf, "joint/gearbox_ratio") == "<gearbox_ratio>0.5</gearbox_ratio>"
    result, sdf = generate(tmp_path, TWO_LINKS.replace("JOINT", joint), target="pybullet")
    assert "W-SDF-GEARBOX" in codes(result)
    joint_xml = fragment(sdf, "joint")
    assert joint_xml.startswith('<joint name="L__G" type="revolute">')
    assert "<xyz>1 0 0</xyz>" in joint_xml
    assert "axis2" not in joint_xml and "gearbox" not in joint_xml
    valid(sdf_checker, pybullet_loader, tmp_path / "out.sdf", 1)


@pytest.mark.parametrize("member, annotation, name", [
    ("sensor S", "annotation IMU { update_rate = G }", "G"),  # corpus 17_testSensorVar
    ("sensor S", "annotation Sonar { sonar = SonarDetails { min = G } }", "G"),
    ("joint J", "annotation Gearbox { gearbox_ratio = G }", "G"),
])
def test_an_annotation_naming_a_constant_without_value_is_E_CONST(
        tmp_path: Path, capsys, member: str, annotation: str, name: str) -> None:
    """Issue 20: the name was written verbatim (`<update_rate>G</update_rate>`)."""
    extra = "flexibly connected to L2" if member.startswith("joint") else ""
    model = tmp_path / "m.rsm"
    model.write_text(HEADER + f"""pmodel M {{
  local link L {{
    def {{ inertial information {{ mass 1 }} }}
    local {member} {{
      def {{
        const {name}: real
        {annotation}
      }}
      {extra}
    }}
  }}
  local link L2 {{ def {{ inertial information {{ mass 1 }} }} }}
}}
""")
    out = tmp_path / "out"
    assert main(["gen", "--sdf", "-o", str(out), str(model)]) == 1
    err = capsys.readouterr().err
    assert "E-CONST" in err and f"::{name}" in err and not out.exists()
    assert main(["gen", "--sdf", "-o", str(out), "--const", f"{name}=0.5", str(model)]) == 0
    assert f">{name}<" not in next(out.glob("*.sdf")).read_text()


@pytest.mark.parametrize("pose", ["nan,0,0,0,0,0", "0,0,inf,0,0,0", "0,0,0,0,0,-inf"])
def test_a_pose_that_is_not_finite_is_a_usage_error(tmp_path: Path, capsys, pose: str) -> None:
    with pytest.raises(SystemExit) as exit:
        main(["gen", "--sdf", "--pose", pose, "-o", str(tmp_path / "o"),
              str(EXAMPLES / "marxbot")])
    assert exit.value.code == 2 and "finite" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_a_negative_pose_needs_no_equals_sign(tmp_path: Path) -> None:
    out = tmp_path / "o"
    assert main(["gen", "--sdf", "--pose", "-1,0,0.5,0,0,-1.5", "-o", str(out),
                 str(EXAMPLES / "marxbot")]) == 0
    root = ET.parse(out / "marXbotBase.sdf").getroot()
    assert root.find("model/pose").text == "-1 0 0.5 0 0 -1.5"


def test_zero_size_box_gives_sdf_that_libsdformat_accepts(tmp_path: Path,
                                                          sdf_checker) -> None:
    """A plate of height 0 (the marXbot's tracks): a warning, and SDF is written."""
    from sdf_tools.validate import check_sdf

    result, sdf = generate(tmp_path, """
        pmodel M { local link L { def { } local body Plate { def {
          box(length = 0.2, width = 0.05, height = 0)
          inertial information { mass 0.1 } } } } }
        """)
    assert [(d.code.id, d.severity.value) for d in result.report.diagnostics] == \
        [("V2", "WARNING")]
    assert check_sdf([tmp_path / "out.sdf"]) == {tmp_path / "out.sdf": []}
