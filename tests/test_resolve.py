"""Name resolution and the scope conditions S1, S2, S4, S5, and member placement (E-MEMBER)."""

from __future__ import annotations

from pathlib import Path

from cyphy import api
from cyphy.diagnostics import Diagnostic
from cyphy.lang import ast


def check(tmp_path: Path, files: dict[str, str]) -> list[Diagnostic]:
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    paths = [tmp_path / name for name in files]
    return api.check(paths, api.CheckOptions(wellformedness=False)).report.diagnostics


def codes_at(diags: list[Diagnostic]) -> list[tuple[str, int]]:
    return [(d.code.id, d.span.line) for d in diags]


ROBOT = """\
package robot
import physmod::joints::Revolute
import physmod::sdf::annotations::*
import physmod::math::*
pmodel Robot {
  local link Base {
    def { inertial information { mass 1.0 } }
    local body B { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref J = Revolute {
      annotation Revolute { axis = Axis { xyz = (|0,0,1|) } }
      instantiation AXIS = (|0,0,1|)
      flexibly connected to Arm
    }
  }
  local link Arm {
    pose { x = 0 y = 0 z = 0.5*cos(PI) roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.5 } }
  }
}
"""


def test_well_formed_model_has_no_scope_errors(tmp_path: Path) -> None:
    assert check(tmp_path, {"robot.rsm": ROBOT}) == []


def test_resolution_records_library_definitions(tmp_path: Path) -> None:
    (tmp_path / "robot.rsm").write_text(ROBOT)
    result = api.check([tmp_path / "robot.rsm"])
    file = result.workspace.files[str(tmp_path / "robot.rsm")]
    pmodel = next(i for i in file.items if isinstance(i, ast.PModel))
    joint = pmodel.blocks[0].blocks[1]
    target = result.resolution.get(joint)
    assert isinstance(target, ast.Definition) and target.name == "Revolute"
    assert target.span.file.endswith("joints.rsm")


def test_unknown_definition_suggests_a_close_name(tmp_path: Path) -> None:
    diags = check(tmp_path, {"robot.rsm": ROBOT.replace("jref J = Revolute {",
                                                         "jref J = Revolte {")})
    assert codes_at(diags) == [("S1", 9)]
    assert "Revolte" in diags[0].message and "Revolute" in diags[0].hint


def test_annotation_template_is_looked_up_among_templates(tmp_path: Path) -> None:
    diags = check(tmp_path, {"robot.rsm": ROBOT.replace("axis = Axis", "axis = Axes")})
    assert codes_at(diags) == [("S1", 10)]
    assert "annotation template 'Axes'" in diags[0].message and "'Axis'" in diags[0].hint


def test_unknown_name_in_pose(tmp_path: Path) -> None:
    diags = check(tmp_path, {"robot.rsm": ROBOT.replace("0.5*cos(PI)", "0.5*cos(PIE)")})
    assert codes_at(diags) == [("S1", 16)]
    assert diags[0].span.column == 36 and "'PI'" in diags[0].hint


def test_unknown_connection_target(tmp_path: Path) -> None:
    diags = check(tmp_path, {"robot.rsm": ROBOT.replace("connected to Arm", "connected to Arms")})
    assert codes_at(diags) == [("S1", 12)]
    assert "Arms" in diags[0].message and "'Arm'" in diags[0].hint


def test_instantiation_of_unknown_constant(tmp_path: Path) -> None:
    diags = check(tmp_path, {"robot.rsm": ROBOT.replace("instantiation AXIS", "instantiation AX")})
    assert codes_at(diags) == [("S1", 11)]
    assert "AXIS" in diags[0].hint


def test_duplicate_blocks_and_variables(tmp_path: Path) -> None:
    text = ROBOT.replace("  local link Arm {", "  local link Base { def { } }\n  local link Arm {")
    text = text.replace("def { inertial information { mass 0.5 } }",
                        "def { inertial information { mass 0.5 } const k: real const k: int }")
    diags = check(tmp_path, {"robot.rsm": text})
    found = codes_at(diags)
    assert ("S2", 15) in found  # the second link Base
    assert any(code == "S2" and "'k'" in d.message for (code, _), d in zip(found, diags))


def test_equation_reaching_outside_its_block_is_S4(tmp_path: Path) -> None:
    text = """\
pmodel P {
  const gain: real = 2
  local link L {
    def { }
    local sensor S {
      def { input u: real output y: real equation y == gain*u + w }
    }
  }
}
"""
    diags = check(tmp_path, {"p.rsm": text})
    assert sorted(codes_at(diags)) == [("S1", 6), ("S4", 6)]
    s4 = next(d for d in diags if d.code.id == "S4")
    line = text.splitlines()[5]
    assert "'gain'" in s4.message and s4.span.column == line.index("gain") + 1


