"""``--default-inertial sdf`` (and a scenario's ``default_inertial = "sdf"``): links without
inertial information get SDFormat's defaults (mass 1 kg, identity inertia at the link's
origin; gazebosim/sdformat ``sdf/1.6/inertial.sdf``), with a warning each, so that the
kinematic tree has equations of motion; without it they stay an ``E-DYNAMICS`` error. The
equations are checked against the same model with those values written out, and against the
pendulum's equation worked out by hand."""

from __future__ import annotations

from pathlib import Path

import pytest
import sympy

from conftest import CORPUS, EXAMPLES, flowstar_binary, needs_corpus, needs_flowstar
from cyphy import api
from cyphy.semantics.dynamics.closed_form import inline_definitions
from cyphy.cli import main

PENDULUM = """
import physmod::math::*
import physmod::joints::Revolute

pmodel P {
    local link Base {
        def { inertial information { mass 2.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Hinge = Revolute {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0 }
        def { BOB }
    }
}
"""
SDF_DEFAULTS = "inertial information { mass 1.0 inertia matrix " \
    "{ ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } }"


def _pendulum(folder: Path, bob: str) -> Path:
    folder.mkdir()
    (folder / "p.rsm").write_text(PENDULUM.replace("BOB", bob))
    return folder


def test_without_the_option_a_massless_moving_link_is_an_error(tmp_path, capsys):
    folder = _pendulum(tmp_path / "p", "")
    assert main(["solve", str(folder)]) == 1
    err = capsys.readouterr().err
    assert "E-DYNAMICS" in err and "P::Bob has no mass properties" in err
    assert "W-DEFAULT-INERTIAL" not in err


def test_sdf_defaults_give_the_equation_of_the_written_out_defaults(tmp_path, capsys):
    bare = _pendulum(tmp_path / "bare", "")
    written = _pendulum(tmp_path / "written", SDF_DEFAULTS)
    assert main(["solve", str(bare), "--default-inertial", "sdf"]) == 0
    err = capsys.readouterr().err
    # One warning, for Bob only (Base has its own inertial), at Bob's declaration.
    assert err.count("W-DEFAULT-INERTIAL") == 1
    assert "p.rsm:14:5: WARNING W-DEFAULT-INERTIAL: link P::Bob has no inertial " \
           "information: SDF's defaults apply (mass 1 kg" in err
    solved = [api.solve([bare], api.SolveOptions(closed_form=False, default_inertial="sdf")),
              api.solve([written], api.SolveOptions(closed_form=False))]
    for result in solved:  # the accelerations as one expression, not named definitions
        inline_definitions(result.reduced, result.system)
    defaulted, explicit = (result.reduced for result in solved)
    theta, v, tau = (sympy.Symbol(n, real=True) for n in ("Hinge_theta", "Hinge_v",
                                                            "Hinge_tau"))
    # By hand: 1 kg at 0.5 m below a hinge about y with iyy = 1 about its centre:
    # J = 1 + 1 * 0.5², gravity torque -1 * 9.81 * 0.5 * sin(theta).
    by_hand = (tau - 9.81 * 0.5 * sympy.sin(theta)) / 1.25
    values = {theta: 0.7, tau: 0.3, v: 1.1}
    for reduced in (defaulted, explicit):
        assert float(reduced.rhs["Hinge_v"].subs(values)) == pytest.approx(
            float(by_hand.subs(values)), rel=1e-12)


