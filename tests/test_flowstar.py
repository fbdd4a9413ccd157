"""Flow* export (issue 9): our grammar of the 2.1.0 format and its lexical traps, the printer,
the exported automata (parsed, and simulated against a direct simulation of the scenario),
scenario diagnostics, and verdicts from recorded Flow* outputs."""

from __future__ import annotations

import math
import stat
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy
from hypothesis import given, settings, strategies as st

from cyphy.cli import main
from cyphy.diagnostics import Report
from cyphy.verify.flowstar.build import build_problem
from cyphy.verify.flowstar.export import output_name, render
from cyphy.verify.flowstar.printer import NotExpressible, flowstar_text, number
from cyphy.verify.flowstar.scenario import load_scenario
from cyphy.verify.flowstar.syntax import FlowstarSyntaxError, parse_model
from cyphy.verify.flowstar.verdict import decide, model_problems

from conftest import EXAMPLES, ROOT

sys.path.insert(0, str(Path(__file__).parent))
from flowstar_sim import interpret, simulate_direct  # noqa: E402
from flowstar_scenarios import CRUISE_COAST_STOP, MOTOR_HEAD, scenario_problem  # noqa: E402
from motors import SSPEED_TABLE  # noqa: E402

SPEC = ROOT.parent / "shared" / "spec" / "flowstar-examples"
DCMOTOR = (EXAMPLES / "dcmotor", EXAMPLES / "dcmotor" / "sampled_stop.toml")
MARXBOT = (EXAMPLES / "marxbot", EXAMPLES / "marxbot" / "obstacle_stop.toml")


@pytest.fixture(scope="module")
def dcmotor():
    return scenario_problem(*DCMOTOR)


@pytest.fixture(scope="module")
def marxbot():
    return scenario_problem(*MARXBOT)


# --------------------------------------------------------------------------- grammar

@pytest.mark.skipif(not SPEC.is_dir(), reason="../shared/spec is absent")
@pytest.mark.parametrize("name", ["dc_motor_pi.model", "dc_motor_sampled_stop.model"])
def test_grammar_reads_the_spec_examples(name):
    model = parse_model((SPEC / name).read_text())
    assert model.settings["time"] == "2"
    assert "w" in model.variables


SMALL = """hybrid reachability
{
 state var x, timer
 setting
 {
  fixed steps 0.01
  time 1
  remainder estimation 1e-2
  identity precondition
  gnuplot octagon timer, x
  fixed orders 4
  cutoff 1e-12
  precision 53
  output small
  max jumps 12
  print off
 }
 modes
 {
  m { poly ode 2 { x' = 2*x - 1  timer' = 1 } inv { timer <= 0.1 } }
 }
 jumps
 {
  m -> m
  guard { timer = 0.1  x >= -1.5e+2 }
  reset { timer' := 0 }
  parallelotope aggregation { }
 }
 init { m { x in [0, 0.5] timer in [0, 0] } }
}
unsafe { m { x >= 3 } }
"""


def test_grammar_reads_a_small_automaton():
    model = parse_model(SMALL)
    assert model.kind == "hybrid" and list(model.modes) == ["m"]
    assert model.settings["max jumps"] == 12
    assert model.jumps[0].guard[1].bounds == ("-1.5e+2",)
    assert model.unsafe["m"][0].rel == ">="


