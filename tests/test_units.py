"""Units (issue 27, item 4): every value with a unit has the dimension of where it is used
(U1), with Pint's units; values are still converted to SI."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT
from cyphy import api
from cyphy.model.units import TABLE, from_pint, units

MODEL = """\
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor
pmodel Arm {{
  local link Base {{
    pose {{ x = {x} y = 0 z = 0 roll = 0 pitch = 0 yaw = {yaw} }}
    def {{ inertial information {{ mass {mass} inertia matrix {{ ixx {ixx} ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
    local body B {{ def {{ box(length = {length}, width = 0.1m, height = 10cm) }} }}
    jref J = Revolute {{
      instantiation AXIS = (|0, 0, 1|)
      aref M = SpeedControlMotor {{ instantiation J = {rotor} }}
      flexibly connected to Tip
    }}
  }}
  local link Tip {{ def {{ inertial information {{ mass 2kg }} }} }}
}}
"""
GOOD = {"x": "0.5m", "yaw": "30deg", "mass": "2kg", "ixx": "1", "length": "20cm",
        "rotor": "0.01"}


def u1(tmp_path: Path, **changes: str) -> list[tuple[int, str, str]]:
    model = tmp_path / "arm.rsm"
    model.write_text(MODEL.format(**{**GOOD, **changes}))
    report = api.check([model]).report
    return [(d.span.line, d.message, d.hint) for d in report.diagnostics if d.code.id == "U1"]


def test_the_table_is_pints() -> None:
    """The stored table is what Pint says (the oracle), for exactly the grammar's suffixes."""
    pytest.importorskip("pint")
    import json

    stored = json.loads(TABLE.read_text())
    assert stored == from_pint(stored)
    grammar = (ROOT / "cyphy" / "lang" / "robosim.lark").read_text()
    pattern = re.search(r"^UNIT\.3: /(.*)/$", grammar, re.M).group(1)  # type: ignore[union-attr]
    suffixes = set(re.findall(r"(?<![A-Za-z?])([A-Za-z]{1,9})(?=[|)])", pattern))
    assert suffixes == set(stored)


def test_a_correct_model_has_no_unit_error(tmp_path: Path) -> None:
    assert u1(tmp_path) == []


@pytest.mark.parametrize("changes, line, text, hint", [
    ({"mass": "2m"}, 6, "the mass of link Arm::Base (2m) has the dimension [length]; "
     "expected [mass]", "kg, g"),
    ({"length": "3kg"}, 7, "the box's length of body Arm::Base::B (3kg) has the dimension "
     "[mass]; expected [length]", "m, cm, km, mm"),
    ({"length": "30deg"}, 7, "the box's length of body Arm::Base::B (30deg) is dimensionless "
     "(an angle); expected [length]", "m, cm"),
    ({"yaw": "2m"}, 5, "the pose's yaw of link Arm::Base (2m) has the dimension [length]; "
     "expected dimensionless", "rad, deg"),
    ({"x": "1s"}, 5, "the pose's x of link Arm::Base (1s) has the dimension [time]; expected "
     "[length]", "m"),
    ({"ixx": "1kg"}, 6, "the inertia ixx of link Arm::Base (1kg) has the dimension [mass]; "
     "expected [mass] * [length] ** 2", "plain number in SI units (no suffix"),
    ({"x": "0.5m + 2kg"}, 5, "(0.5m + 2kg) adds [length] to [mass]", "m"),
    ({"rotor": "2kg"}, 10, "SpeedControlMotor's J in actuator Arm::Base::J::M (2kg) has the "
     "dimension [mass]; expected [mass] * [length] ** 2", "plain number"),
    ({"mass": "(2 * 3m) / 2s"}, 6, "has the dimension [length] / [time]; expected [mass]",
     "kg"),
])
def test_a_unit_of_another_dimension_is_U1(tmp_path: Path, changes: dict[str, str],
                                           line: int, text: str, hint: str) -> None:
    [(at, message, how)] = u1(tmp_path, **changes)
    assert at == line and text in message and hint in how, message


def test_u1_refuses_generation(tmp_path: Path) -> None:
    model = tmp_path / "arm.rsm"
    model.write_text(MODEL.format(**{**GOOD, "mass": "2m"}))
    generated = api.generate_sdf([model])
    assert generated.files == {} and [d.code.id for d in generated.report.errors] == ["U1"]


def test_values_are_still_converted_to_si(tmp_path: Path) -> None:
    model = tmp_path / "arm.rsm"
    model.write_text(MODEL.format(**{**GOOD, "x": "50cm", "mass": "2000g"}))
    elaborated = api.elaborate([model]).model
    assert elaborated is not None
    base = elaborated.links[0]
    x, _, _, _, _, yaw = base.pose.to_xyz_rpy()  # type: ignore[union-attr]
    assert (x, yaw) == pytest.approx((0.5, math.pi / 6), rel=1e-12)
    assert base.inertial.mass == pytest.approx(2.0)  # type: ignore[union-attr]
    assert elaborated.bodies[0].size["length"] == pytest.approx(0.2)
    assert units()["deg"].factor == math.pi / 180


def test_check_does_not_import_pint(tmp_path: Path) -> None:
    """Pint costs seconds to import and set up; `cyphy check` reads the stored table."""
    model = tmp_path / "arm.rsm"
    model.write_text(MODEL.format(**GOOD))
    code = ("import sys; from cyphy import api; "
            f"assert not api.check([{str(model)!r}]).report.has_errors; "
            "print('pint' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=ROOT, timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.stdout.strip() == "False", done.stderr


def test_a_constant_has_the_dimension_of_its_value(tmp_path: Path) -> None:
    model = tmp_path / "c.rsm"
    model.write_text("""\
pmodel C {
  const H: real = 0.05m
  const W: real = 2 * H
  const M: real = 3kg
  const Bad: real = 1m + 1kg
  local link L {
    pose { x = W y = H z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass H } }
    local body B { def { box(length = W, width = M, height = Bad) } }
    local body D { def { box(length = Bad, width = 1, height = 1) } }
  }
}
""")
    found = [(d.span.line, d.message) for d in api.check([model]).report.diagnostics
             if d.code.id == "U1"]
    assert [line for line, _ in found] == [5, 8, 9]  # Bad's sum once, at its definition
    assert "(1m + 1kg) adds [length] to [mass]" in found[0][1]
    assert "the mass of link C::L (H) has the dimension [length]" in found[1][1]
    assert "the box's width of body C::L::B (M) has the dimension [mass]" in found[2][1]


def test_annotation_values_have_their_sdf_units(tmp_path: Path) -> None:
    """Joint limits are angles for a revolute joint and lengths for a prismatic one; sensor
    ranges are lengths (SDFormat's units, physmod::sdf::annotations)."""
    model = tmp_path / "a.rsm"
    model.write_text("""\
import physmod::joints::Revolute
import physmod::joints::Prismatic
import physmod::sdf::annotations::*
pmodel A {
  local link Base {
    def { inertial information { mass 1 } }
    jref J = Revolute {
      annotation Revolute { axis = Axis { limit = Limit { lower = -90deg upper = 2m } } }
      flexibly connected to Tip
    }
    jref P = Prismatic {
      annotation Prismatic { axis = Axis { limit = Limit { lower = -10cm upper = 30deg } } }
      flexibly connected to Tip2
    }
    local sensor S { def { annotation Sonar { sonar = SonarDetails { min = 2cm max = 4kg } } } }
  }
  local link Tip { def { inertial information { mass 1 } } }
  local link Tip2 { def { inertial information { mass 1 } } }
}
""")
    found = [(d.span.line, d.message) for d in api.check([model]).report.diagnostics
             if d.code.id == "U1"]
    assert [line for line, _ in found] == [8, 12, 15], found
    assert "axis.limit.upper of joint A::Base::J (2m) has the dimension [length]" in found[0][1]
    assert "axis.limit.upper of joint A::Base::P (30deg) is dimensionless" in found[1][1]
    assert "sonar.max of sensor A::Base::S (4kg) has the dimension [mass]" in found[2][1]
