"""``gen --sdf --target drake`` (issue 27, item 8): SDF that Drake's parser loads, and Drake as
an oracle of cyphy's dynamics: its mass matrix and bias forces, from its own reading of
cyphy's SDF (the one physics engine here that reads the SDF's inertias: PyBullet's SDF loader
recomputes them from the collision shapes) and of cyphy's URDF, equal cyphy's equations of
motion to 1e-9 relative on the examples and on random trees."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import EXAMPLES
from cyphy import api
from robot_exports import (compare, cyphy_joint_space, drake_bias, drake_mass, names_table,
                           random_states, random_trees)
from test_mjcf import _tree_model

pytest.importorskip("pydrake")

MODELS = {"manipulator": "Manipulator", "marxbot": "marXbotBase", "dcmotor": "DCMotorBase"}
TOLERANCE = 1e-9


def drake_parse_error(path: Path) -> str:
    """Drake's parser's error on a file ('' when it loads)."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)  # kept alive: the parser holds a reference only
    try:
        Parser(plant).AddModels(str(path))
    except RuntimeError as err:
        return str(err)
    return ""


def _export(paths: list[Path], out: Path, model: str | None = None
            ) -> tuple[Path, Path, Path, Path]:
    """cyphy's SDF (``--target drake``) and URDF of the model, each with its name table."""
    out.mkdir(parents=True, exist_ok=True)
    sdf = api.generate_sdf(paths, api.SdfGenOptions(model=model, target="drake"))
    urdf = api.generate_urdf(paths, api.TreeGenOptions(model=model, output=str(out / "urdf")))
    written: dict[str, Path] = {}
    for kind, result in (("sdf", sdf), ("urdf", urdf)):
        assert result.files, [str(d) for d in result.report.diagnostics]
        (out / kind).mkdir(exist_ok=True)
        for name, text in result.files.items():
            (out / kind / name).write_text(text)  # type: ignore[arg-type]
            written[kind + ("-names" if name.endswith(".names.json") else "")] = \
                out / kind / name
    return written["sdf"], written["sdf-names"], written["urdf"], written["urdf-names"]


def worst_disagreement(paths: list[Path], out: Path, states: list[tuple[list[float],
                       list[float]]], model: str | None = None) -> tuple[float, float]:
    """The largest relative differences ``(mass matrix, bias forces)`` between cyphy and
    Drake reading the SDF and the URDF, over ``states`` (in Drake's joint order)."""
    sdf, sdf_names, urdf, urdf_names = _export(paths, out, model)
    elaborated = api.elaborate(paths, api.ElaborateOptions(model=model)).model
    names = drake_mass(sdf, {})[0]
    assert sorted(names) == sorted(drake_mass(urdf, {})[0])
    worst_m = worst_h = 0.0
    for positions, velocities in states:
        q, qd = dict(zip(names, positions)), dict(zip(names, velocities))
        for path, table in ((sdf, sdf_names), (urdf, urdf_names)):
            joints, m, h = cyphy_joint_space(elaborated, names_table(table), q, qd)
            worst_m = max(worst_m, compare({"cyphy": (joints, m), "drake": drake_mass(path, q)}))
            worst_h = max(worst_h, compare({"cyphy": (joints, h),
                                            "drake": drake_bias(path, q, qd)},
                                           floor=float(np.abs(m).max())))
    return worst_m, worst_h


@pytest.mark.parametrize("example", sorted(MODELS))
def test_drake_refuses_sdf_16_and_loads_the_drake_target(tmp_path: Path, example: str) -> None:
    """The reason for the target: Drake's parser refuses `<axis><initial_position>`."""
    paths = [EXAMPLES / example]
    for target, refused in (("gazebo", True), ("drake", False)):
        result = api.generate_sdf(paths, api.SdfGenOptions(model=MODELS[example], target=target))
        path = tmp_path / f"{target}.sdf"
        path.write_text(result.files[f"{MODELS[example]}.sdf"])  # type: ignore[arg-type]
        error = drake_parse_error(path)
        assert ("initial_position" in error) == refused, error
        assert bool(error) == refused, error
        assert "W-SDF-DRAKE" not in [d.code.id for d in result.report.diagnostics]


def test_the_command_line_target(tmp_path: Path) -> None:
    from cyphy.cli import main

    out = tmp_path / "out"
    assert main(["gen", "--sdf", "--target", "drake", "-o", str(out),
                 str(EXAMPLES / "manipulator")]) == 0
    assert drake_parse_error(out / "Manipulator.sdf") == ""


