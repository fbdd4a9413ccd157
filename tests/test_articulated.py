"""The explicit equations of motion of `cyphy solve` (the articulated-body algorithm's named
definitions, cyphy.semantics.dynamics.articulated) and the per-link Newton–Euler equations of
`cyphy show` (cyphy.semantics.dynamics.link_equations), checked against Pinocchio (its model built
with its own API, tests/test_dynamics.py) and against each other.

The definitions are evaluated from the text `cyphy solve --format json` prints (each value is
Python arithmetic with cos and sin), not through cyphy's own code."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

from cyphy import api
from cyphy.cli import main
from cyphy.semantics.dynamics import rigid_body as dynamics
from synthetic import chain_model, write_model

pin = pytest.importorskip("pinocchio")
from test_dynamics import pinocchio_model  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def _solve_json(folder: Path, capsys) -> dict:
    assert main(["solve", str(folder), "--format", "json"]) == 0
    return json.loads(capsys.readouterr().out)


def _evaluate(out: dict, values: dict[str, float]) -> dict[str, float]:
    """Every definition of `solve`'s JSON in order, from ``values`` (states, inputs,
    parameters): Python evaluates the printed text."""
    scope = dict(values)
    functions = {"cos": math.cos, "sin": math.sin, "__builtins__": {}}
    for d in out["definitions"]:
        scope[d["name"]] = eval(d["value"], functions, scope)  # noqa: S307 - our own output
    return scope


def _check_against_aba(folder: Path, capsys, states: int) -> None:
    out = _solve_json(folder, capsys)
    model = api.elaborate([folder]).model
    tree = dynamics.kinematic_tree(model)
    assert len(tree) == states
    prefixes = tree.prefixes
    for p in prefixes:  # the accelerations are named definitions, the ODEs name them
        assert out["odes"][f"{p}_v"] == f"{p}_qdd"
        assert out["odes"][f"{p}_theta"] == f"{p}_v"
    names = [d["name"] for d in out["definitions"]]
    assert len(names) == len(set(names))
    assert len(names) < 130 * len(tree)  # linear in the tree: a bounded number per link
    robot = pinocchio_model(model, tree.names)
    data = robot.createData()
    rng = np.random.default_rng(len(tree))
    for _ in range(3):
        values = {n: float(rng.uniform(-1, 1)) for n in [*out["states"], *out["inputs"],
                                                            *out["parameters"]]}
        scope = _evaluate(out, values)
        q = np.array([values[f"{p}_theta"] for p in prefixes])
        qd = np.array([values[f"{p}_v"] for p in prefixes])
        tau = np.array([scope[f"{p}_tau"] for p in prefixes])  # from the motors' torques
        ours = np.array([scope[f"{p}_qdd"] for p in prefixes])
        reference = pin.aba(robot, data, q, qd, tau)
        assert np.abs(ours - reference).max() <= 1e-9 * np.abs(reference).max(), \
            (ours, reference)


def test_ten_link_arm_accelerations_are_pinocchio_aba(tmp_path: Path, capsys) -> None:
    """A 10-link arm (joints about z, y, x in turn, every link offset): the explicit
    accelerations of `solve` at random states, with the motors' torques as efforts."""
    folder = tmp_path / "arm"
    write_model(folder, chain_model(10, sensors_per_link=0, bent=True))
    _check_against_aba(folder, capsys, 9)


def test_thirty_link_arm_solves_and_matches(tmp_path: Path, capsys) -> None:
    folder = tmp_path / "arm"
    write_model(folder, chain_model(30, sensors_per_link=0, bent=True))
    _check_against_aba(folder, capsys, 29)


def test_solve_output_is_byte_identical_across_runs(tmp_path: Path) -> None:
    folder = tmp_path / "arm"
    write_model(folder, chain_model(4, sensors_per_link=0, bent=True))
    outputs = []
    script = ("import sys\nfrom cyphy.cli import main\n"
              f"main(['solve', {str(folder)!r}])\n"
              f"main(['solve', {str(folder)!r}, '--format', 'json'])\n")
    for seed in ("1", "2"):  # different hash seeds: no set or dict order may leak
        env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONHASHSEED": seed}
        outputs.append(subprocess.run([sys.executable, "-c", script], env=env,
                                      capture_output=True, check=True).stdout)
    assert outputs[0] == outputs[1]
    assert b"definitions (in order" in outputs[0] and b"J2_qdd = " in outputs[0]
    assert b'"definitions": [' in outputs[0]


def test_text_lists_definitions_before_the_odes(tmp_path: Path, capsys) -> None:
    folder = tmp_path / "arm"
    write_model(folder, chain_model(3, sensors_per_link=0, bent=True))
    assert main(["solve", str(folder)]) == 0
    text = capsys.readouterr().out
    assert text.index("definitions (in order") < text.index("J0_v' = J0_qdd")
    # the efforts come first: each joint's from the motor that drives it
    assert "\n  J0_tau = M0_Kt*M0_i - M0_av*M0_b\n" in text
    assert text.index("J0_tau = ") < text.index("J0_u = ") < text.index("J0_qdd = ")


