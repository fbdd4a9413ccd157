"""Platform mappings, PMap1-PMap12 (wellformedness.md): for every condition a small mapping
that violates exactly that condition, and a close variant that does not.

The models: a d-model (``sw.rsm``) whose robotic platform provides move/stop, uses the events
obstacle and distance (typed), and declares a variable and a typed event of its own; a p-model
(``robot.rsm``) with a revolute joint driven by a speed-controlled motor, a lamp and a ring of
IR sensors; and the mapping (``map.rsm``), whose lines are:

    1  import robot::*
    2  map M dmodel soft::Soft to pmodel Robot {
    3    operation move …
    4    operation stop …
    5    input event obstacle …
    6    input event distance ? d …
    7    variable level …
    8    output event lamp ? on …
    9  }
"""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from robot_model import JOINT_LINE, ROBOT
from cyphy import api
from cyphy.diagnostics import Diagnostic

SOFTWARE = """\
package soft
interface MovesI { move(lv: real, av: real) stop() }
interface SeesI { event obstacle event distance: real }
module Soft {
  cycleDef cycle == 1
  robotic platform Platform { provides MovesI uses SeesI var level: real event lamp: boolean }
}
"""

MOVE = "  operation move { var w: real equation Base::J::M.das == lv + w*av }\n"
STOP = "  operation stop { equation Base::J::M.das == 0 }\n"
OBSTACLE = "  input event obstacle { predicate Arm::S[1].voltage >= 3.0 }\n"
DISTANCE = ("  input event distance ? d { predicate Arm::S[0].voltage > 0 "
            "equation d == Arm::S[0].voltage }\n")
LEVEL = "  variable level { equation Base::J::M.das == level }\n"
LAMP = "  output event lamp ? on { action Base::Lamp.on = on }\n"
MAPPING = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
           + MOVE + STOP + OBSTACLE + DISTANCE + LEVEL + LAMP + "}\n")
HEADER, MOVE_LINE, STOP_LINE, OBSTACLE_LINE, DISTANCE_LINE, LEVEL_LINE, LAMP_LINE = range(2, 9)


def check(tmp_path: Path, *, robot: str = ROBOT, mapping: str | None = MAPPING,
          extra: dict[str, str] | None = None) -> list[Diagnostic]:
    files = {"sw.rsm": SOFTWARE, "robot.rsm": robot, **(extra or {})}
    if mapping is not None:
        files["map.rsm"] = mapping
    for name, text in files.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    return api.check([tmp_path / name for name in files]).report.diagnostics


def remap(old: str, new: str) -> str:
    assert old in MAPPING
    return MAPPING.replace(old, new)


def ids(diags: list[Diagnostic]) -> list[tuple[str, int]]:
    return [(d.code.id, d.span.line) for d in diags]


def test_the_fixture_is_clean(tmp_path: Path) -> None:
    assert check(tmp_path) == []


# ---------------------------------------------------------------- PMap1, PMap2: connected joints


def test_PMap1_joint_of_mapped_pmodel_without_flexible_connection(tmp_path: Path) -> None:
    robot = ROBOT.replace("      flexibly connected to Arm\n", "")
    diags = check(tmp_path, robot=robot)
    assert ids(diags) == [("PMap1", JOINT_LINE)]
    assert diags[0].span.file.endswith("robot.rsm")
    assert "joint J of link Base" in diags[0].message
    assert "'flexibly connected to Arm'" in diags[0].hint


def test_PMap1_only_concerns_mapped_pmodels(tmp_path: Path) -> None:
    robot = ROBOT.replace("      flexibly connected to Arm\n", "")
    assert check(tmp_path, robot=robot, mapping=None) == []


