"""Simulation scaling benchmark (issue 31): serial chains of N revolute links, 1 s from rest.

Each chain (:func:`chain_text`) has N links, each 0.1 m along x and z from its parent, joints
turning about z, y, x in turn, every link with a full inertia matrix (products of inertia
non-zero) and a centre of mass offset from its frame, so that every joint's equation couples
all the others. Measured, in one run, for N = 5, 10, 20, 50, 100:

* ``cyphy simulate --numeric`` in process (``api.simulate``, numeric): the whole call
  (elaborate, build the tree, integrate) and the integration alone (``simulate_tree``);
* Pinocchio ``aba`` per call, on the model cyphy builds from the tree;
* MuJoCo, 1 s with RK4 at 1 ms, on the MJCF cyphy exports (``gen --mjcf``);
* the whole model with a PI DC motor on every joint (:func:`motor_chain_text`), in process:
  elaborate, reduce, compile the devices' equations, integrate (the tree by Pinocchio);
* the growth exponent of the integration time in N (least squares on log–log);
* whole ``cyphy simulate`` commands, each a process of its own (wall clock, median of
  ``--command-runs``, after one unmeasured run that caches the bytecode): the 10-link and
  100-link chains ``--numeric`` and the 50-link chain with a motor per joint, imports and
  interpreter start included, as a user waits for them.

Targets (issue 31): 10 links ≤ 0.1 s of integration and ≤ 1 s as a whole command, 100 links
≤ 5 s, 50 links with motors ≤ 10 s, exponent ≤ 1.3. Exit status 0 when they hold, 1 otherwise, 2 when Pinocchio or
MuJoCo is missing.

Run: ``python benchmarks/bench_sim_scaling.py [--quick] [--sizes 5 10 20 50 100] [--runs 1]
[--motors-up-to 50]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402
from timing import median_time  # noqa: E402

_AXES = ("0,0,1", "0,1,0", "1,0,0")


def chain_text(n: int) -> str:
    """RoboSim text of ``Chain<n>``: links ``L0 … L{n-1}`` joined by revolute ``J0 …``."""
    parts = ["package bench\nimport physmod::joints::Revolute\n"
             "import physmod::sdf::annotations::*\n", f"pmodel Chain{n} {{\n"]
    for k in range(n):
        joint = ""
        if k + 1 < n:
            axis = _AXES[k % 3]
            joint = f"""
    jref J{k} = Revolute {{
      annotation Revolute {{ axis = Axis {{ xyz = (|{axis}|) }} }}
      instantiation AXIS = (|{axis}|)
      flexibly connected to L{k + 1}
    }}"""
        pose = f"x = {0.1 * k:.1f} z = {0.1 * k:.1f}"  # link poses are in the model frame
        parts.append(f"""  local link L{k} {{
    pose {{ {pose} y = 0.0 roll = 0.0 pitch = 0.0 yaw = {0.1 * (k % 7):.1f} }}
    def {{ inertial information {{
      mass {1.0 + 0.05 * (k % 5):.2f}
      inertia matrix {{ ixx 0.012 ixy 0.001 ixz -0.0015 iyy 0.010 iyz 0.002 izz 0.008 }}
      pose {{ x = 0.03 y = 0.01 z = 0.04 roll = 0.0 pitch = 0.0 yaw = 0.0 }}
    }} }}
    local body B{k} {{ def {{ box(length = 0.1, width = 0.05, height = 0.1) }} }}{joint}
  }}