def test_simulate_uses_the_definitions_and_agrees_with_the_numeric_algorithm(
        tmp_path: Path) -> None:
    """A 6-joint undriven arm (efforts zero): `simulate` integrates solve's ODEs; the numeric
    articulated-body path integrates the tree; both agree."""
    from cyphy.backends.simulate import SimulationOptions

    folder = tmp_path / "arm"
    write_model(folder, _without_motors(chain_model(7, sensors_per_link=0, bent=True)))
    settings = SimulationOptions(t_end=0.5, init={"J0_v": 1.0, "J3_theta": 0.4},
                                 samples=6, rtol=1e-10, atol=1e-10)
    symbolic = api.simulate([folder], api.SimulateOptions(simulation=settings))
    numeric = api.simulate([folder], api.SimulateOptions(simulation=settings, numeric=True))
    assert not symbolic.numeric and numeric.numeric
    for name in ("J0_theta", "J3_v", "J5_theta"):
        a, b = symbolic.trajectory.column(name), numeric.trajectory.column(name)
        assert np.abs(a - b).max() < 1e-6 * max(1.0, np.abs(b).max())
    assert np.abs(symbolic.trajectory.column("J5_v")).max() > 0.1  # it really moves


def _without_motors(text: str) -> str:
    """The chain's text without its motors: the joints' efforts become inputs."""
    out, skip = [], 0
    for line in text.splitlines():
        if "aref M" in line:
            skip = 3  # the aref line, its relation and its closing brace
        if skip:
            skip -= 1
            continue
        out.append(line)
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------- per link

def _link_values(tree, bodies, q, qd, qdd):
    """The per-link equations evaluated in order (``X``, ``V``, ``dV`` root to leaves, then
    ``F`` leaves to root, then the efforts), with SymPy on the printed AST."""
    from cyphy.translate.to_sympy import to_sympy

    values = {}
    for i, joint in enumerate(tree.joints):
        p = joint.prefix
        values[sympy.Symbol(f"{p}_theta", real=True)] = q[i]
        values[sympy.Symbol(f"{p}_v", real=True)] = qd[i]
        values[sympy.Symbol(f"{p}_a", real=True)] = qdd[i]
    known: dict[str, object] = {}

    def value(equation):
        rhs = to_sympy(equation.right, symbols={**{str(k): v for k, v in values.items()},
                                                **known})
        return sympy.Matrix(rhs).evalf() if isinstance(rhs, sympy.MatrixBase) else \
            sympy.Float(rhs.evalf()) if hasattr(rhs, "evalf") else rhs

    for body in bodies:  # forward: A, G, X, V, dV
        for equation in body.equations[:5]:
            known[equation.left.text] = value(equation)
    for body in reversed(bodies):  # backward: F (children's first), then the effort
        for equation in body.equations[5:]:
            known[equation.left.text] = value(equation)
    return known


def test_link_equations_structure(tmp_path: Path) -> None:
    from cyphy.lang.notation import to_notation
    from cyphy.semantics.dynamics.link_equations import link_equations

    model = api.elaborate([ROOT / "examples" / "manipulator"]).model
    bodies = link_equations(dynamics.kinematic_tree(model))
    assert [b.joint.prefix for b in bodies] == ["Shoulder", "Slide", "Lift"]
    for body in bodies:
        p = body.joint.prefix
        assert [e.left.text for e in body.equations] == [
            f"{p}_{n}" for n in ("A", "G", "X", "V", "dV", "F", "tau")]
    slide = [to_notation(e) for e in bodies[1].equations]
    assert slide[3] == "Slide_V == Slide_X * Shoulder_V + Slide_A * Slide_v"
    assert slide[4] == ("Slide_dV == Slide_X * Shoulder_dV + ad(Slide_V) * Slide_A * Slide_v"
                        " + Slide_A * Slide_a")
    assert slide[5] == ("Slide_F == Slide_G * Slide_dV - transpose(ad(Slide_V)) * Slide_G * "
                        "Slide_V + transpose(Lift_X) * Lift_F")
    root = to_notation(bodies[0].equations[4])
    assert root.startswith("Shoulder_dV == Shoulder_X * (|0, 0, 0, 0, 0, 9.81|)")
    assert "cos(Shoulder_theta)" in to_notation(bodies[0].equations[2])


