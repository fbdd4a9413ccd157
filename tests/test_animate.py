"""``cyphy animate``: the generated theories, run from their text alone, give the
trajectories of ``cyphy simulate`` (an independent path: the model's equations and the
machine's interpreter, never the theory) under the same machine, inputs and constants; theory
mutants that drop a call's effect or leave Init open make the comparison fail; bad input is a
clear error with exit 2 (1 for a theory that cannot be run), never a traceback."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES
from cyphy import api
from cyphy.cli import main
from cyphy.verify.animate.animation import Animation, animate
from cyphy.verify.animate.errors import AnimateError

Series = dict[str, np.ndarray]

DCMOTOR = EXAMPLES / "dcmotor"
MARXBOT = EXAMPLES / "marxbot"
#: The dcmotor's whole_bench.toml: the obstacle from 3.05 m (its [init] interval's midpoint)
#: at 2 m/s, one d-model time unit 0.1 s.
DC_INPUTS = {"Range_distance": "3.05 - 2*t"}
DC_CONSTS = {"tscale": 0.1}
#: avoid_obstacle.toml: its [consts] under the theory's names, the obstacle from 0.255 m
#: approached at the wheels' mean travel (r/2 = 0.0125125 m per rad of each motor's angle).
MOTOR = {"R": 1.0, "L": 0.1, "Kt": 0.05, "Ke": 0.05, "b": 0.01, "J": 0.01, "Kp": 2.0,
         "Ki": 5.0, "Kd": 0.0}
MX_CONSTS = {**{f"{m}_{k}": v for m in ("LMotor", "RMotor") for k, v in MOTOR.items()},
             "Proximity1_a": 0.3, "Proximity1_b": 0.01, "Proximity1_c": 0.0, "tscale": 0.1}
MX_INPUTS = {"Proximity1_distance": "0.255 - 0.0125125*(LMotor_theta + RMotor_theta)"}


def _generate(paths: list[Path], folder: Path) -> Path:
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions())
    assert not generated.report.has_errors, generated.report.diagnostics
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in generated.files.items():
        (folder / name).write_text(text)
    return folder


@pytest.fixture(scope="module")
def sessions(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("animate")
    return {"dcmotor": _generate([DCMOTOR], root / "dcmotor"),
            "marxbot": _generate([MARXBOT / "Mapping.rsm"], root / "marxbot")}


def _simulate(model: Path, scenario: Path, t_end: float) -> dict[str, np.ndarray]:
    """``cyphy simulate``'s trajectories (JSON on stdout, captured)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["simulate", str(model), "--scenario", str(scenario), "--t-end",
                     str(t_end), "--format", "json", "-q"]) == 0
    doc = json.loads(out.getvalue())
    return {"t": np.array(doc["t"]), **{k: np.array(v) for k, v in doc["columns"].items()}}


def _column(animation: Animation, name: str) -> np.ndarray:
    i = animation.columns.index(name)
    return np.array([row[i] for row in animation.rows])


