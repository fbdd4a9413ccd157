"""Operation definitions and output events under RoboSim's cycle semantics (issue 18): the
syntax, the checks, one semantic step of each construct and cycle traces computed by hand
from the rules in ``cyphy/semantics/machines/cycle.py``'s docstring; then a d-model that calls an
operation definition and sends a mapped and an unmapped output event, driving the dcmotor
bench in ``cyphy simulate`` (against the equivalent hand-written ``[controller]`` table) and
in the Flow* export (against the automaton worked out by hand) and the real Flow*."""

from __future__ import annotations

import csv
import io
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES, flowstar_binary, needs_flowstar
from cyphy import api
from cyphy import expr as ex
from cyphy.cli import main
from cyphy.lang import ast
from cyphy.lang.parser import parse_text
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import global_constants, machines_of, operation_definitions
from cyphy.semantics.machines.cycle import MAX_DEPTH, MachineError, MachineInterpreter
from cyphy.semantics.machines.interpreters import interpreter_for
from cyphy.semantics.machines.automaton import compile_machine, describe

INTERFACES = """\
interface OutI { go(x: real) halt() event done: real event ping }
interface InI { event near }
"""


def interpreter(tmp_path: Path, text: str, name: str = "M") -> MachineInterpreter:
    f = tmp_path / "m.rst"
    f.write_text(INTERFACES + text, encoding="utf-8")
    result = api.check([str(f)])
    assert not result.report.has_errors, [d.message for d in result.report.diagnostics]
    files = list(result.workspace.user_files())
    (m,) = [m for m in machines_of(files, result.resolution) if m.name == name]
    scopes = Scopes(result.workspace)
    ops = operation_definitions(m, files, result.resolution, scopes)
    return MachineInterpreter(m, global_constants(m, scopes), operations=ops)


def machine(body: str, name: str = "M") -> str:
    return (f"stm {name} {{\n input context {{ uses InI }}\n"
            f" output context {{ requires OutI uses OutI }}\n{body}\n}}\n")


BLINK = """\
operation Blink(n: real) {
 var k: real = 0
 output context { requires OutI uses OutI }
 initial j0
 state On { entry $go(n + k); k = k + 1 }
 final F
 transition a { from j0 to On }
 transition b { from On to On exec condition k < 2 }
 transition c { from On to F condition k >= 2 action $ping }
}
"""


# ----------------------------------------------------------------------------- syntax

def test_operation_definitions_and_output_events_parse():
    f = parse_text(INTERFACES + BLINK + machine(
        " initial i0 state A { entry Blink(1); $done!2; $ping }\n"
        " transition t0 { from i0 to A }"), "m.rst").file
    op = next(i for i in f.items if isinstance(i, ast.StateMachine) and i.kind == "operation")
    assert [p.name for p in op.params] == ["n"]
    assert [n.kind for n in op.nodes] == ["initial", "final"]
    stm = next(i for i in f.items if isinstance(i, ast.StateMachine) and i.kind == "stm")
    call, send, ping = stm.states[0].actions("entry")
    assert isinstance(call, ast.CallStatement) and isinstance(call.call.func, ex.Name)
    assert isinstance(send, ast.SendStatement) and send.event.name == ("done",)
    assert isinstance(ping, ast.CallStatement) and isinstance(ping.call, ex.PlatformRef)


# ----------------------------------------------------------------------------- checks

def _check(tmp_path: Path, text: str) -> list[tuple[str, str, int]]:
    f = tmp_path / "m.rst"
    f.write_text(INTERFACES + text, encoding="utf-8")
    result = api.check([str(f)])
    return [(d.code.id, d.message, d.span.line) for d in result.report.diagnostics]


def test_a_call_of_an_operation_definition_checks_its_arguments(tmp_path, capsys):
    assert _check(tmp_path, BLINK + machine(
        " initial i0 state A { entry Blink(1) } transition t0 { from i0 to A }")) == []
    f = tmp_path / "bad.rst"
    f.write_text(INTERFACES + BLINK + machine(
        " initial i0 state A { entry Blink(1, 2) } transition t0 { from i0 to A }"))
    assert main(["check", str(f)]) == 1
    err = capsys.readouterr().err
    assert "bad.rst:16:29: ERROR STM3: entry action of A: operation Blink takes 1 argument, " \
           "not 2" in err and "hint: write Blink(n)" in err


