"""Decisive Flow* verdicts (issue 28): jumps without duplicates, exports that keep
precision, falsification before and after Flow*, bounded settings, verdicts for all time.
Known answers come from brute-force enumeration, from arithmetic on Flow*'s steps, and from
trajectories worked out independently (closed forms, SciPy) of the automaton cyphy writes."""

from __future__ import annotations

import itertools
import re
import subprocess
from pathlib import Path

import pytest

from conftest import EXAMPLES, flowstar_binary, needs_flowstar
from flowstar_scenarios import (CRUISE_COAST, CRUISE_COAST_STOP, MOTOR_HEAD, controller,
                                sampled_stop, scenario_problem)
from cyphy.diagnostics import Report
from cyphy.verify.flowstar.build import build_problem
from cyphy.verify.flowstar.export import render
from cyphy.verify.flowstar.guards import targets
from cyphy.verify.flowstar.scenario import load_scenario
from cyphy.verify.flowstar.syntax import parse_model

DCMOTOR = EXAMPLES / "dcmotor"

# Re-issue drive(8) while near; the transition to slow on the same event comes second, so
# it is never taken (the first `when` that holds wins): every cycle stays in fast.
SELF = MOTOR_HEAD + controller("fast", {"fast": ["drive(8)"], "slow": ["drive(2)"]},
                         [("fast", "fast", "near"), ("fast", "slow", "near"),
                          ("slow", "fast", "near")]) + """[unsafe]
constraints = ["Motor_av >= 20"]
"""


def _problem(tmp_path: Path, text: str, name: str = "s"):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return scenario_problem(DCMOTOR, path)


def _flowpipes(text: str, cwd: Path) -> int:
    proc = subprocess.run([str(flowstar_binary())], input=text, capture_output=True,
                          text=True, cwd=cwd, timeout=300)
    out = re.sub(r"\x1b\[[0-9;]*m", "", proc.stdout)
    m = re.search(r"Computation completed: (\d+) flowpipe", out)
    assert m, out + proc.stderr
    return int(m.group(1))


# --------------------------------------------------------------------------- 1. jumps

@pytest.mark.parametrize("transitions", [
    [("B", (("a", False), ("b", False)))],  # stay: not (a and b), once overlapping cubes
    [("A", (("n", False),)), ("B", (("f", False),))],  # a self-transition before another
    [("B", (("a", False),)), ("C", (("b", False),)), ("B", (("c", True),))],
    [("A", (("a", True), ("b", False))), ("C", (("a", False),)), ("A", (("b", True),))],
])
def test_guards_are_disjoint_and_follow_the_first_transition_that_holds(transitions):
    """Brute force over every combination of the events: exactly one cube of one target
    holds, and that target is the first transition's whose literals hold (else A stays)."""
    events = sorted({e for _, lits in transitions for e, _ in lits})
    out = targets("A", transitions)
    assert len({t for t, _ in out}) == len(out)  # one guard per target
    for combo in itertools.product((False, True), repeat=len(events)):
        value = dict(zip(events, combo))
        expected = next((t for t, lits in transitions
                         if all(value[e] != neg for e, neg in lits)), "A")
        holding = [t for t, cubes in out for cube in cubes
                   if all(value[e] != neg for e, neg in cube)]
        assert holding == [expected], (combo, out)


def test_a_self_transition_and_the_stay_are_one_unguarded_jump(tmp_path):
    problem = _problem(tmp_path, SELF.format(horizon=0.5, av=0, distance="[0.95, 1.05]",
                                             env="0"))
    model = parse_model(render(problem, "self"))
    out_of_fast = [j for j in model.jumps if j.source == "fast"]
    assert [(j.target, len(j.guard)) for j in out_of_fast] == [("fast", 1)]  # timer only


@needs_flowstar
def test_flowstar_computes_one_path_on_a_machine_with_a_self_transition(tmp_path):
    """The range straddles the event's threshold: with a duplicate self-jump (`near` and
    the stay's `not near` both admit the enclosure) Flow* doubled its flowpipes at every
    cycle (1112 flowpipes over 0.5 s, 94 s). One path is 5 cycles of 11 flowpipes (10
    steps of 0.01 s and the step ending on the guard `timer = 0.1`) and the last one."""
    problem = _problem(tmp_path, SELF.format(horizon=0.5, av=0, distance="[0.95, 1.05]",
                                             env="0"))
    assert _flowpipes(render(problem, "self"), tmp_path) == 5 * 11 + 1


# --------------------------------------------------------------------------- 3. falsification