def _common(animation: Animation,
            simulated: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the instants both sampled (simulate samples every cycle)."""
    ours = _column(animation, "t")
    pairs = [(i, j) for i, t in enumerate(ours)
             for j in np.flatnonzero(np.isclose(simulated["t"], t, rtol=0, atol=1e-9))[:1]]
    assert len(pairs) >= 20
    return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


def _within_one_percent(animation: Animation, simulated: dict[str, np.ndarray],
                        names: list[str]) -> list[str]:
    """The speeds that differ from simulate's by more than 1% of their range at an instant
    both sampled."""
    mine, theirs_at = _common(animation, simulated)
    bad = []
    for name in names:
        ours = _column(animation, name)[mine]
        theirs = simulated[name][theirs_at]
        scale = max(float(np.max(np.abs(theirs))), 1e-9)
        if float(np.max(np.abs(ours - theirs))) > 0.01 * scale:
            bad.append(name)
    return bad


@pytest.fixture(scope="module")
def dc_simulated() -> dict[str, np.ndarray]:
    return _simulate(DCMOTOR, DCMOTOR / "whole_bench.toml", 2.0)


@pytest.fixture(scope="module")
def mx_simulated() -> dict[str, np.ndarray]:
    return _simulate(MARXBOT, MARXBOT / "avoid_obstacle.toml", 9.0)


@pytest.fixture(scope="module")
def dc_animated(sessions: dict[str, Path]) -> Animation:
    return animate(sessions["dcmotor"], 2.0, DC_INPUTS, DC_CONSTS, samples=41)


@pytest.fixture(scope="module")
def mx_animated(sessions: dict[str, Path]) -> Animation:
    return animate(sessions["marxbot"], 9.0, MX_INPUTS, MX_CONSTS, samples=181)


def test_dcmotor_theory_gives_simulates_trajectories(dc_animated: Animation,
                                                     dc_simulated: Series) -> None:
    assert _within_one_percent(dc_animated, dc_simulated,
                               ["Motor_av", "Motor_i", "Shaft_v"]) == []


def test_dcmotor_cruises_then_the_machine_stops_it_when_near_occurs(dc_animated: Animation) -> None:
    t, av = _column(dc_animated, "t"), _column(dc_animated, "Motor_av")
    mode = _column(dc_animated, "DCMotorSoftware_mode")
    cruise = (t > 0.7) & (t < 1.0)
    assert np.all(np.abs(av[cruise] - 10.0) < 0.5)  # PI control holds 10 rad/s
    near = [e for e in dc_animated.events if e[1] == "registerRead_near" and e[2] is True]
    stop = [e for e in dc_animated.events if e[1] == "registerWrite_stop"]
    # the distance 3.05 - 2t reaches 1 m at t = 1.025: the first reading at or below is 1.1
    assert near and near[0][0] == pytest.approx(1.1)
    assert stop and stop[0][0] == pytest.approx(1.1)
    assert not [e for e in dc_animated.events if e[1] == "registerWrite_drive" and e[0] > 1.05]
    assert np.all(mode[t > 1.15] == 1) and np.all(mode[t < 1.05] == 0)
    assert np.all(_column(dc_animated, "Motor_das")[t > 1.15] == 0.0)


def test_marxbot_theory_gives_simulates_trajectories(mx_animated: Animation,
                                                     mx_simulated: Series) -> None:
    assert _within_one_percent(mx_animated, mx_simulated, ["LMotor_av", "RMotor_av"]) == []


def test_marxbot_stops_before_the_obstacle_and_turns(mx_animated: Animation) -> None:
    t = _column(mx_animated, "t")
    left, right = _column(mx_animated, "LMotor_av"), _column(mx_animated, "RMotor_av")
    distance = _column(mx_animated, "Proximity1_distance")
    assert np.min(distance) > 0.05  # it stops short of the obstacle
    stop = [e for e in mx_animated.events if e[1] == "registerWrite_stop"]
    assert stop and stop[0][0] == pytest.approx(1.8)
    turning = (t > 4.0) & (t < 8.0)  # move(0, 0.5): the wheels opposite, ±av*L/(2r)
    assert np.allclose(left[turning], 0.5 * 0.06 / (2 * 0.025025), rtol=0.01)
    assert np.allclose(right[turning], -0.5 * 0.06 / (2 * 0.025025), rtol=0.01)


def _mutant(folder: Path, tmp: Path, old: str, new: str) -> Path:
    """A copy of the session with ``old`` replaced by ``new`` (once, in one theory)."""
    out = tmp / f"mutant-{folder.name}"
    out.mkdir()
    changed = 0
    for f in folder.iterdir():
        text = f.read_text()
        if f.suffix == ".thy" and old in text:
            assert text.count(old) == 1
            text = text.replace(old, new)
            changed += 1
        (out / f.name).write_text(text)
    assert changed == 1, "the mutation found nothing to change"
    return out


def test_a_call_without_its_effect_fails_the_comparison(sessions: dict[str, Path],
                                                        dc_simulated: Series,
                                                        tmp_path: Path) -> None:
    mutant = _mutant(sessions["dcmotor"], tmp_path,
                     "(registerWrite_drive?(w) \\<^bold>\\<rightarrow> (DriveCall w))",
                     "(registerWrite_drive?(w) \\<^bold>\\<rightarrow> Skip)")
    animation = animate(mutant, 2.0, DC_INPUTS, DC_CONSTS, samples=41)
    assert "Motor_av" in _within_one_percent(animation, dc_simulated, ["Motor_av"])
    assert np.all(_column(animation, "Motor_av") == 0.0)  # the motor never moves


def test_init_left_open_fails_the_comparison(sessions: dict[str, Path], tmp_path: Path) -> None:
    mutant = _mutant(sessions["dcmotor"], tmp_path,
                     "Shaft_v, Motor_i, Motor_theta, Motor_av, Motor_e_int) :=\\<^sub>C "
                     "(0, 0, 0, 0, 0, 0, 0, 0)",
                     "Shaft_v, Motor_theta, Motor_av, Motor_e_int) :=\\<^sub>C "
                     "(0, 0, 0, 0, 0, 0, 0)")
    with pytest.raises(AnimateError) as err:
        animate(mutant, 2.0, DC_INPUTS, DC_CONSTS, samples=11)
    assert err.value.code == "E-ANIMATE-EVOLVE" and err.value.status == 1
    assert "Motor_i" in err.value.message and "Init leaves" in err.value.message


def _cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    try:
        code = main(["animate", *argv])
    except SystemExit as stop:  # argparse's own refusals (exit 2)
        code = int(stop.code or 0)
    got = capsys.readouterr()
    return code, got.out, got.err


def test_csv_json_and_plot_outputs(sessions: dict[str, Path], tmp_path: Path,
                                   capsys: pytest.CaptureFixture[str]) -> None:
    out, png = tmp_path / "a.json", tmp_path / "a.png"
    code, stdout, _err = _cli(capsys, str(sessions["dcmotor"]), "--t-end", "0.3",
                              "--input", "Range_distance=3-2*t", "--const", "tscale=0.1",
                              "--format", "json", "-o", str(out), "--plot", str(png))
    assert code == 0 and stdout == ""
    doc = json.loads(out.read_text())
    assert doc["composition"] == "BenchMapping" and doc["columns"][0] == "t"
    assert [e["channel"] for e in doc["events"][:3]] == ["registerRead_near",
                                                         "registerWrite_drive", "tock"]
    assert doc["events"][1]["value"] == 10.0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, stdout, _err = _cli(capsys, str(sessions["dcmotor"]), "--t-end", "0.3",
                              "--input", "Range_distance=3-2*t", "--const", "tscale=0.1",
                              "--samples", "4")
    lines = stdout.splitlines()
    assert code == 0 and len(lines) == 5 and lines[0].endswith(",events")
    assert "registerWrite_drive.10.0" in lines[1]
    again = _cli(capsys, str(sessions["dcmotor"]), "--t-end", "0.3", "--input",
                 "Range_distance=3-2*t", "--const", "tscale=0.1", "--samples", "4")
    assert again[1] == stdout  # byte-identical across runs


@pytest.mark.parametrize("argv, status, words", [
    (["{tmp}"], 2, "no ROOT file"),
    (["{dc}", "--input", "Range_distanse=1"], 2, "did you mean 'Range_distance'"),
    (["{dc}", "--const", "tscale=nan"], 2, "not a finite number"),
    (["{dc}", "--t-end", "0"], 2, "above 0"),
    (["{dc}", "--t-end", "inf"], 2, "not a finite number"),
    (["{dc}", "--samples", "100000000", "--const", "tscale=0.1"], 2, "give at most --samples"),
    (["{dc}", "--const", "tscal=0.1"], 2, "did you mean 'tscale'?"),
    (["{dc}", "--input", "Range_distance=1/0"], 2, "not a finite value"),
    (["{dc}", "--input", "Motor_av=1", "--const", "tscale=0.1"], 2, "not a world input"),
    (["{dc}", "--input", "Range_distance=3-2*t"], 1, "tscale"),
    (["{dc}", "--input", "Range_distance=1/(t-0.05)", "--const", "tscale=0.1"], 1,
     "E-ANIMATE-VALUE"),
    (["{dc}", "--const", "tscale=0.1", "--const", "cycle=2"], 2, "contradict an axiom"),
])
def test_bad_input_is_a_clear_error(sessions: dict[str, Path], tmp_path: Path,
                                    capsys: pytest.CaptureFixture[str], argv: list[str],
                                    status: int, words: str) -> None:
    out = tmp_path / "out.csv"
    argv = [a.format(tmp=tmp_path, dc=sessions["dcmotor"]) for a in argv] + ["-o", str(out)]
    code, stdout, err = _cli(capsys, *argv)
    assert (code, stdout) == (status, ""), err
    assert words in err and "Traceback" not in err
    assert not out.exists()  # no partial output


Capsys = pytest.CaptureFixture[str]


def test_a_theory_it_cannot_read_is_reported_with_its_line(sessions: dict[str, Path],
                                                           tmp_path: Path,
                                                           capsys: Capsys) -> None:
    mutant = _mutant(sessions["dcmotor"], tmp_path, '"StopCall = (',
                     '"StopCall = ((Motor_das ## 1) ;; ')
    thy = mutant / "DCMotorBase_CyPhyCircus.thy"
    line = next(n for n, text in enumerate(thy.read_text().splitlines(), 1) if "##" in text)
    code, stdout, err = _cli(capsys, str(mutant), "--const", "tscale=0.1")
    assert (code, stdout) == (2, "")
    assert f"{thy}:{line}: ERROR E-ANIMATE-READ" in err


def test_the_animator_reads_the_theory_not_the_model() -> None:
    """``cyphy/verify/animate`` imports no part of cyphy that reads or elaborates models: its
    only inputs are the theory's text (read with check-theory's reader) and the options."""
    import ast
    folder = Path(__file__).resolve().parent.parent / "cyphy" / "verify" / "animate"
    allowed = ("cyphy.verify.animate", "cyphy.verify.theory", "cyphy.diagnostics",
               "cyphy.backends.plotting", "cyphy.limits",  # limits: the memory budget
               "cyphy.constant_keys",  # how a [consts] key names a constant
               "cyphy.verify.flowstar.scenario")  # --scenario's TOML reader: values only
    used = set()
    for path in folder.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module:
                used.add(node.module)
            elif isinstance(node, ast.Import):
                used.update(a.name for a in node.names)
    ours = {m for m in used if m.startswith("cyphy")}
    assert ours and all(m.startswith(allowed) for m in ours), sorted(ours)


# --scenario: the scenario's values, never its model ------------------------------------------

def _animate_cli(capsys: Capsys, *argv: str) -> Animation:
    """The CLI's JSON output as an :class:`Animation` (what the scenario gave went through it)."""
    code, stdout, err = _cli(capsys, *argv, "--format", "json")
    assert code == 0, err
    doc = json.loads(stdout)
    return Animation(doc["columns"], doc["rows"], [], doc["composition"])


