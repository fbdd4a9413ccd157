"""Issue 27: a user's own model is right or refused, never silently wrong (items 3, 5-7:
indexed connections, zero joint axes, a mapping given to `gen`, missing constants at once)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.cli import main

pytest_plugins = ["sdf_tools.fixtures"]

ARM = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Arm {{
  local link Base {{
    def {{ inertial information {{ mass 1 inertia matrix {{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
    local body B {{ def {{ box(length = 0.1, width = 0.1, height = 0.1) }} }}
    jref J = Revolute {{
      annotation Revolute {{ axis = Axis {{ xyz = {xyz} }} }}
      instantiation AXIS = {axis}
      flexibly connected to Tip
    }}
  }}
  local link Tip {{
    pose {{ x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }}
    def {{ inertial information {{ mass 1 inertia matrix {{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
    local body B {{ def {{ box(length = 0.1, width = 0.1, height = 0.1) }} }}
  }}
}}
"""


def codes_of(report: object) -> list[str]:
    return [d.code.id for d in report.diagnostics]  # type: ignore[attr-defined]


# ----- item 5: a zero joint axis is an error
@pytest.mark.parametrize("xyz, axis, what, line", [  # line: the zero vector's
    ("(|0, 0, 0|)", "(|0, 0, 1|)", "the annotation's xyz of joint Arm::Base::J", 8),
    ("(|0, 0, 1|)", "(|0, 0, 0|)", "the AXIS constant of joint Arm::Base::J", 9),
])
def test_zero_axis_is_an_error_and_gen_writes_nothing(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], xyz: str, axis: str,
        what: str, line: int) -> None:
    model = tmp_path / "arm.rsm"
    model.write_text(ARM.format(xyz=xyz, axis=axis))
    report = api.check([model]).report
    [error] = report.errors
    assert (error.code.id, error.span.line) == ("V6", line)
    assert what in error.message and "zero vector" in error.message
    out = tmp_path / "out"
    assert main(["gen", "--sdf", "-o", str(out), str(model)]) == 1
    assert not out.exists() or not any(out.iterdir())
    assert "ERROR V6" in capsys.readouterr().err


def test_non_zero_axes_pass(tmp_path: Path) -> None:
    model = tmp_path / "arm.rsm"
    model.write_text(ARM.format(xyz="(|0, 0, 2|)", axis="(|0, 0, 1|)"))
    assert api.check([model]).report.diagnostics == []


def test_a_zero_axis_is_what_libsdformat_rejects(tmp_path: Path, sdf_checker: Path) -> None:
    """Why V6 is an error: the SDF `gen --sdf` wrote for it before, which SDFormat refuses
    (the non-zero variant passes, so the checker is not refusing everything)."""
    from sdf_tools.validate import check_sdf

    model = tmp_path / "arm.rsm"
    model.write_text(ARM.format(xyz="(|0, 0, 1|)", axis="(|0, 0, 1|)"))
    assert main(["gen", "--sdf", "-o", str(tmp_path), str(model)]) == 0
    good = tmp_path / "Arm.sdf"
    bad = tmp_path / "Zero.sdf"
    bad.write_text(good.read_text().replace("<xyz>0 0 1</xyz>", "<xyz>0 0 0</xyz>"))
    assert bad.read_text() != good.read_text()
    verdicts = check_sdf([good, bad], strict=False, lints=False)
    assert verdicts[good] == [] and verdicts[bad] != []


# ----- item 6: a mapping (or any model file) given to `gen` reads its folder
@pytest.mark.parametrize("flag, suffix", [("--sdf", "sdf"), ("--urdf", "urdf"),
                                          ("--mjcf", "xml")])