def test_a_scenario_key_takes_only_sdf(tmp_path, capsys):
    text = (EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("horizon = 2.0", 'horizon = 2.0\ndefault_inertial = "urdf"'))
    assert main(["gen", str(EXAMPLES / "dcmotor"), "--flowstar", "--scenario", str(bad),
                 "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "E-SCENARIO" in err and "'default_inertial' must be one of 'sdf'" in err
    assert not (tmp_path / "out").exists()
    with pytest.raises(SystemExit) as exit_:
        main(["solve", str(EXAMPLES / "dcmotor"), "--default-inertial", "urdf"])
    assert exit_.value.code == 2 and "invalid choice: 'urdf'" in capsys.readouterr().err


# ----------------------------------------------------------------------------- the corpus

MARXBOT = CORPUS / "marXbot"
SCENARIO = EXAMPLES / "marxbot" / "corpus_smovement.toml"


@needs_corpus
def test_the_corpus_marxbot_solves_with_sdf_defaults_only(capsys):
    assert main(["solve", str(MARXBOT)]) == 1
    assert "E-DYNAMICS" in capsys.readouterr().err
    assert main(["solve", str(MARXBOT), "--default-inertial", "sdf"]) == 0
    out, err = capsys.readouterr()
    # The links without mass of the whole marXbot (base, tracks, wheels, scanner core).
    assert err.count("W-DEFAULT-INERTIAL") == 6
    # Each hinge turns its wheel (SDF's 1 kg, 1 kg m² about the axis) with its effort; the
    # right one (about -y) feels no gravity torque: its acceleration is its effort.
    assert "LHinge_v' = LHinge_qdd" in out and "RHinge_v' = RHinge_qdd" in out
    assert "RHinge_qdd = RHinge_u/RHinge_D" in out
    assert "RHinge_D = 1.0\n" in out and "RHinge_u = RHinge_tau\n" in out


def _csv(text: str) -> dict:
    import csv
    import io

    import numpy as np

    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


@needs_corpus
def test_the_corpus_marxbot_under_its_smovement_simulates_the_machines_phases(capsys):
    import numpy as np

    assert main(["simulate", str(MARXBOT), "--scenario", str(SCENARIO), "--samples",
                 "26"]) == 0
    c = _csv(capsys.readouterr().out)
    t, d = c["t"], c["Proximity1_distance"]
    dl, dr = c["LMotor_e"] + c["LMotor_av"], c["RMotor_e"] + c["RMotor_av"]  # demands
    cruise, turn = 0.1 / 0.025025, 0.5 * 0.06 / 2 / 0.025025  # move(lv, 0), move(0, av)
    # Hand-computed as for avoid_obstacle.toml (the same mapping numbers): the first cycle
    # with the distance at most 0.09 m is t = 1.8 (stop()), Turning from the next cycle.
    stop = t[np.isclose(t, np.round(t, 1)) & (d <= 0.09)][0]
    assert stop == pytest.approx(1.8)
    assert np.allclose(dl[t < stop - 1e-9], cruise) and np.allclose(dr[t < stop - 1e-9], cruise)
    assert dl[np.isclose(t, stop)][0] == pytest.approx(0.0)
    turning = t > stop + 0.1 + 1e-9
    assert np.allclose(dl[turning], turn) and np.allclose(dr[turning], -turn)
    # The hinges' equations of motion are in, with nothing driving them: the wheels rest.
    assert np.all(c["LHinge_v"] == 0) and np.all(c["RHinge_theta"] == 0)
    assert d.min() > 0.05  # the property reach proves


@needs_corpus
def test_the_corpus_marxbot_scenario_exports_the_hinges_motion(tmp_path, capsys):
    assert main(["gen", str(MARXBOT), "--flowstar", "--scenario", str(SCENARIO), "-o",
                 str(tmp_path)]) == 0
    model = (tmp_path / "corpus_smovement.model").read_text()
    # SMovement's automaton, in the corpus's state names: cruise (DMoving), stop (Waiting),
    # six cycles of turning until since(MBC) >= PI/av = 6.28, cruise again.
    jumps = [line.strip() for line in model.splitlines() if "->" in line]
    turning = ["DTurning"] + [f"DTurning_{k}" for k in range(2, 7)]
    assert jumps == ["DMoving -> Waiting", "DMoving -> DMoving", "Waiting -> DTurning",
                     *[f"{a} -> {b}" for a, b in zip(turning, turning[1:])],
                     "DTurning_6 -> DMoving"]
    # The scenario's [consts] give PI = 3.141592653589793, and a given value wins over the
    # declared one (common.pm: PI = 3.1415): the tracks' roll of PI is exact and both hinges'
    # bodies sit on their axes, so gravity exerts no torque on either.
    assert "RHinge_v' = 0" in model and "LHinge_v' = 0" in model
    # With the model's own PI = 3.1415, LHinge's body's default mass sits 2.8e-6 m off its
    # axis (1 kg · 9.81 m/s² · 2.78e-6 m over the unit inertia): a gravity torque, kept.
    scenario = tmp_path / "pi_as_declared.toml"
    scenario.write_text(SCENARIO.read_text().replace("PI = 3.141592653589793", "PI = 3.1415"))
    assert main(["gen", str(MARXBOT), "--flowstar", "--scenario", str(scenario), "-o",
                 str(tmp_path / "declared")]) == 0
    declared = (tmp_path / "declared" / "pi_as_declared.model").read_text()
    assert "LHinge_v' = -2.726795143679001e-05*sin(LHinge_theta)" in declared
    assert "RHinge_v' = 0" in declared


@needs_corpus
@needs_flowstar
def test_real_flowstar_proves_the_corpus_marxbot_under_its_smovement(tmp_path, capsys):
    """RoboTool's marXbot under its own machine keeps 5 cm from the obstacle: SAFE with the
    real Flow* (about 55 s of Flow* on two shared cores)."""
    rc = main(["reach", str(MARXBOT), "--scenario", str(SCENARIO), "-o", str(tmp_path / "out"),
               "--flowstar-bin", str(flowstar_binary())])
    out = capsys.readouterr()
    assert rc == 0 and out.out.startswith("SAFE: Flow* proved the initial set safe"), \
        out.out + out.err


@needs_corpus
def test_gen_isabelle_takes_the_option_and_gen_sdf_refuses_it(tmp_path, capsys):
    """The command a user types: the corpus marXbot's axiomatic theory needs the hinges'
    equations of motion, so without the option nothing is written, with it the theory is;
    the geometric exports refuse the option (a usage error, exit 2)."""
    out = tmp_path / "ax"
    common = ["gen", str(MARXBOT), "--isabelle", "--isabelle-dialect", "axiomatic", "-o"]
    assert main([*common, str(out)]) == 1
    assert "E-DYNAMICS" in capsys.readouterr().err and not out.exists()
    assert main([*common, str(out), "--default-inertial", "sdf"]) == 0
    assert "W-DEFAULT-INERTIAL" in capsys.readouterr().err
    theory = (out / "marXbotBase_AxCyPhyCircus.thy").read_text()
    assert "LHinge_v" in theory and "RHinge_tau" in theory
    assert main(["gen", str(MARXBOT), "--sdf", "--default-inertial", "sdf", "-o",
                 str(tmp_path / "sdf")]) == 2
    assert "--default-inertial is an option of" in capsys.readouterr().err
