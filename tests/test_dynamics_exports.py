"""cyphy's equations of motion (issue 16) against the real tools reading its exports (issue 19):
the mass matrix ``M(q)`` of ``joint_space`` agrees with Pinocchio (URDF), PyBullet (URDF, fixed
base, the file's inertias) and MuJoCo (MJCF), and the bias forces ``h(q, q̇)`` with Pinocchio's
``rnea(q, v, 0)``, PyBullet's inverse dynamics at zero acceleration and MuJoCo's
``qfrc_bias``, at random states, to 1e-9 relative, on the examples and on random trees.

cyphy's qualified joint names are lined up with the exported ones through the export's name
table (``<Model>.names.json``), the table the URDF and MJCF writers name joints by."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import EXAMPLES
from cyphy import api
from robot_exports import (compare, cyphy_joint_space, cyphy_source, mujoco_bias, mujoco_mass,
                           names_table, pinocchio_bias, pinocchio_mass, pybullet_bias,
                           pybullet_mass, random_states, random_trees)
from test_mjcf import _tree_model

pytest.importorskip("pinocchio")
pytest.importorskip("pybullet")
pytest.importorskip("mujoco")

MODELS = {"manipulator": "Manipulator", "marxbot": "marXbotBase", "dcmotor": "DCMotorBase"}
TOLERANCE = 1e-9


def _export(paths: list[Path], out: Path, model: str | None = None) -> tuple[Path, Path, Path]:
    """The URDF, the MJCF and the name table of the p-model, written to ``out``."""
    options = api.TreeGenOptions(model=model, output=str(out))
    files: dict[str, str] = {}
    for result in (api.generate_urdf(paths, options), api.generate_mjcf(paths, options)):
        assert result.files, [str(d) for d in result.report.diagnostics]
        files.update(result.files)  # type: ignore[arg-type]
    out.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out / name).write_text(text)
    (urdf,) = [n for n in files if n.endswith(".urdf")]
    (mjcf,) = [n for n in files if n.endswith(".xml")]
    (table,) = [n for n in files if n.endswith(".names.json")]
    return out / urdf, out / mjcf, out / table


def worst_disagreement(paths: list[Path], out: Path, states: list[tuple[list[float],
                       list[float]]], model: str | None = None) -> tuple[float, float]:
    """The largest relative differences ``(mass matrix, bias forces)`` between cyphy and the
    three tools over ``states`` (positions and velocities in the exported joints' order).
    Bias forces are measured against the larger of their own largest entry and the mass
    matrix's (a force scale: a wheel on a vertical axis has no bias force at all)."""
    urdf, mjcf, table_file = _export(paths, out, model)
    elaborated = api.elaborate(paths, api.ElaborateOptions(model=model)).model
    table = names_table(table_file)
    names = pinocchio_mass(urdf, {})[0]
    worst_m = worst_h = 0.0
    for positions, velocities in states:
        q = dict(zip(names, positions))
        qd = dict(zip(names, velocities))
        joints, m, h = cyphy_joint_space(elaborated, table, q, qd)
        assert sorted(joints) == sorted(names)
        worst_m = max(worst_m, compare({
            "cyphy": cyphy_source(elaborated)(table_file, q), "pinocchio": pinocchio_mass(urdf, q),
            "pybullet": pybullet_mass(urdf, q), "mujoco": mujoco_mass(mjcf, q)}))
        worst_h = max(worst_h, compare({
            "cyphy": (joints, h), "pinocchio": pinocchio_bias(urdf, q, qd),
            "pybullet": pybullet_bias(urdf, q, qd),
            "mujoco": mujoco_bias(mjcf, q, qd)}, floor=float(np.abs(m).max())))
    return worst_m, worst_h


@pytest.mark.parametrize("example", sorted(MODELS))
def test_examples_agree_with_the_tools(tmp_path: Path, example: str) -> None:
    n = {"manipulator": 3, "marxbot": 2, "dcmotor": 1}[example]
    states = random_states(np.random.default_rng(1916), n, 5)
    worst_m, worst_h = worst_disagreement([EXAMPLES / example], tmp_path, states,
                                          MODELS[example])
    assert worst_m < TOLERANCE and worst_h < TOLERANCE, (worst_m, worst_h)


def test_a_wrong_inertia_is_caught(tmp_path: Path) -> None:
    """The comparison can fail: the manipulator's export with one link's mass changed
    disagrees with cyphy's equations of the unchanged model."""
    urdf, mjcf, table_file = _export([EXAMPLES / "manipulator"], tmp_path, "Manipulator")
    elaborated = api.elaborate([EXAMPLES / "manipulator"],
                               api.ElaborateOptions(model="Manipulator")).model
    text = urdf.read_text()
    assert text.count('<mass value="0.4" />') == 1  # the arm
    urdf.write_text(text.replace('<mass value="0.4" />', '<mass value="0.41" />'))
    q = {"Stand__Shoulder": 0.3, "Arm__Slide": 0.1, "Forearm__Lift": 0.05}
    assert compare({"cyphy": cyphy_source(elaborated)(table_file, q),
                    "pinocchio": pinocchio_mass(urdf, q)}) > 1e-3


@settings(max_examples=12, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(random_trees(), st.integers(0, 2**32 - 1))
def test_random_trees_agree_with_the_tools(tmp_path_factory, tree, seed: int) -> None:
    """Chains and trees of 2-8 links (a root at a random pose fixed to the world), revolute
    and prismatic joints with random axes and poses, random masses, centres of mass and
    rotated inertias. Every tool keeps its default gravity: a rotated root link must not
    turn the exported robot relative to the model frame (it did in the URDF)."""
    specs, parents = tree
    folder = tmp_path_factory.mktemp("random")
    (folder / "Random.rsm").write_text(_tree_model(list(parents), specs))
    states = random_states(np.random.default_rng(seed), len(specs) - 1, 2)
    worst_m, worst_h = worst_disagreement([folder / "Random.rsm"], folder / "out", states)
    assert worst_m < TOLERANCE and worst_h < TOLERANCE, (worst_m, worst_h)