def test_operation_definitions_are_checked_as_machines(tmp_path):
    # A behaviour without an initial junction (STM2) and a transition to an unknown node
    # (STM1) inside an operation definition; a definition without behaviour is a
    # declaration only and is left alone.
    found = _check(tmp_path, "operation Op(x: real) {\n state S { }\n"
                   " transition t { from S to T }\n}\n"
                   "operation Declared() { terminates }\n")
    assert sorted((c, line) for c, _, line in found) == [("STM1", 5), ("STM2", 3)]
    messages = sorted(m for _, m, _ in found)
    assert messages == ["operation Op has no initial junction",
                        "transition t: 'T' is not a state or junction of operation Op"]


# ----------------------------------------------------------------------------- semantics

def test_a_call_runs_the_operation_inline_across_its_exec(tmp_path):
    it = interpreter(tmp_path, BLINK + machine("""
 initial i0
 state A { entry Blink(10); $halt() }
 state B { }
 transition t0 { from i0 to A }
 transition t1 { from A to B exec action $done!3 }"""))
    # Cycle 0: i0 -> A; A's entry calls Blink(10): j0 -> On, go(10 + 0), k = 1; On's exec
    # transition b must wait, c does not hold: the cycle ends inside the operation.
    assert it.cycle({}) == (("go", (10.0,)),)
    assert (it.running, it.node, it.configuration().stack[0].node) == ("Blink", "On", "A")
    # Cycle 1: b re-enters On (go(11), k = 2), c holds: ping, final F, the call returns and
    # A's entry goes on (halt). t1 is an exec transition and A was entered in this cycle's
    # action (not rested in since the last cycle): it waits.
    assert it.cycle({}) == (("go", (11.0,)), ("ping", ()), ("halt", ()))
    assert (it.running, it.node, it.configuration().stack) == (None, "A", ())
    assert it.cycle({}) == (("done", (3.0,)),)
    assert it.cycle({}) == ()
    assert it.state == "B"


def test_an_operation_without_exec_returns_in_the_same_cycle(tmp_path):
    it = interpreter(tmp_path, """
operation Twice(x: real) {
 output context { requires OutI }
 initial j0
 final F
 transition a { from j0 to F action $go(x); $go(2*x) }
}
""" + machine("""
 var v: real = 1
 initial i0
 state A { entry Twice(v); v = v + 1 }
 transition t0 { from i0 to A }
 transition t1 { from A to A exec }"""))
    assert [it.cycle({}) for _ in range(3)] == [
        (("go", (1.0,)), ("go", (2.0,))), (("go", (2.0,)), ("go", (4.0,))),
        (("go", (3.0,)), ("go", (6.0,)))]
    assert it.variables == {"v": 4}


def test_nested_calls_and_the_operation_reads_the_cycles_events(tmp_path):
    it = interpreter(tmp_path, """
operation Inner(y: real) {
 output context { requires OutI }
 input context { uses InI }
 initial j0
 state W { }
 final F
 transition a { from j0 to W }
 transition b { from W to F exec condition $near action $go(y) }
}
operation Outer(x: real) {
 output context { requires OutI }
 initial j0
 final F
 transition a { from j0 to F action Inner(x + 1); $go(x) }
}
""" + machine("""
 initial i0
 state A { }
 state B { }
 transition t0 { from i0 to A action Outer(5) }
 transition t1 { from A to B exec }"""))
    # Inner waits in W for near (an exec transition); the stack is M (t0's action), Outer.
    assert it.cycle({}) == ()
    assert [f.running for f in it.configuration().stack] == [None, "Outer"]
    assert it.cycle({"near": None}) == ()
    # near: Inner sends go(6) and returns; Outer sends go(5) and returns; t0 enters A.
    assert it.cycle({"near": True}) == (("go", (6.0,)), ("go", (5.0,)))
    assert (it.running, it.node) == (None, "A")
    assert it.cycle({}) == () and it.state == "B"


def test_operation_clocks_count_cycles_and_configurations_restore(tmp_path):
    it = interpreter(tmp_path, """
operation Hold() {
 output context { requires OutI }
 clock H
 initial j0
 state S { }
 final F
 transition a { from j0 to S }
 transition b { from S to F exec condition since(H) >= 2 action $go(since(H)) }
}
""" + machine("""
 clock C
 initial i0
 state A { entry Hold(); $done!since(C) }
 transition t0 { from i0 to A }
 transition t1 { from A to A exec }"""))
    # The call starts H at 0 in cycle 0; b holds in cycle 2 (H = 2): go(2), then the
    # machine's clock C (also 2) is sent; t1 re-enters A in cycle 3 and calls Hold again.
    assert it.cycle({}) == ()
    saved = it.configuration()
    rest = [it.cycle({}) for _ in range(4)]
    assert rest == [(), (("go", (2.0,)), ("done", (2.0,))), (), ()]
    it.restore(saved)
    assert [it.cycle({}) for _ in range(4)] == rest