def test_link_equations_give_the_efforts_of_rnea_and_pinocchio(tmp_path: Path) -> None:
    """The per-link equations at random states: the joint efforts equal cyphy's numeric
    RNEA and Pinocchio's; the twists equal the definitions `solve` prints (one source)."""
    from cyphy.semantics.dynamics.articulated import explicit_motion
    from cyphy.semantics.dynamics.link_equations import link_equations

    folder = tmp_path / "arm"
    write_model(folder, chain_model(5, sensors_per_link=0, bent=True))
    model = api.elaborate([folder]).model
    tree = dynamics.kinematic_tree(model)
    bodies = link_equations(tree)
    robot = pinocchio_model(model, tree.names)
    rng = np.random.default_rng(5)
    q, qd, qdd = (rng.uniform(-1, 1, len(tree)) for _ in range(3))
    known = _link_values(tree, bodies, q, qd, qdd)
    efforts = np.array([np.array(known[f"{p}_tau"], dtype=float).ravel()[0]
                        for p in tree.prefixes])
    rnea = dynamics.inverse_dynamics(tree, q, qd, qdd)
    reference = pin.rnea(robot, robot.createData(), q, qd, qdd)
    scale = np.abs(reference).max()
    assert np.abs(efforts - reference).max() <= 1e-9 * scale
    assert np.abs(rnea - reference).max() <= 1e-9 * scale
    # the twists of the per-link equations are the twist definitions of solve
    motion = explicit_motion(tree, lambda j, port: f"{j.prefix}_{port}")
    scope = {f"{p}_{n}": float(x[i]) for i, p in enumerate(tree.prefixes)
             for n, x in (("theta", q), ("v", qd))}
    scope.update({f"{p}_tau": 0.0 for p in tree.prefixes})
    functions = {"cos": math.cos, "sin": math.sin, "__builtins__": {}}
    for d in motion.definitions:
        scope[d.name] = eval(d.value.text(), functions, scope)  # noqa: S307
    for p in tree.prefixes:
        twist = np.array(known[f"{p}_V"], dtype=float).ravel()
        ours = np.array([scope.get(f"{p}_V_{k}", 0.0) for k in range(1, 7)])
        assert np.abs(twist - ours).max() <= 1e-12 * max(1.0, np.abs(twist).max())


def test_show_prints_the_link_equations(capsys) -> None:
    assert main(["show", str(ROOT / "examples" / "manipulator")]) == 0
    text = capsys.readouterr().out
    assert "    Lift_tau == transpose(Lift_A) * Lift_F\n" in text
    assert "    Slide_V == Slide_X * Shoulder_V + Slide_A * Slide_v\n" in text


def test_ldl_inverse_inverts_small_matrices() -> None:
    """The inverse of ``D`` for joints of several coordinates: its LDLᵀ factorisation in
    named definitions, evaluated in order, against NumPy's (LAPACK) inverse, for a well and
    a badly conditioned symmetric positive definite matrix."""
    from cyphy.semantics.dynamics.articulated import _ldl_inverse
    from cyphy.semantics.dynamics.polynomial import Polynomial

    rng = np.random.default_rng(3)
    for size, condition in ((3, 1e1), (6, 1e8)):
        basis, _ = np.linalg.qr(rng.uniform(-1, 1, (size, size)))
        m = basis @ np.diag(np.geomspace(1.0, 1.0 / condition, size)) @ basis.T
        definitions: list = []

        def name(key, value, joint, always=False):
            definitions.append((key, Polynomial.lift(value)))
            return Polynomial.atom(key)

        names = [[Polynomial.atom(f"m_{r}_{c}") for c in range(size)] for r in range(size)]
        inverse = _ldl_inverse(names, "p", None, name)
        scope = {f"m_{r}_{c}": float(m[r, c]) for r in range(size) for c in range(size)}
        for key, value in definitions:
            scope[key] = eval(value.text(), {"__builtins__": {}}, scope)  # noqa: S307
        ours = np.array([[scope[x.text()] for x in row] for row in inverse])
        reference = np.linalg.inv(m)
        assert np.abs(ours - reference).max() <= 1e-16 * condition * 100 * \
            np.abs(reference).max()


@pytest.mark.skipif(__import__("shutil").which("pdflatex") is None,
                    reason="pdflatex is not installed")
def test_solve_latex_with_definitions_typesets(tmp_path: Path, capsys) -> None:
    """`solve --format latex` prints the named definitions as rows of the align*: pdflatex
    typesets them in a document (amsmath), as a reader would paste them."""
    folder = tmp_path / "arm"
    write_model(folder, chain_model(3, sensors_per_link=0, bent=True))
    assert main(["solve", str(folder), "--format", "latex"]) == 0
    body = capsys.readouterr().out
    assert body.count("\\\\\n") > 3 * 20  # the definitions' rows, not only the ODEs
    (tmp_path / "s.tex").write_text("\\documentclass{article}\n\\usepackage{amsmath}\n"
                                    f"\\begin{{document}}\n{body}\\end{{document}}\n")
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "s.tex"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-3000:]