WHEEL = """\
package robot
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Wheel {
  local link Hub {
    def { inertial information { mass 0.1 } }
    local body H { def { sphere(radius = 0.02) } }
    jref Spin = Revolute {
      annotation Revolute { axis = Axis { xyz = (|0,1,0|) } }
      instantiation AXIS = (|0,1,0|)
    }
  }
}
"""
PART = "  part W = Wheel { pose { x = 0 y = 0.3 z = 0 roll = 0 pitch = 0 yaw = 0 } }\n"
PART_LINE = 8


def test_PMap2_joint_of_a_part_unconnected(tmp_path: Path) -> None:
    robot = ROBOT.replace("pmodel Robot {\n", "pmodel Robot {\n" + PART)
    diags = check(tmp_path, robot=robot, extra={"wheel.rsm": WHEEL})
    assert ids(diags) == [("PMap2", PART_LINE)]
    assert "joint Spin of part W" in diags[0].message
    assert "joint Spin flexibly connected to" in diags[0].hint


def test_PMap2_joint_connected_by_the_part(tmp_path: Path) -> None:
    part = PART.replace("} }", "}\n    joint Spin flexibly connected to Arm }")
    robot = ROBOT.replace("pmodel Robot {\n", "pmodel Robot {\n" + part)
    assert check(tmp_path, robot=robot, extra={"wheel.rsm": WHEEL}) == []


def test_PMap2_joint_connected_inside_the_part(tmp_path: Path) -> None:
    wheel = WHEEL.replace(
        "    }\n  }\n}", "      flexibly connected to Rim\n    }\n  }\n"
        "  local link Rim { def { inertial information { mass 0.1 } } }\n}")
    assert "flexibly connected to Rim" in wheel
    robot = ROBOT.replace("pmodel Robot {\n", "pmodel Robot {\n" + PART)
    assert check(tmp_path, robot=robot, extra={"wheel.rsm": wheel}) == []


# ---------------------------------------------------------------- PMap3, PMap4: correspondence


def test_PMap3_unmapped_operation_and_event(tmp_path: Path) -> None:
    mapping = MAPPING.replace(STOP, "").replace(DISTANCE, "")
    diags = check(tmp_path, mapping=mapping)
    assert ids(diags) == [("PMap3", HEADER), ("PMap3", HEADER)]
    messages = " ".join(d.message for d in diags)
    assert "operation stop()" in messages and "event distance: real" in messages
    hints = " ".join(d.hint for d in diags)
    assert "'operation stop {" in hints and "'input event distance ? d {" in hints


def test_PMap3_variables_may_stay_unmapped(tmp_path: Path) -> None:
    assert check(tmp_path, mapping=MAPPING.replace(LEVEL, "")) == []


def test_PMap4_mapping_of_an_unknown_operation(tmp_path: Path) -> None:
    mapping = remap(STOP, STOP + "  operation stopp { equation Base::J::M.das == 0 }\n")
    diags = check(tmp_path, mapping=mapping)
    assert ids(diags) == [("PMap4", STOP_LINE + 1)]
    assert "operation 'stopp'" in diags[0].message and "'stop'" in diags[0].hint


def test_PMap4_event_mapped_as_an_operation(tmp_path: Path) -> None:
    mapping = remap(OBSTACLE, "  operation obstacle { equation Base::J::M.das == 0 }\n")
    diags = check(tmp_path, mapping=mapping)
    # The event obstacle is then unmapped as well (PMap3, at the header).
    assert ids(diags) == [("PMap3", HEADER), ("PMap4", OBSTACLE_LINE)]
    assert "operation 'obstacle'" in diags[1].message
    assert "obstacle is an event" in diags[1].hint and "input event obstacle" in diags[1].hint


def test_PMap4_mapping_of_a_platform_variable_and_own_event(tmp_path: Path) -> None:
    # level and lamp are the platform's own: no PMap4 (this is the clean fixture, checked
    # explicitly for these two members).
    diags = check(tmp_path)
    assert not [d for d in diags if d.code.id == "PMap4"]


# ---------------------------------------------------------------- PMap5, PMap6: shape


