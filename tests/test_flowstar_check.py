"""cyphy reach's decisions (issue 17): decomposition into independent parts and splitting of
the initial set (checked by simulating the parts against the whole automaton), the witness
search, and verdicts with the real Flow* on the examples and on scenarios whose answers are
known from simulation (safe, unsafe, borderline, incomplete computation, too few jumps)."""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from cyphy.cli import main
from cyphy.verify.flowstar.check import check, joint, parts, split
from cyphy.verify.flowstar.export import render
from cyphy.verify.flowstar.simulate import BUDGET, Automaton, _Search, find_witness, unsafe_paths
from cyphy.verify.flowstar.syntax import parse_model
from cyphy.verify.flowstar.verdict import decide, model_problems, run_text

from conftest import EXAMPLES, ROOT, flowstar_binary, needs_flowstar

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(ROOT / "benchmarks"))
from flowstar_sim import interpret, simulate_direct  # noqa: E402
from flowstar_scenarios import sampled_stop, scenario_problem  # noqa: E402
from motors import write_motors  # noqa: E402

DCMOTOR = EXAMPLES / "dcmotor"
UNSAFE = ('constraints = ["Motor_av >= 20"]',
          'constraints = ["Motor_av >= 5", "t >= 0.3", "t <= 0.5"]')
BORDER = [("Range_distance = [3, 3.1]", "Range_distance = [3.00001, 3.1]"),
          ('constraints = ["Motor_av >= 20"]',
           'constraints = ["Motor_av <= 5", "t >= 1.15", "t <= 1.2"]')]
SHORT = ("horizon = 2.0", "horizon = 1.3")
# Unsafe only when the stop comes at t = 1.0 exactly (the speed is then between 1 and 5
# rad/s in [1.15, 1.2]; an earlier stop leaves it below 1, a later one above 5): from
# distances in (2.8, 3.0], 1% of the initial interval [0.6, 20.6].
NARROW = [("Range_distance = [3, 3.1]", "Range_distance = [0.6, 20.6]"),
          ('constraints = ["Motor_av >= 20"]',
           'constraints = ["Motor_av >= 1", "Motor_av <= 5", "t >= 1.15", "t <= 1.2"]')]


# --------------------------------------------------------------------------- decomposition

@pytest.fixture(scope="module")
def motors(tmp_path_factory):
    folder = tmp_path_factory.mktemp("motors")
    return folder, write_motors(folder / "either", 2), write_motors(folder / "every", 2,
                                                                     every=True)


def test_each_disjunct_needs_only_its_motor_and_the_range_finder(motors):
    folder, either, _ = motors
    problem = scenario_problem(folder / "either", either)
    disjuncts = problem.disjuncts()
    assert len(disjuncts) == 2
    pieces = [parts(d) for d in disjuncts]
    assert [len(p) for p in pieces] == [1, 1]
    assert pieces[0][0].states == ["Motor1_av", "Motor1_i", "Motor1_int1", "Range_distance"]
    assert pieces[1][0].states == ["Motor2_av", "Motor2_i", "Motor2_int2", "Range_distance"]


def test_a_conjunction_over_independent_motors_has_one_part_per_motor(motors):
    folder, _, every = motors
    pieces = parts(scenario_problem(folder / "every", every))
    assert [p.states for p in pieces] == [
        ["Motor1_av", "Motor1_i", "Motor1_int1", "Range_distance"],
        ["Motor2_av", "Motor2_i", "Motor2_int2", "Range_distance"]]


def test_the_joint_problem_keeps_the_whole_conjunction_on_every_part_s_states(motors):
    folder, _, every = motors
    problem = scenario_problem(folder / "every", every)
    together = joint(problem)
    assert together.states == sorted({x for p in parts(problem) for x in p.states},
                                     key=problem.states.index)
    assert together.unsafe == problem.unsafe
    assert "Motor1_theta" not in together.states  # what no atom needs stays out


def _scripted_flowstar(tmp_path: Path, part1: str, part2: str, joint_: str) -> str:
    """An executable that reads a model like Flow* and answers by what it holds: both
    motors (the joint run), motor 1's part or motor 2's, counting its runs in a file."""
    script = tmp_path / "flowstar"
    script.write_text(
        f"#!{sys.executable}\nimport sys\ntext = sys.stdin.read()\n"
        f"open({str(tmp_path / 'runs')!r}, 'a').write('run\\n')\n"
        "one, two = 'Motor1_av' in text, 'Motor2_av' in text\n"
        f"word = {joint_!r} if one and two else {part1!r} if one else {part2!r}\n"
        "print('Computation completed: 10 flowpipe(s) computed.')\n"
        "print('Result of the safety verification on the computed flowpipes: ' + word)\n")
    script.chmod(0o755)
    return str(script)


