"""The same robot in every command (issue 32): `show` on joints of several coordinates,
`--const` honoured everywhere, joint damping and limits in the equations, orientation
coordinates near their singularity, solve's JSON closed under its names.

Oracles: Pinocchio (its model built with its own joints, tests/test_dynamics_joints.py) and
MuJoCo on cyphy's own MJCF export; the printed equations are read back by the parser and
evaluated by SymPy, never through cyphy's dynamics."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy

from cyphy.cli import main
from cyphy.semantics.dynamics import rigid_body as dynamics

pin = pytest.importorskip("pinocchio")
from test_dynamics_joints import MULTI, _elaborated, pinocchio_model  # noqa: E402


def _write(folder: Path, text: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "m.rsm").write_text(text)
    return folder


def _parse(text: str):
    from cyphy.lang.parser import parse_text

    result = parse_text(f"const e: real = {text}", "<show>")
    assert not result.diagnostics, (text, result.diagnostics)
    return result.file.items[0].value


def _evaluate_show(motion: list[dict], values: dict[str, object]) -> dict[str, object]:
    """The per-body equations `show --format json` printed, read back by the parser and
    evaluated by SymPy: forward (``A``, ``dA``, ``G``, ``X``, ``V``, ``dV``) root to leaves,
    then the wrenches leaves to root, then the efforts."""
    from cyphy.translate.to_sympy import to_sympy

    known: dict[str, object] = dict(values)
    split = [[e.split(" == ", 1) for e in body["equations"]] for body in motion]

    def run(pairs):
        for left, right in pairs:
            value = to_sympy(_parse(right), symbols=dict(known))
            value = sympy.Matrix(value).evalf() if isinstance(value, sympy.MatrixBase) \
                else sympy.Float(sympy.sympify(value).evalf())
            known[left] = value

    for pairs in split:
        run([p for p in pairs if not p[0].endswith(("_F", "_tau"))])
    for pairs in reversed(split):
        run([p for p in pairs if p[0].endswith("_F")])
    for pairs in split:
        run([p for p in pairs if p[0].endswith("_tau")])
    return known


def test_show_on_ball_and_universal_joints_gives_pinocchio_efforts(tmp_path: Path,
                                                                   capsys) -> None:
    """`show` (text and JSON) on a ball–universal chain: the printed Newton–Euler equations,
    evaluated at random states, give the efforts of Pinocchio's RNEA."""
    folder = _write(tmp_path / "multi", MULTI)
    assert main(["show", str(folder)]) == 0
    text = capsys.readouterr().out
    assert "Wrist_dV == Wrist_X * Shoulder_dV + ad(Wrist_V) * Wrist_A * Wrist_v + " \
           "Wrist_A * Wrist_a + Wrist_dA" in text
    assert main(["show", str(folder), "--format", "json"]) == 0
    motion = json.loads(capsys.readouterr().out)["motion"]
    assert [b["kind"] for b in motion] == ["spherical", "universal"]
    model = _elaborated(folder)
    tree = dynamics.kinematic_tree(model)
    robot = pinocchio_model(model, tree.names, False)
    rng = np.random.default_rng(32)
    for _ in range(2):
        q, qd, qdd = (rng.uniform(-1.2, 1.2, tree.dof) for _ in range(3))
        values: dict[str, object] = {}
        for joint, k in zip(tree.joints, tree.offsets):
            for port, x in (("theta", q), ("v", qd), ("a", qdd)):
                values[f"{joint.prefix}_{port}"] = sympy.Matrix(x[k:k + joint.dof])
        known = _evaluate_show(motion, values)
        ours = np.concatenate([np.array(known[f"{p}_tau"], dtype=float).ravel()
                               for p in tree.prefixes])
        reference = pin.rnea(robot, robot.createData(), q, qd, qdd)
        assert np.abs(ours - reference).max() <= 1e-9 * np.abs(reference).max()
