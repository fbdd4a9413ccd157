"""Well-formedness of links, bodies and devices: L1-L8, B1-B3, J1-J3, SE1-SE3, AC1-AC3, JSA1.

For every id: a small model that violates exactly that condition (the diagnostic's id, line and
the element it names are checked) and a close variant that does not.
"""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import pytest

from cyphy import api
from cyphy.diagnostics import Diagnostic, Severity
from cyphy.wellformed import RULES
from cyphy.wellformed import links
from conftest import EXAMPLES

IDS = ("L1", "L2", "L3", "L4", "L5", "L6", "L7", "L8", "B1", "B2", "B3", "J1", "J2", "J3",
       "SE1", "SE2", "SE3", "AC1", "AC2", "AC3", "JSA1")
WARNINGS = {"L3", "B3", "J3", "SE3", "AC3", "L4"}


def _front_end(code: str) -> bool:
    return code.startswith(("E-", "W-")) or re.fullmatch(r"S\d", code) is not None


def check(tmp_path: Path, model: str, extra: dict[str, str] | None = None) -> list[Diagnostic]:
    """The diagnostics of ``model`` (and of ``extra`` files beside it) that are front-end
    codes (parse, placement, S1-S5), PM1 or this family's: the other rule families are
    developed separately and judged by their own tests."""
    path = tmp_path / "model.pm"
    path.write_text(textwrap.dedent(model), encoding="utf-8")
    for name, text in (extra or {}).items():
        (tmp_path / name).write_text(textwrap.dedent(text), encoding="utf-8")
    diags = api.check([path, *(tmp_path / n for n in (extra or {}))]).report.diagnostics
    return [d for d in diags if d.code.id in IDS or d.code.id == "PM1" or _front_end(d.code.id)]


def line_of(model: str, needle: str) -> int:
    """The 1-based line of ``model`` (as written to the file) holding ``needle``."""
    lines = textwrap.dedent(model).splitlines()
    hits = [i + 1 for i, line in enumerate(lines) if needle in line]
    assert len(hits) == 1, (needle, hits)
    return hits[0]


def only(diags: list[Diagnostic], rule_id: str) -> Diagnostic:
    assert [d.code.id for d in diags] == [rule_id], [(d.code.id, d.message) for d in diags]
    return diags[0]


def none_of(diags: list[Diagnostic], rule_id: str) -> None:
    assert diags == [], [(d.code.id, d.message) for d in diags]
    assert rule_id in RULES


HEADER = """\
    import physmod::joints::Revolute
    import physmod::sensors::IR
    import physmod::actuators::SpeedControlMotor
    import physmod::sdf::annotations::*
    """


# --------------------------------------------------------------------------- the registry


def test_every_id_is_registered_with_a_named_documented_check() -> None:
    for rule_id in IDS:
        r = RULES[rule_id]
        assert r.check.__module__ == links.__name__
        assert r.check.__name__.startswith(f"check_{rule_id}_")
        assert r.check.__doc__ and len(r.check.__doc__.split()) > 10
        expected = Severity.WARNING if rule_id in WARNINGS else Severity.ERROR
        assert r.code.severity is expected, rule_id


# --------------------------------------------------------------------------- *1 reference kinds

REF_TO_BODY = """\
    body SomeBody {
        box(length = 1, width = 1, height = 1)
        inertial information { mass 1.0 }
    }
    link SomeLink { inertial information { mass 1.0 } }
    pmodel P {
        lref L = SomeBody
    }
    """


def test_L1_lref_to_a_body_definition(tmp_path: Path) -> None:
    d = only(check(tmp_path, REF_TO_BODY), "L1")
    assert d.span.line == line_of(REF_TO_BODY, "lref L")
    assert "P::L" in d.message and "SomeBody" in d.message and "body definition" in d.message


def test_L1_lref_to_a_link_definition(tmp_path: Path) -> None:
    none_of(check(tmp_path, REF_TO_BODY.replace("= SomeBody", "= SomeLink")), "L1")


def test_L1_unresolved_reference_is_only_S1(tmp_path: Path) -> None:
    diags = check(tmp_path, REF_TO_BODY.replace("= SomeBody", "= Nowhere"))
    assert [d.code.id for d in diags] == ["S1"]


BREF_TO_LINK = """\
    link SomeLink { inertial information { mass 1.0 } }
    body SomeBody { box(length = 1, width = 1, height = 1) }
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            bref B = SomeLink
        }
    }
    """