@pytest.mark.parametrize("answers, verdict, runs, jointly", [
    (("SAFE", "UNKNOWN", "UNKNOWN"), "SAFE", 2, False),  # one part proves the conjunction
    # parts, the ladder's 3 rungs on each, their boxes, joint
    (("UNKNOWN", "UNKNOWN", "SAFE"), "SAFE", 2 + 6 + 8 + 1, True),
    (("UNKNOWN", "UNKNOWN", "UNKNOWN"), "UNKNOWN", 2 + 6 + 8 + 1 + 3 + 4, False),  # never SAFE
])
def test_parts_then_boxes_then_the_joint_run(motors, tmp_path, answers, verdict, runs,
                                             jointly):
    """The combination rule, with a scripted Flow*: SAFE of one part suffices; parts that
    are not proved leave the verdict open until the joint run proves it; the joint run
    split into boxes too when it is open, and without any SAFE the verdict is UNKNOWN."""
    folder, _, every = motors
    problem = scenario_problem(folder / "every", every)
    result = check(problem, "every", _scripted_flowstar(tmp_path, *answers), jobs=1)
    assert result.verdict == verdict, result.reason
    assert len((tmp_path / "runs").read_text().splitlines()) == runs
    assert ("jointly" in result.reason) == jointly
    if verdict == "UNKNOWN":
        assert result.reason.startswith("not proved: ")
        # 4 boxes; notes: 3 rungs of the ladder, 1 split
        assert sum("parts jointly" in d for d in result.details) == 4 + 3 + 1


def test_a_part_is_the_projection_of_the_whole_automaton(motors):
    """Simulated from the same point, a part's states follow the whole automaton's."""
    folder, either, _ = motors
    problem = scenario_problem(folder / "either", either)
    whole, part = problem.disjuncts()[1], parts(problem.disjuncts()[1])[0]
    start = {v: 0.0 for v in [*problem.states, "timer", "t"]}
    start["Range_distance"] = 3.03
    samples = np.linspace(0.05, 1.45, 29)
    a = interpret(render(whole, "whole"), start, samples)
    b = interpret(render(part, "part"), start, samples)
    for v in part.states:
        np.testing.assert_allclose(b[v], a[v], rtol=0, atol=1e-7, err_msg=v)
    assert a["Motor2_av"].max() > 9 and a["Motor2_av"][-1] < 0  # cruised, then stopped


def test_mode_independent_states_keep_one_mode(tmp_path):
    """An atom on the range finder only (its flow is the same in every mode)."""
    path = sampled_stop(tmp_path, "range", ('constraints = ["Motor_av >= 20"]',
                                            'constraints = ["Range_distance <= 0.5"]'))
    (part,) = parts(scenario_problem(DCMOTOR, path))
    assert part.states == ["Range_distance"]
    model = parse_model(render(part, "range"))
    assert list(model.modes) == ["Cruise"] and model.jumps == []


def test_split_boxes_cover_the_initial_interval(tmp_path):
    problem = scenario_problem(DCMOTOR, DCMOTOR / "sampled_stop.toml")
    (part,) = parts(problem)
    boxes = split(part, 4)
    intervals = [parse_model(render(p, "b")).init["Range_distance"] for _, p in boxes]
    assert [float(lo) for lo, _ in intervals] == pytest.approx([3, 3.025, 3.05, 3.075])
    assert [float(hi) for _, hi in intervals] == pytest.approx([3.025, 3.05, 3.075, 3.1])
    assert float(intervals[-1][1]) == 3.1
    assert [label for label, _ in boxes][0].startswith("Range_distance in [3, 3.025]")


# --------------------------------------------------------------------------- witnesses

def test_a_witness_is_a_trajectory_that_really_enters_the_unsafe_set(tmp_path):
    problem = scenario_problem(DCMOTOR, sampled_stop(tmp_path, "u", UNSAFE, SHORT))
    witness = find_witness(render(problem, "u"))
    assert witness is not None
    entry = dict(witness.entry.values)
    assert entry["Motor_av"] >= 5 and 0.3 <= entry["t"] <= 0.5
    # a second derivation: the scenario simulated from the reduced equations directly
    start = dict(witness.start.values)
    times = np.append(np.arange(0.005, 1.3, 0.01), entry["t"])  # every cycle sampled
    direct = simulate_direct(problem, start, times)
    assert direct["Motor_av"][-1] == pytest.approx(entry["Motor_av"], abs=1e-6)


