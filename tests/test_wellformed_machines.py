"""State machines, STM1-STM7: for each condition a small machine that violates it, with the
diagnostic's code, span and exit status, and the same machine corrected (no diagnostic).
The machines are written for the test."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.cli import main

HEADER = """\
interface MoveI { move(lv: real) halt() }
interface SenseI { event near event far }
interface OtherI { beep() }
module Mod {
  robotic platform P { provides MoveI uses SenseI }
  cref c = Ctrl connection P on near to c on near connection P on far to c on far
}
controller Ctrl { uses SenseI requires MoveI sref s = M
  connection Ctrl on near to s on near connection Ctrl on far to s on far }
"""
HEADER_LINES = HEADER.count("\n")

GOOD = """\
stm M {
  const v: real = 1
  var x: real = 0
  clock C
  input context { uses SenseI }
  output context { requires MoveI }
  initial i0
  state A { entry $move(v); #C }
  state B { entry $halt() }
  junction J
  transition t0 { from i0 to A }
  transition t1 { from A to J exec }
  transition t2 { from J to B condition $near /\\ since(C) > 1 action x = x + 1 }
  transition t3 { from J to A condition not ($near /\\ since(C) > 1) }
  transition t4 { from B to A exec }
}
"""


def diagnostics(tmp_path: Path, machine: str, header: str = HEADER
                ) -> list[tuple[str, int, int, str]]:
    f = tmp_path / "m.rst"
    f.write_text(header + machine, encoding="utf-8")
    result = api.check([str(f)], api.CheckOptions(consistency=True))
    return [(d.code.id, d.span.line - HEADER_LINES, d.span.column, d.message)
            for d in result.report.diagnostics]


def codes_of(found: list[tuple[str, int, int, str]]) -> list[str]:
    return [c for c, *_ in found]


def test_a_correct_machine_has_no_diagnostic(tmp_path):
    assert diagnostics(tmp_path, GOOD) == []


def test_stm1_transition_to_an_unknown_state(tmp_path):
    found = diagnostics(tmp_path, GOOD.replace("from B to A exec", "from B to Nowhere exec"))
    assert found == [("STM1", 15, 29, "transition t4: 'Nowhere' is not a state or junction "
                      "of machine M")]


def test_stm1_ends_resolve_in_the_composite_state_that_declares_them(tmp_path):
    nested = GOOD.replace("state B { entry $halt() }",
                          "state B { initial k state In {} transition u { from k to In } "
                          "transition w { from In to A } }")
    found = diagnostics(tmp_path, nested)
    assert [(c, line) for c, line, _, _ in found] == [("STM1", 9)]
    assert "'A' is not a state or junction of state B" in found[0][3]


def test_stm2_no_initial_junction(tmp_path):
    found = diagnostics(tmp_path, GOOD.replace("  initial i0\n", "").replace(
        "  transition t0 { from i0 to A }\n", ""))
    assert found == [("STM2", 1, 1, "machine M has no initial junction")]


def test_stm3_call_of_an_operation_the_platform_does_not_provide(tmp_path):
    machine = GOOD.replace("requires MoveI }", "requires MoveI requires OtherI }").replace(
        "entry $halt()", "entry $beep()")
    header = HEADER.replace("requires MoveI sref", "requires MoveI requires OtherI sref")
    found = diagnostics(tmp_path, machine, header)
    assert found == [("STM3", 9, 19, "entry action of B: the robotic platform P of module "
                      "Mod does not provide the operation beep")]


def test_stm12_a_machine_calls_an_operation_its_controller_does_not_require(tmp_path):
    """The machine requires OtherI, its controller does not (and the platform does not
    provide it: STM3 too); the hint is the controller's missing line."""
    machine = GOOD.replace("requires MoveI }", "requires MoveI requires OtherI }").replace(
        "entry $halt()", "entry $beep()")
    f = tmp_path / "m.rst"
    f.write_text(HEADER + machine, encoding="utf-8")
    diags = api.check([str(f)]).report.diagnostics
    found = [(d.code.id, d.span.line - HEADER_LINES, d.span.column) for d in diags]
    assert sorted(found) == [("STM12", 9, 19), ("STM3", 9, 19)]
    stm12 = next(d for d in diags if d.code.id == "STM12")
    assert stm12.message == ("entry action of B: machine M calls beep of interface OtherI, "
                                "which its controller Ctrl does not require: the controller "
                                "passes the machine only what it requires itself")
    assert stm12.hint == "add 'requires OtherI' to controller Ctrl, as machine M has it " \
        f"(line {HEADER_LINES + 6})"


def test_stm3_call_outside_the_output_context_and_wrong_arity(tmp_path):
    found = diagnostics(tmp_path, GOOD.replace("entry $halt()", "entry $beep(); $move(1, 2)"))
    assert codes_of(found) == ["STM3", "STM3"]
    assert "'beep' is not an operation of the output context of M" in found[0][3]
    assert "move takes 1 argument, not 2" in found[1][3]


def test_stm4_unknown_event(tmp_path):
    found = [d for d in diagnostics(tmp_path, GOOD.replace("condition $near /\\",
                                                           "condition $nea /\\"))
             if d[0] != "STM7"]  # t2 and t3 no longer read the same event
    assert len(found) == 1 and found[0][:3] == ("STM4", 13, 41)
    assert "'nea' is not an input event of M" in found[0][3]


def test_stm5_unknown_names_clock_resets_and_constants_assigned(tmp_path):
    machine = GOOD.replace("action x = x + 1", "action v = y; #D").replace(
        "since(C) > 1)", "C > 1)")
    found = sorted((d for d in diagnostics(tmp_path, machine) if d[0] != "STM7"),
                   key=lambda d: (d[1], d[2]))
    assert [(c, line) for c, line, _, _ in found] == [("STM5", 13)] * 3 + [("STM5", 14)]
    messages = " | ".join(m for *_, m in found)
    assert "unknown name 'y'" in messages and "'#D' resets no clock" in messages
    assert "'v' is a constant" in messages and "the clock C is read as a value" in messages


def test_stm6_unreachable_state_is_a_warning(tmp_path):
    found = diagnostics(tmp_path, GOOD.replace("  junction J\n", "  junction J\n  state Lost {}\n"))
    assert found == [("STM6", 11, 3, "state Lost of M is unreachable: no transition path "
                      "from the initial junction enters it")]


def test_stm7_junction_that_can_get_stuck_or_choose(tmp_path):
    machine = GOOD.replace("condition not ($near /\\ since(C) > 1)", "condition $far")
    found = diagnostics(tmp_path, machine)
    assert codes_of(found) == ["STM7", "STM7"]
    assert "no transition leaving it is enabled" in found[0][3]
    assert "t2 and t3 can be enabled at once" in found[1][3]


def test_stm7_conditions_over_unknown_constants_are_decided(tmp_path):
    # since(C) < k/a and since(C) >= k/a: exhaustive and exclusive whatever k and a (a != 0).
    machine = GOOD.replace("const v: real = 1", "const v: real = 1, k: real, a: real").replace(
        "$near /\\ since(C) > 1 action", "since(C) < k/a action").replace(
        "not ($near /\\ since(C) > 1)", "since(C) >= k/a")
    # k and a are open (a family of machines): STM15 says simulate and reach need them
    assert [(code, name) for code, _, _, message in diagnostics(tmp_path, machine)
            for name in "ka" if f"constant {name} read" in message] == \
        [("STM15", "k"), ("STM15", "a")]
    assert [d for d in diagnostics(tmp_path, machine) if d[0] != "STM15"] == []


def test_bad_machine_exits_1_with_spans(tmp_path, capsys):
    f = tmp_path / "m.rst"
    f.write_text(HEADER + GOOD.replace("to Nowhere", "").replace("from B to A exec",
                                                                 "from B to Nowhere exec"))
    assert main(["check", str(f)]) == 1
    out = capsys.readouterr().err
    assert f"m.rst:{HEADER_LINES + 15}:29: ERROR STM1" in out


def test_examples_machines_are_well_formed():
    for folder in ("dcmotor", "marxbot"):
        result = api.check([str(EXAMPLES / folder)])
        assert [d.code.id for d in result.report.diagnostics] == [], folder


@needs_corpus
def test_corpus_machine_has_no_machine_diagnostic():
    result = api.check([str(CORPUS / "marXbot")])
    found = [d for d in result.report.diagnostics if d.code.id.startswith("STM")]
    # but the warnings that SMovement's PI, lv and av are open (the paper's family)
    assert [(d.code.id, d.message.split()[2]) for d in found] == \
        [("STM15", "PI"), ("STM15", "lv"), ("STM15", "av")]


def test_junction_conditions_are_checked_only_with_consistency(tmp_path):
    f = tmp_path / "m.rst"
    f.write_text(HEADER + GOOD.replace("condition not ($near /\\ since(C) > 1)",
                                       "condition $far"), encoding="utf-8")
    assert api.check([str(f)]).report.diagnostics == []
    found = api.check([str(f)], api.CheckOptions(consistency=True)).report.diagnostics
    assert [d.code.id for d in found] == ["STM7", "STM7"]


def test_rules_are_listed(capsys):
    assert main(["check", "--list-rules"]) == 0
    listed = [line.split()[0] for line in capsys.readouterr().out.splitlines()]
    assert [r for r in listed if r.startswith("STM")] == [f"STM{i}" for i in range(1, 16)]


@pytest.mark.parametrize("rule", ["STM6", "STM7"])
def test_behaviour_rules_are_warnings(rule):
    from cyphy.wellformed import RULES

    assert RULES[rule].code.severity.value == "WARNING"


# ---------------------------------------------------------------- STM10, STM11: the module
TWO = """\
const PERIOD: real = {period}
interface SenseI { event near }
module Mod {
  {module_cycle}
  robotic platform P { uses SenseI }
  cref c = Ctrl
  connection P on near to c on near
}
controller Ctrl {
  uses SenseI
  {controller_links}
  stm A {
    cycleDef cycle == 1
    input context { uses SenseI }
    initial i0 state S {} transition t0 { from i0 to S }
    transition t1 { from S to S exec condition $near }
  }
  stm B {
    cycleDef cycle == PERIOD
    input context { uses SenseI }
    initial i0 state S {} transition t0 { from i0 to S }
  }
}
"""
LINKS = "connection Ctrl on near to A on near"


def _module(tmp_path: Path, module_cycle: str = "", period: str = "1",
            controller_links: str = LINKS) -> list[tuple[str, int, int, str]]:
    f = tmp_path / "m.rst"
    f.write_text(TWO.replace("{module_cycle}", module_cycle).replace("{period}", period)
                 .replace("{controller_links}", controller_links), encoding="utf-8")
    return [(d.code.id, d.span.line, d.span.column, d.message)
            for d in api.check([str(f)]).report.diagnostics]


def test_machines_of_one_cycle_pass(tmp_path):
    assert _module(tmp_path) == []
    assert _module(tmp_path, "cycleDef cycle == 1", "1.0") == []


def test_a_machine_whose_period_constant_differs_is_refused_at_its_cycledef(tmp_path):
    """Without a module cycleDef the first machine's period is the reference; B's period
    is a constant of the package, evaluated."""
    found = _module(tmp_path, period="3")
    assert [(c, line, col) for c, line, col, _ in found] == [("STM10", 19, 23)]
    assert "machine B is 3 time units, but machine A's is 1" in found[0][3]


def test_a_module_cycle_is_the_reference(tmp_path):
    found = _module(tmp_path, "cycleDef cycle == 2", "2")
    assert [(c, line) for c, line, *_ in found] == [("STM10", 13)]
    assert "machine A is 1 time units, but module Mod's is 2" in found[0][3]


def test_an_event_the_controller_does_not_pass_on_is_a_warning_at_the_read(tmp_path):
    found = _module(tmp_path, controller_links="")
    assert [(c, line, col) for c, line, col, _ in found] == [("STM11", 16, 48)]
    assert "controller Ctrl has no connection" in found[0][3]
    from cyphy.wellformed import RULES

    assert RULES["STM11"].code.severity.value == "WARNING"