# The obstacle approaches at 2 m/s whatever the controller does: d(t) = d0 - 2 t. It comes
# within 0.02 m by t = 1 exactly when d0 <= 2.02: the lowest 5% of [2.0, 2.4].
CORNER = [("Range_distance = [3, 3.1]", "Range_distance = [2.0, 2.4]"),
          ('constraints = ["Motor_av >= 20"]',
           'constraints = ["Range_distance <= 0.02", "t <= 1"]'),
          ("horizon = 2.0", "horizon = 1.2")]


@needs_flowstar
def test_a_violation_from_a_five_percent_corner_is_unsafe_with_its_witness(tmp_path):
    from cyphy.verify.flowstar.check import check

    report = Report()
    scenario = load_scenario(sampled_stop(tmp_path, "corner", *CORNER), report)
    problem, _ = build_problem([DCMOTOR], scenario, report)
    result = check(problem, "corner", str(flowstar_binary()), jobs=1)
    assert result.verdict == "UNSAFE", result.reason
    start, entry = dict(result.witness.start.values), dict(result.witness.entry.values)
    d0, t = start["Range_distance"], result.witness.entry.time
    assert 2.0 <= d0 <= 2.02 and t <= 1.0
    assert entry["Range_distance"] == pytest.approx(d0 - 2 * t, abs=1e-6)  # the closed form
    assert entry["Range_distance"] <= 0.02


@needs_flowstar
def test_without_the_corner_the_same_property_is_not_unsafe(tmp_path, capsys):
    from cyphy.cli import main

    path = sampled_stop(tmp_path, "clear", ("Range_distance = [3, 3.1]",
                                            "Range_distance = [2.03, 2.4]"), *CORNER[1:])
    rc = main(["reach", str(DCMOTOR), "--scenario", str(path), "-o", str(tmp_path / "o"),
               "--flowstar-bin", str(flowstar_binary())])
    out = capsys.readouterr().out
    assert rc == 0 and out.startswith("SAFE"), out  # min d = 0.03 > 0.02


# --------------------------------------------------------------------------- 4. bounds

