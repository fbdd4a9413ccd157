"""Issue: symbolic equations with SymPy — reduction to explicit ODEs, closed forms, failures."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from cyphy import api
from cyphy.semantics.dynamics.closed_form import inline_definitions
from cyphy.cli import main
from conftest import EXAMPLES

MOTOR = """\
import physmod::actuators::SpeedControlMotor
pmodel Drive { local link Shaft { def { inertial information { mass 1 } } aref Motor = SpeedControlMotor { } } }
"""
CONSTS = dict(J=0.01, b=0.1, Ke=0.01, Kt=0.01, R=1, L=0.5, Kp=100, Ki=200, Kd=1)


def solve_text(tmp_path: Path, text: str, **options: object) -> api.SolveResult:
    (tmp_path / "m.rsm").write_text(text)
    return api.solve([tmp_path / "m.rsm"], api.SolveOptions(**options))  # type: ignore[arg-type]


def test_speed_control_motor_reduces_to_a_linear_system(tmp_path: Path) -> None:
    r = solve_text(tmp_path, MOTOR, closed_form=False).reduced
    assert r.states == ["Motor_av", "Motor_i", "Motor_int1", "Motor_theta"]
    assert r.obstacles == []
    states = [r.symbols[s] for s in r.states]
    for s in r.states:
        assert sympy.Poly(r.rhs[s], *states).total_degree() <= 1  # linear in the states
    assert r.rhs["Motor_theta"] == r.symbols["Motor_av"]
    assert "Motor_das" in r.inputs and "Motor_Kp" in r.parameters


def test_closed_form_matches_numerical_integration(tmp_path: Path) -> None:
    result = solve_text(tmp_path, MOTOR, consts=CONSTS)
    r, closed = result.reduced, result.closed_form
    assert closed is not None and set(closed) == set(r.states)
    das = 2.0
    given = {sympy.Symbol("Motor_das", real=True): das,
             sympy.Symbol("der_Motor_das", real=True): 0}
    x0 = {"Motor_av": 0.1, "Motor_i": 0.2, "Motor_int1": -0.1, "Motor_theta": 0.5}
    f = sympy.lambdify([r.symbols[s] for s in r.states],
                       [r.rhs[s].xreplace(given) for s in r.states])
    numeric = solve_ivp(lambda t, y: f(*y), (0, 2), [x0[s] for s in r.states], rtol=1e-11,
                        atol=1e-12, dense_output=True)
    times = np.linspace(0, 2, 20)
    t = sympy.Symbol("t", real=True)
    for k, s in enumerate(r.states):
        expr = closed[s].xreplace({**given, **{sympy.Symbol(f"{n}_0", real=True): v
                                               for n, v in x0.items()}})
        ours = np.array([float(expr.subs(t, tt)) for tt in times])
        theirs = numeric.sol(times)[k]
        assert np.all(np.abs(ours - theirs) <= 1e-6 * np.maximum(np.abs(theirs), 1e-3)), s


def test_marxbot_move_mapping_gives_wheel_speeds() -> None:
    result = api.solve([EXAMPLES / "marxbot"], api.SolveOptions(
        model="marXbotBase", mapping_call="move(lv, av)", closed_form=False))
    r = result.reduced
    assert {"LMotor_i", "LMotor_av", "RMotor_i", "RMotor_av"} <= set(r.rhs)
    lv, av = sympy.Symbol("lv", real=True), sympy.Symbol("av", real=True)
    radius, axis = sympy.Rational("0.025025"), sympy.Rational("0.06")
    assert sympy.simplify(r.outputs["LMotor_das"] - (lv / radius + av * axis / (2 * radius))) == 0
    assert sympy.simplify(r.outputs["RMotor_das"] - (lv / radius - av * axis / (2 * radius))) == 0
    # Both motors: their current follows the mapped speed.
    assert r.rhs["LMotor_i"].has(lv) and r.rhs["RMotor_i"].has(av)
    # The equations of motion: each hinge turns its wheel (a solid cylinder of 0.02 kg, radius
    # 0.025025 m, about its axis) with its motor's torque.
    assert not r.obstacles and result.report.exit_code == 0
    assert r.rhs["LHinge_v"] == sympy.Symbol("LHinge_qdd", real=True)  # a named definition
    inline_definitions(r, result.system)
    wheel = 0.02 * 0.025025 ** 2 / 2
    for side in "LR":
        difference = r.rhs[f"{side}Hinge_v"] - r.outputs[f"{side}Motor_T"] / wheel
        free = difference.free_symbols | r.rhs[f"{side}Hinge_v"].free_symbols
        values = {s: 0.5 + k for k, s in enumerate(sorted(free, key=str))}
        scale = float(r.rhs[f"{side}Hinge_v"].subs(values))
        assert abs(scale) > 1 and abs(float(difference.subs(values))) < 1e-9 * abs(scale)


@pytest.mark.parametrize("equations, kind, variable", [
    ("equation derivative(x) == y", "underdetermined", "y"),
    ("equation derivative(x) == y equation y == g(y) + x", "unknown-function", "y"),
    ("equation derivative(x) == y equation y*y*y + y == -(y^5) + x*sin(y)", "algebraic-loop", "y"),
])
def test_failures_name_the_obstacle(tmp_path: Path, equations: str, kind: str,
                                    variable: str) -> None:
    text = f"""\