def test_no_witness_on_the_borderline_scenario(tmp_path):
    """The distance starts 1e-5 above the stopping threshold at t = 1.0: no trajectory
    stops then, and by t = 1.15 the motor stopped at t = 1.1 still turns above 5 rad/s."""
    problem = scenario_problem(DCMOTOR, sampled_stop(tmp_path, "b", *BORDER, SHORT))
    assert find_witness(render(problem, "b")) is None
    times = np.arange(0.005, 1.3, 0.01)  # every cycle sampled
    window = (times >= 1.15) & (times <= 1.2)
    for d in np.linspace(3.00001, 3.1, 9):
        start = {v: 0.0 for v in problem.states}
        start["Range_distance"] = d
        assert simulate_direct(problem, start, times)["Motor_av"][window].min() > 5


def test_the_search_finds_a_violation_from_a_narrow_region_of_the_initial_set(tmp_path):
    """41 evenly spaced starts all miss the region (checked by the direct simulation); the
    search, deterministic, finds a start in it within its budget, twice the same."""
    problem = scenario_problem(DCMOTOR, sampled_stop(tmp_path, "narrow", *NARROW, SHORT))
    times = np.append(np.arange(0.005, 1.3, 0.01), np.linspace(1.15, 1.2, 11))
    window = (times >= 1.15 - 1e-12) & (times <= 1.2 + 1e-12)

    def enters(d: float) -> bool:
        start = {v: 0.0 for v in problem.states}
        start["Range_distance"] = d
        av = simulate_direct(problem, start, times)["Motor_av"][window]
        return bool(np.any((av >= 1) & (av <= 5)))

    assert not any(enters(d) for d in np.linspace(0.6, 20.6, 41))
    text = render(problem, "narrow")
    search = _Search(Automaton(text), [], BUDGET)
    witness = search.run()
    assert witness is not None and len(search.seen) < BUDGET
    start = dict(witness.start.values)
    assert 2.8 < start["Range_distance"] <= 3.0 and enters(start["Range_distance"])
    assert [p.time for p in witness.switches] == pytest.approx([1.0])  # stopped at t = 1.0
    entry = dict(witness.entry.values)
    assert 1 <= entry["Motor_av"] <= 5 and 1.15 <= entry["t"] <= 1.2
    again = find_witness(text)
    assert again is not None and again.start == witness.start


def test_the_search_is_drawn_to_the_path_flow_star_flagged(tmp_path):
    """The guided score: a trajectory that follows Flow*'s unsafe path is scored on that
    path's last flow; one that departs from it scores worse than any that follows it."""
    problem = scenario_problem(DCMOTOR, sampled_stop(tmp_path, "g", *NARROW, SHORT))
    automaton = Automaton(render(problem, "g"))
    path = ["Cruise"] * 10 + ["Stopped"]  # the stop at t = 1.0
    start = {v: 0.0 for v in automaton.variables}
    on, off = dict(start, Range_distance=2.9), dict(start, Range_distance=10.0)
    rho_on, guided_on = automaton.measure(on, [path])
    rho_off, guided_off = automaton.measure(off, [path])
    assert rho_on < 0 < rho_off  # the first enters the unsafe set, the other does not
    assert guided_on == pytest.approx(rho_on) and guided_off > 1 > guided_on


def test_a_decision_on_a_guard_boundary_is_no_witness(tmp_path):
    """From exactly 3.0 the distance reaches the threshold 1 m exactly at t = 1.0: the
    stop there is on the guard's boundary, so that trajectory proves nothing."""
    problem = scenario_problem(DCMOTOR, sampled_stop(
        tmp_path, "edge", ("Range_distance = [3, 3.1]", "Range_distance = 3"),
        ('constraints = ["Motor_av >= 20"]', 'constraints = ["Motor_av <= 5", "t >= 1.15"]'),
        SHORT))
    assert Automaton(render(problem, "edge")).run(
        {v: 3.0 if v == "Range_distance" else 0.0 for v in [*problem.states, "timer", "t"]}
    ) is None


def test_the_counterexample_paths_are_read():
    text = ("Unsafe flowpipes:\n\ncruise\n{\ncomputation path\n{\n\ncruise;\n\n}\n\n}\n\n"
            "Unknown flowpipes:\n\nstopped\n{\ncomputation path\n{\n\ncruise ( 1 , [0.1 , "
            "0.1]) -> stopped;\n\n}\n}\nUnsafe flowpipes:\n\nstopped\n{\ncomputation path\n"
            "{\n\ncruise ( 2 , [9.9e-02 , 1.0e-01]) -> cruise ( 1 , [0.1 , 0.1]) -> "
            "stopped;\n\n}\n\n}\n")
    assert unsafe_paths(text) == [["cruise"], ["cruise", "cruise", "stopped"]]