""")
    parts.append("}\n")
    return "".join(parts)


def motor_chain_text(n: int, inductance: float = 0.1) -> str:
    """``Chain<n>`` with a PI speed-controlled DC motor on every joint (``M0`` … on ``J0``
    …, the constants of ``examples/dcmotor``; ``inductance`` its L, 0.1 H there: 1e-5 makes
    the motors stiff)."""
    from motors import speed_control_motor

    text = chain_text(n).replace("import physmod::joints::Revolute\n",
                                 "import physmod::joints::Revolute\n"
                                 "import physmod::actuators::SpeedControlMotor\n")
    for k in range(n - 1):
        motor = speed_control_motor(f"M{k}", f"J{k}").replace(
            "instantiation L = 0.1", f"instantiation L = {inductance!r}")
        text = text.replace(f"flexibly connected to L{k + 1}\n",
                            f"flexibly connected to L{k + 1}{motor}\n")
    return text


def _mujoco(mjcf: Path, dof: int) -> tuple[float, np.ndarray]:
    """1 s of MuJoCo, RK4 at 1 ms, contacts off (cyphy's tree has none): time and q(1)."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(mjcf))
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.timestep = 1e-3
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    data = mujoco.MjData(model)
    start = time.perf_counter()
    for _ in range(1000):
        mujoco.mj_step(model, data)
    elapsed = time.perf_counter() - start
    names = [f"L{k}__J{k}" for k in range(dof)]  # the MJCF's names of joint Jk of link Lk
    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) for name in names]
    assert min(ids) >= 0, f"joints not found in the MJCF: {names}"
    q = np.array([data.qpos[model.jnt_qposadr[i]] for i in ids])
    return elapsed, q


def measure_motors(n: int, runs: int) -> float:
    """The whole in-process call (elaborate, reduce, compile, integrate) of 1 s of
    ``Chain<n>`` with a motor per joint, its first motor's demand 10 rad/s."""
    from cyphy import api
    from cyphy.backends import simulate as sim

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "chain.pm").write_text(motor_chain_text(n))
        settings = sim.SimulationOptions(t_end=1.0, inputs={"M0_das": "10"})
        options = api.SimulateOptions(simulation=settings)
        result: list[object] = []

        def run() -> None:
            out = api.simulate([folder], options)
            assert out.trajectory is not None, out.report.diagnostics
            assert "Pinocchio" in out.trajectory.engine, out.trajectory.engine
            result.append(out)

        return median_time(run, runs)


