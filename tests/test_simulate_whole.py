"""Whole models with motors under `cyphy simulate` (issue 31): the kinematic tree evaluated by
Pinocchio and the devices' equations compiled once (cyphy.backends.whole_model), against the
symbolic path (every articulated-body definition compiled: the reference), the analytic
Jacobian against central differences, and the integrator chosen by stiffness
(cyphy.backends.stiffness): a motor whose electrical time constant L/R is 10 µs makes the
model stiff (BDF), the same motor at 0.1 s and a tree alone do not (DOP853)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest

from bench_sim_scaling import chain_text, motor_chain_text  # benchmarks/: the chains
from cyphy.cli import main

pytest.importorskip("pinocchio")

from cyphy.backends import simulate as sim  # noqa: E402
from cyphy.backends.stiffness import STIFF_SPAN, fastest_decay  # noqa: E402
from cyphy.backends.whole_model import system_dynamics  # noqa: E402
from cyphy.pipeline.elaborate import ElaborateOptions, elaborate  # noqa: E402
from cyphy.semantics.dynamics import rigid_body as rb  # noqa: E402
from cyphy.semantics.dynamics.equations import assemble  # noqa: E402
from cyphy.semantics.dynamics.reduce import reduce_system  # noqa: E402


def _reduced(folder: Path, text: str):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "chain.pm").write_text(text)
    model = elaborate([folder], ElaborateOptions()).model
    assert model is not None
    return reduce_system(assemble(model, definitions=True)), \
        rb.kinematic_tree(model, rb.STANDARD_GRAVITY)


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


@pytest.fixture(scope="module")
def motors(tmp_path_factory: pytest.TempPathFactory):
    return _reduced(tmp_path_factory.mktemp("motors"), motor_chain_text(4))


def test_pinocchio_and_the_symbolic_tree_give_one_trajectory(motors) -> None:
    """Four links, a PI motor on each of the three joints, two demands: the run whose tree
    Pinocchio evaluates equals the run of the compiled articulated-body definitions (tight
    tolerances, so that the integrators' errors do not hide a difference)."""
    reduced, tree = motors
    options = sim.SimulationOptions(t_end=0.5, inputs={"M0_das": "10", "M2_das": "-5*t"},
                                    rtol=1e-10, atol=1e-12, samples=11, method="DOP853")
    fast = sim.simulate_reduced(reduced, options, tree=tree)
    reference = sim.simulate_reduced(reduced, options)
    assert "Pinocchio" in fast.engine and "Pinocchio" not in reference.engine
    assert fast.names == reference.names
    states = [fast.names.index(s) for s in reduced.states]
    assert np.allclose(fast.values[:, states], reference.values[:, states], rtol=1e-7,
                       atol=1e-8)
    # the joints moved (the motors drive them against gravity): not a trivial agreement
    assert np.abs(fast.column("J0_theta")).max() > 1e-3
    # the outputs too (the motors' torques, the joints' accelerations J_a = J_qdd)
    assert np.allclose(fast.values, reference.values, rtol=1e-6, atol=1e-6)


def test_the_analytic_jacobian_matches_central_differences(motors) -> None:
    reduced, tree = motors
    states, inputs = list(reduced.states), list(reduced.inputs)
    dynamics = system_dynamics(states, inputs, [reduced.rhs[s] for s in states], [],
                               reduced.definitions, tree)
    assert dynamics.make_jacobian is not None
    jacobian = dynamics.make_jacobian()
    rng = np.random.default_rng(7)
    x, u = rng.normal(size=len(states)), rng.normal(size=len(inputs))

    def f(y: np.ndarray) -> np.ndarray:
        return np.asarray(dynamics.rhs(*y, *u, 0.3), dtype=float)

    numeric = np.zeros((len(x), len(x)))
    for k in range(len(x)):
        h = 1e-6
        up, down = x.copy(), x.copy()
        up[k] += h
        down[k] -= h
        numeric[:, k] = (f(up) - f(down)) / (2 * h)
    analytic = jacobian(*x, *u, 0.3)
    assert np.allclose(analytic, numeric, rtol=1e-5, atol=1e-6)
    # the accelerations depend on the motors' currents through the torque Kt·i = 0.05·i
    row, col = states.index("J0_v"), states.index("M0_i")
    assert abs(analytic[row, col]) > 1e-3


def test_a_stiff_motor_gets_a_stiff_method_and_a_tree_does_not(tmp_path: Path,
                                                               capsys) -> None:
    stiff = tmp_path / "stiff"
    stiff.mkdir()
    (stiff / "chain.pm").write_text(motor_chain_text(3, inductance=1e-5))
    assert main(["simulate", str(stiff), "--t-end", "0.2", "--samples", "5",
                 "--input", "M0_das=10"]) == 0
    captured = capsys.readouterr()
    assert "integrated with BDF (stiff:" in captured.err
    assert "analytic Jacobian" in captured.err
    stiff_run = _csv(captured.out)
    # the current settles in L/R = 10 µs: the motor's speed follows the PI loop as with a
    # slow motor, and --method overrides the choice with the same trajectory
    assert main(["simulate", str(stiff), "--t-end", "0.2", "--samples", "5",
                 "--input", "M0_das=10", "--method", "Radau"]) == 0
    captured = capsys.readouterr()
    assert "integrated with Radau (asked for" in captured.err
    radau = _csv(captured.out)
    for name in ("M0_av", "M0_i", "J0_theta"):
        assert np.allclose(stiff_run[name], radau[name], rtol=1e-4, atol=1e-6), name
    assert stiff_run["M0_av"][-1] > 0.5

    for folder, text in (("slow", motor_chain_text(3)), ("tree", chain_text(3))):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "chain.pm").write_text(text)
        extra = ["--numeric"] if folder == "tree" else []
        assert main(["simulate", str(tmp_path / folder), "--samples", "3", *extra]) == 0
        assert "integrated with DOP853 (explicit: not stiff" in capsys.readouterr().err