# --------------------------------------------------------------------------- real Flow*

def _reach(capsys, folder, scenario, tmp_path, *extra):
    rc = main(["reach", str(folder), "--scenario", str(scenario), "-o", str(tmp_path / "out"),
               "--flowstar-bin", str(flowstar_binary()), *extra])
    out = capsys.readouterr()
    return rc, out.out, out.err


@needs_flowstar
def test_real_flowstar_proves_the_dcmotor_example(tmp_path, capsys):
    rc, out, err = _reach(capsys, DCMOTOR, DCMOTOR / "sampled_stop.toml", tmp_path)
    assert rc == 0 and out.startswith("SAFE: Flow* proved the initial set safe"), out + err


@needs_flowstar
def test_real_flowstar_proves_the_marxbot_example(tmp_path, capsys):
    """The paper's property: SAFE (about 30 s of Flow* on 2 cores)."""
    rc, out, err = _reach(capsys, EXAMPLES / "marxbot",
                          EXAMPLES / "marxbot" / "obstacle_stop.toml", tmp_path)
    assert rc == 0 and out.startswith("SAFE:"), out + err


@needs_flowstar
def test_real_flowstar_unsafe_is_confirmed_and_printed(tmp_path, capsys):
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(tmp_path, "u", UNSAFE, SHORT), tmp_path)
    assert rc == 1, out + err
    lines = out.splitlines()
    assert lines[0].startswith("UNSAFE: a simulated trajectory from the initial set enters")
    entry = next(ln for ln in lines if re.match(r"\s+t = \S+\s+unsafe", ln))
    t = float(entry.split()[2])
    av = float(re.search(r"Motor_av = (\S+),", entry).group(1))
    assert 0.3 <= t <= 0.5 and av >= 5


@needs_flowstar
def test_real_flowstar_unsafe_from_a_narrow_region_is_confirmed(tmp_path, capsys):
    """Flow* flags the box; the search finds the trajectory that stops at t = 1.0."""
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(tmp_path, "narrow", *NARROW, SHORT),
                          tmp_path)
    assert rc == 1, out + err
    lines = out.splitlines()
    assert lines[0].startswith("UNSAFE: a simulated trajectory from the initial set enters")
    start = next(ln for ln in lines if re.match(r"\s+t = 0\s+start", ln))
    assert 2.8 < float(re.search(r"Range_distance = (\S+)", start).group(1)) <= 3.0
    jump = next(ln for ln in lines if re.match(r"\s+t = \S+\s+jump\s+Stopped", ln))
    assert float(jump.split()[2]) == pytest.approx(1.0)


@needs_flowstar
def test_real_flowstar_proves_a_conjunction_jointly_when_no_part_does(tmp_path, capsys):
    """Two identical motors: motor 1 above 8 rad/s and motor 2 below 2 rad/s at once. Each
    atom alone is reached (a part is UNSAFE on its own), so no part proves it, and before
    the joint fallback the verdict was UNKNOWN; together the speeds are equal, and Flow*
    proves the conjunction on the joint problem."""
    folder = tmp_path / "two"
    path = write_motors(folder, 2, horizon=1.2, every=True)
    path.write_text(path.read_text().replace(
        '"Motor1_av >= 20", "Motor2_av >= 20"', '"Motor1_av >= 8", "Motor2_av <= 2"'))
    rc, out, err = _reach(capsys, folder, path, tmp_path)
    assert rc == 0, out + err
    assert out.startswith("SAFE: Flow* proved the initial set safe (its independent parts "
                          "jointly: none proved it alone) in 3 runs")
    runs = out.split("Flow* runs:\n")[1].splitlines()
    assert [r.split(": ")[0].strip() for r in runs] == [
        "part 1/2 [Motor1_av, Motor1_i, Motor1_int1, Range_distance]",
        "part 2/2 [Motor2_av, Motor2_i, Motor2_int2, Range_distance]",
        "parts jointly [Motor1_av, Motor1_i, Motor1_int1, Motor2_av, Motor2_i, Motor2_int2, "
        "Range_distance]"]
    assert ": UNSAFE (" in runs[0] and ": UNSAFE (" in runs[1] and ": SAFE (" in runs[2]
    # the parts' UNSAFE is real for their own atoms: a trajectory of each part enters them
    for k, atom in ((1, "Motor1_av >= 8"), (2, "Motor2_av <= 2")):
        problem = scenario_problem(folder, path)
        (part,) = [p for p in parts(problem) if f"Motor{k}_av" in p.states]
        assert find_witness(render(part, f"p{k}")) is not None, atom


