"""`cyphy check --consistency` on vector-typed ports: a thruster's wrench input written whole
or per component, a gyroscope's vector output read per component. The checks go through the
scalarisation the Isabelle printers use, one Z3 constant per component.

The second derivation: each mapping is also written by hand against scalar twins of the same
devices (``ScalarThruster``'s ``w1`` … ``w6``, ``ScalarGyro``'s ``mx`` … ``mz``); both must give
the same verdicts, naming the same components, and every witness is checked against the
equations it claims to contradict."""

from __future__ import annotations

import re
from fractions import Fraction
from pathlib import Path

import pytest

from cyphy.api import CheckOptions, check

ROBOT = """package vectorRobot

import physmod::sensors::Gyroscope

// A thruster that applies the wrench it is given (moment; force).
actuator Thruster {
	input wrench: vector(real, 6)
	output W: vector(real, 6)
	equation W == wrench
}

// The same thruster with one input per component.
actuator ScalarThruster {
	input w1: real, w2: real, w3: real, w4: real, w5: real, w6: real
	output W: vector(real, 6)
	equation W == (|w1, w2, w3, w4, w5, w6|)
}

// A gyroscope with one port per axis.
sensor ScalarGyro {
	input x: real, y: real, z: real
	output mx: real, my: real, mz: real
	equation mx == x
	equation my == y
	equation mz == z
}

pmodel Robot {
	local link Base {
		def {
			inertial information {
				mass 1.0
				inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 }
			}
		}
		sref Gyro = Gyroscope { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } }
		sref SG = ScalarGyro { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } }
		aref T = Thruster { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } }
		aref S = ScalarThruster { pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 } }
	}
}
"""

SOFTWARE = """package vectorSoftware

interface PushI {
	push(f: real)
}

interface SenseI {
	event spinning
	event rate: real
}

module Soft {
	cycleDef cycle == 1
	robotic platform P {
		provides PushI
		uses SenseI
	}
}
"""

#: The consistent mapping, element by element, written against the vector ports.
CONSISTENT = {
    "push": "operation push { equation Base::T.wrench == (|0, 0, 0, 0, 0, f|) }",
    "spinning": "input event spinning { predicate Base::Gyro.measuredAngularVelocity[3] > 1 }",
    "rate": """input event rate ? r {
		predicate Base::Gyro.measuredAngularVelocity[3] > 0
		equation r == Base::Gyro.measuredAngularVelocity[3]
	}""",
}
#: name → the element that makes the mapping inconsistent (the others as in CONSISTENT).
FAULTS = {
    # (the faults do not write one name twice as `x == e`: that is PMap16, refused before any
    # consistency check runs; these shapes are left to C1 and C3)
    "contradiction": ("push", """operation push {
		equation Base::T.wrench[3] - f == 0
		equation Base::T.wrench == (|0, 0, 2 * f, 0, 0, 0|)
	}"""),
    "underdetermined": ("push", """operation push {
		var x: real
		equation Base::T.wrench == (|0, 0, 0, 0, x, f - x|)
	}"""),
    "never": ("spinning", """input event spinning {
		predicate Base::Gyro.measuredAngularVelocity[3] > 1 /\\ Base::Gyro.measuredAngularVelocity[3] < 0
	}"""),
    "no value": ("rate", """input event rate ? r {
		predicate Base::Gyro.measuredAngularVelocity[1] > 0
		equation r == Base::Gyro.measuredAngularVelocity[3]
		equation r - Base::Gyro.measuredAngularVelocity[2] == 0
	}"""),
}
MAPPINGS = {"consistent": "".join(f"\n\t{e}" for e in CONSISTENT.values())} | {
    name: "".join(f"\n\t{text if k == element else e}" for k, e in CONSISTENT.items())
    for name, (element, text) in FAULTS.items()}
EXPECTED = {"consistent": [], "contradiction": ["C1"], "underdetermined": ["C2"] * 2,
            "never": ["C4"], "no value": ["C3"]}


def scalar(text: str) -> str:
    """The hand-scalarised twin of a mapping: components become the scalar devices' ports."""
    def vector(m: re.Match[str]) -> str:
        items = [i.strip() for i in m.group(1).split(",")]
        return " /\\ ".join(f"Base::S.w{k + 1} == {v}" for k, v in enumerate(items))

    text = re.sub(r"equation Base::T\.wrench == \(\|(.*)\|\)", lambda m: "equation " +
                  vector(m).replace(" /\\ ", "\n\t\tequation "), text)
    text = re.sub(r"Base::T\.wrench\[(\d)\]", r"Base::S.w\1", text)
    return re.sub(r"Base::Gyro\.measuredAngularVelocity\[(\d)\]",
                  lambda m: "Base::SG.m" + "xyz"[int(m.group(1)) - 1], text)


def diagnostics(folder: Path, name: str, body: str) -> list[dict]:
    (folder / "robot.rsm").write_text(ROBOT, encoding="utf-8")
    (folder / "sw.rsm").write_text(SOFTWARE, encoding="utf-8")
    mapping = folder / "map.rsm"
    mapping.write_text("import vectorRobot::*\nimport vectorSoftware::*\n\n"
                       f"map M dmodel Soft to pmodel Robot {{{body}\n}}\n", encoding="utf-8")
    result = check([str(mapping), str(folder / "robot.rsm"), str(folder / "sw.rsm")],
                   CheckOptions(consistency=True))
    return [d.to_json() for d in result.report.diagnostics
            if d.code.id.startswith("C") or d.severity == "ERROR"]