def test_recursion_without_end_and_a_call_of_nothing_are_errors(tmp_path):
    it = interpreter(tmp_path, """
operation Loop() {
 initial j0
 state S { entry Loop() }
 transition a { from j0 to S }
}
""" + machine(" initial i0 state A { entry Loop() } transition t0 { from i0 to A }"))
    with pytest.raises(MachineError, match=f"more than {MAX_DEPTH} operation calls"):
        it.cycle({})


# ----------------------------------------------------------------------------- the bench

SOFTWARE = """\
package rampSoftware

interface SpeedI { drive(w: real) }
interface NearI { event near }
interface SignalI { event brake: real }
// Not an event of the platform, so the mapping cannot map it: observable only.
interface AlarmI { event alarm }

module RampSoftware {
\tcycleDef cycle == 1
\trobotic platform Bench { provides SpeedI uses NearI uses SignalI }
\tcref ctrl = RampController
\tconnection Bench on near to ctrl on near (_async)
}

controller RampController {
\tcycleDef cycle == 1
\tuses NearI requires SpeedI uses SignalI
\tsref sm = SRamp
\tconnection RampController on near to sm on near
}

// Half the speed for one cycle, then the full speed.
operation Ramp(w: real) {
\toutput context { requires SpeedI }
\tvar k: real = 0
\tinitial j0
\tstate Step { entry k = k + 1; $drive(w*k/2) }
\tfinal Done
\ttransition a { from j0 to Step }
\ttransition b { from Step to Step exec condition k < 2 }
\ttransition c { from Step to Done condition k >= 2 }
}

stm SRamp {
\tcycleDef cycle == 1
\tinput context { uses NearI }
\toutput context { requires SpeedI uses SignalI uses AlarmI }
\tinitial i0
\tstate Start { entry Ramp(10) }
\tstate Cruising { }
\tjunction Check
\tstate Stopped { }
\ttransition t0 { from i0 to Start }
\ttransition t1 { from Start to Cruising }
\ttransition t2 { from Cruising to Check exec }
\ttransition t3 { from Check to Cruising condition not $near }
\ttransition t4 { from Check to Stopped condition $near action $brake!0; $alarm }
}
"""

MAPPING = """\
package rampMapping
import dcMotorBase::*
import rampSoftware::*
map RampMapping dmodel RampSoftware to pmodel DCMotorBase {
\toperation drive { equation Bench::Shaft::Motor.das == w }
\toutput event brake ? x { equation Bench::Shaft::Motor.das == x }
\tinput event near { predicate Bench::Range.range <= 1.0 }
}
"""

# What the machine does, as the hand-written table it amounts to (the first cycle calls
# drive(5), the second drive(10) and the mapped brake!0 sets the speed to 0): the distance
# is far above 1 m at t = 0.1, so `not near` is the first cycle's transition.
TABLE = """\
[controller]
initial = "Ramp"
[controller.states.Ramp]
calls = ["drive(5)"]
[controller.states.Cruising]
calls = ["drive(10)"]
[controller.states.Stopped]
calls = ["drive(0)"]
[[controller.transitions]]
from = "Ramp"
to = "Cruising"
when = "not near"
[[controller.transitions]]
from = "Cruising"
to = "Stopped"
when = "near"
"""


@pytest.fixture()
def bench(tmp_path: Path) -> Path:
    folder = tmp_path / "ramp"
    folder.mkdir()
    shutil.copy(EXAMPLES / "dcmotor" / "DCMotorBase.rsm", folder)
    (folder / "Software.rsm").write_text(SOFTWARE)
    (folder / "Mapping.rsm").write_text(MAPPING)
    text = (EXAMPLES / "dcmotor" / "sampled_stop.toml").read_text()
    (folder / "ramp.toml").write_text(text.replace("max_jumps = 25\n", ""))
    (tmp_path / "table.toml").write_text(text.replace("[unsafe]", TABLE + "\n[unsafe]"))
    return folder