@pytest.mark.parametrize("broken, why", [
    ("x' = 2*x -1", "a leading minus belongs to the number: `x -1` is x then -1"),
    ("x' = 2*x-1", "the same without a space"),
    ("x' = 2*x - 1e+5", "an exponent '+' needs a decimal point"),
    ("x' = 2*x - 1E-3", "no capital E"),
    ("x' = 2/x", "no division in poly ode"),
    ("x' = sin(x)", "no functions in poly ode"),
    ("inv { timer < 0.1 }", "there is no '<'"),
    ("state var x, time", "reserved words are not names"),
    ("unsafe { m", "1.x's 'unsafe set' is gone"),
    ("m { x in [0, 0.5] timer in [0, 0] } }", "one initial mode only"),
    ("guard { timer = 0.1  x >= y }", "the right side is a number or a parameter, here fine"),
])
def test_grammar_traps(broken, why):
    text = {
        "x' = 2*x -1": SMALL.replace("x' = 2*x - 1", "x' = 2*x -1"),
        "x' = 2*x-1": SMALL.replace("x' = 2*x - 1", "x' = 2*x-1"),
        "x' = 2*x - 1e+5": SMALL.replace("x' = 2*x - 1", "x' = 2*x - 1e+5"),
        "x' = 2*x - 1E-3": SMALL.replace("x' = 2*x - 1", "x' = 2*x - 1E-3"),
        "x' = 2/x": SMALL.replace("x' = 2*x - 1", "x' = 2/x"),
        "x' = sin(x)": SMALL.replace("x' = 2*x - 1", "x' = sin(x)"),
        "inv { timer < 0.1 }": SMALL.replace("timer <= 0.1", "timer < 0.1"),
        "state var x, time": SMALL.replace("state var x, timer", "state var x, time"),
        "unsafe { m": SMALL.replace("unsafe {", "unsafe set {"),
        "m { x in [0, 0.5] timer in [0, 0] } }": SMALL.replace(
            "init { m { x in [0, 0.5] timer in [0, 0] } }",
            "init { m { x in [0, 0.5] timer in [0, 0] } m { x in [1, 1] } }"),
        "guard { timer = 0.1  x >= y }": SMALL.replace("x >= -1.5e+2", "x >= y"),
    }[broken]
    if broken.startswith("guard"):
        assert parse_model(text).jumps[0].guard[1].bounds == ("y",)
        return
    with pytest.raises(FlowstarSyntaxError):
        parse_model(text)


def test_grammar_allows_names_that_only_start_with_a_reserved_word():
    import re
    text = re.sub(r"\bx\b", "poly", SMALL.replace("timer", "timestep"))
    assert parse_model(text).variables == ["poly", "timestep"]


# --------------------------------------------------------------------------- printer

def test_numbers_use_the_spellings_flowstar_reads():
    assert number(1e-12) == "1.0e-12"
    assert number(1.5e20) == "1.5e+20"
    assert number(0.1) == "0.1"
    assert number(sympy.Rational(41, 2)) == "20.5"
    assert number(-3) == "3"  # the sign is the caller's


def test_printer_spaces_binary_minus_and_refuses_what_flowstar_lacks():
    x, y = sympy.symbols("x y", real=True)
    assert flowstar_text(x - 1) == "x - 1"
    assert flowstar_text(-sympy.Rational(41, 2) * x + 200) == "200 - 20.5*x"
    assert flowstar_text(x - (y - 1)) == "x - y + 1"
    with pytest.raises(NotExpressible):
        flowstar_text(x / y)
    with pytest.raises(NotExpressible):
        flowstar_text(sympy.tan(x), polynomial=False)
    assert flowstar_text(x / y + sympy.sin(x), polynomial=False) == "x/y + sin(x)"


_coeff = st.fractions(min_value=-1000, max_value=1000, max_denominator=64)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(_coeff, st.integers(0, 3), st.integers(0, 3)), min_size=1,
                max_size=6), st.floats(-3, 3), st.floats(-3, 3))
def test_printed_polynomials_parse_back_to_the_same_values(terms, xv, yv):
    x, y = sympy.symbols("x y", real=True)
    poly = sum(sympy.Rational(c.numerator, c.denominator) * x**i * y**j for c, i, j in terms)
    if poly == 0:
        return
    text = SMALL.replace("x' = 2*x - 1", f"x' = {flowstar_text(sympy.expand(poly))}")
    rhs = parse_model(text).modes["m"].flow["x"]
    from cyphy.translate.to_sympy import to_sympy
    back = to_sympy(rhs, symbols={"x": x, "y": y})
    want = float(poly.subs({x: xv, y: yv}))
    assert math.isclose(float(back.subs({x: xv, y: yv})), want, rel_tol=1e-12, abs_tol=1e-9)


# --------------------------------------------------------------------------- export