def _as_scalar_names(text: str) -> str:
    text = re.sub(r"T\.wrench\[(\d)\]", r"S.w\1", text)
    return re.sub(r"Gyro\.measuredAngularVelocity\[(\d)\]",
                  lambda m: "SG.m" + "xyz"[int(m.group(1)) - 1], text)


def _without_numbers(text: str) -> str:
    return re.sub(r"-?\d+(\.\d+)?(/\d+)?( \(≈ [^)]*\))?", "#", text)


@pytest.mark.parametrize("name", list(MAPPINGS))
def test_vector_ports_get_the_verdicts_of_their_scalar_twins(tmp_path: Path, name: str) -> None:
    body = MAPPINGS[name]
    (tmp_path / "v").mkdir()
    (tmp_path / "s").mkdir()
    vector = diagnostics(tmp_path / "v", name, body)
    twin = diagnostics(tmp_path / "s", name, scalar(body))
    assert [d["code"] for d in vector] == EXPECTED[name], vector
    assert [d["code"] for d in twin] == EXPECTED[name], twin
    for v, s in zip(vector, twin):
        assert _without_numbers(_as_scalar_names(v["message"])) == \
            _without_numbers(s["message"])


def test_underdetermined_names_each_free_component(tmp_path: Path) -> None:
    diags = diagnostics(tmp_path, "underdetermined", MAPPINGS["underdetermined"])
    free = [re.search(r"do not determine (\S+):", d["message"]).group(1) for d in diags]
    assert free == ["Base::T.wrench[5]", "Base::T.wrench[6]"]


def test_contradiction_witness_contradicts_the_component_equations(tmp_path: Path) -> None:
    """C1's witness f must make wrench[3] - f == 0 and wrench[3] == 2 f disagree (f ≠ 0), and
    the core names the third component of the vector equation."""
    [c1] = diagnostics(tmp_path, "contradiction", MAPPINGS["contradiction"])
    f = Fraction(re.search(r"push\(f = (-?[\d./]+)\)", c1["message"]).group(1))
    assert f != 0 and f != 2 * f
    notes = "\n".join(c1["notes"])
    assert "Base::T.wrench[3] - f == 0" in notes and "(component 3)" in notes


def test_never_uses_the_gyroscope_equations_per_component(tmp_path: Path) -> None:
    [c4] = diagnostics(tmp_path, "never", MAPPINGS["never"])
    assert "can never hold" in c4["message"]
    assert not any("were not used" in n for n in c4["notes"])


def test_a_vector_of_open_size_is_not_checked_and_says_why(tmp_path: Path) -> None:
    robot = ROBOT.replace("input wrench: vector(real, 6)", "input wrench: vector(real)")
    robot = robot.replace("equation W == wrench", "")
    (tmp_path / "robot.rsm").write_text(robot, encoding="utf-8")
    (tmp_path / "sw.rsm").write_text(SOFTWARE, encoding="utf-8")
    mapping = tmp_path / "map.rsm"
    mapping.write_text("import vectorRobot::*\nimport vectorSoftware::*\n\nmap M dmodel Soft "
                       "to pmodel Robot {" + MAPPINGS["contradiction"] + "\n}\n",
                       encoding="utf-8")
    result = check([str(mapping), str(tmp_path / "robot.rsm"), str(tmp_path / "sw.rsm")],
                   CheckOptions(consistency=True))
    unknown = [d for d in result.report.diagnostics if d.code.id == "C-UNKNOWN"]
    assert len(unknown) == 1 and "size is not declared" in unknown[0].message, unknown


def test_vector_parameters_and_locals_are_per_component(tmp_path: Path) -> None:
    """press(v) through a vector local g: determined, so only the conflict with push on the
    wrench's components (C5), each witness naming v's components."""
    (tmp_path / "robot.rsm").write_text(ROBOT, encoding="utf-8")
    software = SOFTWARE.replace("push(f: real)", "push(f: real)\n\tpress(v: vector(real, 6))")
    (tmp_path / "sw.rsm").write_text(software, encoding="utf-8")
    press = ("\n\toperation press { var g: vector(real, 6) equation g == v "
             "equation Base::T.wrench == g }")
    mapping = tmp_path / "map.rsm"
    mapping.write_text("import vectorRobot::*\nimport vectorSoftware::*\n\nmap M dmodel Soft "
                       "to pmodel Robot {" + MAPPINGS["consistent"] + press + "\n}\n",
                       encoding="utf-8")
    result = check([str(mapping), str(tmp_path / "robot.rsm"), str(tmp_path / "sw.rsm")],
                   CheckOptions(consistency=True))
    [c5] = [d for d in result.report.diagnostics if d.code.id.startswith("C")]
    assert c5.code.id == "C5" and len(c5.notes) == 6
    for k, note in enumerate(c5.notes, start=1):
        values = dict(re.findall(r"v\[(\d)\] = (-?[\d./]+)", note.split("press(")[1]))
        set_to = Fraction(note.rsplit(" to ", 1)[1])
        assert note.startswith(f"Base::T.wrench[{k}]:") and Fraction(values[str(k)]) == set_to
