"""The elaborated model: parts, indices, constants, poses, inertials, devices (issue 3)."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy import api
from cyphy.model.elements import ElaboratedModel
from cyphy.model.poses import Pose
from conftest import EXAMPLES


def elaborate(tmp_path: Path, files: dict[str, str], model: str | None = None,
              consts: dict | None = None) -> api.ElaborateResult:
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    return api.elaborate([tmp_path / n for n in files],
                         api.ElaborateOptions(model=model, consts=consts or {}))


def model_of(tmp_path: Path, files: dict[str, str], **kw: object) -> ElaboratedModel:
    result = elaborate(tmp_path, files, **kw)  # type: ignore[arg-type]
    assert result.model is not None, result.report.diagnostics
    return result.model


def xyzrpy(pose: Pose | None) -> np.ndarray:
    assert pose is not None
    return np.array(pose.to_xyz_rpy())


NESTED = """\
import physmod::math::*
pmodel Top {
  part mid = Middle { pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = PI/2 } }
  local link Base { def { } }
}
pmodel Middle {
  part low = Bottom { pose { x = 0 y = 2 z = 0 roll = 0 pitch = 0 yaw = 0 } instantiation H = 3*K }
  const K: int = 2
}
pmodel Bottom {
  const H: real
  local link Tip { pose { x = 0 y = 0 z = H roll = PI/2 pitch = 0 yaw = 0 } def { } }
}
"""


def test_nested_parts_three_levels(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"n.rsm": NESTED})
    tip = m.element("Top::mid::low::Tip")
    # Top·mid: translate (1,0,0), yaw 90°; mid·low: translate (0,2,0); Tip: z = H = 3*K = 6.
    # (0,2,6) rotated by yaw 90° is (-2,0,6); plus (1,0,0) gives (-1,0,6).
    assert np.allclose(tip.pose.position, (-1.0, 0.0, 6.0))
    expected = Pose.from_xyz_rpy(0, 0, 0, 0, 0, math.pi / 2).compose(
        Pose.from_xyz_rpy(0, 0, 0, math.pi / 2, 0, 0))
    assert tip.pose.isclose(Pose(tip.pose.position, expected.rotation))
    assert m.constants["Top::mid::low::H"] == 6.0  # instantiated in the container's scope
    assert isinstance(m.constants["Top::mid::low::H"], float)  # declared real
    assert m.constants["Top::mid::K"] == 2 and isinstance(m.constants["Top::mid::K"], int)


SENSORS = """\
import physmod::math::*
import physmod::sensors::IR
pmodel Ring {
  local link Core {
    def { }
    sref Eye = IR {
      pose { x = (0.085*cos(2*j*PI/24))m y = (8.5*sin(2*j*PI/24))cm z = 2mm roll = 0 pitch = 0 yaw = 2*j*PI/24 }
      index j : [0,24)
      instantiation a = 1.5 instantiation b = 0 instantiation c = 0.25
    }
  }
}
"""


def test_indexed_sensors_with_trigonometry_and_units(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"s.rsm": SENSORS})
    assert [s.name for s in m.sensors][:3] == ["Ring::Core::Eye::0", "Ring::Core::Eye::1",
                                                "Ring::Core::Eye::2"]
    assert len(m.sensors) == 24 and len({s.name for s in m.sensors}) == 24
    five = m.element("Ring::Core::Eye::5")
    angle = 2 * 5 * math.pi / 24
    assert np.allclose(xyzrpy(five.pose), (0.085 * math.cos(angle), 0.085 * math.sin(angle),
                                           0.002, 0, 0, angle))
    assert five.device.prefix == "Eye5"
    assert five.device.port("voltage").mangled == "Eye5_voltage"
    assert five.device.port("a").value == 1.5  # instantiation overrides the definition


TWO_BODIES = """\
pmodel Dumbbell {
  local link Bar {
    def { }
    local body Left { pose { x = -1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      def { sphere(radius = 0.1) inertial information { mass 2 } } }
    local body Right { pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      def { box(length = 0.2, width = 0.2, height = 0.2)
            inertial information { mass 1 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 2 iyz 0 izz 3 } } } }
  }
}
"""


def test_inertial_combined_from_two_bodies(tmp_path: Path) -> None:
    link = model_of(tmp_path, {"d.rsm": TWO_BODIES}).links[0]
    assert link.inertial_source == "bodies"
    i = link.inertial
    assert i.mass == 3.0
    # centre of mass: (2·(-1) + 1·1) / 3 = -1/3
    assert np.allclose(i.com.position, (-1 / 3, 0, 0))
    # sphere: 2/5·m·r² = 0.008 on each axis; offsets from the centre of mass: -2/3 and +4/3
    # ixx = 0.008 + 1 = 1.008; iyy = izz parts: 0.008 + 2·(2/3)² and 2 + 1·(4/3)² / 3 + 1·(4/3)²
    sphere = 0.4 * 2 * 0.01
    iyy = sphere + 2 * (2 / 3) ** 2 + 2 + (4 / 3) ** 2
    izz = sphere + 2 * (2 / 3) ** 2 + 3 + (4 / 3) ** 2
    assert np.allclose(i.inertia, (sphere + 1, 0, 0, iyy, 0, izz))


def test_reference_overrides_and_library_devices(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"r.rsm": """\
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor
pmodel Arm {
  local link A { def { } jref J = Revolute {
      instantiation AXIS = (|1, 0, 0|)
      flexibly connected to B
      aref M = SpeedControlMotor { relation M.T == J.tau } } }
  local link B { pose { x = 0 y = 0 z = 1 roll = 0 pitch = 0 yaw = 0 } def { } }
}
"""})
    joint = m.joints[0]
    assert joint.parent.name == "Arm::A" and joint.child.name == "Arm::B"
    assert list(joint.axis) == [1.0, 0.0, 0.0]
    assert np.allclose(xyzrpy(joint.pose), (0, 0, -1, 0, 0, 0))  # relative to the child
    assert [a.name for a in joint.actuators] == ["Arm::A::J::M"]
    motor = joint.actuators[0].device
    assert motor.port("das").mangled == "M_das"
    from cyphy.lang.notation import to_notation
    assert "M_Tm == M_Kt * M_i" in [to_notation(e) for e in motor.equations]
    assert [to_notation(r) for r in m.relations] == ["M_T == J_tau"]
    assert "SpeedControlMotor::Kp" in m.missing


def test_const_option_fills_missing_constants(tmp_path: Path) -> None:
    files = {"n.rsm": NESTED.replace("instantiation H = 3*K", "")}
    result = elaborate(tmp_path, files)
    assert "Bottom::H" in result.model.missing
    assert result.model.element("Top::mid::low::Tip").pose is None  # symbolic
    m = model_of(tmp_path, files, consts={"Bottom::H": 5})
    assert m.missing == {} and m.constants["Top::mid::low::H"] == 5.0
    assert np.allclose(m.element("Top::mid::low::Tip").pose.position, (-1, 0, 5))


def test_device_names_made_unique(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"u.rsm": """\
import physmod::sensors::IR
pmodel Two { part l = Side { } part r = Side { } }
pmodel Side { local link Wheel { def { } sref S = IR { } } }
"""})
    assert sorted(s.device.prefix for s in m.sensors) == ["l_Wheel_S", "r_Wheel_S"]


def test_graphs(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"r.rsm": TWO_BODIES.replace("local link Bar {", """\
local link Base { def { } fixed to Bar }
  local link Bar {""")})
    g = m.kinematic_graph()
    assert set(g.nodes) == {"Dumbbell::Base", "Dumbbell::Bar"}
    assert list(g.edges) [0][:2] == ("Dumbbell::Base", "Dumbbell::Bar")


def test_marxbot_example_elaborates() -> None:
    result = api.elaborate([EXAMPLES / "marxbot"], api.ElaborateOptions(model="marXbotBase"))
    m = result.model
    assert len([s for s in m.sensors if s.simple_name == "Proximity"]) == 24
    assert {j.child.name for j in m.joints} == {"marXbotBase::LTreel::Wheel",
                                                "marXbotBase::RTreel::Wheel"}
    assert {(f.parent.name, f.child.name) for f in m.fixed} == {
        ("marXbotBase::Core", "marXbotBase::LTreel::Track"),
        ("marXbotBase::Core", "marXbotBase::RTreel::Track")}
    assert "LMotor_T == LHinge_tau" in [
        __import__("cyphy.lang.notation", fromlist=["x"]).to_notation(r) for r in m.relations]


def test_several_pmodels_need_model_option(tmp_path: Path) -> None:
    result = elaborate(tmp_path, {"a.rsm": "pmodel A { local link L { def {} } }\n"
                                           "pmodel B { local link L { def {} } }\n"})
    assert result.model is None
    (d,) = [d for d in result.report.diagnostics if d.code.id.startswith("E-")]
    assert d.code.id == "E-MODEL" and "--model" in d.hint


@settings(max_examples=25, deadline=None)
@given(lo=st.integers(-3, 3), width=st.integers(0, 6), closed=st.booleans())
def test_index_expansion_gives_distinct_copies(lo: int, width: int, closed: bool) -> None:
    hi = lo + width
    text = (f"pmodel I {{ local link L {{ index i : [{lo},{hi}{']' if closed else ')'} "
            "def { } pose { x = i y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } } }\n")
    with tempfile.TemporaryDirectory() as tmp:
        m = model_of(Path(tmp), {"i.rsm": text})
    expected = width + (1 if closed else 0)
    assert len(m.links) == expected and len({l.name for l in m.links}) == expected
    assert [l.pose.position[0] for l in m.links] == [float(v) for v in range(lo, lo + expected)]


POSES = st.tuples(*[st.floats(-2, 2, allow_nan=False)] * 3,
                  *[st.floats(-3, 3, allow_nan=False)] * 3)


@settings(max_examples=25, deadline=None)
@given(POSES)
def test_moving_a_part_moves_every_element(pose: tuple[float, ...]) -> None:
    """Elaborate a part at the origin and at `pose`: every link moves by exactly `pose`."""
    inner = ("pmodel Inner { local link A { pose { x = 1 y = 2 z = 3 roll = 0.1 pitch = 0.2 "
             "yaw = 0.3 } def { } } local link B { pose { x = -1 y = 0 z = 0.5 roll = 0 "
             "pitch = 1 yaw = 0 } def { } } }\n")
    text = "pose {{ x = {} y = {} z = {} roll = {} pitch = {} yaw = {} }}"
    moved = text.format(*[repr(v) if v >= 0 else f"-{-v!r}" for v in pose])
    with tempfile.TemporaryDirectory() as tmp:
        base = model_of(Path(tmp), {"a.rsm": inner + "pmodel O { part p = Inner { } }\n"},
                        model="O")
        shifted = model_of(Path(tmp), {"a.rsm": inner + f"pmodel O {{ part p = Inner {{ {moved} }} }}\n"},
                           model="O")
    frame = Pose.from_xyz_rpy(*pose)
    for a, b in zip(base.links, shifted.links):
        assert frame.compose(a.pose).isclose(b.pose, tol=1e-9)


def test_fragment_is_inlined_and_holds_sensors(tmp_path: Path) -> None:
    m = model_of(tmp_path, {"f.rsm": """\
import physmod::sensors::IR
fragment Kit { local link Extra { def { } } sref Probe = IR { } }
pmodel Robot { local link Base { def { } } part kit = Kit { } }
"""}, model="Robot")
    assert [l.name for l in m.links] == ["Robot::Base", "Robot::Extra"]
    assert [s.name for s in m.sensors] == ["Robot::Probe"] and m.sensors[0].link is None


def test_require_constants_lists_every_missing_one(tmp_path: Path) -> None:
    from cyphy.diagnostics import Report
    from cyphy.model.choose import require_constants

    m = model_of(tmp_path, {"n.rsm": NESTED.replace("instantiation H = 3*K", "")
                            .replace("const K: int = 2", "const K: int local link M { "
                                     "pose { x = K } def { } }")})
    report = Report()
    assert require_constants(m, report, "SDF generation") is False
    (d,) = report.diagnostics
    assert d.code.id == "E-CONST" and "Bottom::H, Middle::K" in d.message
    assert "--const" in d.hint and len(d.notes) == 2


def test_given_value_an_instantiation_overrides_is_a_warning(tmp_path: Path) -> None:
    """An instantiation wins over --const (docs/dynamics.md), so ``--const H=10`` where the
    only H is instantiated (``instantiation H = 3*K``) changes nothing: W-CONST-INSTANTIATED
    at the instantiation's value, and the pose keeps 3*K. A key that also sets a constant
    that is not instantiated (K), or that gives the instantiated value itself, is silent."""
    ignored = elaborate(tmp_path, {"n.rsm": NESTED}, model="Top", consts={"H": 10.0})
    found = [d for d in ignored.report.diagnostics if d.code.id == "W-CONST-INSTANTIATED"]
    assert [(d.span.line, d.span.column) for d in found] == [(7, 95)]  # at 3*K
    assert "H does not reach 'Top::mid::low::H': an instantiation sets it" in found[0].message
    assert ignored.model is not None
    assert ignored.model.element("Top::mid::low::Tip").pose.position[2] == 6.0
    applied = elaborate(tmp_path, {"n.rsm": NESTED}, model="Top", consts={"K": 5})
    assert applied.model.element("Top::mid::low::Tip").pose.position[2] == 15.0
    same = elaborate(tmp_path, {"n.rsm": NESTED}, model="Top", consts={"H": 6})
    assert not [d for d in [*applied.report.diagnostics, *same.report.diagnostics]
                if d.code.id == "W-CONST-INSTANTIATED"]
    # H given while one part instantiates it and another does not: the second takes it, the
    # first keeps 3*K, and the warning says which one the value did not reach
    both = NESTED.replace("pmodel Top {", "pmodel Top {\n  part bare = Bottom { }")
    partly = elaborate(tmp_path, {"n.rsm": both}, model="Top", consts={"H": 10.0})
    (warning,) = [d for d in partly.report.diagnostics if d.code.id == "W-CONST-INSTANTIATED"]
    assert "does not reach 'Top::mid::low::H' (it sets the others it names)" in \
        warning.message
    assert partly.model.element("Top::bare::Tip").pose.position[2] == 10.0
    assert partly.model.element("Top::mid::low::Tip").pose.position[2] == 6.0


REPLACED = """pmodel M {
\tconst PI: real = 3.1415
\tconst AXIS: vector(real, 3) = (|0, 0, 1|)
\tconst K: real = 2*PI
\tlocal link L { pose { x = K y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } def { } }
}
"""


def test_given_value_replacing_a_declared_one_is_a_warning(tmp_path: Path) -> None:
    """W-CONST-REPLACED at the declaration (line:column of the name), with both values, once
    per declaration; no warning when the given value equals the declared one (1 and 1.0 are
    one value), and the given value still wins (the pose moves with it)."""
    result = elaborate(tmp_path, {"m.rsm": REPLACED},
                       consts={"PI": 3.141592653589793, "AXIS": [0, 0, 1.0]})
    found = [d for d in result.report.diagnostics if d.code.id == "W-CONST-REPLACED"]
    assert [(d.span.line, d.span.column) for d in found] == [(2, 8)]
    assert "'M::PI' is declared 3.1415" in found[0].message
    assert "3.141592653589793 replaces it" in found[0].message
    assert found[0].code.severity.name == "WARNING"
    assert result.model.element("M::L").pose.position[0] == 2 * 3.141592653589793
    assert result.model.constants["M::K"] == 2 * 3.141592653589793  # evaluated from the given
    same = elaborate(tmp_path, {"m.rsm": REPLACED}, consts={"PI": 3.1415, "K": 6.3})
    assert [(d.span.line, d.message) for d in same.report.diagnostics
            if d.code.id == "W-CONST-REPLACED"] == [
        (4, "constant 'M::K' is declared 6.283; the given value 6.3 replaces it")]