def test_the_bench_machine_compiles_to_the_automaton_worked_out_by_hand(bench):
    result = api.check([str(bench)])
    assert not result.report.has_errors
    files = list(result.workspace.user_files())
    (m,) = machines_of(files, result.resolution)
    it = interpreter_for(m, files, result.resolution, Scopes(result.workspace),
                         pmodel="DCMotorBase")
    # brake has a mapping; alarm, an event the platform does not use, has none.
    assert it.observable == {"alarm"} and list(it.operations) == ["Ramp"]
    # The first cycle rests inside Ramp (Step, drive(5)); the second returns and rests in
    # Cruising (drive(10), held while nothing is called); near: brake(0), alarm left out.
    assert describe(compile_machine(it)).splitlines() == [
        "initial Ramp_Step", "mode Ramp_Step [drive(5)]", "mode Cruising [drive(10)]",
        "mode Stopped [brake(0)]", "Ramp_Step -> Cruising when true",
        "Cruising -> Stopped when near"]


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def test_simulate_runs_the_operation_applies_the_mapped_event_and_records_the_other(
        bench, capsys):
    fine = ["--samples", "41", "--rtol", "1e-9", "--atol", "1e-12"]
    assert main(["simulate", str(bench), "--scenario", str(bench / "ramp.toml"),
                 "--format", "json", *fine]) == 0
    out = json.loads(capsys.readouterr().out)
    # The distance falls from 3.05 at 2 m/s: range <= 1 first sampled at t = 1.1.
    assert [(round(e["t"], 9), e["name"], e["values"]) for e in out["events"]] == [
        (1.1, "alarm", [])]
    assert main(["simulate", str(EXAMPLES / "dcmotor"), "--scenario",
                 str(bench.parent / "table.toml"), *fine]) == 0
    table = _csv(capsys.readouterr().out)
    for name in ("Motor_av", "Motor_i", "Range_distance"):
        assert np.allclose(out["columns"][name], table[name], rtol=0, atol=1e-9), name
    # The ramp is visible: the speed error's integral grows by (5 - av) then (10 - av).
    assert 0 < out["columns"]["Motor_av"][2] < 5


@needs_flowstar
def test_real_flowstar_proves_the_bench_under_the_ramp_machine_safe(bench, capsys):
    assert main(["reach", str(bench), "--scenario", str(bench / "ramp.toml"),
                 "--flowstar-bin", str(flowstar_binary()), "-o",
                 str(bench / "out")]) == 0
    assert capsys.readouterr().out.startswith("SAFE")
    model = (bench / "out" / "ramp.model").read_text()
    assert "Ramp_Step -> Cruising" in model and "Cruising -> Stopped" in model


def test_calls_and_operation_clocks_compile_to_the_automaton_worked_out_by_hand(tmp_path):
    it = interpreter(tmp_path, """
operation Hold(n: real) {
 output context { requires OutI }
 clock H
 initial j0
 state S { }
 final F
 transition a { from j0 to S action $go(n) }
 transition b { from S to F exec condition since(H) >= 2 }
}
""" + machine("""
 initial i0
 state A { entry Hold(1); $go(7) }
 state B { entry Hold(3) }
 transition t0 { from i0 to A }
 transition t1 { from A to B exec condition $near }
 transition t2 { from B to A exec }"""))
    # Each call rests in Hold's S for the cycles with since(H) = 0 and 1 (two modes, the
    # second holding the call's go), returns when since(H) = 2 (A sends go(7) after it);
    # B -> A calls Hold(1) again: back to the first configuration (H saturates at 3).
    assert describe(compile_machine(it)).splitlines() == [
        "initial Hold_S", "mode Hold_S [go(1)]", "mode Hold_S_2 [go(1)]", "mode A [go(7)]",
        "mode Hold_S_3 [go(3)]", "mode Hold_S_4 [go(3)]", "mode B [go(3)]",
        "Hold_S -> Hold_S_2 when true", "Hold_S_2 -> A when true", "A -> Hold_S_3 when near",
        "Hold_S_3 -> Hold_S_4 when true", "Hold_S_4 -> B when true", "B -> Hold_S when true"]


def test_show_dmodel_lists_operation_definitions(tmp_path, capsys):
    f = tmp_path / "m.rst"
    f.write_text(INTERFACES + BLINK + machine(
        " initial i0 state A { entry Blink(1) } transition t0 { from i0 to A }"))
    assert main(["show", str(f), "--dmodel", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [m["name"] for m in data["machines"]] == ["M"]
    (op,) = data["operation_definitions"]
    assert op["name"] == "Blink" and op["parameters"] == [{"name": "n", "type": "real"}]
    assert op["constants"] == [] and op["variables"] == [
        {"name": "k", "type": "real", "value": "0"}]
    assert op["finals"] == ["F"] and [t["name"] for t in op["transitions"]] == ["a", "b", "c"]
    assert main(["show", str(f), "--dmodel"]) == 0
    assert "operation Blink(n: real)\n  variable k: real = 0\n" in capsys.readouterr().out