def test_dcmotor_export_matches_the_spec_example_in_structure(dcmotor):
    model = parse_model(render(dcmotor, "sampled_stop"))
    # The modes are those of the d-model's machine SSpeed, compiled (no [controller]).
    assert list(model.modes) == ["Cruise", "Stopped"]
    assert all(m.ode == "lti ode" for m in model.modes.values())  # the plant is affine
    # the spec's example also has stopped -> stopped; a final state flows to the horizon
    assert [(j.source, j.target) for j in model.jumps] == [
        ("Cruise", "Stopped"), ("Cruise", "Cruise")]
    assert [c.bounds for c in model.modes["Cruise"].invariant] == [("0.1",)]
    assert model.modes["Stopped"].invariant == []
    assert all(j.resets.keys() == {"timer"} for j in model.jumps)
    assert set(model.unsafe) == set(model.modes)
    assert model.settings["max jumps"] == 25
    assert model.initial_mode == "Cruise" and model.init["Range_distance"] == ("3", "3.1")
    # the plant of dc_motor_sampled_stop.model: wref = 10 in cruise, 0 once stopped
    cruise, stopped = model.modes["Cruise"].flow, model.modes["Stopped"].flow
    from cyphy.translate.to_sympy import to_sympy
    w, i, z = sympy.symbols("Motor_av Motor_i Motor_int1", real=True)
    names = {"Motor_av": w, "Motor_i": i, "Motor_int1": z}
    assert sympy.expand(to_sympy(cruise["Motor_i"], symbols=names)
                        - 10 * (2 * (10 - w) + 5 * z - i - 0.05 * w)) == 0
    assert sympy.expand(to_sympy(stopped["Motor_int1"], symbols=names) + w) == 0
    assert model_problems(render(dcmotor, "x"), 21) == []


def test_marxbot_export_has_every_mode_under_unsafe_and_polynomial_guards(marxbot):
    text = render(marxbot, "obstacle_stop")
    model = parse_model(text)
    assert list(model.modes) == ["Cruising", "Stopped"]
    assert set(model.unsafe) == {"Cruising", "Stopped"}
    assert model.settings["max jumps"] == 41  # ceil(4 / 0.1) + 1
    guard = model.jumps[0].guard
    assert [c.rel for c in guard] == ["=", "<="]  # timer = 0.1, obstacle (no division)
    assert model_problems(text, marxbot.required_jumps) == []
    assert text == render(marxbot, "obstacle_stop")  # deterministic


def _compare(problem, point=None):
    s = problem.scenario
    start = {v: (lo + hi) / 2 for v, (lo, hi) in s.init.items()}
    start.update(point or {})
    start.update({"timer": 0.0, "t": 0.0})
    samples = np.linspace(0.0137, s.horizon - 0.0137, 50)
    automaton = interpret(render(problem, "x"), start, samples)
    direct = simulate_direct(problem, start, samples)
    for v in problem.states:
        assert not np.isnan(automaton[v]).any() and not np.isnan(direct[v]).any()
        np.testing.assert_allclose(automaton[v], direct[v], rtol=0, atol=1e-6, err_msg=v)
    return direct


def test_dcmotor_automaton_agrees_with_direct_simulation(dcmotor):
    direct = _compare(dcmotor)
    assert direct["Motor_av"].max() > 9  # it cruised at 10 rad/s, then stopped
    assert abs(direct["Motor_av"][-1]) < 2


def test_marxbot_automaton_agrees_with_direct_simulation(marxbot):
    direct = _compare(marxbot, {"Proximity1_distance": 0.2537})
    d = direct["Proximity1_distance"]
    assert d[0] > d[25] and d.min() > 0.05  # the distance falls; the robot stops in time
    assert abs(direct["LMotor_av"][-1]) < 0.01


HELD = "\n" + MOTOR_HEAD.format(
    horizon=1.5, av=0, distance="[1.4, 1.5]", env="-0.05*Motor_av").replace(
    "tscale = 0.1", "tscale = 0.05\ncycle = 2") + CRUISE_COAST_STOP + """[unsafe]
constraints = ["Motor_av >= 20", "t >= 0.5"]
"""


