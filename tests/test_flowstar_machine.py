"""The d-model's state machine as the Flow* controller: the compiled automaton (modes,
calls, guards) against automata worked out by hand, the export of the dcmotor example
(which has no [controller]) against the export under its former hand-written controller,
diagnostics, and real Flow* verdicts for a safe and an unsafe bound."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, flowstar_binary, needs_corpus, needs_flowstar
from flowstar_scenarios import controller
from cyphy import api
from cyphy.cli import main
from cyphy.diagnostics import Report
from cyphy.verify.flowstar.build import build_problem
from cyphy.verify.flowstar.export import render
from cyphy.verify.flowstar.scenario import load_scenario
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import global_constants, machines_of
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter
from cyphy.semantics.machines.automaton import compile_machine, describe
from motors import SSPEED_TABLE

SCENARIO = EXAMPLES / "dcmotor" / "sampled_stop.toml"


def automaton_of(paths: list[Path], name: str, consts: dict | None = None):
    result = api.check([str(p) for p in paths])
    assert not result.report.has_errors
    (m,) = [m for m in machines_of(list(result.workspace.user_files()), result.resolution)
            if m.name == name]
    it = MachineInterpreter(m, {**global_constants(m, Scopes(result.workspace)),
                                **(consts or {})})
    return describe(compile_machine(it))


def machine_file(tmp_path: Path, body: str, events: str = "event a event b") -> Path:
    f = tmp_path / "m.rst"
    f.write_text(f"interface OutI {{ go(x: real) event out }}\ninterface InI {{ {events} }}\n"
                 "stm M {\n input context { uses InI }\n output context { requires OutI "
                 f"uses OutI }}\n{body}\n}}\n", encoding="utf-8")
    return f


def test_dcmotor_machine_compiles_to_the_hand_written_controller():
    assert automaton_of([EXAMPLES / "dcmotor"], "SSpeed").splitlines() == [
        "initial Cruise", "mode Cruise [drive(10)]", "mode Stopped [stop()]",
        "Cruise -> Stopped when near"]


def test_marxbot_machine_turns_for_sixty_three_cycles():
    # since(C) >= PI/(av*tu) = PI/(0.5*0.1) = 62.83 time units first holds 63 cycles after
    # the stop: modes Spinning..Spinning_62, each calling move(0, 0.5) (repeated calls set
    # the same speeds), 6.3 s of turning at 0.5 rad/s when a time unit is 0.1 s.
    lines = automaton_of([EXAMPLES / "marxbot" / "marXbotSoftware.rsm"], "SMovement").splitlines()
    assert lines[:4] == ["initial Cruising", "mode Cruising [move(0.1, 0)]",
                         "mode Stopped [stop()]", "mode Spinning [move(0, 0.5)]"]
    spinning = ["Spinning"] + [f"Spinning_{k}" for k in range(2, 63)]
    assert [x for x in lines if "->" in x] == [
        "Cruising -> Stopped when obstacle", "Stopped -> Spinning when true",
        *(f"{a} -> {b} when true" for a, b in zip(spinning, spinning[1:])),
        "Spinning_62 -> Cruising when true"]


@needs_corpus
def test_corpus_smovement_compiles_with_scenario_constants():
    text = automaton_of([CORPUS / "marXbot" / "Movement.rst",
                         CORPUS / "marXbot" / "marXbotSoftware.rst"], "SMovement",
                        {"PI": 3.0, "lv": 0.1, "av": 1.0})
    assert text.splitlines() == [
        "initial DMoving", "mode DMoving [move(0.1, 0)]", "mode Waiting [stop()]",
        "mode DTurning [move(0, 1)]", "mode DTurning_2 [move(0, 1)]",
        "DMoving -> Waiting when obstacle", "Waiting -> DTurning when true",
        "DTurning -> DTurning_2 when true", "DTurning_2 -> DMoving when true"]


def test_guards_are_conjunctions_of_event_literals(tmp_path):
    # From Idle: a and b -> Both; a and not b -> OnlyA; otherwise stay.
    f = machine_file(tmp_path, """
 initial i0
 state Idle { entry $go(0) }
 state OnlyA { entry $go(1) }
 state Both { entry $go(2) }
 junction J
 transition t0 { from i0 to Idle }
 transition t1 { from Idle to J exec }
 transition t2 { from J to Both condition $a /\\ $b }
 transition t3 { from J to OnlyA condition $a /\\ not $b }
 transition t4 { from J to Idle condition not $a }""")
    lines = automaton_of([f], "M").splitlines()
    assert [x for x in lines if "->" in x] == ["Idle -> OnlyA when a /\\ not b",
                                               "Idle -> Both when a /\\ b"]


def test_clocks_saturate_and_variables_are_explored(tmp_path):
    # n counts 0, 1, 2 (cycles 0-2) and stays; since(C) > 4 first holds in cycle 5, where T
    # is entered. S_4 and S_5 rest in S without calls: they keep go(2). The clock saturates
    # at 5 cycles (one past 4), so T, which never leaves, is one mode.
    f = machine_file(tmp_path, """
 var n: int = 0
 clock C
 initial i0
 state S { entry $go(n) }
 state T { entry $go(5) }
 transition t0 { from i0 to S }
 transition t1 { from S to S exec condition n < 2 action n = n + 1 }
 transition t2 { from S to T exec condition n >= 2 /\\ since(C) > 4 }""")
    lines = automaton_of([f], "M").splitlines()
    assert lines == ["initial S", "mode S [go(0)]", "mode S_2 [go(1)]", "mode S_3 [go(2)]",
                     "mode S_4 [go(2)]", "mode S_5 [go(2)]", "mode T [go(5)]",
                     "S -> S_2 when true", "S_2 -> S_3 when true", "S_3 -> S_4 when true",
                     "S_4 -> S_5 when true", "S_5 -> T when true"]


@pytest.mark.parametrize("body, events, words", [
    (" initial i0 state S { } transition t0 { from i0 to S condition $a }\n"
     " transition t1 { from i0 to S condition not $a action $go(1) }", "event a event b",
     "first cycle of M depends on its inputs"),
    (" initial i0 state S { } transition t0 { from i0 to S }", "event a: real",
     "typed input event a"),
    (" var x: real = 1 clock C initial i0 state S { } transition t0 { from i0 to S }\n"
     " transition t1 { from S to S exec condition since(C) > x }", "event a",
     "compared with something that is not a constant"),
    (" var x: real = 0 initial i0 state S { } transition t0 { from i0 to S }\n"
     " transition t1 { from S to S exec action x = x + 1; $go(x) }", "event a",
     "more than 5000 configurations"),
])
def test_machines_that_cannot_be_compiled_are_reported(tmp_path, body, events, words):
    f = machine_file(tmp_path, body, events)
    result = api.check([str(f)])
    (m,) = machines_of(list(result.workspace.user_files()), result.resolution)
    with pytest.raises(MachineError, match=words):
        compile_machine(MachineInterpreter(m))


def _export(tmp_path: Path, text: str, name: str) -> str:
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    report = Report()
    scenario = load_scenario(path, report)
    assert scenario is not None
    problem, _ = build_problem([EXAMPLES / "dcmotor"], scenario, report)
    assert problem is not None, [d.message for d in report.diagnostics]
    return render(problem, "x")


def test_dcmotor_export_under_sspeed_equals_the_hand_written_controller(tmp_path):
    machine = SCENARIO.read_text()
    assert "\n[controller]" not in machine
    hand = _export(tmp_path, machine + SSPEED_TABLE, "hand")
    compiled = _export(tmp_path, machine, "machine")
    renamed = hand.replace("cruise", "Cruise").replace("stopped", "Stopped").replace(
        "hand.toml", "machine.toml")
    assert compiled == renamed


def test_scenario_with_both_controller_and_machine_is_an_error(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('machine = "SSpeed"\n' + SCENARIO.read_text() + SSPEED_TABLE)
    report = Report()
    assert load_scenario(path, report) is None
    assert [d.code.id for d in report.diagnostics] == ["E-SCENARIO"]
    assert "either a [controller] or 'machine'" in report.diagnostics[0].message


def test_unknown_machine_is_reported(tmp_path, capsys):
    code = main(["gen", str(EXAMPLES / "dcmotor"), "--flowstar", "--scenario", str(SCENARIO),
                 "--machine", "SSped", "-o", str(tmp_path)])
    assert code == 1
    err = capsys.readouterr().err
    assert "no state machine 'SSped' among the files" in err and "SSpeed" in err
    assert list(tmp_path.iterdir()) == []


def test_machine_option_with_a_controller_table_is_an_error(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO.read_text() + SSPEED_TABLE)
    code = main(["gen", str(EXAMPLES / "dcmotor"), "--flowstar", "--scenario", str(path),
                 "--machine", "SSpeed", "-o", str(tmp_path / "out")])
    assert code == 1
    assert "the scenario has a [controller]" in capsys.readouterr().err


@needs_flowstar
@pytest.mark.parametrize("bound, verdict, code", [("20", "SAFE", 0), ("5", "UNSAFE", 1)])
def test_real_flowstar_verdicts_under_sspeed_match_the_hand_written_controller(
        tmp_path, capsys, bound, verdict, code):
    text = SCENARIO.read_text().replace('"Motor_av >= 20"', f'"Motor_av >= {bound}"')
    for name, scenario in (("machine", text), ("hand", text + SSPEED_TABLE)):
        path = tmp_path / f"{name}.toml"
        path.write_text(scenario)
        rc = main(["reach", str(EXAMPLES / "dcmotor"), "--scenario", str(path),
                   "--flowstar-bin", str(flowstar_binary()), "-o", str(tmp_path / name)])
        out = capsys.readouterr().out
        assert (rc, out.split(":")[0]) == (code, verdict), out


def test_marxbot_avoid_obstacle_scenario_is_driven_by_smovement(tmp_path):
    path = EXAMPLES / "marxbot" / "avoid_obstacle.toml"
    assert "\n[controller]" not in path.read_text()
    report = Report()
    scenario = load_scenario(path, report)
    problem, _ = build_problem([EXAMPLES / "marxbot"], scenario, report)
    assert problem is not None, [d.message for d in report.diagnostics]
    assert list(problem.effects) == ["Cruising", "Stopped", "Spinning",
                                     *(f"Spinning_{k}" for k in range(2, 63))]
    # move(0.1, 0) drives both wheels at lv/r = 3.996 rad per time unit; move(0, 0.5) turns
    # them at +-av*axis/(2r) = +-0.5994; stop() sets both to 0.
    assert float(problem.effects["Cruising"]["LMotor_das"]) == pytest.approx(0.1 / 0.025025)
    assert float(problem.effects["Spinning"]["RMotor_das"]) == pytest.approx(
        -0.5 * 0.06 / (2 * 0.025025))
    assert float(problem.effects["Stopped"]["LMotor_das"]) == 0


def test_obstacle_stop_under_sstop_exports_its_former_hand_written_table(tmp_path):
    # The table the scenario used to carry (Cruising: move(lv, 0), Stopped: stop(), on
    # obstacle) gives the same Flow* model, byte for byte, as the machine SStop.
    scenario = EXAMPLES / "marxbot" / "obstacle_stop.toml"
    text = scenario.read_text()
    assert "[controller]\ninitial" not in text and 'machine = "SStop"' in text
    table = tmp_path / "obstacle_stop.toml"
    table.write_text(text.replace('machine = "SStop"', "").replace(
        "[consts]\n", "[consts]\nlv = 0.1\n").replace("[unsafe]", controller(
            "Cruising", {"Cruising": ["move(lv, 0)"], "Stopped": ["stop()"]},
            [("Cruising", "Stopped", "obstacle")]) + "\n[unsafe]"))
    models = []
    for path, out in ((scenario, tmp_path / "machine"), (table, tmp_path / "table")):
        assert main(["gen", str(EXAMPLES / "marxbot"), "--flowstar", "--scenario", str(path),
                     "-o", str(out)]) == 0
        models.append((out / "obstacle_stop.model").read_text())
    assert models[0] == models[1]


COUNTED = """ var n: int = 0 var k: real = 0 var w: real = 1 clock C initial i0
 state A { entry $go(w) } state B { entry $go(2 * w) }
 transition t0 { from i0 to A }
 transition t1 { from A to B exec condition since(C) >= 2 action n = n + 1; #C }
 transition t2 { from B to A exec condition since(C) >= 2 action #C; k = n * 2 }"""


def test_a_counter_nothing_reads_is_left_out_of_the_automaton(tmp_path):
    # n counts the turns and k doubles it; neither is read by a guard or a call, so the
    # automaton is the one of the machine without them (it had a mode per value of n, past
    # 5000: refused). w is read by the calls: kept.
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    counted = automaton_of([machine_file(tmp_path / "a", COUNTED)], "M")
    plain = COUNTED.replace(" var n: int = 0 var k: real = 0", "").replace(
        " action n = n + 1; #C", " action #C").replace("; k = n * 2", "")
    assert counted == automaton_of([machine_file(tmp_path / "b", plain)], "M")
    # two cycles in each state (since(C) >= 2 first holds two cycles after the reset)
    assert counted.splitlines() == [
        "initial A", "mode A [go(1)]", "mode A_2 [go(1)]", "mode B [go(2)]", "mode B_2 [go(2)]",
        "A -> A_2 when true", "A_2 -> B when true", "B -> B_2 when true", "B_2 -> A when true"]


@pytest.mark.parametrize("reads, unread", [
    ("", {"n", "k"}),
    ("$go(k)", set()),                 # a call reads k, and k reads n
    ("$go(w) ; n = 0", {"n", "k"}),    # written only
])
def test_unread_variables_follow_what_guards_and_calls_read(tmp_path, reads, unread):
    from cyphy.semantics.machines.relevance import unread_variables
    body = COUNTED.replace("state B { entry $go(2 * w) }",
                           f"state B {{ entry $go(2 * w) {'; ' + reads if reads else ''} }}")
    result = api.check([str(machine_file(tmp_path, body))])
    assert not result.report.has_errors, [d.message for d in result.report.diagnostics]
    (m,) = machines_of(list(result.workspace.user_files()), result.resolution)
    assert unread_variables(m, {}) == unread
