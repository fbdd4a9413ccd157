"""S3: expressions are well-typed (booleans, numbers, vectors and matrices, function arity)."""

from __future__ import annotations

from pathlib import Path

import pytest

from cyphy import api

BASE = """\
import physmod::math::*
const FLAG: boolean = true
const AXIS: vector(real,3) = (|0,0,1|)
const M: matrix(real,2,3) = [|1,0,0;0,1,0|]
function scale(k: real, v: vector(real,3)): vector(real,3)
pmodel P {{
  local link L {{
    pose {{ x = {pose_x} y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
    def {{ inertial information {{ mass {mass} }} }}
    local sensor S {{
      def {{
        input u: real output y: real local w: vector(real,3)
        equation {equation}
      }}
    }}
  }}
}}
"""
GOOD = {"pose_x": "0.1*cos(PI/4)", "mass": "1.5", "equation": "y == 2*u + sqrt(u)"}


def s3(tmp_path: Path, **changes: str) -> list[tuple[int, str]]:
    text = BASE.format(**{**GOOD, **changes})
    (tmp_path / "m.rsm").write_text(text)
    diags = api.check([tmp_path / "m.rsm"],
                      api.CheckOptions(wellformedness=False)).report.diagnostics
    assert all(d.code.id == "S3" for d in diags), diags
    return [(d.span.line, d.message) for d in diags]


def test_well_typed_model(tmp_path: Path) -> None:
    assert s3(tmp_path) == []


@pytest.mark.parametrize("equation, line, message", [
    ("y + u", 13, "an equation of sensor S is a number, not a predicate"),
    ("y == u + FLAG", 13, "arithmetic ('+') on a boolean"),
    ("y == 1 /\\ u", 13, "'/\\' needs booleans, but this is a number"),
    ("not u", 13, "'not' applied to a number"),
    ("y == FLAG", 13, "'==' compares a number with a boolean"),
    ("w == (|1, 2|)", 13, "'==' compares a 3-vector with a 2-vector"),
    ("w == AXIS + (|1, 2|)", 13, "'+' between a 3-vector and a 2-vector"),
    ("w == M * AXIS", 13, "'==' compares a 3-vector with a 2-vector"),
    ("w == M * (|1, 2|)", 13, "matrix product of a 2x3 matrix and a 2-vector"),
    ("y == sqrt(u, u)", 13, "sqrt takes 1 argument, not 2"),
    ("w == scale(u)", 13, "scale takes 2 arguments, not 1"),
    ("y == if u then 1 else 0 end", 13, "the condition of 'if' is a number"),
    ("y < AXIS", 13, "'<' orders numbers, but this is a 3-vector"),
    ("w == transpose(M) * (|1, 2, 3|)", 13, "matrix product of a 3x2 matrix and a 3-vector"),
    ("w == transpose(AXIS)", 13, "'==' compares a 3-vector with a 1x3 matrix"),
    ("y == norm(ScrewAxis(AXIS, (|1, 2|)))", 13, "'v' of ScrewAxis is a 3-vector, but this is a "
     "2-vector"),
    ("w == ScrewAxis(AXIS, AXIS)", 13, "'==' compares a 3-vector with a 6-vector"),
    ("y == norm(ad(AXIS) * ScrewAxis(AXIS, AXIS))", 13, "'V' of ad is a 6-vector, but this is a 3-vector"),
    ("w == Adjoint(identity(4)) * AXIS", 13, "matrix product of a 6x6 matrix and a 3-vector"),
    ("w == inverse(M) * AXIS", 13, "'==' compares a 3-vector with a 2-vector"),
])
def test_ill_typed_equations(tmp_path: Path, equation: str, line: int, message: str) -> None:
    found = s3(tmp_path, equation=equation)
    assert [l for l, _ in found] == [line]
    assert found[0][1].startswith(message), found


@pytest.mark.parametrize("equation", [
    "w == scale(u, AXIS)", "w == AXIS + AXIS", "y == if u > 0 then 1 else 0 end",
    "derivative(y) == -u", "w[1] == u", "y == u^-1 /\\ not (u < 0)",
    "y == transpose(AXIS) * AXIS", "w == transpose(M) * (|1, 2|)",
    "w == identity(3) * AXIS", "w == transpose(M) * M * AXIS",
])


def test_close_variants_are_well_typed(tmp_path: Path, equation: str) -> None:
    assert s3(tmp_path, equation=equation) == []


def test_transposed_matrix_equation_says_so(tmp_path: Path) -> None:
    """RoboTool's newer generated files (the corpus SimpleArm) equate a 3x4 matrix with a
    4x3 literal: S3, with a hint that names the transposition."""
    text = BASE.format(**{**GOOD, "equation": "y == u"}).replace(
        "local w: vector(real,3)", "local w: vector(real,3), X: matrix(real,3,4)").replace(
        "equation y == u", "equation X == [|1,0,0;0,1,0;0,0,1;0,0,0|]")
    (tmp_path / "m.rsm").write_text(text)
    diags = api.check([tmp_path / "m.rsm"],
                      api.CheckOptions(wellformedness=False)).report.diagnostics
    assert [(d.code.id, d.span.line) for d in diags] == [("S3", 13)]
    assert diags[0].message == "'==' compares a 3x4 matrix with a 4x3 matrix"
    assert "the other's transpose" in diags[0].hint


def test_pose_and_mass_must_be_numbers(tmp_path: Path) -> None:
    found = s3(tmp_path, pose_x="FLAG", mass="AXIS")
    assert found == [(8, "pose field 'x' must be a number, not a boolean"),
                     (9, "a value of the inertial information of link L must be a number, "
                         "not a 3-vector")]


def test_declared_type_of_constants(tmp_path: Path) -> None:
    text = ("const A: boolean = 1\nconst B: real = true\nconst C: vector(real,3) = (|1,2|)\n"
            "const D: matrix(real,6,1) = (|1,0,0,0,0,0|)\n")
    (tmp_path / "c.rsm").write_text(text)
    diags = api.check([tmp_path / "c.rsm"],
                      api.CheckOptions(wellformedness=False)).report.diagnostics
    assert [(d.code.id, d.span.line) for d in diags] == [("S3", 1), ("S3", 2), ("S3", 3)]
    assert "'C' is declared a 3-vector but its value is a 2-vector" == diags[2].message
