"""The SDF validation tools (tests/sdf_tools) detect what they claim to detect.

Anchors: ../shared/spec/sdf-validation.md, measured on RoboTool's 200 generated SDF files.
"""

from __future__ import annotations

import re
import subprocess
from collections import Counter
from pathlib import Path

import pytest
from conftest import CORPUS, needs_corpus
from sdf_tools import check_sdf, pybullet_load_many

pytest_plugins = ["sdf_tools.fixtures"]  # the sdf_checker and pybullet_loader fixtures

INERTIAL = (
    "<inertial><mass>0.5</mass><inertia><ixx>0.01</ixx><ixy>0</ixy><ixz>0</ixz>"
    "<iyy>0.01</iyy><iyz>0</iyz><izz>0.01</izz></inertia></inertial>"
)
BOX = "<geometry><box><size>0.1 0.2 0.05</size></box></geometry>"
AXIS = (
    "<axis><xyz>0 0 1</xyz><initial_position>0.1</initial_position>"
    "<limit><lower>-1.5</lower><upper>1.5</upper></limit></axis>"
)

# A minimal valid SDF 1.6 model: two links, a limited revolute joint, an IMU.
# <initial_position> is valid in 1.6 (libsdformat 12 only knows 1.9, so it is whitelisted).
VALID = f"""<?xml version="1.0"?>
<sdf version="1.6">
  <model name="arm">
    <self_collide>true</self_collide>
    <pose>0 0 0.5 0 0 0</pose>
    <link name="base">
      <pose>0 0 0 0 0 0</pose>
      {INERTIAL}
      <collision name="base_collision">{BOX}</collision>
      <visual name="base_visual">{BOX}</visual>
    </link>
    <link name="upper">
      <pose>0 0 0.2 0 0 0</pose>
      {INERTIAL}
      <collision name="upper_collision">{BOX}</collision>
      <visual name="upper_visual">{BOX}</visual>
      <sensor name="imu" type="imu"><update_rate>10</update_rate></sensor>
    </link>
    <joint name="shoulder" type="revolute">
      <pose>0 0 0 0 0 0</pose>
      <parent>base</parent>
      <child>upper</child>
      {AXIS}
    </joint>
  </model>
</sdf>
"""