def test_PMap5_typed_event_without_parameter(tmp_path: Path) -> None:
    mapping = remap(DISTANCE, "  input event distance { predicate Arm::S[0].voltage > 0 "
                              "var x: real equation x == Arm::S[0].voltage }\n")
    diags = check(tmp_path, mapping=mapping)
    assert ids(diags) == [("PMap5", DISTANCE_LINE)]
    assert "event distance is typed (real)" in diags[0].message
    assert "input event distance ? d" in diags[0].hint


def test_PMap5_untyped_event_with_parameter(tmp_path: Path) -> None:
    mapping = remap(OBSTACLE, "  input event obstacle ? o { predicate Arm::S[1].voltage >= 3.0 }\n")
    diags = check(tmp_path, mapping=mapping)
    assert ids(diags) == [("PMap5", OBSTACLE_LINE)]
    assert diags[0].span.column == len("  input event obstacle ") + 1
    assert "event obstacle is untyped" in diags[0].message and "'o'" in diags[0].message


def test_PMap6_operation_without_equations_or_actions(tmp_path: Path) -> None:
    diags = check(tmp_path, mapping=remap(STOP, "  operation stop { }\n"))
    assert ids(diags) == [("PMap6", STOP_LINE)]
    assert "operation stop has neither equations nor actions" in diags[0].message


def test_PMap6_operation_with_equations_and_actions(tmp_path: Path) -> None:
    stop = ("  operation stop { equation Base::J::M.das == 0\n"
            "    action Base::J::M.das = 0 }\n")
    diags = check(tmp_path, mapping=remap(STOP, stop))
    assert ids(diags) == [("PMap6", STOP_LINE + 1)]
    assert "operation stop has both equations and actions" in diags[0].message


def test_PMap6_predicate_outside_input_events(tmp_path: Path) -> None:
    stop = "  operation stop { equation Base::J::M.das == 0 predicate true }\n"
    diags = check(tmp_path, mapping=remap(STOP, stop))
    assert ids(diags) == [("PMap6", STOP_LINE)]
    assert "operation stop has a predicate" in diags[0].message


def test_PMap6_typed_input_event_needs_equations(tmp_path: Path) -> None:
    distance = "  input event distance ? d { predicate Arm::S[0].voltage > 0 }\n"
    diags = check(tmp_path, mapping=remap(DISTANCE, distance))
    assert ids(diags) == [("PMap6", DISTANCE_LINE)]
    assert "value of event distance" in diags[0].message


def test_PMap6_actions_alone_are_fine(tmp_path: Path) -> None:
    assert check(tmp_path, mapping=remap(STOP, "  operation stop { action Base::J::M.das = 0 }\n"
                                         )) == []


# ---------------------------------------------------------------- PMap7-PMap10: access


def test_PMap7_input_event_mentions_actuator_and_sensor_input(tmp_path: Path) -> None:
    obstacle = ("  input event obstacle { var x: real predicate Arm::S[1].voltage >= 3.0 "
                "equation x == Base::J::M.das + Arm::S[1].distance }\n")
    diags = check(tmp_path, mapping=remap(OBSTACLE, obstacle))
    # The sum also adds an angular speed (rad/s) to a length (m): U2.
    assert sorted(ids(diags)) == [("PMap7", OBSTACLE_LINE), ("PMap7", OBSTACLE_LINE),
                                  ("U2", OBSTACLE_LINE)]
    access = [d for d in diags if d.code.id == "PMap7"]
    assert "input das of actuator M (Base::J::M.das)" in access[0].message
    assert "input distance of sensor S (Arm::S[1].distance)" in access[1].message
    assert "read an output of sensor S instead (voltage)" in access[1].hint