def test_the_dcmotor_scenario_gives_simulates_trajectories(sessions: dict[str, Path],
                                                           dc_simulated: Series,
                                                           capsys: Capsys) -> None:
    """whole_bench.toml alone: its horizon (2 s), tscale (0.1) and the obstacle from its
    [init] interval's midpoint at its [environment] rate; no option."""
    animation = _animate_cli(capsys, str(sessions["dcmotor"]), "--scenario",
                             str(DCMOTOR / "whole_bench.toml"), "--samples", "41")
    assert _column(animation, "t")[-1] == pytest.approx(2.0)
    assert _within_one_percent(animation, dc_simulated,
                               ["Motor_av", "Motor_i", "Shaft_v"]) == []


def test_the_marxbot_scenario_gives_its_constants(sessions: dict[str, Path],
                                                  mx_simulated: Series,
                                                  capsys: Capsys) -> None:
    """avoid_obstacle.toml's 12 [consts] (per block: both motors take SpeedControlMotor's)
    and tscale; the distance, whose rate depends on the state, from --input."""
    animation = _animate_cli(capsys, str(sessions["marxbot"]), "--scenario",
                             str(MARXBOT / "avoid_obstacle.toml"), "--t-end", "9", "--input",
                             "Proximity1_distance=" + MX_INPUTS["Proximity1_distance"],
                             "--samples", "181")
    assert _within_one_percent(animation, mx_simulated, ["LMotor_av", "RMotor_av"]) == []