def test_the_stiffness_test_reads_the_electrical_time_constant() -> None:
    """A motor's current decays at R/L (here with the back-EMF and the PI loop around it):
    the fastest decay rate is about R/L, stiff over 1 s when R/L·1 s > STIFF_SPAN."""
    for inductance, stiff in ((0.1, False), (1e-5, True)):
        r, kt, ke, b, j = 1.0, 0.05, 0.05, 0.01, 0.01
        a = np.array([[-b / j, kt / j], [-ke / inductance, -r / inductance]])
        rate = fastest_decay(a)
        assert rate == pytest.approx(r / inductance, rel=0.05)
        assert (rate * 1.0 > STIFF_SPAN) == stiff


def _motor_torque(das: float, t_end: float):
    """The library's SpeedControlMotor written out by hand (cyphy/lang/library/physmod/
    actuators.rsm, examples/dcmotor's constants): ``J·av' = T``, ``L·i' = V − R·i − Ke·av``,
    ``V = Kp·e + Ki·∫e``, ``e = das − av``, ``T = Kt·i − b·av``; its torque as a function of t."""
    from scipy.integrate import solve_ivp

    r, ind, kt, ke, b, j, kp, ki = 1.0, 0.1, 0.05, 0.05, 0.01, 0.01, 2.0, 5.0

    def f(_t: float, x: np.ndarray) -> list[float]:
        av, i, integral = x
        e = das - av
        return [(kt * i - b * av) / j, (kp * e + ki * integral - r * i - ke * av) / ind, e]

    solution = solve_ivp(f, (0.0, t_end), [0.0, 0.0, 0.0], method="DOP853", rtol=1e-12,
                         atol=1e-14, dense_output=True)
    return lambda t: float(kt * solution.sol(t)[1] - b * solution.sol(t)[0])


def test_a_motor_chain_agrees_with_mujoco_driven_by_the_motor_written_by_hand(
        tmp_path: Path, capsys) -> None:
    """Three links, a motor on each joint, the first demanded 10 rad/s, the second -5: the
    joints' angles after 0.5 s agree with MuJoCo (RK4 at 0.1 ms, contacts off) stepping
    cyphy's MJCF export under the torques of the motors integrated by hand (an oracle that
    shares neither the tree nor the motor's equations with cyphy)."""
    mujoco = pytest.importorskip("mujoco")
    (tmp_path / "chain.pm").write_text(motor_chain_text(3))
    t_end = 0.5
    assert main(["simulate", str(tmp_path), "--t-end", str(t_end), "--samples", "6",
                 "--input", "M0_das=10", "--input", "M1_das=-5"]) == 0
    ours = _csv(capsys.readouterr().out)
    assert main(["gen", str(tmp_path), "--mjcf", "-o", str(tmp_path / "mjcf")]) == 0
    capsys.readouterr()
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "mjcf" / "Chain3.xml"))
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.timestep = 1e-4
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    data = mujoco.MjData(model)
    joints = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"L{k}__J{k}")
              for k in range(2)]
    assert min(joints) >= 0
    torques = [_motor_torque(10.0, t_end), _motor_torque(-5.0, t_end)]
    steps = round(t_end / model.opt.timestep)
    for step in range(steps):
        middle = (step + 0.5) * model.opt.timestep  # the torque held over the step
        for joint, torque in zip(joints, torques):
            data.qfrc_applied[model.jnt_dofadr[joint]] = torque(middle)
        mujoco.mj_step(model, data)
    for k, joint in enumerate(joints):
        theirs = data.qpos[model.jnt_qposadr[joint]]
        assert abs(ours[f"J{k}_theta"][-1] - theirs) < 1e-4, (k, ours[f"J{k}_theta"][-1],
                                                              theirs)
    assert abs(ours["M0_T"][-1] - torques[0](t_end)) < 1e-6
    assert np.abs(ours["J0_theta"]).max() > 1e-2  # the motor turned it