def test_held_inputs_agree_with_direct_simulation(tmp_path):
    """A state without calls keeps the inputs: they become held state variables."""
    path = tmp_path / "held.toml"
    path.write_text(HELD)
    problem = scenario_problem(EXAMPLES / "dcmotor", path)
    assert problem.held_inputs == ["Motor_das"]
    model = parse_model(render(problem, "held"))
    assert "Motor_das" in model.variables
    into_stopped = [j for j in model.jumps if j.target == "stopped"]
    assert into_stopped and all("Motor_das" in j.resets for j in into_stopped)
    assert model.init["Motor_das"] == ("8", "8")
    _compare(problem)


# --------------------------------------------------------------------------- diagnostics

def _diagnose(tmp_path, text, folder=EXAMPLES / "dcmotor"):
    path = tmp_path / "s.toml"
    path.write_text(text)
    report = Report()
    scenario = load_scenario(path, report)
    if scenario is not None:
        build_problem([folder], scenario, report)
    assert report.has_errors
    return [(d.code.id, d.message, d.span.line, d.hint) for d in report.diagnostics
            if d.severity.value == "ERROR"]


BASE = (EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text() + SSPEED_TABLE


@pytest.mark.parametrize("edit, code, words", [
    (("horizon = 2.0", ""), "E-SCENARIO", "needs 'horizon'"),
    (("horizon = 2.0", "horizon = 2.0\nhorizn = 3"), "E-SCENARIO", "unknown key 'horizn'"),
    (('to = "stopped"', 'to = "stoped"'), "E-SCENARIO", "must name a controller state"),
    (('when = "near"', 'when = "far"'), "E-FLOWSTAR", "no input event 'far'"),
    (("Motor_theta = 0\n", ""), "E-FLOWSTAR", "no initial interval for Motor_theta"),
    (("max_jumps = 25", "max_jumps = 5"), "E-FLOWSTAR", "max_jumps = 5 is too small"),
    (('"Motor_av >= 20"', '"sin(Motor_av) >= 0.5"'), "E-FLOWSTAR", "no Flow* constraint"),
    (('Range_distance = "-2"', ''), "E-FLOWSTAR", "nothing gives the input"),
    (('calls = ["drive(10)"]', 'calls = ["drive(10, 2)"]'), "E-FLOWSTAR", "takes 1 argument"),
    (("[init]", "[init\n"), "E-SCENARIO", "not valid TOML"),
])
def test_bad_scenarios_get_diagnostics(tmp_path, edit, code, words):
    old, new = edit
    assert old in BASE
    errors = _diagnose(tmp_path, BASE.replace(old, new, 1))
    assert any(c == code and words in m for c, m, _, _ in errors), errors


def test_a_diagnostic_points_at_the_scenario_line(tmp_path):
    errors = _diagnose(tmp_path, BASE.replace("max_jumps = 25", "max_jumps = 5"))
    line = BASE.splitlines().index("max_jumps = 25") + 1
    assert any(ln == line for c, m, ln, h in errors if "too small" in m)


# --------------------------------------------------------------------------- verdicts

BOLD = "\x1b[1m"
END = "\x1b[0m"
COMPLETED = f"{BOLD}Computation completed: 332 flowpipe(s) computed.{END}\n\n"
TIME = "Total time cost:\x1b[1m 1.36\x1b[0m seconds.\n"


def _verdict(word):
    return f"{BOLD}Result of the safety verification on the computed flowpipes: {word}{END}\n\n"


def test_verdict_safe():
    out = decide(0, COMPLETED + _verdict("SAFE") + TIME + "Preparing for plotting...\n", "")
    assert (out.verdict, out.exit_code, out.seconds) == ("SAFE", 0, 1.36)


def test_verdict_unsafe_even_when_not_completed():
    out = decide(0, "Computation not completed: 12 flowpipe(s) computed.\n" +
                 _verdict("UNSAFE") + TIME, "")
    assert (out.verdict, out.exit_code) == ("UNSAFE", 1)


def test_verdict_unknown():
    out = decide(0, COMPLETED + _verdict("UNKNOWN") + TIME, "")
    assert (out.verdict, out.exit_code) == ("UNKNOWN", 3)
    assert "partially" in out.reason


def test_not_completed_is_never_safe():
    stdout = (f"{BOLD}Computation not completed: 0 flowpipe(s) computed.{END}\n"
              "Please try smaller step sizes or larger Taylor model orders.\n"
              + _verdict("SAFE") + TIME)
    out = decide(0, stdout, "")
    assert (out.verdict, out.exit_code) == ("UNKNOWN", 3)
    assert "did not complete" in out.reason


def test_syntax_error_is_an_error_despite_exit_status_0():
    out = decide(0, "", "Error line 12: syntax error\n")
    assert (out.verdict, out.exit_code) == ("ERROR", 2)
    assert "Error line 12: syntax error" in out.reason


def test_semantic_error_and_crash_are_errors_division_by_zero_is_unknown():
    assert decide(1, "", "Error @line 7:State variable tan is not declared.\n").exit_code == 2
    assert decide(139, COMPLETED + _verdict("SAFE"), "").verdict == "ERROR"
    assert decide(1, "Exception: Divided by 0.\n", "").verdict == "UNKNOWN"


def test_safe_with_a_flawed_model_is_unknown():
    text = SMALL.replace("unsafe { m { x >= 3 } }", "unsafe { }")
    problems = model_problems(text, 11)
    assert problems and "m not listed" in problems[0]
    assert decide(0, COMPLETED + _verdict("SAFE") + TIME, "", problems).verdict == "UNKNOWN"
    low = model_problems(SMALL, 40)
    assert low and "max jumps 12" in low[0]
    assert decide(0, COMPLETED + _verdict("SAFE") + TIME, "", low).verdict == "UNKNOWN"


# --------------------------------------------------------------------------- commands

def _fake_flowstar(tmp_path, stdout, stderr="", rc=0):
    """An executable that reads the model from stdin, like Flow*, and replays a run."""
    script = tmp_path / "flowstar"
    script.write_text(f"#!{sys.executable}\nimport sys\ntext = sys.stdin.read()\n"
                      f"assert text.startswith('#')\nsys.stdout.write({stdout!r})\n"
                      f"sys.stderr.write({stderr!r})\nsys.exit({rc})\n")
    script.chmod(script.stat().st_mode | stat.S_IEXEC)
    return str(script)


@pytest.mark.parametrize("stdout, stderr, code, word", [
    (COMPLETED + _verdict("SAFE") + TIME, "", 0, "SAFE:"),
    # Flow*'s UNSAFE on the safe motor: no simulated trajectory confirms it
    (COMPLETED + _verdict("UNSAFE") + TIME, "", 3, "UNKNOWN: Flow* found a flowpipe"),
    ("Computation not completed: 0 flowpipe(s) computed.\n" + _verdict("SAFE"), "", 3,
     "UNKNOWN:"),
    ("", "Error line 3: syntax error\n", 2, "ERROR:"),
])
def test_reach_prints_one_line_and_the_exit_status(tmp_path, capsys, stdout, stderr, code,
                                                   word):
    binary = _fake_flowstar(tmp_path, stdout, stderr)
    rc = main(["reach", str(DCMOTOR[0]), "--scenario", str(DCMOTOR[1]), "-o",
               str(tmp_path / "out"), "--flowstar-bin", binary])
    captured = capsys.readouterr()
    assert rc == code
    line = (captured.err if code == 2 else captured.out).strip().splitlines()[0]
    assert line.startswith(word) and str(tmp_path / "out" / "sampled_stop.model") in line


def test_reach_without_flowstar_is_an_error(tmp_path, capsys):
    rc = main(["reach", str(DCMOTOR[0]), "--scenario", str(DCMOTOR[1]), "-o", str(tmp_path),
               "--flowstar-bin", str(tmp_path / "nowhere")])
    assert rc == 2 and "Flow* not found" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_gen_flowstar_writes_the_model(tmp_path, capsys):
    rc = main(["gen", str(MARXBOT[0]), "--flowstar", "--scenario", str(MARXBOT[1]), "-o",
               str(tmp_path)])
    assert rc == 0
    written = tmp_path / "obstacle_stop.model"
    assert parse_model(written.read_text()).kind == "hybrid"


def test_gen_flowstar_with_a_bad_scenario_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(BASE.replace("max_jumps = 25", "max_jumps = 3"))
    out = tmp_path / "out"
    rc = main(["gen", str(DCMOTOR[0]), "--flowstar", "--scenario", str(bad), "-o", str(out)])
    assert rc == 1 and not out.exists()
    assert "E-FLOWSTAR" in capsys.readouterr().err


# --------------------------------------------------------------------------- defects (issue 17)

def _reach(tmp_path, text, binary=None, extra=()):
    path = tmp_path / "s.toml"
    path.write_text(text)
    binary = binary or _fake_flowstar(tmp_path, COMPLETED + _verdict("SAFE") + TIME)
    return main(["reach", str(DCMOTOR[0]), "--scenario", str(path), "-o",
                 str(tmp_path / "out"), "--flowstar-bin", binary, *extra])


@pytest.mark.parametrize("old, new, words", [
    ("horizon = 2.0", "horizon = nan", "'horizon' must be a finite number"),
    ("horizon = 2.0", "horizon = inf", "'horizon' must be a finite number"),
    ("Range_distance = [3, 3.1]", "Range_distance = [3, inf]", "must be a finite number"),
    ("Motor_av = 0\n", "Motor_av = nan\n", "must be a finite number"),
    ("step = 0.01", "step = nan", "'flowstar.step' must be a finite number"),
    ("remainder = 1e-2", "remainder = -inf", "must be a finite number"),
    ("horizon = 2.0", 'horizon = "2"', "'horizon' must be a number"),
    ("order = 6", "order = 6.5", "'flowstar.order' must be a positive integer"),
    ('calls = ["drive(10)"]', 'calls = "drive(10)"', "must be a list of calls"),
    ('when = "near"', "when = 3", "'when' must be an input event"),
    ('constraints = ["Motor_av >= 20"]', "constraints = [20]", "non-empty list"),
    ('constraints = ["Motor_av >= 20"]', 'constraints = ["Motor_xx >= 20"]', "Motor_xx"),
    ('Range_distance = "-2"', 'Range_distance = "-2*Motor_q"', "'Motor_q' is not a var"),
    ('Range_distance = "-2"', 'Range_distance = "-2 - tan(t)"', "'tan' is not a function"),
    ("Motor_theta = 0\n", "Motor_theta = 0\nMotor_omega = 1\n", "not a state variable"),
    ('initial = "cruise"', "initial = 1", "needs 'initial'"),
    ("\n[controller]\n", "\n[controllr]\n", "unknown key 'controllr'"),
    ('"Motor_av >= 20"', '"Motor_av >= "', "cannot read the expression"),
    ('"Motor_av >= 20"', '"Motor_av >= 1e400"', "'1e400' in 'Motor_av >= 1e400' is not a fin"),
    ('"Motor_av >= 20"', '"Motor_av / 0 >= 1"', "the unsafe set is undefined"),
    ('calls = ["drive(10)"]', 'calls = ["drive(1e400)"]', "beyond what a double holds"),
    ('calls = ["drive(10)"]', 'calls = ["drive(w)"]', "leaves Motor_das = w, not a number"),
    ('when = "near"', 'when = "not"', "no input event 'not'"),
])
def test_malformed_scenarios_are_located_errors_with_exit_2(tmp_path, capsys, old, new, words):
    assert old in BASE
    rc = _reach(tmp_path, BASE.replace(old, new, 1))
    err = capsys.readouterr().err
    assert rc == 2, err
    assert words in err and "s.toml:" in err and "internal error" not in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["Motor_das", "Motor_e", "Motor_V"])
