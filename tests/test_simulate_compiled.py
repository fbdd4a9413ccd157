"""`cyphy simulate --numeric` with Pinocchio's compiled ABA (issue 31): the model cyphy builds
from the kinematic tree (cyphy.backends.pinocchio_tree) against cyphy's own NumPy ABA (a
second derivation, itself checked against Pinocchio built from the elaborated model in
test_dynamics_joints) on Hypothesis trees of every joint kind, its analytic Jacobian against
finite differences, and whole runs against MuJoCo stepping cyphy's MJCF export."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench_sim_scaling import chain_text  # benchmarks/: the benchmark's chains
from cyphy.cli import main
from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.dynamics import rigid_body as dynamics
from test_dynamics_joints import _axes_from_the_test, _random_state, mixed_trees  # noqa: F401

pin = pytest.importorskip("pinocchio")

from cyphy.backends import pinocchio_tree  # noqa: E402


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(mixed_trees(), st.booleans(), st.integers(0, 2**32 - 1))
def test_compiled_tree_agrees_with_the_numpy_aba(model: ElaboratedModel, floating: bool,
                                                 seed: int) -> None:
    """Revolute, prismatic, universal and ball joints, fixed links, a floating base or not:
    the accelerations agree to 1e-9 relative, and, for trees of revolute and prismatic joints
    (the others' motion subspaces turn with q: no analytic Jacobian), the Jacobian agrees
    with central differences of the NumPy ABA."""
    tree = dynamics.kinematic_tree(model, floating_base=floating)
    compiled = pinocchio_tree.pinocchio_model(tree)
    assert compiled is not None
    rng = np.random.default_rng(seed)
    q, qd = _random_state(tree, rng)
    tau = rng.uniform(-2, 2, tree.dof)
    reference = dynamics.forward_dynamics(tree, q, qd, tau)
    scale = max(1.0, float(np.abs(reference).max()))
    assert np.abs(compiled.forward_dynamics(q, qd, tau) - reference).max() < 1e-9 * scale
    assert compiled.derivatives == all(j.kind in ("revolute", "prismatic")
                                       for j in tree.joints)
    if not compiled.derivatives:
        return
    jacobian = compiled.jacobian(q, qd, tau)
    n, h = tree.dof, 1e-6
    x = np.concatenate([q, qd])
    for k in range(2 * n):
        step = np.zeros(2 * n)
        step[k] = h
        up, down = x + step, x - step
        column = (dynamics.forward_dynamics(tree, up[:n], up[n:], tau)
                  - dynamics.forward_dynamics(tree, down[:n], down[n:], tau)) / (2 * h)
        assert np.abs(jacobian[n:, k] - column).max() < 1e-5 * max(1.0, np.abs(column).max())
    assert np.array_equal(jacobian[:n, n:], np.eye(n)) and not jacobian[:n, :n].any()


def _chain(tmp_path: Path, links: int) -> Path:
    folder = tmp_path / "chain"
    folder.mkdir()
    (folder / "chain.pm").write_text(chain_text(links))
    return folder


def test_numeric_chain_agrees_with_mujoco(tmp_path: Path, capsys) -> None:
    """A 5-link arm (full inertias, offset centres of mass), 1 s from rest under gravity: the
    joint angles agree with MuJoCo (RK4 at 0.1 ms, contacts off) on cyphy's MJCF to 1e-5 rad;
    the default integrator is DOP853 and the note says so."""
    mujoco = pytest.importorskip("mujoco")
    folder = _chain(tmp_path, 5)
    assert main(["simulate", str(folder), "--numeric", "--samples", "11"]) == 0
    captured = capsys.readouterr()
    assert "integrated with DOP853 (explicit" in captured.err
    assert "Pinocchio's articulated-body algorithm" in captured.err
    ours = _csv(captured.out)
    assert main(["gen", str(folder), "--mjcf", "-o", str(tmp_path / "mjcf")]) == 0
    capsys.readouterr()
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "mjcf" / "Chain5.xml"))
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.timestep = 1e-4
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    data = mujoco.MjData(model)
    for _ in range(10000):
        mujoco.mj_step(model, data)
    for k in range(4):
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"L{k}__J{k}")
        assert joint >= 0
        theirs = data.qpos[model.jnt_qposadr[joint]]
        assert abs(ours[f"J{k}_theta"][-1] - theirs) < 1e-5
    assert np.abs(ours["J1_theta"]).max() > 0.1  # it did swing


def test_stiff_method_on_request_and_the_numpy_fallback(tmp_path: Path, capsys,
                                                       monkeypatch) -> None:
    """--method BDF (Pinocchio's analytic Jacobian) and, without Pinocchio, the NumPy ABA
    give the default run's trajectory; the notes name the method and the engine."""
    folder = _chain(tmp_path, 4)
    common = ["simulate", str(folder), "--numeric", "--samples", "11", "--input",
              "J0_tau=0.5*sin(3*t)", "--rtol", "1e-9", "--atol", "1e-11"]
    assert main(common) == 0
    default = _csv(capsys.readouterr().out)
    assert main([*common, "--method", "BDF"]) == 0
    captured = capsys.readouterr()
    assert "integrated with BDF (asked for" in captured.err
    stiff = _csv(captured.out)
    monkeypatch.setattr(pinocchio_tree, "available", lambda: False)
    assert main(common) == 0
    captured = capsys.readouterr()
    assert "cyphy's NumPy articulated-body algorithm (Pinocchio" in captured.err
    fallback = _csv(captured.out)
    for name in default:
        assert np.abs(stiff[name] - default[name]).max() < 1e-5
        assert np.abs(fallback[name] - default[name]).max() < 1e-8