def test_gen_of_a_mapping_file_generates_its_pmodel(tmp_path: Path, flag: str,
                                                    suffix: str) -> None:
    marxbot = EXAMPLES / "marxbot"
    assert main(["gen", flag, "-o", str(tmp_path / "a"), str(marxbot / "Mapping.rsm")]) == 0
    assert main(["gen", flag, "-o", str(tmp_path / "b"), str(marxbot / "marXbotBase.rsm")]) == 0
    from_mapping = (tmp_path / "a" / f"marXbotBase.{suffix}").read_text()
    assert from_mapping == (tmp_path / "b" / f"marXbotBase.{suffix}").read_text()


def test_gen_of_a_dmodel_file_takes_the_folders_only_pmodel(tmp_path: Path) -> None:
    marxbot = EXAMPLES / "marxbot"
    assert main(["gen", "--sdf", "-o", str(tmp_path), str(marxbot / "marXbotSoftware.rsm")]) == 0
    assert (tmp_path / "marXbotBase.sdf").is_file()


@pytest.mark.parametrize("given", ["marXbotBase.rsm", "marXbotSoftware.rsm"])
def test_the_semantics_of_a_pmodel_or_dmodel_file_uses_the_folders_mapping(
        tmp_path: Path, given: str) -> None:
    """`gen --cyphycircus` (and --isabelle, --latex) of the p-model or the d-model file: the
    mapping of the folder that maps them (before: E-MAPPING, no platform mapping)."""
    marxbot = EXAMPLES / "marxbot"
    assert main(["gen", "--cyphycircus", "-o", str(tmp_path / "a"), str(marxbot / given)]) == 0
    assert main(["gen", "--cyphycircus", "-o", str(tmp_path / "b"),
                 str(marxbot / "Mapping.rsm")]) == 0
    assert (tmp_path / "a" / "M.cpc").read_text() == (tmp_path / "b" / "M.cpc").read_text()