def test_PMap7_input_event_assigns_a_sensor_output(tmp_path: Path) -> None:
    obstacle = ("  input event obstacle { predicate Arm::S[1].voltage >= 3.0 "
                "action Arm::S[1].voltage = 0 }\n")
    diags = check(tmp_path, mapping=remap(OBSTACLE, obstacle))
    assert ids(diags) == [("PMap7", OBSTACLE_LINE)]
    assert "assigns output voltage of sensor S" in diags[0].message


def test_PMap7_input_event_reads_sensor_outputs(tmp_path: Path) -> None:
    obstacle = ("  input event obstacle { var x: real predicate x >= 3.0 "
                "equation x == Arm::S[1].voltage + Arm::S[2].voltage }\n")
    assert check(tmp_path, mapping=remap(OBSTACLE, obstacle)) == []


def test_PMap8_output_event_reads_a_sensor_and_an_actuator_output(tmp_path: Path) -> None:
    lamp = ("  output event lamp ? on { equation Base::Lamp.on == on "
            "equation Base::Lamp.lit == (Arm::S[0].voltage > 1) }\n")
    diags = check(tmp_path, mapping=remap(LAMP, lamp))
    assert ids(diags) == [("PMap8", LAMP_LINE), ("PMap8", LAMP_LINE)]
    assert "output lit of actuator Lamp" in diags[0].message
    assert "set an input of actuator Lamp instead (on)" in diags[0].hint
    assert "output voltage of sensor S" in diags[1].message


def test_PMap8_output_event_writes_actuator_inputs(tmp_path: Path) -> None:
    lamp = "  output event lamp ? on { equation Base::Lamp.on == (on /\\ true) }\n"
    assert check(tmp_path, mapping=remap(LAMP, lamp)) == []


def test_PMap9_operation_depends_on_a_sensor(tmp_path: Path) -> None:
    stop = "  operation stop { equation Base::J::M.das == Arm::S[0].voltage }\n"
    diags = check(tmp_path, mapping=remap(STOP, stop))
    assert ids(diags) == [("PMap9", STOP_LINE)]
    assert "output voltage of sensor S (Arm::S[0].voltage)" in diags[0].message
    assert "input event" in diags[0].hint


def test_PMap9_operation_assigns_its_parameter(tmp_path: Path) -> None:
    move = "  operation move { action lv = 0 ; Base::J::M.das = av }\n"
    diags = check(tmp_path, mapping=remap(MOVE, move))
    assert ids(diags) == [("PMap9", MOVE_LINE)]
    assert "assigns parameter lv" in diags[0].message


def test_PMap9_operation_assigns_actuator_inputs_from_parameters(tmp_path: Path) -> None:
    move = "  operation move { var w: real action w = lv + av ; Base::J::M.das = w }\n"
    assert check(tmp_path, mapping=remap(MOVE, move)) == []


def test_PMap10_variable_writes_a_joint_port(tmp_path: Path) -> None:
    level = "  variable level { equation Base::J.tau == level }\n"
    diags = check(tmp_path, mapping=remap(LEVEL, level))
    assert ids(diags) == [("PMap10", LEVEL_LINE)]
    assert "input tau of joint J (Base::J.tau)" in diags[0].message


def test_PMap10_variable_may_use_block_constants(tmp_path: Path) -> None:
    level = "  variable level { equation Base::J::M.das == level * Base::J::M.Kp }\n"
    assert check(tmp_path, mapping=remap(LEVEL, level)) == []


# ---------------------------------------------------------------- PMap11, PMap12


def test_PMap11_action_calls_a_dmodel_operation(tmp_path: Path) -> None:
    stop = "  operation stop { action Base::J::M.das = 0 ; move(0, 0) }\n"
    diags = check(tmp_path, mapping=remap(STOP, stop))
    pmap = [d for d in diags if d.code.id.startswith("PMap")]
    assert ids(pmap) == [("PMap11", STOP_LINE)]
    assert "calls d-model operation move (of interface MovesI)" in pmap[0].message
    # Name resolution leaves the call to PMap11: it is the only diagnostic.
    assert [d.code.id for d in diags] == ["PMap11"]