def test_B1_bref_to_a_link_definition(tmp_path: Path) -> None:
    d = only(check(tmp_path, BREF_TO_LINK), "B1")
    assert d.span.line == line_of(BREF_TO_LINK, "bref B")
    assert "P::L::B" in d.message and "SomeLink" in d.message


def test_B1_bref_to_a_body_definition(tmp_path: Path) -> None:
    none_of(check(tmp_path, BREF_TO_LINK.replace("= SomeLink", "= SomeBody")), "B1")


JREF_TO_SENSOR = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            jref J = IR {
                flexibly connected to L2
            }
        }
        local link L2 { def { inertial information { mass 1.0 } } }
    }
    """


def test_J1_jref_to_a_sensor_definition(tmp_path: Path) -> None:
    d = only(check(tmp_path, JREF_TO_SENSOR), "J1")
    assert d.span.line == line_of(JREF_TO_SENSOR, "jref J")
    assert "P::L::J" in d.message and "IR" in d.message and "sensor definition" in d.message


def test_J1_jref_to_a_joint_definition(tmp_path: Path) -> None:
    model = JREF_TO_SENSOR.replace("= IR {", "= Revolute {\n instantiation AXIS = (|0,0,1|)")
    none_of(check(tmp_path, model), "J1")


SREF_TO_ACTUATOR = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            sref S = SpeedControlMotor
        }
    }
    """


def test_SE1_sref_to_an_actuator_definition(tmp_path: Path) -> None:
    d = only(check(tmp_path, SREF_TO_ACTUATOR), "SE1")
    assert d.span.line == line_of(SREF_TO_ACTUATOR, "sref S")
    assert "P::L::S" in d.message and "SpeedControlMotor" in d.message


def test_SE1_sref_to_a_sensor_definition(tmp_path: Path) -> None:
    none_of(check(tmp_path, SREF_TO_ACTUATOR.replace("= SpeedControlMotor", "= IR")), "SE1")


AREF_TO_SENSOR = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            aref A = IR
        }
    }
    """


def test_AC1_aref_to_a_sensor_definition(tmp_path: Path) -> None:
    d = only(check(tmp_path, AREF_TO_SENSOR), "AC1")
    assert d.span.line == line_of(AREF_TO_SENSOR, "aref A")
    assert "P::L::A" in d.message and "IR" in d.message and "actuator definition" in d.message


def test_AC1_aref_to_an_actuator_definition(tmp_path: Path) -> None:
    none_of(check(tmp_path, AREF_TO_SENSOR.replace("= IR", "= SpeedControlMotor")), "AC1")


# --------------------------------------------------------------------------- *2 local definitions

LOCAL_WITHOUT_DEF = HEADER + """\
    pmodel P {
        local link L {
            LDEF
            local body B {
                BDEF
                pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            }
            local joint J {
                JDEF
                flexibly connected to L2
            }
            local sensor S {
                SDEF
                pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            }
            local actuator A {
                ADEF
                pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            }
        }
        local link L2 { def { inertial information { mass 1.0 } } }
    }
    """
DEFS = {
    "LDEF": "def { inertial information { mass 1.0 } }",
    "BDEF": "def { box(length = 1, width = 1, height = 1) }",
    "JDEF": "def { input tau: real }",
    "SDEF": "def { output reading: real }",
    "ADEF": "def { input command: real }",
}
MISSING = {"L2": ("LDEF", "local link L {", "P::L"), "B2": ("BDEF", "local body B {", "P::L::B"),
           "J2": ("JDEF", "local joint J {", "P::L::J"),
           "SE2": ("SDEF", "local sensor S {", "P::L::S"),
           "AC2": ("ADEF", "local actuator A {", "P::L::A")}


def _without(placeholder: str | None) -> str:
    model = LOCAL_WITHOUT_DEF
    for key, text in DEFS.items():
        model = model.replace(key, "" if key == placeholder else text)
    return model


@pytest.mark.parametrize("rule_id", list(MISSING))
def test_local_block_without_def(tmp_path: Path, rule_id: str) -> None:
    placeholder, header, qualified = MISSING[rule_id]
    model = _without(placeholder)
    if rule_id == "L2":  # keep L4 quiet: the link's body carries the inertial information
        model = model.replace("height = 1)", "height = 1) inertial information { mass 1.0 }")
    d = only(check(tmp_path, model), rule_id)
    assert d.span.line == line_of(model, header)
    assert qualified in d.message and "def" in d.message


def test_local_blocks_with_def(tmp_path: Path) -> None:
    none_of(check(tmp_path, _without(None)), "L2")


def test_empty_def_is_a_definition(tmp_path: Path) -> None:
    model = _without(None).replace(DEFS["SDEF"], "def { }").replace(DEFS["JDEF"], "def{}")
    none_of(check(tmp_path, model), "SE2")


# --------------------------------------------------------------------------- *3 anonymous defs

NAMED_LIKE_A_DEFINITION = HEADER + """\
    link Tip { inertial information { mass 1.0 } }
    body Wheel { cylinder(radius = 0.1, length = 0.05) }
    pmodel P {
        local link LNAME {
            def { inertial information { mass 2.0 } }
            local body BNAME { def { sphere(radius = 0.1) } }
            local joint JNAME {
                def { input tau: real }
                flexibly connected to L2
            }
            local sensor SNAME { def { output reading: real } }
            local actuator ANAME { def { input command: real } }
        }
        local link L2 { def { inertial information { mass 1.0 } } }
    }
    """
CLASHES = {"L3": ("LNAME", "Tip", "link"), "B3": ("BNAME", "Wheel", "body"),
           "J3": ("JNAME", "Revolute", "joint"), "SE3": ("SNAME", "IR", "sensor"),
           "AC3": ("ANAME", "SpeedControlMotor", "actuator")}


def _named(clash: str | None) -> str:
    model = NAMED_LIKE_A_DEFINITION
    for rule_id, (placeholder, definition, _) in CLASHES.items():
        model = model.replace(placeholder, definition if rule_id == clash else f"My{placeholder}")
    return model


@pytest.mark.parametrize("rule_id", list(CLASHES))
def test_local_block_named_like_a_definition(tmp_path: Path, rule_id: str) -> None:
    _, definition, kind = CLASHES[rule_id]
    model = _named(rule_id)
    d = only(check(tmp_path, model), rule_id)
    assert d.severity is Severity.WARNING
    assert d.span.line == line_of(model, f"local {kind} {definition}")
    assert f"::{definition}" in d.message and f"{kind} definition" in d.message


def test_local_blocks_with_their_own_names(tmp_path: Path) -> None:
    none_of(check(tmp_path, _named(None)), "L3")


def test_reference_named_like_its_definition_is_fine(tmp_path: Path) -> None:
    model = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            sref IR = IR
        }
    }
    """
    none_of(check(tmp_path, model), "SE3")