def write(tmp_path: Path, text: str, name: str = "model.sdf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def variant(tmp_path: Path, old: str, new: str) -> Path:
    assert old in VALID
    return write(tmp_path, VALID.replace(old, new, 1))


def errors(path: Path, **flags: bool) -> list[str]:
    result = check_sdf([path], **flags)
    assert list(result) == [path]
    return result[path]


IGN_ONLY = {"strict": False, "lints": False}  # exactly `ign sdf -k`


# --- sdfcheck ------------------------------------------------------------------------


def test_valid_model_passes(tmp_path, sdf_checker):
    path = write(tmp_path, VALID)
    assert errors(path) == []
    assert errors(path, **IGN_ONLY) == []


def test_cli_prints_one_line_per_file_and_sets_the_exit_status(tmp_path, sdf_checker):
    good = write(tmp_path, VALID, "good.sdf")
    bad = write(tmp_path, "<sdf version='1.6'><model name='m'>", "bad.sdf")
    ok = subprocess.run([sdf_checker, good], check=False, capture_output=True, text=True)
    assert (ok.returncode, ok.stdout) == (0, f"OK {good}\n")
    both = subprocess.run([sdf_checker, good, bad], check=False, capture_output=True, text=True)
    assert both.returncode == 1
    lines = both.stdout.splitlines()
    assert lines[0] == f"OK {good}"
    assert lines[1:] and all(ln.startswith(f"ERROR {bad}: ") for ln in lines[1:])


def test_duplicate_sibling_links_are_named(tmp_path, sdf_checker):
    path = variant(tmp_path, '<link name="upper">', '<link name="base">')
    errs = errors(path, **IGN_ONLY)
    assert any(e.startswith("DUPLICATE_NAME:") and "[base]" in e for e in errs), errs


def test_collision_and_visual_with_one_name_fail_the_ign_name_check(tmp_path, sdf_checker):
    # RoboTool's most common defect: it loads, but `ign sdf -k` rejects it.
    path = variant(tmp_path, 'name="upper_collision"', 'name="upper_body"')
    path.write_text(path.read_text().replace('name="upper_visual"', 'name="upper_body"'))
    errs = errors(path, **IGN_ONLY)
    assert errs == ['non-unique name "upper_body" used by 2 children of <link name="upper">']


def test_revolute_joint_without_axis_fails(tmp_path, sdf_checker):
    path = variant(tmp_path, AXIS, "")
    errs = errors(path)
    assert errs == [
        'lint joint_no_axis: model "arm": joint "shoulder" of type revolute has no <axis>'
    ]
    assert errors(path, **IGN_ONLY) == []  # SDFormat itself accepts it (and assumes z)


def test_axis_without_limit_fails(tmp_path, sdf_checker):
    path = variant(tmp_path, "<limit><lower>-1.5</lower><upper>1.5</upper></limit>", "")
    errs = errors(path)
    assert len(errs) == 1 and errs[0].startswith("lint axis_no_limit:") and "shoulder" in errs[0]


def test_link_with_two_parents_and_disconnected_links_fail(tmp_path, sdf_checker):
    extra = f"""<link name="loose">{INERTIAL}</link>
    <link name="tip">{INERTIAL}</link>
    <joint name="a" type="fixed"><parent>base</parent><child>tip</child></joint>
    <joint name="b" type="fixed"><parent>upper</parent><child>tip</child></joint>
  </model>"""
    errs = errors(variant(tmp_path, "</model>", extra))
    assert len(errs) == 2, errs
    assert errs[0].startswith('lint multi_parent: model "arm": link "tip"')
    assert errs[1] == 'lint disconnected: model "arm": 2 root links (base, loose)'


def test_invalid_sensor_type_fails(tmp_path, sdf_checker):
    path = variant(tmp_path, 'type="imu"', 'type="light"')
    errs = errors(path, **IGN_ONLY)
    assert any(e.startswith("ATTRIBUTE_INVALID:") and "sensor type" in e for e in errs), errs


def test_malformed_xml_fails(tmp_path, sdf_checker):
    path = variant(tmp_path, "</link>", "")
    errs = errors(path, **IGN_ONLY)
    assert errs[0].startswith("FILE_READ:")
    assert any("Error parsing XML" in e for e in errs), errs


def test_missing_file_fails(tmp_path, sdf_checker):
    assert errors(tmp_path / "absent.sdf")[0].startswith("FILE_READ:")


def test_unknown_element_fails_only_in_strict_mode(tmp_path, sdf_checker):
    surface = "<surface><bounce><threshold>1</threshold></bounce></surface>"
    visual = f'<visual name="base_visual">{BOX}'
    path = variant(tmp_path, visual, visual + surface)
    errs = errors(path)
    assert len(errs) == 1 and errs[0].startswith("strict: ELEMENT_INCORRECT_TYPE:")
    assert "Element[surface], child of element[visual]" in errs[0]
    assert errors(path, **IGN_ONLY) == []


def test_invalid_inertia_fails(tmp_path, sdf_checker):
    path = variant(tmp_path, "<mass>0.5</mass>", "<mass>-18</mass>")
    assert any(e.startswith("LINK_INERTIA_INVALID:") for e in errors(path, **IGN_ONLY))


# --- PyBullet ------------------------------------------------------------------------


def test_valid_model_loads_in_pybullet(tmp_path, pybullet_loader):
    path = write(tmp_path, VALID)
    assert pybullet_loader(path) is None
    assert pybullet_loader(path, expect_joints=1) is None
    assert "expected 2 joints, Bullet made 1" in pybullet_loader(path, expect_joints=2)


def test_pybullet_refusal_is_reported(tmp_path, pybullet_loader):
    path = variant(tmp_path, "<limit><lower>-1.5</lower><upper>1.5</upper></limit>", "")
    error = pybullet_loader(path)
    assert error is not None and "does not specify limits" in error


def test_pybullet_crash_is_reported(tmp_path, pybullet_loader):
    # A link with two parent joints segfaults Bullet's SDF importer.
    extra = f"""<link name="tip">{INERTIAL}</link>
    <joint name="a" type="fixed"><parent>base</parent><child>tip</child></joint>
    <joint name="b" type="fixed"><parent>upper</parent><child>tip</child></joint>
  </model>"""
    error = pybullet_loader(variant(tmp_path, "</model>", extra))
    assert error is not None and error.startswith("crashed with SIGSEGV")


def test_pybullet_malformed_xml_is_reported(tmp_path, pybullet_loader):
    error = pybullet_loader(write(tmp_path, "<sdf version='1.6'><model name='m'>"))
    assert error is not None and error.startswith("pybullet.error: Cannot load SDF file.")


# --- RoboTool's generated SDF (sdf-validation.md's anchors) --------------------------


def robotool_files() -> list[Path]:
    """The 200 generated files of sdf-validation.md: 199 `expected/` (some are two folders
    deep, e.g. Index/IndexedJoint/expected, so `*/expected/*.sdf` alone finds only 168) and
    Index/IndexedLinkIndexedSensor/sdf-gen/ILIS.sdf."""
    return sorted(p for p in CORPUS.rglob("*.sdf") if p.parent.name in ("expected", "sdf-gen"))


@pytest.fixture(scope="module")
def robotool_verdicts(sdf_checker) -> dict[Path, list[str]]:
    files = robotool_files()
    assert len(files) == 200
    return check_sdf(files)  # strict + lints; the `ign sdf -k` verdict is derived below


def kind(message: str) -> str:
    if message.startswith("lint "):
        return message.split(":")[0]
    if message.startswith(("strict: ", "parser said: ")):
        return message.split(":")[0]
    if re.match(r"[A-Z_]+: ", message):
        return "load"
    return "ign check"  # checkCanonicalLinkNames..., non-unique sibling names


@needs_corpus
def test_robotool_sdf_sdformat_anchor(robotool_verdicts):
    kinds = {path: {kind(m) for m in msgs} for path, msgs in robotool_verdicts.items()}
    load_fail = sum("load" in k for k in kinds.values())
    ign_pass = sum(not k & {"load", "ign check"} for k in kinds.values())
    strict_fail = sum(bool(k & {"load", "strict"}) for k in kinds.values())
    lint_files = Counter(x for k in kinds.values() for x in k if x.startswith("lint "))
    lints = {"lint joint_no_axis", "lint axis_no_limit", "lint multi_parent", "lint disconnected"}
    clean_no_lint = sum(not k & ({"load"} | lints) for k in kinds.values())
    assert load_fail == 19  # Root::Load, default policies: 181 / 19
    assert ign_pass == 38  # + the `ign sdf -k` checks: 38 / 162
    assert strict_fail == 162  # strict (unknown elements are errors): 38 / 162
    assert clean_no_lint == 101  # Root::Load OK and no tree lint: 101 / 99
    assert lint_files == {
        "lint axis_no_limit": 42,
        "lint disconnected": 37,
        "lint multi_parent": 16,
        "lint joint_no_axis": 15,
    }
    assert sum(not m for m in robotool_verdicts.values()) == 16  # passes the whole gate


@needs_corpus
def test_robotool_sdf_pybullet_anchor(pybullet_loader):
    # All 200 files: about 0.1-0.35 s each (one child process per file), in parallel.
    results = pybullet_load_many(robotool_files())
    causes = Counter()
    for error in results.values():
        if error is None:
            causes["loads"] += 1
        elif error.startswith("crashed with SIGSEGV"):
            causes["segfault"] += 1
        elif re.search(
            r"type (REVOLUTE|PRISMATIC) (but it does not specify|without) limits", error
        ):
            causes["no limits"] += 1
        elif "has unknown type:\nError: gearbox" in error:  # Bullet logs it in pieces
            causes["gearbox"] += 1
        else:
            causes[error] += 1
    assert causes == {"loads": 121, "no limits": 42, "gearbox": 6, "segfault": 31}