def test_PMap11_library_functions_may_be_called(tmp_path: Path) -> None:
    stop = "  operation stop { action Base::J::M.das = cos(0) - 1 }\n"
    assert check(tmp_path, mapping=remap(STOP, stop)) == []


def test_PMap12_input_event_without_predicate_occurs_every_cycle(tmp_path: Path) -> None:
    """RoboTool's newer mappings (issue 20): accepted, with a warning saying what is assumed;
    the semantics then tests `true`."""
    diags = check(tmp_path, mapping=remap(OBSTACLE, "  input event obstacle { }\n"))
    assert ids(diags) == [("PMap12", OBSTACLE_LINE)]
    assert diags[0].severity.value == "WARNING"
    assert "input event obstacle has no predicate" in diags[0].message
    assert "occurs in every cycle (predicate true)" in diags[0].message


def test_PMap12_predicate_over_an_actuator_port(tmp_path: Path) -> None:
    obstacle = "  input event obstacle { predicate Base::J::M.das >= 3.0 }\n"
    diags = check(tmp_path, mapping=remap(OBSTACLE, obstacle))
    assert ids(diags) == [("PMap12", OBSTACLE_LINE)]
    assert "input das of actuator M (Base::J::M.das)" in diags[0].message


def test_PMap12_predicate_over_the_parameter(tmp_path: Path) -> None:
    distance = "  input event distance ? d { predicate d > 0 equation d == Arm::S[0].voltage }\n"
    diags = check(tmp_path, mapping=remap(DISTANCE, distance))
    assert ids(diags) == [("PMap12", DISTANCE_LINE)]
    assert "parameter d" in diags[0].message


def test_PMap12_predicate_over_locals_and_constants(tmp_path: Path) -> None:
    obstacle = ("  input event obstacle { var x: real const limit: real = 3.0 "
                "predicate x >= limit equation x == Arm::S[1].voltage }\n")
    assert check(tmp_path, mapping=remap(OBSTACLE, obstacle)) == []


# ---------------------------------------------------------------- the marXbot


def _pmap(diags: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in diags if d.code.id.startswith("PMap")]


def test_example_marxbot_mapping_is_well_formed() -> None:
    result = api.check([EXAMPLES / "marxbot"])
    assert _pmap(result.report.diagnostics) == []
    assert any(m for f in result.workspace.user_files() for m in f.items
               if type(m).__name__ == "PlatformMapping")


@needs_corpus
def test_corpus_marxbot_mapping_is_well_formed() -> None:
    folder = CORPUS / "marXbot"
    files = sorted(folder.glob("*.p*")) + sorted(folder.glob("*.rst"))
    assert _pmap(api.check(files).report.diagnostics) == []


@pytest.mark.parametrize("rule", [f"PMap{i}" for i in range(1, 13)])
def test_every_pmap_rule_is_registered(rule: str) -> None:
    from cyphy.wellformed import RULES

    assert rule in RULES and RULES[rule].check.__module__ == "cyphy.wellformed.mappings"


def test_an_input_event_without_predicate_generates_as_true(tmp_path: Path) -> None:
    import shutil

    from cyphy import api
    from conftest import EXAMPLES

    folder = tmp_path / "marxbot"
    shutil.copytree(EXAMPLES / "marxbot", folder)
    mapping = folder / "Mapping.rsm"
    mapping.write_text(mapping.read_text().replace(
        "predicate Core::Proximity[1].voltage >= 3.0", ""))
    generated = api.generate_cyphycircus([mapping], "text")
    assert [d.code.id for d in generated.report.diagnostics] == ["PMap12"]
    text = generated.files["M.cpc"]
    assert "ObstacleToDModel ≙" in text
    obstacle = text[text.index("ObstacleToDModel ≙"):].split("\n")[0]
    assert obstacle.startswith("ObstacleToDModel ≙ if true then registerRead.obstacle!true")