# --------------------------------------------------------------------------- L4

NO_INERTIAL = """\
    body Heavy {
        box(length = 1, width = 1, height = 1)
        inertial information { mass 1.0 }
    }
    body Light { box(length = 1, width = 1, height = 1) }
    link Massive { inertial information { mass 1.0 } }
    link Massless { }
    pmodel P {
        local link L {
            def { }
            local body B { def { box(length = 1, width = 1, height = 1) } }
        }
    }
    """


def test_L4_link_without_inertial(tmp_path: Path) -> None:
    d = only(check(tmp_path, NO_INERTIAL), "L4")
    assert d.severity is Severity.WARNING
    assert d.span.line == line_of(NO_INERTIAL, "local link L")
    assert "P::L" in d.message and "(B)" in d.message


def test_L4_inertial_in_a_body(tmp_path: Path) -> None:
    model = NO_INERTIAL.replace("height = 1) } }", "height = 1)\n inertial information "
                                "{ mass 1.0 } } }")
    none_of(check(tmp_path, model), "L4")


def test_L4_inertial_in_a_referenced_body(tmp_path: Path) -> None:
    model = NO_INERTIAL.replace("local body B { def { box(length = 1, width = 1, height = 1) } }",
                                "bref B = Heavy")
    none_of(check(tmp_path, model), "L4")
    light = NO_INERTIAL.replace("local body B { def { box(length = 1, width = 1, height = 1) } }",
                                "bref B = Light")
    assert only(check(tmp_path, light), "L4").span.line == line_of(light, "local link L")


def test_L4_inertial_in_a_referenced_link(tmp_path: Path) -> None:
    massive = NO_INERTIAL.replace("local link L {", "lref L = Massive {").replace(
        "def { }", "")
    none_of(check(tmp_path, massive), "L4")
    massless = massive.replace("= Massive", "= Massless")
    d = only(check(tmp_path, massless), "L4")
    assert d.span.line == line_of(massless, "lref L") and "P::L" in d.message