ONE_JOINT = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel P {{
  local link Base {{
    def {{ inertial information {{ mass 1 inertia matrix {{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
    jref J = Revolute {{
      annotation Revolute {{ axis = Axis {{ xyz = (|0, 0, 1|) {initial} }} }}
      instantiation AXIS = (|0, 0, 1|)
      flexibly connected to Tip
    }}
  }}
  local link Tip {{
    def {{ inertial information {{ mass 1 inertia matrix {{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }} }} }}
  }}
}}
"""


@pytest.mark.parametrize("initial, warned", [("", False), ("initial_position = 0", False),
                                             ("initial_position = 0.5", True)])
def test_dropping_a_non_zero_initial_position_is_a_warning(tmp_path: Path, initial: str,
                                                           warned: bool) -> None:
    model = tmp_path / "p.rsm"
    model.write_text(ONE_JOINT.format(initial=initial))
    drake = api.generate_sdf([model], api.SdfGenOptions(target="drake"))
    gazebo = api.generate_sdf([model])
    codes = [d.code.id for d in drake.report.diagnostics]
    assert codes == (["W-SDF-DRAKE"] if warned else [])
    if warned:
        assert "initial_position 0.5 is left out" in drake.report.diagnostics[0].message
    assert "initial_position" not in drake.files["P.sdf"]  # type: ignore[operator]
    assert "<initial_position>" in gazebo.files["P.sdf"]  # type: ignore[operator]
    (tmp_path / "P.sdf").write_text(drake.files["P.sdf"])  # type: ignore[arg-type]
    assert drake_parse_error(tmp_path / "P.sdf") == ""


@pytest.mark.parametrize("example", sorted(MODELS))
def test_examples_agree_with_drake(tmp_path: Path, example: str) -> None:
    n = {"manipulator": 3, "marxbot": 2, "dcmotor": 1}[example]
    states = random_states(np.random.default_rng(2027), n, 5)
    worst_m, worst_h = worst_disagreement([EXAMPLES / example], tmp_path, states,
                                          MODELS[example])
    assert worst_m < TOLERANCE and worst_h < TOLERANCE, (worst_m, worst_h)


def test_a_wrong_inertia_is_caught_by_drake(tmp_path: Path) -> None:
    """The comparison can fail: the SDF with the arm's mass changed disagrees with cyphy."""
    sdf, table, _, _ = _export([EXAMPLES / "manipulator"], tmp_path, "Manipulator")
    elaborated = api.elaborate([EXAMPLES / "manipulator"],
                               api.ElaborateOptions(model="Manipulator")).model
    text = sdf.read_text()
    assert text.count("<mass>0.4</mass>") == 1, text  # the arm
    sdf.write_text(text.replace("<mass>0.4</mass>", "<mass>0.41</mass>"))
    q = {"Stand__Shoulder": 0.3, "Arm__Slide": 0.1, "Forearm__Lift": 0.05}
    joints, m, _ = cyphy_joint_space(elaborated, names_table(table), q, {})
    assert compare({"cyphy": (joints, m), "drake": drake_mass(sdf, q)}) > 1e-3


@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(random_trees(), st.integers(0, 2**32 - 1))
def test_random_trees_agree_with_drake(tmp_path_factory, tree, seed: int) -> None:
    """Chains and trees of 2-8 links (the root at a random pose), revolute and prismatic
    joints with random axes and poses, random masses, centres of mass and rotated inertias
    (the trees of test_dynamics_exports), read by Drake from the SDF and from the URDF.

    Drake takes an axis component of about 1e-9 as 0: with the axis (0, 1, 1e-9) its bias
    forces are exactly 0 where cyphy's (and the tilt's own physics, linear in it: 2.6e-5 for
    1e-5, 2.6e-9 for 1e-9) are not, 1e-7 of the mass matrix apart. So components below 1e-6,
    which Hypothesis likes to draw, are made 0 here; MuJoCo and Pinocchio take them as
    written (test_dynamics_exports)."""
    specs, parents = tree
    specs = [(*s[:6], tuple(0.0 if abs(c) < 1e-6 else c for c in s[6]), *s[7:]) for s in specs]
    folder = tmp_path_factory.mktemp("random")
    (folder / "Random.rsm").write_text(_tree_model(list(parents), specs))
    states = random_states(np.random.default_rng(seed), len(specs) - 1, 2)
    worst_m, worst_h = worst_disagreement([folder / "Random.rsm"], folder / "out", states)
    assert worst_m < TOLERANCE and worst_h < TOLERANCE, (worst_m, worst_h)


def test_paired_indexed_joints_agree_with_drake(tmp_path: Path) -> None:
    """Issue 27 item 3 against a real tool: a rover whose indexed axles go element i to
    element i is a tree of two wheels, and Drake, reading its SDF and URDF, gets cyphy's
    dynamics (RoboTool's cross product gave two joints per wheel: no tree at all)."""
    from test_model_refuse import PAIRED, ROVER

    model = tmp_path / "rover.rsm"
    model.write_text(ROVER.format(**PAIRED))
    states = random_states(np.random.default_rng(27), 2, 3)
    worst_m, worst_h = worst_disagreement([model], tmp_path / "out", states)
    assert worst_m < TOLERANCE and worst_h < TOLERANCE, (worst_m, worst_h)
    assert sorted(drake_mass(tmp_path / "out" / "sdf" / "Rover.sdf", {})[0]) == [
        "Chassis__Axle_0", "Chassis__Axle_1"]