def test_options_win_over_the_scenario(sessions: dict[str, Path], capsys: Capsys) -> None:
    """--t-end over the horizon; --input over [environment]: an obstacle already near stops
    the motor in the first cycle, where the scenario's drives it for a second."""
    argv = [str(sessions["dcmotor"]), "--scenario", str(DCMOTOR / "whole_bench.toml"),
            "--t-end", "0.5", "--samples", "6"]
    driven = _animate_cli(capsys, *argv)
    stopped = _animate_cli(capsys, *argv, "--input", "Range_distance=0.5")
    assert _column(driven, "t")[-1] == pytest.approx(0.5)
    assert _column(driven, "Motor_av")[-1] > 1.0
    assert abs(_column(stopped, "Motor_av")[-1]) < 0.5 * _column(driven, "Motor_av")[-1]
    code, _out, _err = _cli(capsys, *argv, "--const", "tscale=0.2", "--samples", "2",
                            "--format", "json")
    assert code == 0


@pytest.mark.parametrize("scenario, status, words", [
    ("horizon = [1", 2, "E-ANIMATE-SCENARIO"),
    ('model = "M"\nhorizon = 1\ntscale = 0.1\n[init]\nRange_distance = 3\n'
     '[environment]\nRange_distance = "-Motor_av"\n', 2, "--input Range_distance=EXPR"),
])
def test_a_scenario_it_cannot_use_is_a_clear_error(sessions: dict[str, Path], tmp_path: Path,
                                                   capsys: Capsys, scenario: str, status: int,
                                                   words: str) -> None:
    toml = tmp_path / "s.toml"
    toml.write_text(scenario)
    code, stdout, err = _cli(capsys, str(sessions["dcmotor"]), "--scenario", str(toml))
    assert (code, stdout) == (status, "") and words in err and "Traceback" not in err


