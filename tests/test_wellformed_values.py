"""V1-V5: value checks on the elaborated model (each: a violating model and a close variant)."""

from __future__ import annotations

from pathlib import Path

import pytest

from cyphy import api

TEMPLATE = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel V {{
  local link A {{
    def {{ {link_def} }}
    local body B1 {{ pose {{ x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }} def {{ {body1} }} }}
    local body B2 {{ pose {{ x = {b2x} y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }} def {{ {body2} }} }}
    jref J = Revolute {{
      annotation Revolute {{ axis = Axis {{ xyz = {xyz} }} }}
      instantiation AXIS = {axis}
      flexibly connected to C
    }}
  }}
  local link C {{
    pose {{ x = {cx} y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
    def {{ inertial information {{ mass 1 }} }}
    local body B {{ def {{ box(length = 0.1, width = 0.1, height = 0.1) }} }}
  }}
  local link D {{
    def {{ inertial information {{ mass 1 }} }}
    local body B {{ def {{ box(length = 0.1, width = 0.1, height = 0.1) }} }}
  }}
}}
"""
GOOD = {
    "link_def": "inertial information { mass 2 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } }",
    "body1": "box(length = 1, width = 1, height = 1)",
    "body2": "sphere(radius = 0.5) bounce { restitution coefficient 0.5 }",
    "b2x": "1", "xyz": "(|0, 0, 2|)", "axis": "(|0, 0, 1|)", "cx": "1",
}


def diags(tmp_path: Path, **changes: str) -> list[tuple[str, int, str]]:
    (tmp_path / "v.rsm").write_text(TEMPLATE.format(**{**GOOD, **changes}))
    found = api.check([tmp_path / "v.rsm"]).report.diagnostics
    return [(d.code.id, d.span.line, d.message) for d in found]


def test_clean_model(tmp_path: Path) -> None:
    assert diags(tmp_path) == []


@pytest.mark.parametrize("changes, code, line, text", [
    ({"link_def": "inertial information { mass -2 }"}, "V1", 5, "mass of link V::A is -2"),
    ({"link_def": "inertial information { mass 2 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 3 } }"},
     "V1", 5, "inertia matrix of link V::A"),
    ({"body1": "box(length = 1, width = -1, height = 1)"}, "V2", 6,
     "box of body V::A::B1 has width = -1"),
    ({"body1": 'mesh { shape "meshes/arm.dae" }'}, "V2", 6,
     "mesh 'meshes/arm.dae' of body V::A::B1 does not exist"),
    ({"body2": "sphere(radius = 0.5) bounce { restitution coefficient 1.5 }"}, "V3", 7,
     "restitution_coefficient of body V::A::B2 is 1.5"),
    ({"body2": "sphere(radius = 0.5) friction { translational { coefficient1 -0.2 } }"}, "V3",
     7, "coefficient1 of body V::A::B2 is -0.2"),
    ({"axis": "(|1, 0, 0|)"}, "V4", 10, "AXIS (1, 0, 0) and the annotation's xyz (0, 0, 2)"),
    ({"xyz": "(|0, 0, 0|)"}, "V6", 9, "the annotation's xyz of joint V::A::J is the zero"),
    ({"b2x": "0", "body2": "box(length = 1, width = 1, height = 1)"}, "V5", 7,
     "bodies V::A::B1 and V::A::B2 have the same shape at the same place"),
    ({"cx": "0"}, "V5", 19, "links V::C and V::D have the same shape at the same place"),
])
def test_value_checks(tmp_path: Path, changes: dict[str, str], code: str, line: int,
                      text: str) -> None:
    """Each at the value's line (the mass, the inertia matrix, the AXIS instantiation, the
    annotation's xyz), not at its block's."""
    found = diags(tmp_path, **changes)
    assert [(c, l) for c, l, _ in found] == [(code, line)], found
    assert text in found[0][2]


def test_existing_mesh_passes(tmp_path: Path) -> None:
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "arm.dae").write_text("<COLLADA/>")
    assert diags(tmp_path, body1='mesh { shape "meshes/arm.dae" }') == []


def test_values_from_const_option(tmp_path: Path) -> None:
    text = TEMPLATE.format(**{**GOOD, "body1": "box(length = 1, width = 1, height = H)"})
    text = text.replace("pmodel V {", "const H: real\npmodel V {")
    (tmp_path / "v.rsm").write_text(text)
    assert api.check([tmp_path / "v.rsm"]).report.diagnostics == []  # H unknown: skipped
    found = api.check([tmp_path / "v.rsm"], api.CheckOptions(consts={"H": -1})).report
    assert [d.code.id for d in found.diagnostics] == ["V2"]


def test_a_zero_size_is_a_warning(tmp_path: Path) -> None:
    """Degenerate but loadable (libsdformat, PyBullet; the marXbot's track plates): issue 20."""
    (tmp_path / "v.rsm").write_text(TEMPLATE.format(
        **{**GOOD, "body1": "box(length = 1, width = 1, height = 0)"}))
    found = api.check([tmp_path / "v.rsm"]).report
    assert [(d.code.id, d.severity.value) for d in found.diagnostics] == [("V2", "WARNING")]
    assert "height = 0" in found.diagnostics[0].message and not found.has_errors


@pytest.mark.parametrize("uri, why", [
    ("../../etc/passwd", "a path that leaves the model's folder"),
    ("meshes/../../secret.dae", "a path that leaves the model's folder"),
    ("/etc/passwd", "an absolute path"),
    ("/nonexistent/arm.dae", "an absolute path"),
    ("C:\\\\models\\\\arm.dae", "an absolute path"),
    ("http://example.org/arm.dae", "a URL"),
    ("file:///etc/passwd", "a URL"),
])
def test_a_mesh_outside_the_folder_is_a_warning_that_reveals_nothing(
        tmp_path: Path, uri: str, why: str) -> None:
    """Whether the file exists must not change the diagnostic (issue 20)."""
    found = diags(tmp_path, body1=f'mesh {{ shape "{uri}" }}')
    assert [(c, l) for c, l, _ in found] == [("V2", 6)]
    assert why in found[0][2] and "does not exist" not in found[0][2]
    report = api.check([tmp_path / "v.rsm"]).report
    assert not report.has_errors


def test_mesh_place_is_judged_from_the_text() -> None:
    from cyphy.model.mesh_paths import outside_model_folder

    assert outside_model_folder("meshes/arm.dae") is None
    assert outside_model_folder("./a/../arm.stl") is None
    assert outside_model_folder("model://robot/meshes/arm.dae") is None
    assert outside_model_folder("package://robot/arm.dae") is None
    assert outside_model_folder("..") == "a path that leaves the model's folder"
    assert outside_model_folder("https://x/y.dae") == "a URL"