@pytest.mark.parametrize("edit, message", [
    (("Range_distance = [3, 3.1]", "Range_distance = [-1e308, 1e308]"), "beyond ±1e+15"),
    (("order = 6", "order = 100000"), "'flowstar.order' = 100000 is above 50"),
    (("order = 6", "order = [4, 100000]"), "'flowstar.order' = 100000 is above 50"),
    (("precision = 53", "precision = 100000"), "'flowstar.precision' = 100000 is above"),
    (("cutoff = 1e-12", "cutoff = 1e-12\nmax_jumps = 2147483648"),
     "'flowstar.max_jumps' = 2147483648 is above 2147483647"),
    (("horizon = 2.0", "horizon = 1e9"), "more jumps than Flow* can count"),
])
def test_settings_that_would_overflow_or_run_for_days_are_refused(tmp_path, capsys, edit,
                                                                  message):
    from cyphy.cli import main

    path = sampled_stop(tmp_path, "bad", edit)
    rc = main(["gen", "--flowstar", str(DCMOTOR), "--scenario", str(path), "-o",
               str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 1 and message in err, err  # gen's exit status for a model with errors
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("option", [["--timeout", "nan"], ["--timeout", "inf"],
                                    ["--timeout", "0"], ["--split", "100000"],
                                    ["--split", "0"]])
def test_reach_options_out_of_range_exit_2(tmp_path, capsys, option):
    from cyphy.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["reach", str(DCMOTOR), "--scenario", str(DCMOTOR / "sampled_stop.toml"),
              "-o", str(tmp_path / "o"), *option])
    assert stop.value.code == 2
    assert option[0] in capsys.readouterr().err


@needs_flowstar
def test_the_output_folder_holds_the_models_flowstar_ran(tmp_path, capsys):
    """Two boxes: two runs, each model the box's initial interval, and each one Flow*
    decides the same again when re-run from the file."""
    from cyphy.cli import main
    from cyphy.verify.flowstar.verdict import run_text

    out = tmp_path / "o"
    path = sampled_stop(tmp_path, "two", ("horizon = 2.0", "horizon = 1.3"))
    rc = main(["reach", str(DCMOTOR), "--scenario", str(path), "-o", str(out), "--split", "2",
               "--flowstar-bin", str(flowstar_binary())])
    assert rc == 0, capsys.readouterr()
    runs = sorted((out / "runs").iterdir())
    assert [r.name for r in runs] == ["two.001.model", "two.002.model"]
    boxes = [parse_model(r.read_text()).init["Range_distance"] for r in runs]
    assert boxes == [("3", "3.05"), ("3.05", "3.1")]
    assert run_text(runs[0].read_text(), str(flowstar_binary())).verdict == "SAFE"


# --------------------------------------------------------------------------- 2. precision

DECAY = MOTOR_HEAD.format(horizon=5.0, av="[9.5, 10]", distance=0, env="0").replace(
    "Motor_i = 0", "Motor_i = [0, 0.5]") + """[controller]
initial = "stopped"
[controller.states.stopped]
calls = ["stop()"]
[unsafe]
constraints = ["Motor_av >= 12"]
"""


def _decay_peak() -> float:
    """The largest speed over [0, 5] s from the initial box, from the motor's equations
    written by hand (spec example: i' = 10 (2 (wref - w) + 5 z - i - 0.05 w), w' = -w + 5 i,
    z' = wref - w, wref = 0): linear, so at each time the largest w over the box is the
    sum over coordinates of the larger of the two ends (SciPy's matrix exponential)."""
    import numpy as np
    from scipy.linalg import expm

    a = np.array([[-1.0, 5.0, 0.0], [-20.5, -10.0, 50.0], [-1.0, 0.0, 0.0]])
    box = [(9.5, 10.0), (0.0, 0.5), (0.0, 0.0)]
    peak = -np.inf
    for t in np.linspace(0, 5, 2001):
        row = expm(a * t)[0]
        peak = max(peak, sum(max(r * lo, r * hi) for r, (lo, hi) in zip(row, box)))
    return peak


@needs_flowstar
def test_a_decaying_motor_over_five_seconds_is_safe_with_lti_ode(tmp_path):
    from cyphy.verify.flowstar.check import check
    from cyphy.verify.flowstar.verdict import run_text

    assert _decay_peak() < 12  # the truth: SAFE
    problem = _problem(tmp_path, DECAY, "decay")
    text = render(problem, "decay")
    assert parse_model(text).modes["stopped"].ode == "lti ode"
    result = check(problem, "decay", str(flowstar_binary()), jobs=1)
    assert result.verdict == "SAFE", result.reason
    assert len(result.runs) == 1  # decided by the first run: no ladder, no split
    # the same automaton in poly ode 2: the enclosure explodes before 5 s (issue 28)
    poly = run_text(text.replace("lti ode", "poly ode 2"), str(flowstar_binary()), 300)
    assert poly.verdict != "SAFE"


WAVE = MOTOR_HEAD.format(horizon=1.0, av=0, distance="[1.4, 1.5]",
                   env="-0.5 + 0.3*cos(3*t)").replace("tscale = 0.1", "tscale = 0.05\ncycle = 2") \
    + CRUISE_COAST_STOP + """[unsafe]
constraints = ["Motor_av >= 12"]
"""


@needs_flowstar
def test_a_held_input_beside_cos_3t_is_decided(tmp_path):
    """The actuator input is held in coast; the obstacle moves as -0.5 + 0.3 cos(3t). In
    nonpoly ode Flow* computed no flowpipe at the default step; with cos(3t) as a linear
    state pair every mode is affine and the property is proved. Its truth: the speed peaks
    near 10.0 (independent simulation of the reduced equations, cycle by cycle)."""
    import numpy as np
    from flowstar_sim import simulate_direct

    from cyphy.verify.flowstar.check import check

    problem = _problem(tmp_path, WAVE, "wave")
    assert "cyphy_cos1" in problem.states
    samples = np.linspace(0, 1.0, 401)
    peak = max(np.nanmax(simulate_direct(problem, {
        "Motor_av": 0, "Motor_i": 0, "Motor_int1": 0, "Motor_theta": 0, "Range_distance": d,
        "cyphy_sin1": 0, "cyphy_cos1": 1}, samples)["Motor_av"]) for d in (1.4, 1.45, 1.5))
    assert 9 < peak < 12
    result = check(problem, "wave", str(flowstar_binary()), jobs=1)
    assert result.verdict == "SAFE", result.reason


@needs_flowstar
def test_the_ladder_halves_a_step_too_large_before_splitting(tmp_path):
    """At step 0.05 the example's enclosure of the speed reaches [-13, 27] (UNKNOWN for
    Motor_av >= 20; the simulated range is [-2.5, 13.0]); the first rung, step 0.025,
    proves it, before any split."""
    from cyphy.verify.flowstar.check import check

    report = Report()
    scenario = load_scenario(sampled_stop(tmp_path, "coarse", ("step = 0.01", "step = 0.05"),
                                          ("horizon = 2.0", "horizon = 1.3")), report)
    problem, _ = build_problem([DCMOTOR], scenario, report)
    result = check(problem, "coarse", str(flowstar_binary()), jobs=1)
    assert result.verdict == "SAFE", result.reason
    assert len(result.runs) == 2
    assert result.details[0].startswith("  run: UNKNOWN") and \
        result.details[0].endswith("retried with step 0.025")
    assert "fixed steps 0.025" in result.runs["runs/coarse.002.model"]


# --------------------------------------------------------------------------- 5. for all time

# cruise (drive(8)) and coast (drive(6)) on the range finder's event; the obstacle stays far,
# so every cycle of 0.5 s (cycle = 5) jumps from cruise to cruise. The motor's equilibrium
# under drive(8) is w = 8, i = 1.6, z = 0.4; the box around it below is invariant.
PERIODIC = MOTOR_HEAD.format(horizon=2.0, av="[7.8, 8.2]", distance="[3, 3.1]", env="0").replace(
    "Motor_i = 0", "Motor_i = [1.38, 1.82]").replace("Motor_int1 = 0", "Motor_int1 = [0.36, 0.44]"
    ).replace("tscale = 0.1", "tscale = 0.1\ncycle = 5") + CRUISE_COAST + """[unsafe]
constraints = ["Motor_av >= 20"]
"""


def _maps_box_inside(period: float) -> bool:
    """The independent oracle: the motor's hand-written linear flow (see _decay_peak) with
    wref = 8, shifted to its equilibrium, maps the box's half-widths r strictly inside
    themselves after one period: |expm(A T)| r < r componentwise."""
    import numpy as np
    from scipy.linalg import expm

    a = np.array([[-1.0, 5.0, 0.0], [-20.5, -10.0, 50.0], [-1.0, 0.0, 0.0]])
    assert np.allclose(a @ np.array([8.0, 1.6, 0.4]) + np.array([0, 160.0, 8.0]), 0)
    r = np.array([0.2, 0.22, 0.04])
    return bool(np.all(np.abs(expm(a * period)) @ r < r))


@needs_flowstar
def test_a_periodic_controller_whose_box_recurs_is_safe_for_every_horizon(tmp_path):
    from cyphy.verify.flowstar.check import check, parts
    from cyphy.verify.flowstar.invariant import invariant_model

    assert _maps_box_inside(0.5)
    assert not _maps_box_inside(0.1)  # with a cycle of 0.1 s no such box recurs
    problem = _problem(tmp_path, PERIODIC, "periodic")
    assert invariant_model(problem, "cycle") is None  # the angle grows from its point
    (part,) = parts(problem)  # the speed's part leaves the angle out
    model = parse_model(invariant_model(part, "cycle"))
    # one cycle, then the sinks: 2 faces per coordinate that moves; the distance does not
    assert set(model.unsafe) == {"cruise", "cyphy_elsewhere"} | {
        f"cyphy_face{k}" for k in range(1, 7)}
    result = check(problem, "periodic", str(flowstar_binary()), jobs=1)
    assert result.verdict == "SAFE", result.reason
    assert "for every horizon" in result.reason
    # the obstacle approaching (never near within 2 s): the distance leaves the box, so
    # the same SAFE holds up to the horizon only
    moving = _problem(tmp_path, PERIODIC.replace('Range_distance = "0"',
                                                 'Range_distance = "-0.1"'), "moving")
    result = check(moving, "moving", str(flowstar_binary()), jobs=1)
    assert result.verdict == "SAFE" and "up to the horizon of 2 s" in result.reason, \
        result.reason


@pytest.mark.parametrize("flowpipes, scope", [(10, "up to the horizon of 2 s"),
                                              (60, "for every horizon")])
def test_an_invariant_safe_counts_only_when_the_jumps_reached_the_sinks(tmp_path, flowpipes,
                                                                        scope):
    """A scripted Flow* that says SAFE for every model: with no more flowpipes than one
    cycle of 0.5 s at step 0.01 has (50 steps and the one ending on the guard), no jump
    reached a sink and the invariant's SAFE would be vacuous."""
    import sys

    from cyphy.verify.flowstar.check import check

    script = tmp_path / "flowstar"
    script.write_text(
        f"#!{sys.executable}\nimport sys\nsys.stdin.read()\n"
        f"print('Computation completed: {flowpipes} flowpipe(s) computed.')\n"
        "print('Result of the safety verification on the computed flowpipes: SAFE')\n")
    script.chmod(0o755)
    result = check(_problem(tmp_path, PERIODIC, "periodic"), "periodic", str(script), jobs=1)
    assert result.verdict == "SAFE" and scope in result.reason, result.reason
