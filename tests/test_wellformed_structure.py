"""Well-formedness of the model's structure: connections (Fix1-Fix3, Flex1-Flex3), parts
(P1-P3), indices and poses (IX1, IX2, PO1) and annotations (AN1-AN4).

Every condition has at least one small model that violates exactly that condition (and is
otherwise clean) and a close variant that does not violate it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from cyphy import api
from cyphy.diagnostics import Diagnostic, Severity
from cyphy.wellformed import RULES

from conftest import CORPUS, EXAMPLES, needs_corpus

IDS = ("Fix1", "Fix2", "Fix3", "Flex1", "Flex2", "Flex3", "P1", "P2", "P3", "IX1", "IX2",
       "PO1", "AN1", "AN2", "AN3", "AN4")

BASE = """\
package robot
import physmod::sdf::annotations::*
import physmod::math::*

pmodel Robot {
	const N: int = 3
	local link Base {
		def { inertial information { mass 1.0
			inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
		local body Box { def { box(length = 0.1, width = 0.1, height = 0.1) } }
		local joint Hinge {
			def { annotation Revolute { axis = Axis { xyz = (|0, 0, 1|) } } }
			flexibly connected to Arm
		}
	}
	local link Arm {
		pose { x = 0 y = 0 z = 0.5 roll = 0 pitch = 0 yaw = 0 }
		def { inertial information { mass 0.5
			inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
		local body Rod { def { cylinder(radius = 0.01, length = 0.2) } }
	}
	part w = Wheel {
		pose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
		instantiation R = 0.05
		link Rim fixed to Base
	}
}

pmodel Wheel {
	const R: real
	const W: real = 0.02
	local link Rim {
		def { inertial information { mass 0.2
			inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
		local body Disc { def { cylinder(radius = R, length = W) } }
	}
}
"""

INERTIA = "inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 }"
REVOLUTE = "def { annotation Revolute { axis = Axis { xyz = (|0, 0, 1|) } } }"


def edit(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, f"{old!r} occurs {text.count(old)} times"
    return text.replace(old, new)


def line_of(text: str, snippet: str) -> int:
    lines = [n for n, line in enumerate(text.splitlines(), 1) if snippet in line]
    assert len(lines) == 1, f"{snippet!r} is on lines {lines}"
    return lines[0]


def diagnose(tmp_path: Path, text: str) -> list[Diagnostic]:
    path = tmp_path / "robot.pm"
    path.write_text(text, encoding="utf-8")
    return api.check([path]).report.diagnostics


def render(diags: list[Diagnostic]) -> str:
    return "\n".join(f"{d.code.id} {d.span.line}: {d.message} | {d.hint}" for d in diags)


# --------------------------------------------------------------------------- models

# The wheel carries a joint with a link inside it: S1 finds that link, but it is not a link
# of the p-model itself, so a part cannot fix it.
NESTED_LINK = edit(edit(BASE, "\t\tlocal body Disc {", f"""\
		local joint Axle {{
			{REVOLUTE}
			local link Inner {{ def {{ inertial information {{ mass 0.1 {INERTIA} }} }} }}
		}}
		local body Disc {{"""), "link Rim fixed to Base", "link Inner fixed to Base")

# A wheel whose link has a joint that the part connects.
SPIN = edit(edit(BASE, "\t\tlocal body Disc {", f"""\
		local joint Spin {{ {REVOLUTE} }}
		local body Disc {{"""), "link Rim fixed to Base", "joint Spin flexibly connected to Arm")

# ... and a second link with a joint of the same name.
TWO_SPINS = edit(SPIN, "length = W) } }\n\t}\n}\n", f"""\
length = W) }} }}
	}}
	local link Hub {{
		pose {{ x = 0 y = 0.1 z = 0 roll = 0 pitch = 0 yaw = 0 }}
		def {{ inertial information {{ mass 0.2 {INERTIA} }} }}
		local joint Spin {{ {REVOLUTE} }}
	}}
}}
""")

# An indexed body: three studs on the base.
STUDS = edit(BASE, "\t\tlocal body Box {", """\
		local body Stud {
			index k: [0, N)
			pose { x = 0.02*k y = 0 z = 0.1 roll = 0 pitch = 0 yaw = 0 }
			def { sphere(radius = 0.01) }
		}
		local body Box {""")

SOLUTION = edit(STUDS, "\tconst N: int = 3\n", """\
	const N: int = 3
	solution { solutionExpr u : real order 0 group 0 method Eval Constraint (u) [t == 0] == N }
""")

MATRIX = edit(BASE, "\tconst N: int = 3\n", "\tconst N: int = 3\n"
              "\tconst M: matrix(real, 2, 2) = [|1, 2; 3, 4|]\n")

WITH_LOCAL = edit(BASE, "def { inertial information { mass 0.5",
                  "def { local v: real inertial information { mass 0.5")

SONAR = edit(BASE, "\t\tlocal body Box {", """\
		local sensor Sound {
			def { annotation Sonar { always_on = true sonar = SonarDetails { min = 0.1 max = 2.0 } } }
		}
		local body Box {""")

TEMPLATES = BASE + """
annotation template Loop1 extends Loop2 {
	a: real = 0
}
annotation template Loop2 {
	b: real = 0
}
annotation template MyRay extends Ray {
	frames: nat = 1
}
"""


@dataclass(frozen=True)
class Case:
    """A model violating ``id`` at the line holding ``at`` (``names`` in the message), and
    ``good``, a close variant that is clean."""

    id: str
    name: str
    bad: str
    at: str
    names: tuple[str, ...]
    good: str
    severity: Severity = Severity.ERROR


CASES = [
    # ---------------------------------------------------------------- connections
    # S1 cannot check a target in a part declared after the link: Fix1 does.
    Case("Fix1", "target not a link of the part", edit(
        BASE, "\t\tlocal body Rod", "\t\tfixed to Hub in w\n\t\tlocal body Rod"),
        "fixed to Hub in w", ("Arm", "Hub", "w", "Wheel"), edit(
        BASE, "\t\tlocal body Rod", "\t\tfixed to Rim in w\n\t\tlocal body Rod")),
    Case("Fix2", "source link nested in a joint", NESTED_LINK, "link Inner fixed to",
         ("w", "Inner", "Axle"), edit(NESTED_LINK, "link Inner fixed to", "link Rim fixed to")),
    Case("Fix3", "part link fixed to itself", edit(BASE, "link Rim fixed to Base",
                                                   "link Rim fixed to Rim in w"),
         "link Rim fixed to", ("w", "Rim", "itself"), BASE),
    Case("Fix3", "target in a part declared later", edit(
        edit(BASE, "link Rim fixed to Base", "link Rim fixed to Hub in v"),
        "\t}\n}\n\npmodel Wheel", "\t}\n\tpart v = Wheel {\n\t\tpose { x = 2 y = 0 z = 0 roll = 0 "
        "pitch = 0 yaw = 0 }\n\t\tinstantiation R = 0.05\n\t}\n}\n\npmodel Wheel"),
         "link Rim fixed to", ("Rim", "Hub", "v"), edit(
        edit(BASE, "link Rim fixed to Base", "link Rim fixed to Rim in v"),
        "\t}\n}\n\npmodel Wheel", "\t}\n\tpart v = Wheel {\n\t\tpose { x = 2 y = 0 z = 0 roll = 0 "
        "pitch = 0 yaw = 0 }\n\t\tinstantiation R = 0.05\n\t}\n}\n\npmodel Wheel")),
    Case("Flex1", "joint connected to its own link", edit(
        BASE, "flexibly connected to Arm", "flexibly connected to Base"),
        "flexibly connected to", ("Hinge", "Base", "own link"), BASE),
    Case("Flex1", "target not a link of the part", edit(
        BASE, "flexibly connected to Arm", "flexibly connected to Hub in w"),
        "flexibly connected to", ("Hinge", "Hub", "w"),
        edit(BASE, "flexibly connected to Arm", "flexibly connected to Rim in w")),
    Case("Flex2", "ambiguous joint", TWO_SPINS, "joint Spin flexibly connected",
         ("w", "Spin", "Rim", "Hub"), edit(TWO_SPINS, f"Spin {{ {REVOLUTE} }}\n\t}}\n}}",
                                           f"Turn {{ {REVOLUTE} }}\n\t}}\n}}")),
    Case("Flex3", "part joint connected to its own link", edit(
        SPIN, "joint Spin flexibly connected to Arm", "joint Spin flexibly connected to Rim in w"),
        "joint Spin flexibly connected", ("w", "Spin", "Rim", "own link"), SPIN),
    # ---------------------------------------------------------------- parts
    Case("P1", "constant without value not instantiated", edit(
        BASE, "\t\tinstantiation R = 0.05\n", ""), "part w = Wheel", ("w", "R", "Wheel"), BASE,
        Severity.WARNING),
    Case("P2", "constant with a value instantiated", edit(
        BASE, "instantiation R = 0.05\n", "instantiation R = 0.05\n\t\tinstantiation W = 0.03\n"),
        "instantiation W", ("w", "W", "Wheel"), BASE),
    Case("P3", "undeclared constant", edit(
        BASE, "instantiation R = 0.05\n", "instantiation R = 0.05\n\t\tinstantiation Rad = 1\n"),
        "instantiation Rad", ("w", "Rad", "Wheel"), BASE),
    Case("P3", "value of the wrong type", edit(
        BASE, "instantiation R = 0.05", "instantiation R = true"),
        "instantiation R", ("w", "R", "boolean"), edit(
        BASE, "instantiation R = 0.05", "instantiation R = N * 0.01")),
    # ---------------------------------------------------------------- indices and poses
    Case("IX1", "reversed range", edit(STUDS, "[0, N)", "[N, 0)"), "index k",
         ("k", "Stud", "[3, 0)"), STUDS),
    Case("IX1", "empty range", edit(STUDS, "[0, N)", "[N, N)"), "index k",
         ("k", "Stud", "empty"), edit(STUDS, "[0, N)", "[N, N]"), Severity.WARNING),
    Case("IX1", "real bound", edit(STUDS, "[0, N)", "[0, 2.5)"), "index k",
         ("k", "Stud", "2.5", "integer"), STUDS),
    # S1 does not look into solutions: IX2 finds the index variable there.
    Case("IX2", "index variable used outside its block", edit(
        SOLUTION, "[t == 0] == N", "[t == 0] == k"), "solution", ("k", "Stud"), SOLUTION),
    Case("PO1", "coordinate given twice", edit(BASE, "z = 0.5 roll", "z = 0.5 z = 0.6 roll"),
         "z = 0.5 z = 0.6", ("z", "Arm", "twice"), BASE),
    Case("PO1", "a matrix row, not a number", edit(MATRIX, "z = 0.5 roll", "z = M[1] roll"),
         "z = M[1]", ("z", "Arm", "2-vector"), edit(MATRIX, "z = 0.5 roll", "z = M[1, 2] roll")),
    Case("PO1", "a local variable, not a constant", edit(WITH_LOCAL, "z = 0.5 roll", "z = v roll"),
         "z = v roll", ("z", "Arm", "'v'", "local"), WITH_LOCAL),
    # ---------------------------------------------------------------- annotations
    Case("AN1", "nested template as annotation", edit(
        BASE, "annotation Revolute { axis = Axis { xyz = (|0, 0, 1|) } }",
        "annotation Axis { xyz = (|0, 0, 1|) }"), "annotation Axis",
        ("Hinge", "Axis", "Revolute", "axis"), BASE),
    Case("AN2", "undeclared parameter", edit(BASE, "xyz = (|0, 0, 1|)", "xzy = (|0, 0, 1|)"),
         "xzy", ("Axis", "xzy"), BASE),
    Case("AN3", "wrong nested template", edit(BASE, "axis = Axis {", "axis = Limit {"),
         "axis = Limit", ("axis", "Revolute", "Axis", "Limit"),
         edit(BASE, "axis = Axis {", "axis = Axis { limit = Limit { } ")),
    Case("AN3", "value of the wrong type", edit(BASE, "xyz = (|0, 0, 1|)", "xyz = true"),
         "xyz = true", ("xyz", "Axis", "boolean"),
         edit(BASE, "xyz = (|0, 0, 1|)", "xyz = (|1, 0, 0|)")),
    Case("AN3", "Sonar written for SonarDetails",
         edit(SONAR, "sonar = SonarDetails", "sonar = Sonar"),
         "sonar = Sonar", ("sonar", "SonarDetails", "Sonar {"), SONAR),
    Case("AN4", "extension cycle", edit(TEMPLATES, "annotation template Loop2 {",
                                        "annotation template Loop2 extends Loop1 {"),
         "template Loop1", ("Loop1", "Loop2", "itself"), TEMPLATES),
    Case("AN4", "parameter declared again",
         edit(TEMPLATES, "frames: nat = 1", "always_on: boolean"),
         "always_on: boolean", ("always_on", "MyRay", "SensorBase"), TEMPLATES),
]


def _case_id(case: Case) -> str:
    return f"{case.id}-{case.name.replace(' ', '_')}"


def test_base_models_are_clean(tmp_path: Path) -> None:
    for text in (BASE, NESTED_LINK.replace("Inner fixed", "Rim fixed"), SPIN, STUDS, SOLUTION,
                 MATRIX, WITH_LOCAL, SONAR, TEMPLATES):
        assert diagnose(tmp_path, text) == [], render(diagnose(tmp_path, text))


def test_every_condition_has_a_case() -> None:
    assert {c.id for c in CASES} == set(IDS)


@pytest.mark.parametrize("case", CASES, ids=_case_id)
def test_violation(tmp_path: Path, case: Case) -> None:
    diags = diagnose(tmp_path, case.bad)
    assert [(d.code.id, d.span.line) for d in diags] == [(case.id, line_of(case.bad, case.at))], \
        render(diags)
    (d,) = diags
    assert d.severity is case.severity
    for name in case.names:
        assert name in d.message, d.message
    assert d.hint


@pytest.mark.parametrize("case", CASES, ids=_case_id)
def test_close_variant_is_clean(tmp_path: Path, case: Case) -> None:
    diags = diagnose(tmp_path, case.good)
    assert diags == [], render(diags)


# --------------------------------------------------------------------------- details


def test_hints_suggest_close_names(tmp_path: Path) -> None:
    (d,) = diagnose(tmp_path, edit(BASE, "xyz = (|0, 0, 1|)", "xzy = (|0, 0, 1|)"))
    assert "'xyz'" in d.hint
    (d,) = diagnose(tmp_path, edit(BASE, "instantiation R = 0.05\n",
                                   "instantiation R = 0.05\n\t\tinstantiation Ww = 1\n"))
    assert "'W'" in d.hint
    (d,) = diagnose(tmp_path, edit(BASE, "\t\tlocal body Rod", "\t\tfixed to Rin in w\n"
                                   "\t\tlocal body Rod"))
    assert d.code.id == "Fix1" and "'Rim'" in d.hint


def test_s1_is_not_repeated(tmp_path: Path) -> None:
    """What S1 reports is not reported again: a connection target S1 checks (the part comes
    before the link), an index variable used outside its block where S1 finds no name."""
    part = ("\tpart w = Wheel {\n\t\tpose { x = 1 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }\n"
            "\t\tinstantiation R = 0.05\n\t\tlink Rim fixed to Base\n\t}\n")
    first = edit(edit(BASE, part, ""), "\tconst N: int = 3\n", "\tconst N: int = 3\n" + part)
    first = edit(first, "\t\tlocal body Rod", "\t\tfixed to Hub in w\n\t\tlocal body Rod")
    diags = diagnose(tmp_path, first)
    assert [(d.code.id, d.span.line) for d in diags] == [
        ("S1", line_of(first, "fixed to Hub"))], render(diags)
    outside = edit(STUDS, "z = 0.5 roll", "z = k roll")
    diags = diagnose(tmp_path, outside)
    assert [(d.code.id, d.span.line) for d in diags] == [
        ("S1", line_of(outside, "z = k"))], render(diags)


def test_const_option_gives_the_missing_constant(tmp_path: Path) -> None:
    path = tmp_path / "robot.pm"
    path.write_text(edit(BASE, "\t\tinstantiation R = 0.05\n", ""), encoding="utf-8")
    diags = api.check([path], api.CheckOptions(consts={"Wheel::R": 0.05})).report.diagnostics
    assert diags == [], render(diags)


def test_nested_index_range_depending_on_an_outer_index_is_not_evaluated(tmp_path: Path) -> None:
    text = edit(STUDS, "def { sphere(radius = 0.01) }", "def { sphere(radius = 0.01) }\n"
                "\t\t\tlocal sensor S { index j: [0, k] }")
    assert [d.code.id for d in diagnose(tmp_path, text)
            if d.code.id in ("IX1", "IX2")] == []


def test_element_path_parameters_take_paths(tmp_path: Path) -> None:
    contact = edit(BASE, "\t\tlocal body Box {", """\
		local sensor Touch {
			def { annotation Contact { contact = ContactDetails { collision = Base::Box } } }
		}
		local body Box {""")
    assert diagnose(tmp_path, contact) == []
    bad = edit(contact, "collision = Base::Box", "collision = 3")
    diags = diagnose(tmp_path, bad)
    assert [(d.code.id, d.span.line) for d in diags] == [("AN3", line_of(bad, "collision"))]
    assert "element path" in diags[0].message


def test_template_defaults_are_checked(tmp_path: Path) -> None:
    bad = edit(TEMPLATES, "frames: nat = 1", "frames: nat = true")
    diags = diagnose(tmp_path, bad)
    assert [(d.code.id, d.span.line) for d in diags] == [("AN3", line_of(bad, "frames"))]
    assert "default" in diags[0].message and "frames" in diags[0].message


def test_bounds_needing_a_constant_without_value_are_not_checked(tmp_path: Path) -> None:
    text = edit(edit(STUDS, "[0, N)", "[K, 0)"), "\tconst N: int = 3\n",
                "\tconst N: int = 3\n\tconst K: int\n")
    assert [d.code.id for d in diagnose(tmp_path, text) if d.code.id in IDS] == []


def test_part_instantiates_a_variable(tmp_path: Path) -> None:
    bad = edit(edit(BASE, "\tconst W: real = 0.02\n", "\tconst W: real = 0.02\n\tinput F: real\n"),
               "instantiation R = 0.05\n", "instantiation R = 0.05\n\t\tinstantiation F = 1\n")
    diags = diagnose(tmp_path, bad)
    assert [(d.code.id, d.span.line) for d in diags] == [("P3", line_of(bad, "instantiation F"))]
    assert "input" in diags[0].message and "not a constant" in diags[0].message


def test_rules_are_registered_with_their_condition() -> None:
    for rule_id in IDS:
        r = RULES[rule_id]
        assert r.check.__name__.startswith(f"check_{rule_id}_")
        assert r.check.__doc__ and r.summary
    assert RULES["P1"].code.severity is Severity.WARNING


def test_marxbot_example_satisfies_the_structure_conditions() -> None:
    files = sorted(p for p in (EXAMPLES / "marxbot").iterdir()
                   if p.suffix in (".rsm", ".pm", ".rst"))
    diags = api.check(files).report.diagnostics
    assert [d for d in diags if d.code.id in IDS] == []


# The corpus models these conditions find wrong, and why: BodyPlusSonarSensorRef writes
# `sonar = Sonar { min … max … _radius … }` where the `sonar` parameter of Sonar takes a
# SonarDetails (notation.md, part C.1). Every other corpus project satisfies them.
CORPUS_FINDINGS = {("BodyPlusSonarSensorRef", "AN3", "BodyPlusSonarSensorRef.pm", 35)}


@needs_corpus
def test_corpus_findings() -> None:
    folders = sorted({p.parent for p in CORPUS.rglob("*.pm")})
    found = set()
    for folder in folders:
        for d in api.check(sorted(folder.glob("*.pm"))).report.diagnostics:
            if d.code.id in IDS:
                found.add((str(folder.relative_to(CORPUS)), d.code.id, Path(d.span.file).name,
                           d.span.line))
    assert found == CORPUS_FINDINGS
