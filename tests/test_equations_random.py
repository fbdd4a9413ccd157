"""Issue 27, item 3: random trees with random extra relations are either solved, with every
equation holding along `simulate`'s trajectory, or refused with E-OVERDETERMINED /
E-UNDERDETERMINED; never solved with an equation left out.

A chain of one or two revolute joints (random axes, offsets and masses), each driven by a
TorqueControlMotor, a SpeedControlMotor or nothing, a Sonar reading one joint, and up to two
relations drawn from those a user writes: speeds tied together (an index-2 constraint: refused),
a motor's speed tied to its joint (over-determined: refused), torque feedback, a fixed effort.
Each scalar residual of the assembled equations whose variables the trajectory gives (the
states, the outputs, the inputs, the states' derivatives from the right-hand side, the
equations of motion's definitions evaluated in order) is evaluated at every sample; every
relation and every equation of motion must be among them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cyphy import api
from cyphy.backends.simulate import SimulationOptions
from cyphy.semantics.dynamics.reduce import Reducer
from cyphy.translate.to_sympy import T

MOTOR = dict(J=0.01, b=0.1, Ke=0.05, Kt=0.05, R=1.0, L=0.1, Kp=2.0, Ki=5.0, Kd=0.0)
AXES = ["(|1, 0, 0|)", "(|0, 1, 0|)", "(|0, 0, 1|)"]
STRUCTURAL = {"E-OVERDETERMINED", "E-UNDERDETERMINED"}


@st.composite
def robots(draw: Any) -> tuple[str, list[str]]:
    joints = draw(st.integers(1, 2))
    names = [f"J{k}" for k in range(joints)]
    drives = [draw(st.sampled_from(["none", "torque", "speed"])) for _ in names]
    pool: list[str] = []
    if joints == 2:
        pool.append("J0.v == J1.v")
    for name, drive in zip(names, drives):
        if drive == "speed":
            pool.append(f"M{name}.av == {name}.v")
        if drive == "torque":
            pool.append(f"M{name}.TorqueIn == -0.5 * {name}.theta - 0.1 * {name}.v")
        pool.append(f"{name}.tau == 0.2")
    extra = draw(st.lists(st.sampled_from(pool), min_size=1, max_size=2, unique=True))
    links, blocks = [], []
    for k, (name, drive) in enumerate(zip(names, drives)):
        axis = draw(st.sampled_from(AXES))
        offset = draw(st.sampled_from([0.3, 0.5]))
        mass = draw(st.sampled_from([0.5, 1.0, 2.0]))
        device = {"none": "",
                  "torque": f"aref M{name} = TorqueControlMotor {{ relation "
                            f"M{name}.TorqueOut == {name}.tau }}",
                  "speed": f"aref M{name} = SpeedControlMotor {{ relation M{name}.T == "
                           f"{name}.tau }}"}[drive]
        sensor = "sref Echo = Sonar { relation Echo.distance == 1 + J0.theta }" if k == 0 \
            else ""
        relations = " ".join(f"relation {r}" for r in extra) if k == joints - 1 else ""
        blocks.append((name, axis, device, sensor, relations))
        links.append((offset, mass))
    text = ["import physmod::math::*", "import physmod::joints::Revolute",
            "import physmod::actuators::*", "import physmod::sensors::*", "pmodel R {",
            "local link L0 { def { inertial information { mass 1 inertia matrix { ixx 1 ixy 0 "
            "ixz 0 iyy 1 iyz 0 izz 1 } } }"]
    for k, (name, axis, device, sensor, relations) in enumerate(blocks):
        z = -sum(o for o, _ in links[:k + 1])
        text.append(f"jref {name} = Revolute {{ pose {{ x = 0 y = 0 z = {-sum(o for o, _ in links[:k])} "
                    f"roll = 0 pitch = 0 yaw = 0 }} instantiation AXIS = {axis} flexibly "
                    f"connected to L{k + 1} {device} {sensor} {relations} }} }}")
        text.append(f"local link L{k + 1} {{ pose {{ x = 0.1 y = 0 z = {z} roll = 0 pitch = 0 "
                    f"yaw = 0 }} def {{ inertial information {{ mass {links[k][1]} inertia "
                    "matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.02 iyz 0 izz 0.03 } } }")
    text.append("} }")
    return "\n".join(text) + "\n", extra


def _definitions(reduced: Any, values: dict[str, float]) -> dict[str, float]:
    """The equations of motion's definitions at one sample, in order."""
    symbols: dict[str, Any] = {n: sympy.Float(v) for n, v in values.items()}
    out = {}
    for name, value in reduced.definitions:
        expr = value.to_sympy(symbols) if hasattr(value, "to_sympy") else \
            value.xreplace({s: symbols.get(str(s), s) for s in value.free_symbols})
        symbols[name] = sympy.Float(expr)
        out[name] = float(expr)
    return out


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(robot=robots())
def test_random_robots_are_solved_right_or_refused(tmp_path_factory, robot) -> None:
    text, extra = robot
    folder = tmp_path_factory.mktemp("robot")
    (folder / "r.rsm").write_text(text)
    solved = api.solve([folder], api.SolveOptions(consts=MOTOR, closed_form=False))
    codes = {d.code.id for d in solved.report.diagnostics if d.severity.value == "ERROR"}
    if codes:
        assert codes <= STRUCTURAL, (text, [d.message for d in solved.report.diagnostics])
        assert solved.reduced is None or not solved.reduced.rhs
        return
    inputs = {n: "0.3" for n in solved.reduced.inputs if not n.startswith("der_")}
    run = api.simulate([folder], api.SimulateOptions(consts=MOTOR, simulation=SimulationOptions(
        t_end=0.4, samples=5, inputs=inputs, rtol=1e-11, atol=1e-12, method="DOP853",
        init={s: 0.2 for s in solved.reduced.states if s.endswith("_theta")})))
    assert not run.report.has_errors, [d.message for d in run.report.diagnostics]
    trajectory, reduced, system = run.trajectory, solved.reduced, solved.system
    residuals = Reducer(system).residuals([])
    checked: set[int] = set()
    for row in range(len(trajectory.times)):
        values = {n: float(trajectory.values[row, k]) for k, n in enumerate(trajectory.names)}
        values.update({n: float(v) for n, v in inputs.items()})
        values.update({n: 0.0 for n in system.inputs if n not in values})
        values.update({f"der_{n}": 0.0 for n in system.inputs})
        values.update(_definitions(reduced, values))
        rates = {s: float(reduced.rhs[s].xreplace({reduced.symbols.get(n, sympy.Symbol(
            n, real=True)): v for n, v in values.items()})) for s in reduced.states}
        for k, (r, eq) in enumerate(residuals):
            sub: dict[Any, Any] = {}
            for d in r.atoms(sympy.Derivative):
                name = d.expr.func.__name__
                if name in rates:
                    sub[d] = rates[name]
            r = r.xreplace(sub)
            sub = {f: values[f.func.__name__] for f in r.atoms(sympy.Function)
                   if hasattr(f, "func") and f.func.__name__ in values and f.args == (T,)}
            sub.update({s: values[str(s)] for s in r.free_symbols if str(s) in values})
            r = sympy.sympify(r.xreplace(sub))  # a residual that is one variable becomes a float
            if r.free_symbols or r.atoms(sympy.Derivative) or any(
                    f.args == (T,) for f in r.atoms(sympy.Function)):
                continue  # a variable the trajectory does not give (a joint's wrench)
            assert abs(float(r)) < 1e-8, (text, eq.origin, r)
            checked.add(k)
    for k, (_, eq) in enumerate(residuals):
        if eq.origin == "relation" or eq.origin.endswith(" motion"):
            assert k in checked, (text, eq.origin, str(residuals[k][0]))