def test_unsafe_sets_may_name_actuator_inputs_and_what_derives_from_them(tmp_path, name):
    """``Motor_das`` is a constant of each mode: each mode's unsafe set has its value."""
    path = tmp_path / "u.toml"
    path.write_text(BASE.replace('"Motor_av >= 20"', f'"{name} >= 5"'))
    text = render(scenario_problem(EXAMPLES / "dcmotor", path), "u")
    model = parse_model(text)
    assert set(model.unsafe) == {"cruise", "stopped"}
    if name == "Motor_das":  # 10 in cruise: everything; 0 once stopped: nothing
        assert [(c.rel, c.bounds) for c in model.unsafe["cruise"]] == [(">=", ("0",))]
        assert [(c.rel, c.bounds) for c in model.unsafe["stopped"]] == [("<=", ("-1",))]
    else:  # Motor_e and Motor_V involve das: its value differs per mode
        assert model.unsafe["cruise"] != model.unsafe["stopped"]


def test_environment_functions_of_time_become_linear_auxiliary_states(tmp_path):
    """sin(5*t) is the state pair s' = 5*c, c' = -5*s (s(0) = 0, c(0) = 1): the modes are
    affine again (lti ode), and the trajectories are the functions themselves: checked
    against numpy's sin and the closed form d(t) = d0 - 2 t + (cos 5t - 1)/5 (no jump
    before the stop at d <= 1)."""
    path = tmp_path / "sin.toml"
    path.write_text(BASE.replace('Range_distance = "-2"', 'Range_distance = "-2 - sin(5*t)"'))
    text = render(scenario_problem(EXAMPLES / "dcmotor", path), output_name(str(path)))
    model = parse_model(text)
    assert all(m.ode == "lti ode" for m in model.modes.values())
    assert model.init["cyphy_sin1"] == ("0", "0") and model.init["cyphy_cos1"] == ("1", "1")
    samples = np.linspace(0, 0.9, 10)
    run = interpret(text, {"Range_distance": 3.0}, samples)
    assert np.allclose(run["cyphy_sin1"], np.sin(5 * samples), atol=1e-8)
    assert np.allclose(run["Range_distance"],
                       3.0 - 2 * samples + (np.cos(5 * samples) - 1) / 5, atol=1e-8)


