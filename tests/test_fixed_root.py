"""A fixed root's parent twist and its rate are zero (issue 26): the joints on a root link get
``pV == 0`` and ``pA == 0`` in ``cyphy solve``'s system (so ``simulate`` and ``reach``) and in
the CyPhyCircus ``Evolve``; the whole dcmotor (no ``elements``) then simulates, checked
against the hinge's motion derived by hand."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from cyphy import api
from cyphy import expr as ex
from cyphy.cli import main
from cyphy.semantics.dynamics.equations import assemble, fixed_root_twists

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
DCMOTOR = EXAMPLES / "dcmotor"


def _model():  # type: ignore[no-untyped-def]
    model = api.elaborate([DCMOTOR], api.ElaborateOptions("DCMotorBase")).model
    assert model is not None
    return model


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def test_the_joint_on_the_root_link_gets_a_zero_parent_twist() -> None:
    model = _model()
    equations = fixed_root_twists(model)
    zero = ex.Vector((tuple(ex.Num("0") for _ in range(6)),))
    assert [e.expr for e in equations] == [ex.BinOp("==", ex.Name(("Shaft_pV",)), zero),
                                           ex.BinOp("==", ex.Name(("Shaft_pA",)), zero)]
    assert fixed_root_twists(model, floating_base=True) == []  # the base's twist is its own
    system = assemble(model)
    assert not {"Shaft_pV", "Shaft_pA"} & system.inputs  # no longer free inputs
    floating = assemble(model, floating_base=True, definitions=True)
    assert {"Shaft_pV", "Shaft_pA"} <= floating.inputs


def test_the_whole_dcmotor_simulates_and_the_flywheel_follows_the_motor(capsys) -> None:
    """The bench is the root (fixed), the flywheel's only joint turns about z through its
    centre of mass, so its equation of motion is tau = izz * a with izz = 0.001 kg m²; the
    relation Motor.T == Shaft.tau and J * av' = T (J = 0.01) give Shaft_v = (J / izz) *
    Motor_av = 10 * Motor_av from rest (by hand). The motor itself moves as in the scenario
    restricted to the motor and the range finder."""
    assert main(["simulate", str(DCMOTOR), "--scenario", str(DCMOTOR / "whole_bench.toml"),
                 "--samples", "41", "--rtol", "1e-9", "--atol", "1e-12"]) == 0
    whole = _csv(capsys.readouterr().out)
    for k in range(1, 7):
        assert np.all(whole[f"Shaft_pV_{k}"] == 0) and np.all(whole[f"Shaft_pA_{k}"] == 0)
    assert np.allclose(whole["Shaft_v"], 10 * whole["Motor_av"], rtol=1e-6, atol=1e-6)
    assert np.allclose(whole["Shaft_theta"], 10 * whole["Motor_theta"], rtol=1e-6, atol=1e-6)
    assert main(["simulate", str(DCMOTOR), "--scenario", str(DCMOTOR / "sampled_stop.toml"),
                 "--samples", "41", "--rtol", "1e-9", "--atol", "1e-12"]) == 0
    motor = _csv(capsys.readouterr().out)
    assert np.allclose(whole["t"], motor["t"])
    assert np.allclose(whole["Motor_av"], motor["Motor_av"], rtol=1e-6, atol=1e-6)
    t, speed = whole["t"], whole["Motor_av"]
    assert np.all(np.abs(speed[(t > 0.7) & (t <= 1.05)] - 10.0) < 0.5)  # cruising
    assert abs(speed[-1]) < 1.0  # stopped after near