# --------------------------------------------------------------------------- L5, L6

LINK_IN_LINK = """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            local link Inner {
                def { inertial information { mass 1.0 } }
            }
        }
    }
    """


def test_L5_link_inside_a_link(tmp_path: Path) -> None:
    d = only(check(tmp_path, LINK_IN_LINK), "L5")
    assert d.span.line == line_of(LINK_IN_LINK, "local link Inner")
    assert "P::L::Inner" in d.message and "P::L" in d.message


def test_L5_links_side_by_side(tmp_path: Path) -> None:
    model = """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
        }
        local link Inner {
            def { inertial information { mass 1.0 } }
            fixed to L
        }
    }
    """
    none_of(check(tmp_path, model), "L5")


def test_L5_a_part_inside_a_link_is_a_placement_error(tmp_path: Path) -> None:
    model = """\
    pmodel Q {
        local link W { def { inertial information { mass 1.0 } } }
    }
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            part Q1 = Q { }
        }
    }
    """
    diags = check(tmp_path, model)
    assert [(d.code.id, d.span.line) for d in diags] == [("E-MEMBER", line_of(model, "part Q1"))]


FIXED_TO_SELF = """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            fixed to L
        }
        local link L2 { def { inertial information { mass 1.0 } } }
    }
    """


def test_L6_link_fixed_to_itself(tmp_path: Path) -> None:
    d = only(check(tmp_path, FIXED_TO_SELF), "L6")
    assert d.span.line == line_of(FIXED_TO_SELF, "fixed to L")
    assert "P::L" in d.message and "itself" in d.message


def test_L6_link_fixed_to_another(tmp_path: Path) -> None:
    none_of(check(tmp_path, FIXED_TO_SELF.replace("fixed to L\n", "fixed to L2\n")), "L6")


def test_L6_same_name_in_a_part_is_another_link(tmp_path: Path) -> None:
    model = """\
    pmodel Q {
        local link L { def { inertial information { mass 1.0 } } }
    }
    pmodel P {
        part Q1 = Q { }
        local link L {
            def { inertial information { mass 1.0 } }
            fixed to L in Q1
        }
    }
    """
    none_of(check(tmp_path, model), "L6")


# --------------------------------------------------------------------------- L7

SENSOR_IN_BODY = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            local body B {
                def { box(length = 1, width = 1, height = 1) }
                sref S = IR
            }
        }
    }
    """


def test_L7_sensor_inside_a_body(tmp_path: Path) -> None:
    d = only(check(tmp_path, SENSOR_IN_BODY), "L7")
    assert d.span.line == line_of(SENSOR_IN_BODY, "sref S")
    assert "P::L::B::S" in d.message and "body P::L::B" in d.message


def test_L7_sensor_beside_the_body(tmp_path: Path) -> None:
    model = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            local body B {
                def { box(length = 1, width = 1, height = 1) }
            }
            sref S = IR
        }
    }
    """
    none_of(check(tmp_path, model), "L7")


