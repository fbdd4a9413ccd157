"""The kinematic tree's equations of motion in the CyPhyCircus semantics (issue 16 item 2):
``Evolve`` carries one ``<Joint>_tau = M(q)·a + h(q, v)`` per joint, in the text (read back
by the text reader), the LaTeX and the Isabelle theory (which still passes the HOL type
checker). Each equation read back from the text is evaluated at random states and checked
against Pinocchio's inverse dynamics (its model built with its own API, tests/test_dynamics.py)
and against ``cyphy solve``: the accelerations solve derives, put into the semantics'
equation, give back the effort the motor applies."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import sympy

from conftest import EXAMPLES
from cyphy import api
from cyphy import expr as ex
from cyphy.backends.circus.latex import program_to_latex
from cyphy.backends.circus.reader import read_program
from cyphy.backends.circus.text import program_to_text
from cyphy.backends.isabelle.theory import generate_session
from cyphy.semantics.circus import ast as c
from cyphy.semantics.dynamics import rigid_body as dynamics
from motors import speed_control_motor
from test_dynamics import pin, pinocchio_model
from test_isabelle import check_session, semantics

# A two-link arm swinging in the x-z plane under gravity, each hinge driven by a motor: its
# equations of motion have sin and cos of both joint angles.
ARM = """
package arm
import physmod::math::*
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor

pmodel Arm {
  local link Base {
    def { inertial information { mass 1.0
      inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 } } }
    jref Hip = Revolute {
      pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
      instantiation AXIS = (|0, 1, 0|)
      flexibly connected to Upper""" + speed_control_motor("HipMotor", "Hip") + """
    }
  }
  local link Upper {
    pose { x = 0 y = 0 z = -0.4 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 1.5
      inertia matrix { ixx 0.02 ixy 0 ixz 0 iyy 0.03 iyz 0 izz 0.01 } } }
    jref Knee = Revolute {
      pose { x = 0 y = 0 z = -0.2 roll = 0 pitch = 0 yaw = 0 }
      instantiation AXIS = (|0, 1, 0|)
      flexibly connected to Lower""" + speed_control_motor("KneeMotor", "Knee") + """
    }
  }
  local link Lower {
    pose { x = 0.05 y = 0 z = -0.9 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.7
      inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.015 iyz 0 izz 0.005 } } }
  }
}

interface DriveI { drive(w: real) }

module ArmSoftware {
  cycleDef cycle == 1
  robotic platform P { provides DriveI }
}

map ArmMapping dmodel ArmSoftware to pmodel Arm {
  operation drive {
    equation Base::Hip::HipMotor.das == w
    equation Upper::Knee::KneeMotor.das == -w
  }
}
"""

# model folder or file, the joints' motors (joint prefix → motor prefix)
CASES = {
    "dcmotor": (EXAMPLES / "dcmotor" / "Mapping.rsm", {"Shaft": "Motor"}),
    "marxbot": (EXAMPLES / "marxbot" / "Mapping.rsm", {"LHinge": "LMotor",
                                                       "RHinge": "RMotor"}),
    "arm": (None, {"Hip": "HipMotor", "Knee": "KneeMotor"}),
}


def _paths(case: str, tmp_path: Path) -> list[Path]:
    path, _ = CASES[case]
    if path is None:
        path = tmp_path / "arm.rsm"
        path.write_text(ARM)
    return [path]


def _evaluate(e: ex.Expr, values: dict[str, float]) -> float:
    """A scalar expression of the text reader's AST, evaluated here (not by cyphy)."""
    if isinstance(e, ex.Num):
        return float(e.text)
    if isinstance(e, ex.Name):
        return values[e.text]
    if isinstance(e, ex.UnaryOp) and e.op == "-":
        return -_evaluate(e.operand, values)
    if isinstance(e, ex.BinOp):
        a, b = _evaluate(e.left, values), _evaluate(e.right, values)
        return {"+": a + b, "-": a - b, "*": a * b, "/": a / b}[e.op] if e.op != "^" \
            else a ** b
    if isinstance(e, ex.Call) and isinstance(e.func, ex.Name) and e.func.text in ("sin", "cos"):
        return getattr(math, e.func.text)(_evaluate(e.args[0], values))
    raise AssertionError(f"unexpected node in an equation of motion: {e!r}")


def _evolve(program: c.Program) -> c.Evolution:
    evolve = next(d for d in program.pmodel.actions if d.name == "Evolve")
    assert isinstance(evolve.body, c.Evolution)
    return evolve.body


def _motion_in(evolution: c.Evolution, joint: str) -> ex.Expr:
    """The right-hand side of the one equation ``<joint>_tau = …`` whose right side names the
    joint's acceleration ``<joint>_a``: the equation of motion (the library's
    ``tau = transpose(F) * A`` names no acceleration)."""
    found = [e.right for e in evolution.equations
             if isinstance(e, ex.BinOp) and e.op == "==" and e.left == ex.Name((f"{joint}_tau",))
             and ex.Name((f"{joint}_a",)) in set(e.right.walk())]
    assert len(found) == 1, (joint, found)
    return found[0]