def test_imports_must_resolve(tmp_path: Path) -> None:
    text = "import physmod::jionts::*\nimport physmod::joints::Revolut\npmodel P { local link L { def {} } }\n"
    diags = check(tmp_path, {"p.rsm": text})
    assert codes_at(diags) == [("S5", 1), ("S5", 2)]
    assert "physmod::joints" in diags[0].hint and "Revolute" in diags[1].hint


def test_part_cycle_is_S5(tmp_path: Path) -> None:
    text = """\
pmodel A { part b = B { } local link L { def {} } }
pmodel B { part a = A { } local link M { def {} } }
"""
    diags = check(tmp_path, {"p.rsm": text})
    assert [d.code.id for d in diags] == ["S5"]
    assert "A → B → A" in diags[0].message or "B → A → B" in diags[0].message


def test_user_package_shadows_the_library(tmp_path: Path) -> None:
    own = "package physmod::joints\njoint Revolute { input torque: real }\n"
    use = ROBOT.replace("instantiation AXIS = (|0,0,1|)", "")
    diags = check(tmp_path, {"joints.rsm": own, "robot.rsm": use})
    assert diags == []
    (tmp_path / "robot.rsm").write_text(ROBOT)
    diags = api.check([tmp_path / "robot.rsm"],
                      api.CheckOptions(wellformedness=False)).report.diagnostics
    assert codes_at(diags) == [("S1", 11)]  # our Revolute has no AXIS


MAPPING_FILES = {
    "sw.rsm": """\
interface Moves { move(lv: real, av: real) stop() }
interface Sees { event obstacle event distance: real }
module Soft {
  cycleDef cycle == 1
  robotic platform Platform { provides Moves uses Sees }
}
""",
    "robot.rsm": ROBOT.replace("flexibly connected to Arm",
                               "flexibly connected to Arm\n      aref M = physmod::actuators::SpeedControlMotor")
    .replace("package robot\n", "package robot\nimport physmod::sensors::IR\n")
    .replace("local link Arm {", "local link Arm {\n    sref S = IR { index i : [0,4) }"),
    "map.rsm": """\
import robot::*
map M dmodel Soft to pmodel Robot {
  operation move { var w: real equation Base::J::M.das == lv + w*av }
  operation stop { equation Base::J::M.das == 0 }
  input event obstacle { predicate Arm::S[1].voltage >= 3.0 }
}
""",
}


def test_mapping_paths_resolve(tmp_path: Path) -> None:
    assert check(tmp_path, MAPPING_FILES) == []


def test_mapping_unknown_element_and_port(tmp_path: Path) -> None:
    files = dict(MAPPING_FILES)
    files["map.rsm"] = files["map.rsm"].replace("Base::J::M.das == 0", "Base::K::M.das == 0")
    files["map.rsm"] = files["map.rsm"].replace("S[1].voltage", "S[1].volts")
    files["map.rsm"] = files["map.rsm"].replace("lv + w*av", "lv + w*avv")
    diags = check(tmp_path, files)
    assert codes_at(diags) == [("S1", 3), ("S1", 4), ("S1", 5)]
    assert "'avv'" in diags[0].message and "'av'" in diags[0].hint
    assert "link Base has no element 'K'" in diags[1].message and "J" in diags[1].hint
    assert "sensor S has no variable 'volts'" in diags[2].message and "voltage" in diags[2].hint


def test_mapping_header_must_resolve(tmp_path: Path) -> None:
    files = dict(MAPPING_FILES)
    files["map.rsm"] = files["map.rsm"].replace("dmodel Soft to pmodel Robot",
                                                "dmodel Sofft to pmodel Robott")
    diags = check(tmp_path, files)
    assert [(d.code.id, d.span.line, d.span.column) for d in diags] == [
        ("S1", 2, 14), ("S1", 2, 30)]
    assert "'Soft'" in diags[0].hint and "'Robot'" in diags[1].hint


def test_misplaced_members(tmp_path: Path) -> None:
    text = """\
pmodel P {
  local link L {
    def { box(length = 1, width = 1, height = 1) }
    flexibly connected to L
    a == b
  }
  local link B2 { def { } local body B { def { box(length = 1, width = 1) } } }
}
"""
    diags = check(tmp_path, {"p.rsm": text})
    members = [(d.code.id, d.span.line) for d in diags if d.code.id.startswith("E-")]
    assert members == [("E-MEMBER", 3), ("E-MEMBER", 4), ("E-MEMBER", 5), ("E-MEMBER", 7)]
    assert "lacks height" in diags[-1].message or any("lacks height" in d.message for d in diags)