def test_environment_functions_of_states_make_a_nonpoly_mode(tmp_path):
    path = tmp_path / "sin.toml"
    path.write_text(BASE.replace('Range_distance = "-2"',
                                 'Range_distance = "-2 - sin(Range_distance)"'))
    problem = scenario_problem(EXAMPLES / "dcmotor", path)
    model = parse_model(render(problem, output_name(str(path))))
    assert all(m.ode == "nonpoly ode" for m in model.modes.values())
    from cyphy.translate.to_sympy import to_sympy
    d = sympy.Symbol("Range_distance", real=True)
    rhs = to_sympy(model.modes["cruise"].flow["Range_distance"], symbols={"Range_distance": d})
    assert sympy.simplify(rhs - (-2 - sympy.sin(d))) == 0


def test_a_held_input_needs_a_value_at_time_0(tmp_path):
    """The initial state calls nothing: the held input's value at time 0 is not invented."""
    text = HELD.replace('initial = "cruise"', 'initial = "coast"')
    errors = _diagnose(tmp_path, text)
    assert any("held actuator input Motor_das" in m and "Motor_das = 0" in h
               for _, m, _, h in errors), errors
    path = tmp_path / "given.toml"
    path.write_text(text.replace("[init]\n", "[init]\nMotor_das = 3\n"))
    model = parse_model(render(scenario_problem(EXAMPLES / "dcmotor", path), "given"))
    assert model.init["Motor_das"] == ("3", "3")