# the axiomatic dialect: the same executor, the axiomatic checker's reader ------------------

@pytest.fixture(scope="module")
def ax_sessions(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("animate_ax")
    out = {}
    for key, paths in (("dcmotor", [DCMOTOR]), ("marxbot", [MARXBOT / "Mapping.rsm"])):
        generated = api.generate_isabelle(paths, api.SemanticsGenOptions(dialect="axiomatic"))
        assert not generated.report.has_errors, generated.report.diagnostics
        (root / key).mkdir()
        for name, text in generated.files.items():
            (root / key / name).write_text(text)
        out[key] = root / key
    return out


def test_the_axiomatic_dcmotor_gives_simulates_trajectories(ax_sessions: dict[str, Path],
                                                           dc_simulated: Series) -> None:
    """Range_distance from --input: its value at the start, then its rate (d/dt of the
    expression) chosen before each Evolve, as the theory's cSpec of the rates allows."""
    animation = animate(ax_sessions["dcmotor"], 2.0, DC_INPUTS, DC_CONSTS, samples=41)
    assert _within_one_percent(animation, dc_simulated,
                               ["Motor_av", "Motor_i", "Shaft_v"]) == []
    stops = [t for t, c, _v in animation.events if c == "registerWrite_stop"]
    assert stops and 0.9 <= stops[0] <= 1.2  # near once the obstacle is within 1 m


def test_the_axiomatic_marxbot_gives_simulates_trajectories(ax_sessions: dict[str, Path],
                                                           mx_simulated: Series) -> None:
    animation = animate(ax_sessions["marxbot"], 9.0, MX_INPUTS, MX_CONSTS, samples=181)
    assert _within_one_percent(animation, mx_simulated, ["LMotor_av", "RMotor_av"]) == []
    # the world inputs no --input gives start at 0 and keep still (named on stderr)
    assert "Acc_acceleration_1" in animation.held
    assert "Proximity1_distance" not in animation.held


def test_an_axiomatic_call_without_its_effect_fails_the_comparison(
        ax_sessions: dict[str, Path], dc_simulated: Series, tmp_path: Path) -> None:
    mutant = _mutant(ax_sessions["dcmotor"], tmp_path, "(((Motor_das = 0)))",
                     "(((Motor_das = 10.0)))")  # stop() leaves the cruise set-point
    animation = animate(mutant, 2.0, DC_INPUTS, DC_CONSTS, samples=41)
    assert "Motor_av" in _within_one_percent(animation, dc_simulated, ["Motor_av"])


def test_an_axiomatic_construct_it_cannot_run_is_reported_with_its_line(
        ax_sessions: dict[str, Path], tmp_path: Path, capsys: Capsys) -> None:
    mutant = _mutant(ax_sessions["dcmotor"], tmp_path, "((StopFromDModel ;; Y)",
                     "((StopFromDModel \\<interleave> Y)")
    thy = next(mutant.glob("*.thy"))
    code, stdout, err = _cli(capsys, str(mutant), "--const", "tscale=0.1", "--input",
                             "Range_distance=3-2*t")
    assert (code, stdout) == (2, ""), err
    # the line is the definition last entered (DriveFromDModel's, run by the choice)
    assert f"{thy}:" in err and ": ERROR E-ANIMATE-UNSUPPORTED" in err
    assert "the action interleave" in err and "Traceback" not in err


def test_an_axiomatic_input_must_be_a_world_input(ax_sessions: dict[str, Path],
                                                  capsys: Capsys) -> None:
    code, stdout, err = _cli(capsys, str(ax_sessions["dcmotor"]), "--input", "Motor_av=1",
                             "--const", "tscale=0.1")
    assert (code, stdout) == (2, "") and "not a world input" in err


def test_the_axiomatic_marxbot_runs_from_its_scenario_alone(ax_sessions: dict[str, Path],
                                                           mx_simulated: Series,
                                                           capsys: Capsys) -> None:
    """The axiomatic theory moves the distance at a rate it chooses before each Evolve: the
    scenario's rate over the state (the wheels' speeds) is that rate, no --input needed."""
    animation = _animate_cli(capsys, str(ax_sessions["marxbot"]), "--scenario",
                             str(MARXBOT / "avoid_obstacle.toml"), "--t-end", "9",
                             "--samples", "181")
    assert _within_one_percent(animation, mx_simulated, ["LMotor_av", "RMotor_av"]) == []


def test_scenario_consts_name_constants_as_simulate_does() -> None:
    """A [consts] key sets the theory constants ``simulate`` would set: by qualified or
    definition-qualified name or a ``::`` suffix of either, never another block's constant
    that only shares the last segment (the names.tsv rows below are made up)."""
    from cyphy.verify.animate.scenario import _targets

    rows = [("R::Core::LMotor::R", "LMotor_R", "SpeedControlMotor::R"),
            ("R::Core::RMotor::R", "RMotor_R", "SpeedControlMotor::R"),
            ("R::Core::Heater::R", "Heater_R", "Resistor::R"),
            ("R::Core::LMotor.das", "LMotor_das", "")]
    assert _targets("SpeedControlMotor::R", rows) == ["LMotor_R", "RMotor_R"]
    assert _targets("Resistor::R", rows) == ["Heater_R"]
    assert _targets("LMotor::R", rows) == ["LMotor_R"]
    assert _targets("R", rows) == ["Heater_R", "LMotor_R", "RMotor_R"]
    assert _targets("Heater_R", rows) == ["Heater_R"]
    assert _targets("Other::R", rows) == [] and _targets("das", rows) == []