@pytest.mark.parametrize("case", sorted(CASES))
def test_evolve_carries_the_equations_of_motion(case: str, tmp_path: Path) -> None:
    sem = semantics(_paths(case, tmp_path))
    program = read_program(program_to_text(sem.program))  # what the text says
    assert program == sem.program
    evolution = _evolve(program)
    joints = CASES[case][1]
    rhs = {j: _motion_in(evolution, j) for j in joints}

    # Pinocchio: τ = M(q)·q̈ + h(q, q̇) of the elaborated model at random states
    model = sem.model
    names = dynamics.kinematic_tree(model).names
    prefixes = [next(j.device.prefix for j in model.joints if j.name == n) for n in names]
    assert set(prefixes) == set(joints)
    robot = pinocchio_model(model, names)
    data = robot.createData()
    rng = np.random.default_rng(24)
    for _ in range(5):
        q, qd, qdd = (rng.uniform(-2, 2, len(names)) for _ in range(3))
        tau = pin.rnea(robot, data, q, qd, qdd)
        values = {}
        for i, p in enumerate(prefixes):
            values.update({f"{p}_theta": q[i], f"{p}_v": qd[i], f"{p}_a": qdd[i]})
        for i, p in enumerate(prefixes):
            assert _evaluate(rhs[p], values) == pytest.approx(tau[i], rel=1e-9, abs=1e-12)

    # the same equations that `cyphy solve` reduces: its accelerations give back the motors'
    # torques (Motor_T = Joint_tau is the model's relation)
    reduced = _solved(case, tmp_path, model.name)
    for _ in range(5):
        state = {s: rng.uniform(-1, 1) for s in reduced.states}
        given = {u: rng.uniform(0.5, 1) for u in [*reduced.inputs, *reduced.parameters]}
        subs = {reduced.symbols.get(n, sympy.Symbol(n, real=True)): v
                for n, v in {**state, **given}.items()}
        # solve's equations of motion are named definitions (the articulated-body
        # algorithm): each printed value is evaluated in order, as Python arithmetic
        scope: dict[str, float] = {**state, **given}
        for name, value in reduced.definitions:
            text = value.text() if hasattr(value, "text") else sympy.sstr(value)
            scope[name] = eval(text, {"cos": math.cos, "sin": math.sin,  # noqa: S307
                                      "__builtins__": {}}, scope)
            subs[sympy.Symbol(name, real=True)] = scope[name]
        values = dict(state)
        for p in joints:
            values[f"{p}_a"] = float(reduced.rhs[f"{p}_v"].subs(subs))
        for p, motor in joints.items():
            torque = float(reduced.outputs[f"{motor}_T"].subs(subs))
            assert _evaluate(rhs[p], values) == pytest.approx(torque, rel=1e-8, abs=1e-10)


def _solved(case: str, tmp_path: Path, name: str):  # type: ignore[no-untyped-def]
    path = _paths(case, tmp_path)[0]
    folder = [path.parent] if case != "arm" else [path]
    result = api.solve(folder, api.SolveOptions(closed_form=False, model=name))
    assert result.reduced is not None and not result.reduced.obstacles
    return result.reduced


@pytest.mark.parametrize("case", sorted(CASES))
def test_isabelle_and_latex_carry_the_equations_of_motion(case: str, tmp_path: Path) -> None:
    sem = semantics(_paths(case, tmp_path))
    session = generate_session(sem.program, sem.names)
    # the static checks and the HOL type checker (cyphy/verify/theory/utp_types.py), and every
    # definition read back from the theory into the action it was printed from
    check_session(session, sem.program)
    evolution = session.actions["Evolve"].body
    assert isinstance(evolution, c.Evolution)
    for joint in CASES[case][1]:
        rhs = _motion_in(evolution, joint)  # exactly one, naming the joint's acceleration
        assert rhs == _motion_in(_evolve(sem.program), joint)
    theory = session.files[f"{session.theory_name}.thy"]
    latex = program_to_latex(sem.program)
    for joint in CASES[case][1]:
        assert f"{joint}\\_a" in latex
    if case == "arm":  # gravity and the coupling of the two links: sines and cosines
        assert "(uop sin $Knee_theta)" in theory and "(uop cos $Knee_theta)" in theory
        assert '"HOL.Transcendental"' in session.files["CyPhyCircus_Prelude.thy"]
        assert "sin(Knee\\_theta)" in latex and "cos(Knee\\_theta)" in latex


def test_a_tree_without_equations_of_motion_is_a_warning_not_a_silent_cut(
        tmp_path: Path, capsys) -> None:
    from cyphy.cli import main

    lower = ("def { inertial information { mass 0.7\n      inertia matrix { ixx 0.01 ixy 0 "
             "ixz 0 iyy 0.015 iyz 0 izz 0.005 } } }")
    assert lower in ARM
    (tmp_path / "arm.rsm").write_text(ARM.replace(lower, "def { }"))
    assert main(["gen", str(tmp_path / "arm.rsm"), "--cyphycircus", "-o",
                 str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert "W-SEMANTICS-MOTION" in err and "Arm::Lower has no mass properties" in err
    program = read_program((tmp_path / "out" / "ArmMapping.cpc").read_text())
    tau = {e.left.text for e in _evolve(program).equations
           if isinstance(e, ex.BinOp) and isinstance(e.left, ex.Name)}
    assert {"Hip_tau", "Knee_tau"} <= tau  # the library's tau = transpose(F) * A stays
    assert not any(ex.Name(("Knee_a",)) in set(e.walk()) and isinstance(e.left, ex.Name)
                   and e.left.text.endswith("_tau") for e in _evolve(program).equations)