def test_the_max_jumps_message_speaks_of_seconds(tmp_path):
    errors = _diagnose(tmp_path, BASE.replace("max_jumps = 25", "max_jumps = 5"))
    message = next(m for _, m, _, _ in errors if "too small" in m)
    assert "the horizon of 2 s is 20 cycles of 0.1 s (cycle × tscale)" in message


def test_a_relative_flowstar_bin_is_found_from_the_scratch_folder(tmp_path, capsys,
                                                                   monkeypatch):
    binary = _fake_flowstar(tmp_path, COMPLETED + _verdict("SAFE") + TIME)
    monkeypatch.chdir(tmp_path)
    rc = main(["reach", str(DCMOTOR[0]), "--scenario", str(DCMOTOR[1]), "-o", "out",
               "--flowstar-bin", "./" + Path(binary).name])
    assert rc == 0, capsys.readouterr().err
    assert capsys.readouterr().out.startswith("SAFE:")


def test_a_timeout_kills_the_whole_process_group(tmp_path):
    import os
    import time

    from cyphy.verify.flowstar.verdict import run_text

    pidfile = tmp_path / "child.pid"
    script = tmp_path / "slow"
    script.write_text(f"#!{sys.executable}\nimport subprocess, sys, time\nsys.stdin.read()\n"
                      f"child = subprocess.Popen(['sleep', '60'])\n"
                      f"open({str(pidfile)!r}, 'w').write(str(child.pid))\n"
                      "time.sleep(60)\n")
    script.chmod(script.stat().st_mode | stat.S_IEXEC)
    started = time.monotonic()
    outcome = run_text(SMALL, str(script), timeout=1.5)
    assert outcome.verdict == "UNKNOWN" and "within 1.5 s" in outcome.reason
    assert time.monotonic() - started < 20
    child = int(pidfile.read_text())
    for _ in range(50):  # the child is gone (or a zombie about to be reaped by init)
        try:
            os.kill(child, 0)
            with open(f"/proc/{child}/stat") as f:
                if f.read().split()[2] == "Z":
                    break
        except (ProcessLookupError, FileNotFoundError):
            break
        time.sleep(0.1)
    else:
        pytest.fail("the grandchild survived the timeout")