def test_the_pmodel_a_mapping_names_is_checked(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """The p-model file found for the mapping is checked as if named: its errors stop `gen`."""
    folder = tmp_path / "marxbot"
    shutil.copytree(EXAMPLES / "marxbot", folder)
    base = folder / "marXbotBase.rsm"
    base.write_text(base.read_text().replace("mass 0.5kg", "mass -0.5kg", 1))
    assert main(["gen", "--sdf", "-o", str(tmp_path / "out"), str(folder / "Mapping.rsm")]) == 1
    err = capsys.readouterr().err
    assert "ERROR V1" in err and "marXbotBase.rsm" in err
    assert not (tmp_path / "out").exists()
    # `solve` and `show` elaborate a model too
    assert main(["show", str(folder / "Mapping.rsm")]) == 1


# ----- item 7: every missing constant a target needs, at once
@needs_corpus
def test_corpus_testvar_names_every_missing_constant_at_once(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The part's pose needs ``d`` as well as ``k``: before, ``d`` was named only once ``k``
    and ``a`` had values."""
    folder = CORPUS / "26_testvar"
    out = tmp_path / "out"
    assert main(["gen", "--sdf", "-o", str(out), str(folder)]) == 1
    [line] = [l for l in capsys.readouterr().err.splitlines() if "ERROR E-CONST" in l]
    assert line.endswith("needs values for 3 constants without one: "
                         "my_sonar_sensor::a, testvar::d, testvar::k")
    given = ["--const", "my_sonar_sensor::a=1", "--const", "testvar::k=1",
             "--const", "testvar::d=0.5"]
    assert main(["gen", "--sdf", "-o", str(out), *given, str(folder)]) == 0


def test_missing_constants_in_one_expression_pose_and_inertial(tmp_path: Path) -> None:
    model = tmp_path / "m.rsm"
    model.write_text("""\
pmodel M {
  const a: real const b: real const c: real const d: real const e: real
  local link L {
    pose { x = a + b y = 0 z = c roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass d inertia matrix { ixx e ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
  }
}
""")
    generated = api.generate_sdf([model])
    [error] = generated.report.errors
    assert error.code.id == "E-CONST" and error.message.endswith("M::a, M::b, M::c, M::d, M::e")
    assert generated.files == {}


# ----- item 3: indexed connections, element i to element i; unique qualified names
ROVER = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Rover {{
  local link Chassis {{
    def {{ inertial information {{ mass 4 inertia matrix {{ ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 }} }} }}
    local body B {{ def {{ box(length = 0.4, width = 0.2, height = 0.1) }} }}
    jref Axle = Revolute {{
      {joint_index}
      pose {{ x = {joint_x} y = 0.1 z = 0 roll = 0 pitch = 0 yaw = 0 }}
      annotation Revolute {{ axis = Axis {{ xyz = (|0, 1, 0|) }} }}
      instantiation AXIS = (|0, 1, 0|)
      flexibly connected to Wheel
    }}
  }}
  local link Wheel {{
    {wheel_index}
    pose {{ x = {wheel_x} y = 0.12 z = 0 roll = 0 pitch = 0 yaw = 0 }}
    def {{ inertial information {{ mass 0.5 inertia matrix {{ ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 }} }} }}
    local body B {{ def {{ cylinder(radius = 0.05, length = 0.02) }} }}
  }}
}}
"""
PAIRED = {"joint_index": "index i: [0, 2)", "joint_x": "0.3 * i - 0.1",
          "wheel_index": "index i: [0, 2)", "wheel_x": "0.3 * i - 0.1"}


def rover(tmp_path: Path, **changes: str) -> Path:
    model = tmp_path / "rover.rsm"
    model.write_text(ROVER.format(**{**PAIRED, **changes}))
    return model


def test_indexed_joint_to_indexed_link_pairs_element_i_with_element_i(tmp_path: Path) -> None:
    """Before: four joints (two named Axle::0), each device shared between two of them."""
    model = rover(tmp_path)
    assert api.check([model]).report.diagnostics == []
    elaborated = api.elaborate([model]).model
    assert elaborated is not None
    joints = [(j.name, j.child.name) for j in elaborated.joints]  # type: ignore[union-attr]
    assert joints == [("Rover::Chassis::Axle::0", "Rover::Wheel::0"),
                      ("Rover::Chassis::Axle::1", "Rover::Wheel::1")]
    # Each joint sits where its own wheel is (by hand: x = 0.3 i - 0.1 on both sides, and
    # y 0.1 against 0.12): 0.02 m from the wheel's origin, never 0.3 m off.
    for j in elaborated.joints:
        assert j.pose is not None
        x, y, z = j.pose.to_xyz_rpy()[:3]
        assert (x, y, z) == pytest.approx((0.0, -0.02, 0.0), abs=1e-12)
    devices = [j.device.prefix for j in elaborated.joints]  # type: ignore[union-attr]
    assert devices == ["Axle0", "Axle1"]


def test_show_lists_each_joint_once(tmp_path: Path,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["show", str(rover(tmp_path))]) == 0
    out = capsys.readouterr().out
    lines = [l.split()[1] for l in out.splitlines() if l.strip().startswith("joint ")]
    assert lines == ["Rover::Chassis::Axle::0", "Rover::Chassis::Axle::1"]


@pytest.mark.parametrize("changes, what", [
    ({"wheel_index": "index i: [0, 3)"},
     "joint Axle has 2 copies but is connected to 3 copies of Wheel"),
    ({"wheel_index": "index i: [1, 2]"},  # two and two, but other values: not element i to i
     "joint Axle has 2 copies but is connected to 2 copies of Wheel"),
    ({"joint_index": "", "joint_x": "0"},
     "joint Rover::Chassis::Axle is one joint but is connected to 2 copies of Wheel"),
])
def test_unmatched_indexed_connections_are_IX3(tmp_path: Path, changes: dict[str, str],
                                               what: str) -> None:
    model = rover(tmp_path, **changes)
    report = api.check([model]).report
    assert [(d.code.id, d.span.line) for d in report.diagnostics] == [("IX3", 7)]
    assert what in report.diagnostics[0].message
    assert api.generate_sdf([model]).files == {}


def test_a_joint_in_an_indexed_link_pairs_by_the_links_index(tmp_path: Path) -> None:
    model = tmp_path / "legs.rsm"
    model.write_text("""\
import physmod::joints::Revolute
pmodel Legs {
  local link Hip {
    index k: [0, 3)
    pose { x = k y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1 } }
    jref Knee = Revolute { instantiation AXIS = (|0, 1, 0|) flexibly connected to Shin }
  }
  local link Shin {
    index k: [0, 3)
    pose { x = k y = 0 z = -1 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1 } }
  }
}
""")
    assert [d.code.id for d in api.check([model]).report.errors] == []
    elaborated = api.elaborate([model]).model
    assert elaborated is not None
    assert [(j.parent.name, j.child.name) for j in elaborated.joints] == [  # type: ignore
        (f"Legs::Hip::{k}", f"Legs::Shin::{k}") for k in range(3)]


@needs_corpus
def test_corpus_joint_to_indexed_link_is_refused_where_robotool_duplicates_names() -> None:
    """RoboTool's IJTIL: 4 prismatic joints to 2 copies of Top, written as 8 joints with
    4 names (sdf-robotool.md 1.8)."""
    folder = CORPUS / "Index" / "IndexedJointToIndexedLink"
    report = api.check(sorted(folder.glob("*.pm"))).report
    assert [d.code.id for d in report.errors] == ["IX3"]
    assert "joint PJ has 4 copies but is connected to 2 copies of Top" in report.errors[0].message


def test_a_connection_written_twice_is_IX4(tmp_path: Path) -> None:
    model = tmp_path / "twice.rsm"
    model.write_text("""\
pmodel D {
  local link A { def { inertial information { mass 1 } } fixed to B fixed to B }
  local link B { def { inertial information { mass 1 } } }
}
""")
    [error] = api.check([model]).report.errors
    assert (error.code.id, error.span.line) == ("IX4", 2)
    assert "two elements are named D::A::fixedJoint::D::B" in error.message


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.one_of(st.none(), st.tuples(st.integers(0, 2), st.integers(0, 3))),
       st.one_of(st.none(), st.tuples(st.integers(0, 2), st.integers(0, 3))))
def test_any_indexed_connection_is_paired_or_refused(tmp_path_factory, joint_range,
                                                     wheel_range) -> None:
    """Whatever the two ranges: either IX3, or every joint has one child, the copy of Wheel
    with its own index value (or the only Wheel), and no two elements share a name."""
    def index(r: tuple[int, int] | None) -> str:
        return "" if r is None else f"index i: [{r[0]}, {r[1]})"

    def values(r: tuple[int, int] | None) -> list[int]:
        return [] if r is None else list(range(r[0], r[1]))

    folder = tmp_path_factory.mktemp("ranges")
    model = rover(folder, joint_index=index(joint_range), wheel_index=index(wheel_range),
                  joint_x="0", wheel_x="0")
    report = api.check([model]).report
    codes = {d.code.id for d in report.errors}
    joints, wheels = values(joint_range), values(wheel_range)
    if wheel_range is not None and not wheels:
        return  # no wheel at all: nothing to connect to (IX1 warns about the empty range)
    paired = wheel_range is None or len(wheels) == 1 or joints == wheels
    if not paired or (joint_range is not None and not joints):
        assert "IX3" in codes or (joint_range is not None and not joints), codes
        return
    assert "IX3" not in codes and "IX4" not in codes, codes
    elaborated = api.elaborate([model]).model
    assert elaborated is not None
    names = [e.name for e in [*elaborated.links, *elaborated.joints, *elaborated.bodies]]
    assert len(names) == len(set(names))
    for j in elaborated.joints:
        assert j.child is not None
        if len(wheels) > 1:
            assert j.child.index == j.index