def measure(n: int, runs: int, motors: bool = True) -> dict[str, float]:
    """One row of the table for a chain of ``n`` links (``motors``: and with a motor per
    joint, which takes a minute at 100 links)."""
    from cyphy import api
    from cyphy.backends import simulate as sim
    from cyphy.backends.pinocchio_tree import pinocchio_model
    from cyphy.semantics.dynamics import rigid_body as rb

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "chain.pm").write_text(chain_text(n))
        settings = sim.SimulationOptions(t_end=1.0)
        options = api.SimulateOptions(simulation=settings, numeric=True)
        whole = median_time(lambda: api.simulate([folder], options), runs)
        elaborated = api.elaborate([folder], api.ElaborateOptions())
        tree = rb.kinematic_tree(elaborated.model, rb.STANDARD_GRAVITY)
        result: list[sim.Trajectory] = []
        integration = median_time(lambda: result.append(sim.simulate_tree(tree, settings)), runs)
        trajectory = result[-1]
        compiled = pinocchio_model(tree)
        assert compiled is not None
        rng = np.random.default_rng(n)
        q, qd, tau = rng.normal(size=(3, tree.dof))
        calls = 2000
        start = time.perf_counter()
        for _ in range(calls):
            compiled.forward_dynamics(q, qd, tau)
        aba = (time.perf_counter() - start) / calls
        start = time.perf_counter()
        for _ in range(calls // 20):
            rb.forward_dynamics(tree, q, qd, tau)
        numpy_aba = (time.perf_counter() - start) / (calls // 20)
        gen = api.generate_mjcf([folder], api.TreeGenOptions(output=str(folder / "out")))
        (mjcf_name,) = [k for k in gen.files if k.endswith(".xml")]
        mjcf = folder / mjcf_name
        mjcf.write_text(gen.files[mjcf_name])  # type: ignore[arg-type]
        mujoco_time, mujoco_q = _mujoco(mjcf, tree.dof)
        cyphy_q = np.array([trajectory.column(f"J{k}_theta")[-1] for k in range(tree.dof)])
    return {"n": n, "whole": whole, "integration": integration, "aba": aba,
            "numpy_aba": numpy_aba, "mujoco": mujoco_time,
            "differs": float(np.abs(cyphy_q - mujoco_q).max()),
            "motors": measure_motors(n, runs) if motors else float("nan")}


def measure_command(text: str, extra: tuple[str, ...], runs: int) -> float:
    """Median wall time of ``cyphy simulate`` of the model ``text`` (1 s, CSV written) as a
    process of its own, this source tree's code; one unmeasured run first caches bytecode."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "chain.pm").write_text(text)
        env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONPYCACHEPREFIX=str(folder / "pyc"))
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        argv = [sys.executable, "-P", "-m", "cyphy", "simulate", str(folder / "chain.pm"),
                "--t-end", "1", *extra, "-o", str(folder / "out.csv")]

        def run() -> None:
            subprocess.run(argv, cwd=ROOT, env=env, check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

        run()
        return median_time(run, runs)


def exponent(sizes: list[int], times: list[float]) -> float:
    """The slope of log(time) against log(N), least squares."""
    return float(np.polyfit(np.log(sizes), np.log(times), 1)[0])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=None)
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--quick", action="store_true",
                        help="N = 5, 10, 20, one run: a check in about a minute")
    parser.add_argument("--motors-up-to", type=int, default=50,
                        help="the largest N measured with a motor per joint (default 50)")
    parser.add_argument("--command-runs", type=int, default=5,
                        help="runs of each whole command (default 5; 0 skips them)")
    args = parser.parse_args()
    sizes = args.sizes or ([5, 10, 20] if args.quick else [5, 10, 20, 50, 100])
    try:
        import mujoco  # noqa: F401
        import pinocchio  # noqa: F401
    except ImportError as err:
        print(f"bench_sim_scaling: needs Pinocchio and MuJoCo ({err})")
        return 2
    measure(3, 1)  # warm-up: imports, grammar, library
    rows = [measure(n, args.runs, n <= args.motors_up_to) for n in sizes]
    print("| N | simulate --numeric (in process) | integration alone | with a motor per joint "
          "(in process) | Pinocchio aba per call | cyphy NumPy ABA per call "
          "| MuJoCo 1 s (RK4, 1 ms) | max |q(1) cyphy - MuJoCo| |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        motors = "not run" if r["motors"] != r["motors"] else f"{r['motors']:.3f} s"
        print(f"| {r['n']} | {r['whole']:.3f} s | {r['integration']:.3f} s | {motors} | "
              f"{r['aba'] * 1e6:.1f} µs | {r['numpy_aba'] * 1e3:.2f} ms | {r['mujoco']:.3f} s | "
              f"{r['differs']:.1e} rad |")
    slope = exponent([r["n"] for r in rows], [r["integration"] for r in rows])
    print(f"growth exponent of the integration time in N: {slope:.2f}")
    with_motors = [r for r in rows if r["motors"] == r["motors"]]
    if len(with_motors) > 1:
        print("growth exponent with a motor per joint (whole call): "
              f"{exponent([r['n'] for r in with_motors], [r['motors'] for r in with_motors]):.2f}")
    by_n = {r["n"]: r for r in rows}
    ok = slope <= 1.3
    if 10 in by_n:
        ok &= by_n[10]["integration"] <= 0.1
    if 100 in by_n:
        ok &= by_n[100]["integration"] <= 5.0
    if 50 in by_n and by_n[50]["motors"] == by_n[50]["motors"]:
        ok &= by_n[50]["motors"] <= 10.0
    if args.command_runs > 0:
        commands = [(f"`simulate CHAIN{n} --numeric`", chain_text(n), ("--numeric",), limit)
                    for n, limit in ((10, 1.0), (100, 5.0)) if n in by_n]
        if 50 in by_n and args.motors_up_to >= 50:
            commands.append(("`simulate CHAIN50 --input M0_das=10` (a motor per joint)",
                             motor_chain_text(50), ("--input", "M0_das=10"), 10.0))
        print("\n| whole command (wall clock, own process) | time | target |")
        print("| --- | --- | --- |")
        for label, text, extra, limit in commands:
            wall = measure_command(text, extra, args.command_runs)
            ok &= wall <= limit
            print(f"| {label} | {wall:.2f} s | ≤ {limit:g} s |")
    print("targets (10 links ≤ 0.1 s of integration and ≤ 1 s as a command, 100 links ≤ 5 s, "
          "50 links with motors ≤ 10 s, exponent ≤ 1.3):", "met" if ok else "NOT met")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