def test_L7_actuator_inside_a_sensor(tmp_path: Path) -> None:
    model = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            local sensor S {
                def { output reading: real }
                aref A = SpeedControlMotor
            }
        }
    }
    """
    d = only(check(tmp_path, model), "L7")
    assert d.span.line == line_of(model, "aref A")
    assert "P::L::S::A" in d.message and "sensor P::L::S" in d.message


FIXED_TO_BODY = """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            local body B { def { box(length = 1, width = 1, height = 1) } }
        }
        local link L2 {
            def { inertial information { mass 1.0 } }
            fixed to B
        }
    }
    """


def test_L7_link_fixed_to_a_body(tmp_path: Path) -> None:
    # The target names no link, so S1 reports it too; L7 says what it is instead.
    diags = check(tmp_path, FIXED_TO_BODY)
    assert sorted(d.code.id for d in diags) == ["L7", "S1"]
    d = next(d for d in diags if d.code.id == "L7")
    assert d.span.line == line_of(FIXED_TO_BODY, "fixed to B")
    assert "P::L2" in d.message and "P::L::B" in d.message and "body" in d.message


def test_L7_link_fixed_to_the_link_of_the_body(tmp_path: Path) -> None:
    none_of(check(tmp_path, FIXED_TO_BODY.replace("fixed to B", "fixed to L")), "L7")


def test_L7_joint_connected_to_a_body_of_a_part(tmp_path: Path) -> None:
    model = HEADER + """\
    pmodel Q {
        local link W {
            def { inertial information { mass 1.0 } }
            local body Tyre { def { cylinder(radius = 0.1, length = 0.05) } }
        }
    }
    pmodel P {
        part Q1 = Q { }
        local link L {
            def { inertial information { mass 1.0 } }
            jref J = Revolute {
                instantiation AXIS = (|0,0,1|)
                flexibly connected to Tyre in Q1
            }
        }
    }
    """
    diags = check(tmp_path, model)
    assert sorted(d.code.id for d in diags) == ["L7", "S1"]
    d = next(d for d in diags if d.code.id == "L7")
    assert d.span.line == line_of(model, "flexibly connected to Tyre")
    assert "P::L::J" in d.message and "Q::W::Tyre" in d.message
    none_of(check(tmp_path, model.replace("to Tyre in", "to W in")), "L7")


# --------------------------------------------------------------------------- L8

TWO_INERTIALS = """\
    pmodel P {
        local link L {
            def { inertial information { mass 2.0 } }
            local body B {
                def {
                    box(length = 1, width = 1, height = 1)
                    inertial information { mass 1.0 }
                }
            }
        }
    }
    """


def test_L8_link_and_body_both_give_inertials(tmp_path: Path) -> None:
    d = only(check(tmp_path, TWO_INERTIALS), "L8")
    assert d.span.line == line_of(TWO_INERTIALS, "inertial information { mass 1.0 }")
    assert "P::L" in d.message and "P::L::B" in d.message


def test_L8_only_the_link_gives_one(tmp_path: Path) -> None:
    model = TWO_INERTIALS.replace("""
                    inertial information { mass 1.0 }
""", "\n")
    none_of(check(tmp_path, model), "L8")


def test_L8_referenced_body_gives_one(tmp_path: Path) -> None:
    model = """\
    body Heavy {
        box(length = 1, width = 1, height = 1)
        inertial information { mass 1.0 }
    }
    pmodel P {
        local link L {
            def { inertial information { mass 2.0 } }
            bref B = Heavy
        }
    }
    """
    d = only(check(tmp_path, model), "L8")
    assert d.span.line == line_of(model, "bref B")
    assert "P::L::B" in d.message and "Heavy" in d.message


# --------------------------------------------------------------------------- JSA1

MOTOR_RELATION = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            jref J = Revolute {
                instantiation AXIS = (|0,0,1|)
                flexibly connected to L2
                aref M = SpeedControlMotor {
                    relation RELATION
                }
            }
        }
        local link L2 { def { inertial information { mass 1.0 } } }
    }
    """


@pytest.mark.parametrize("relation", ["M.T >= J.tau", "M.T == J.tau /\\ M.av < J.v",
                                      "M.T == J.tau == 0", "M.T"])
def test_JSA1_relation_that_is_not_equalities(tmp_path: Path, relation: str) -> None:
    model = MOTOR_RELATION.replace("RELATION", relation)
    d = only(check(tmp_path, model), "JSA1")
    assert d.span.line == line_of(model, "relation ")
    assert "P::L::J::M" in d.message


@pytest.mark.parametrize("relation", ["M.T == J.tau", "M.T == J.tau /\\ M.av == J.v"])
def test_JSA1_equalities(tmp_path: Path, relation: str) -> None:
    none_of(check(tmp_path, MOTOR_RELATION.replace("RELATION", relation)), "JSA1")


def test_JSA1_bare_relation_of_an_sref(tmp_path: Path) -> None:
    model = HEADER + """\
    pmodel P {
        local link L {
            def { inertial information { mass 1.0 } }
            sref S = IR { S.distance <= 0.1 }
        }
    }
    """
    d = only(check(tmp_path, model), "JSA1")
    assert d.span.line == line_of(model, "sref S") and "P::L::S" in d.message
    none_of(check(tmp_path, model.replace("<=", "==")), "JSA1")


def test_JSA1_does_not_apply_to_joints(tmp_path: Path) -> None:
    model = MOTOR_RELATION.replace("RELATION", "M.T == J.tau").replace(
        "flexibly connected to L2", "flexibly connected to L2\n relation J.tau >= 0")
    none_of(check(tmp_path, model), "JSA1")


# --------------------------------------------------------------------------- examples


def test_marxbot_example_satisfies_the_link_conditions() -> None:
    diags = api.check([EXAMPLES / "marxbot"]).report.diagnostics
    assert [d for d in diags if d.code.id in IDS] == []