import physmod::math::*
function g(v: real): real
actuator Box {{ input u: real local x: real, y: real {equations} }}
pmodel P {{ local link L {{ def {{ inertial information {{ mass 1 }} }} aref B = Box {{ }} }} }}
"""
    result = solve_text(tmp_path, text, closed_form=False)
    (obstacle,) = result.reduced.obstacles
    assert obstacle.kind == kind
    if kind == "underdetermined":  # the structural analysis: x' = y leaves one of x, y free
        assert obstacle.variables == ("B_x", "B_y")
    else:
        assert obstacle.variables == (f"B_{variable}",)
    code = "E-UNDERDETERMINED" if kind == "underdetermined" else "E-REDUCE"
    (d,) = [d for d in result.report.diagnostics if d.code.id == code]
    assert d.span.line == 3 and d.hint


@settings(max_examples=15, deadline=None)
@given(st.data())
def test_random_linear_systems_match_numpy(data: st.DataObject) -> None:
    """Random x' = A w + b u with algebraic aliases w = C x: the reduced right-hand side at a
    random point equals A·C·x + b·u computed by NumPy."""
    n = data.draw(st.integers(1, 3))
    coeff = st.integers(-5, 5)
    a = np.array([[data.draw(coeff) for _ in range(n)] for _ in range(n)], dtype=float)
    c = np.array([[data.draw(coeff) for _ in range(n)] for _ in range(n)], dtype=float)
    b = np.array([data.draw(coeff) for _ in range(n)], dtype=float)

    def lin(row: np.ndarray, names: list[str]) -> str:
        return " + ".join(f"({int(k)})*{v}" for k, v in zip(row, names)) or "0"

    xs, ws = [f"x{i}" for i in range(n)], [f"w{i}" for i in range(n)]
    eqs = [f"equation derivative(x{i}) == {lin(a[i], ws)} + ({int(b[i])})*u" for i in range(n)]
    eqs += [f"equation w{i} == {lin(c[i], xs)}" for i in range(n)]
    text = ("actuator Box { input u: real local " + ", ".join(f"{v}: real" for v in xs + ws)
            + " " + " ".join(eqs) + " }\n"
            "pmodel P { local link L { def { inertial information { mass 1 } } aref B = Box { } } }\n")
    with tempfile.TemporaryDirectory() as tmp:
        r = solve_text(Path(tmp), text, closed_form=False).reduced
    point = np.array([data.draw(st.floats(-2, 2)) for _ in range(n)])
    u = data.draw(st.floats(-2, 2))
    expected = a @ c @ point + b * u
    env = {sympy.Symbol(f"B_{v}", real=True): float(p) for v, p in zip(xs, point)}
    env[sympy.Symbol("B_u", real=True)] = u
    for i in range(n):
        rhs = r.rhs.get(f"B_x{i}")
        assert rhs is not None, r.obstacles
        assert float(rhs.xreplace(env)) == pytest.approx(expected[i], abs=1e-9)


def test_solve_cli_json(tmp_path: Path, capsys) -> None:
    (tmp_path / "m.rsm").write_text(MOTOR)
    argv = ["solve", str(tmp_path / "m.rsm"), "--format", "json"]
    argv += [f"--const={k}={v}" for k, v in CONSTS.items()]
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["states"] == ["Motor_av", "Motor_i", "Motor_int1", "Motor_theta"]
    assert data["odes"]["Motor_theta"] == "Motor_av" and data["closed_form"]
    assert main(["solve", str(tmp_path / "m.rsm"), "--format", "latex"]) == 0
    assert capsys.readouterr().out.startswith("\\begin{align*}")


def test_check_and_show_do_not_import_sympy() -> None:
    code = ("import sys\nfrom cyphy.cli import main\n"
            f"main(['show', {str(EXAMPLES / 'marxbot')!r}, '--model', 'marXbotBase'])\n"
            "print('SYMPY', 'sympy' in sys.modules)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert "SYMPY False" in proc.stdout, proc.stderr


def test_second_derivative_gets_an_intermediate_state(tmp_path: Path) -> None:
    """m·x'' = F - k·x: the oscillator becomes x' = x_dot, x_dot' = (F - k·x)/m."""
    text = """\
actuator Spring { input F: real local x: real const m: real, k: real
  equation m * derivative(derivative(x)) == F - k * x }
pmodel P { local link L { def { inertial information { mass 1 } } aref S = Spring { } } }
"""
    r = solve_text(tmp_path, text, closed_form=False).reduced
    assert r.states == ["S_x", "S_x_dot"] and r.obstacles == []
    x, x_dot, f, m, k = (sympy.Symbol(n, real=True)
                         for n in ("S_x", "S_x_dot", "S_F", "S_m", "S_k"))
    assert r.rhs["S_x"] == x_dot
    assert sympy.simplify(r.rhs["S_x_dot"] - (f - k * x) / m) == 0