def test_a_final_state_keeps_its_cycles_when_the_unsafe_set_reads_the_timer(tmp_path):
    path = tmp_path / "timer.toml"
    path.write_text(BASE.replace('"Motor_av >= 20"', '"Motor_av >= 20", "timer >= 0.05"'))
    model = parse_model(render(scenario_problem(EXAMPLES / "dcmotor", path), "timer"))
    assert ("stopped", "stopped") in [(j.source, j.target) for j in model.jumps]
    assert model.modes["stopped"].invariant


def test_a_disjunctive_unsafe_set_is_one_model_per_disjunct(tmp_path, capsys):
    either = tmp_path / "either.toml"
    either.write_text(BASE.replace('"Motor_av >= 20"', '"Motor_av >= 20 \\\\/ Motor_i >= 30"'))
    rc = main(["gen", str(DCMOTOR[0]), "--flowstar", "--scenario", str(either), "-o",
               str(tmp_path / "out")])
    assert rc == 0, capsys.readouterr().err
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert written == ["either_1.model", "either_2.model"]
    first = parse_model((tmp_path / "out" / "either_1.model").read_text())
    second = parse_model((tmp_path / "out" / "either_2.model").read_text())
    assert [c.bounds for c in first.unsafe["cruise"]] == [("20",)]
    assert [c.bounds for c in second.unsafe["cruise"]] == [("30",)]


def test_adaptive_steps_and_orders_are_passed_through(tmp_path):
    path = tmp_path / "adaptive.toml"
    path.write_text(BASE.replace("step = 0.01", "step = [0.002, 0.01]"))
    model = parse_model(render(scenario_problem(EXAMPLES / "dcmotor", path), "adaptive"))
    assert model.settings["adaptive steps"] == ("0.002", "0.01")
    path.write_text(BASE.replace("order = 6", "order = [4, 8]"))
    text = render(scenario_problem(EXAMPLES / "dcmotor", path), "adaptive")
    assert "adaptive orders { min 4 , max 8 }" in text and parse_model(text)
    errors = _diagnose(tmp_path, BASE.replace("step = 0.01", "step = [0.002, 0.01]")
                       .replace("order = 6", "order = [4, 8]"))
    assert any("not both" in m for _, m, _, _ in errors)
    errors = _diagnose(tmp_path, BASE.replace("order = 6", "order = [8, 4]"))
    assert any("[min, max]" in m for _, m, _, _ in errors)


def test_d_model_speeds_reach_the_motors_per_second(marxbot):
    """``move(lv, 0)`` with lv = 0.1: the mapping's equations are taken as written, in the
    p-model's seconds, so each wheel is asked for lv / r rad/s and the obstacle approaches
    at lv m/s; tscale (0.1 s) only sets the cycle."""
    r = 0.025025
    das = float(marxbot.effects["Cruising"]["LMotor_das"])
    assert das == pytest.approx(0.1 / r)
    av = {sympy.Symbol("LMotor_av", real=True): das, sympy.Symbol("RMotor_av", real=True): das}
    assert float(marxbot.rhs["Proximity1_distance"].xreplace(av)) == pytest.approx(-0.1)
    assert marxbot.scenario.period == pytest.approx(0.1)