@needs_flowstar
def test_real_flowstar_borderline_unsafe_is_unknown(tmp_path, capsys):
    """Flow* says UNSAFE (a spurious stop at t = 1.0); the system is safe."""
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(tmp_path, "b", *BORDER, SHORT), tmp_path)
    assert rc == 3, out + err
    assert out.startswith("UNKNOWN: Flow* found a flowpipe inside the unsafe set")
    assert "spurious branch" in out and "Cruise ×10 -> Stopped" in out
    assert "split into 4 boxes" in out


@needs_flowstar
def test_real_flowstar_incomplete_computation_is_unknown(tmp_path, capsys):
    # a quadratic environment makes the modes poly ode 2 (an affine mode is lti ode, whose
    # integrator completes at this step), and Picard's iteration fails at step 0.05
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(
        tmp_path, "big", SHORT, ("step = 0.01", "step = 0.05"),
        ('Range_distance = "-2"', 'Range_distance = "-0.5*Range_distance*Range_distance"')),
        tmp_path, "--no-auto-split")
    assert rc == 3 and "did not complete" in out, out + err


@needs_flowstar
def test_real_flowstar_too_few_jumps_is_not_safe(tmp_path):
    """With max jumps 5 Flow* covers t <= 0.6 only and prints SAFE, although the motor is
    at rest (below 5 rad/s) after t = 1.5 on every trajectory."""
    problem = scenario_problem(DCMOTOR, sampled_stop(
        tmp_path, "few", ('constraints = ["Motor_av >= 20"]',
                          'constraints = ["Motor_av <= 5", "t >= 1.5"]'), ("horizon = 2.0",
                                                                            "horizon = 1.6")))
    text = render(problem, "few").replace(f"max jumps {problem.max_jumps}", "max jumps 5")
    with tempfile.TemporaryDirectory() as scratch:
        done = subprocess.run([str(flowstar_binary())], input=text, capture_output=True,
                              text=True, cwd=scratch, check=False)
    said = decide(done.returncode, done.stdout, done.stderr)
    assert said.verdict == "SAFE"  # Flow*'s own word
    outcome = run_text(text, str(flowstar_binary()), None, problem.required_jumps)
    assert outcome.verdict == "UNKNOWN" and "max jumps 5 is below the 17" in outcome.reason
    assert model_problems(text, problem.required_jumps)


@needs_flowstar
def test_real_flowstar_checks_actuator_inputs_and_environment_functions(tmp_path, capsys):
    """Unsafe: the desired speed is still 10 rad/s after t = 1.2 (the stop comes at 1.0 or
    1.1: SAFE); the obstacle's approach speed varies with sin (a nonpoly mode)."""
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(
        tmp_path, "das", ('constraints = ["Motor_av >= 20"]',
                          'constraints = ["Motor_das >= 5", "t >= 1.2"]'),
        ("horizon = 2.0", "horizon = 1.3")), tmp_path)
    assert rc == 0, out + err
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(
        tmp_path, "wave", ('Range_distance = "-2"', 'Range_distance = "-2 - sin(5*t)"'),
        ("horizon = 2.0", "horizon = 0.3")), tmp_path, "--no-auto-split")
    assert rc in (0, 3) and not out.startswith("ERROR"), out + err


@needs_flowstar
def test_real_flowstar_split_and_disjunctions(tmp_path, capsys):
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(
        tmp_path, "either", SHORT, ('constraints = ["Motor_av >= 20"]',
                                    'constraints = ["Motor_av >= 20 \\\\/ Motor_i >= 30"]')),
        tmp_path, "--split", "2")
    assert rc == 0, out + err
    assert "every disjunct of the unsafe set safe in 4 runs" in out
    assert out.count(": SAFE (") == 4


@needs_flowstar
def test_real_flowstar_accepts_adaptive_orders(tmp_path, capsys):
    rc, out, err = _reach(capsys, DCMOTOR, sampled_stop(tmp_path, "adaptive", SHORT,
                                                        ("order = 6", "order = [4, 8]")),
                          tmp_path, "--no-auto-split")
    assert rc == 0 and "adaptive orders { min 4 , max 8 }" in (
        tmp_path / "out" / "adaptive.model").read_text(), out + err
