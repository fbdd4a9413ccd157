"""RoboSim's cycle semantics (cyphy.semantics.machines.cycle) against traces computed by hand from
the rules in the module's docstring. Each machine is written for the test; each trace lists,
per cycle, the input events and the calls and output events expected."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import global_constants, machines_of
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter

INTERFACES = """\
interface OutI { go(x: real) halt() event done: real event ping }
interface InI { event near event dist: real }
"""


def interpreter(tmp_path: Path, body: str, consts: dict | None = None,
                name: str = "M", refused: str | None = None) -> MachineInterpreter:
    """The machine's interpreter; ``refused``: the one code ``check`` refuses it with (the
    interpreter is built all the same, to see that it refuses at run time too)."""
    f = tmp_path / "m.rst"
    f.write_text(INTERFACES + f"stm {name} {{\n input context {{ uses InI }}\n"
                 f" output context {{ requires OutI uses OutI }}\n{body}\n}}\n",
                 encoding="utf-8")
    result = api.check([str(f)])
    codes = [d.code.id for d in result.report.diagnostics if d.severity.value == "ERROR"]
    assert codes == ([refused] if refused else []), \
        [d.message for d in result.report.diagnostics]
    (m,) = machines_of(list(result.workspace.user_files()), result.resolution)
    return MachineInterpreter(m, {**global_constants(m, Scopes(result.workspace)),
                                  **(consts or {})})


def run(it: MachineInterpreter, trace: list[tuple[dict, tuple]]) -> None:
    for k, (events, expected) in enumerate(trace):
        assert it.cycle(events) == expected, f"cycle {k}"


def test_exec_transitions_wait_for_the_next_cycle(tmp_path):
    it = interpreter(tmp_path, """
 initial i0
 state A { entry $go(1) }
 state B { entry $go(2) }
 junction J
 transition t0 { from i0 to A }
 transition t1 { from A to J exec }
 transition t2 { from J to B condition $near }
 transition t3 { from J to A condition not $near }
 transition t4 { from B to A exec }""")
    run(it, [({}, (("go", (1.0,)),)),             # i0 -> A, then rests: t1 needs a cycle
             ({"near": None}, (("go", (1.0,)),)),  # A -> J -> A (absent is None)
             ({"near": True}, (("go", (2.0,)),)),  # A -> J -> B
             ({}, (("go", (1.0,)),)),              # B -> A
             ({"near": False}, (("go", (1.0,)),))])  # False: an untyped event is absent
    assert it.state == "A"


def test_transitions_without_exec_run_in_the_same_cycle_in_order(tmp_path):
    it = interpreter(tmp_path, """
 var n: int = 0
 initial i0
 state A { entry n = n + 1; $go(n) exit $halt() }
 state B { }
 transition t0 { from i0 to A }
 transition t1 { from A to B condition n >= 3 action $ping }
 transition t2 { from A to A condition n < 3 }""")
    # i0 -> A (n=1) -> A (n=2) -> A (n=3) -> B, all in the first cycle; self-transitions
    # exit and re-enter A.
    run(it, [({}, (("go", (1.0,)), ("halt", ()), ("go", (2.0,)), ("halt", ()), ("go", (3.0,)),
                   ("halt", ()), ("ping", ()))),
             ({}, ())])
    assert it.state == "B"


def test_clocks_count_cycles_times_the_cycle(tmp_path):
    it = interpreter(tmp_path, """
 cycleDef cycle == 0.5
 clock C
 initial i0
 state A { }
 state B { entry $done!since(C) }
 transition t0 { from i0 to A action #C }
 transition t1 { from A to B exec condition since(C) >= 1.5 }
 transition t2 { from B to A exec action #C }""")
    # since(C) is 0, 0.5, 1.0, 1.5 in cycles 0-3: B is entered in cycle 3.
    run(it, [({}, ())] * 3 + [({}, (("done", (1.5,)),)), ({}, ()), ({}, ()), ({}, ()),
                              ({}, (("done", (1.5,)),))])


def test_exec_and_wait_inside_actions_split_them_across_cycles(tmp_path):
    it = interpreter(tmp_path, """
 initial i0
 state A { }
 state B { entry $go(9) }
 transition t0 { from i0 to A }
 transition t1 { from A to B action $go(1); exec; $go(2); wait(2); $go(3) }""")
    run(it, [({}, (("go", (1.0,)),)), ({}, (("go", (2.0,)),)), ({}, ()),
             ({}, (("go", (3.0,)), ("go", (9.0,)))), ({}, ())])


def test_event_values_bind_and_during_actions_run_each_cycle(tmp_path):
    it = interpreter(tmp_path, """
 var d: real = 0
 var k: int = 0
 initial i0
 state A { during k = k + 1 }
 transition t0 { from i0 to A }
 transition t1 { from A to A exec condition $dist?d /\\ d < 1 action $done!(d + k) }""")
    # cycle 0: enter A, during k=1. cycle 1: during k=2, dist absent. cycle 2: during k=3,
    # dist 0.25 binds d: t1 sends 3.25, re-enters A (during k=4).
    run(it, [({}, ()), ({"dist": None}, ()), ({"dist": 0.25}, (("done", (3.25,)),)),
             ({"dist": 2.0}, ())])
    assert it.variables["k"] == 5 and it.variables["d"] == 0.25


def test_composite_states_enter_their_initial_junction_and_outer_transitions_win(tmp_path):
    it = interpreter(tmp_path, """
 initial i0
 state Outer {
   entry $go(1)
   exit $go(-1)
   initial j0
   state In { entry $go(2) exit $go(-2) }
   transition u0 { from j0 to In }
   transition u1 { from In to In exec action $ping }
 }
 state Done { }
 transition t0 { from i0 to Outer }
 transition t1 { from Outer to Done exec condition $near }""")
    run(it, [({}, (("go", (1.0,)), ("go", (2.0,)))),
             ({}, (("go", (-2.0,)), ("ping", ()), ("go", (2.0,)))),
             ({"near": True}, (("go", (-2.0,)), ("go", (-1.0,))))])
    assert it.state == "Done"


def test_reset_starts_again(tmp_path):
    it = interpreter(tmp_path, """
 var n: int = 0
 initial i0
 state A { entry n = n + 1; $go(n) }
 transition t0 { from i0 to A }
 transition t1 { from A to A exec }""")
    run(it, [({}, (("go", (1.0,)),)), ({}, (("go", (2.0,)),))])
    it.reset()
    run(it, [({}, (("go", (1.0,)),))])


def test_configurations_restore_the_run(tmp_path):
    it = interpreter(tmp_path, """
 var n: int = 0
 clock C
 initial i0
 state A { entry n = n + 1; $go(n) }
 transition t0 { from i0 to A }
 transition t1 { from A to A exec condition since(C) > 1 action #C }""")
    it.cycle({})
    it.cycle({})
    saved = it.configuration()
    first = [it.cycle({}) for _ in range(3)]
    it.restore(saved)
    assert [it.cycle({}) for _ in range(3)] == first


def test_constant_without_value_and_loops_are_errors(tmp_path):
    with pytest.raises(MachineError, match="the constant k of M has no value"):
        interpreter(tmp_path, " const k: real\n initial i0\n state A { }\n"
                    " transition t0 { from i0 to A }")
    it = interpreter(tmp_path, " const k: real\n initial i0\n state A { entry $go(k) }\n"
                     " transition t0 { from i0 to A }", {"k": 4})
    assert it.cycle({}) == (("go", (4.0,)),)
    # check refuses the loop without exec (STM13); run all the same, the interpreter too
    loop = interpreter(tmp_path, " initial i0\n state A { }\n transition t0 { from i0 to A }\n"
                       " transition t1 { from A to A }", refused="STM13")
    with pytest.raises(MachineError, match="without ending its cycle"):
        loop.cycle({})


def test_example_dcmotor_speed_machine():
    result = api.check([str(EXAMPLES / "dcmotor")])
    (m,) = machines_of(list(result.workspace.user_files()), result.resolution)
    it = MachineInterpreter(m)
    # Cruise re-entered every cycle (drive again) until near; then stop, and nothing more.
    assert [it.cycle({"near": e}) for e in (None, None, True, None, True)] == [
        (("drive", (10.0,)),), (("drive", (10.0,)),), (("stop", ()),), (), ()]


@needs_corpus
def test_corpus_smovement_turns_for_pi_over_av_cycles():
    result = api.check([str(CORPUS / "marXbot" / "Movement.rst"),
                        str(CORPUS / "marXbot" / "marXbotSoftware.rst")])
    (m,) = machines_of(list(result.workspace.user_files()), result.resolution)
    it = MachineInterpreter(m, {"PI": 3.0, "lv": 0.1, "av": 1.0})
    outputs = [it.cycle({"obstacle": True if k == 2 else None}) for k in range(7)]
    # Obstacle in cycle 2: stop (MBC reset); cycle 3 turn (MBC = 1); since(MBC) reaches
    # PI/av = 3 in cycle 5: forward again.
    assert outputs == [(("move", (0.1, 0.0)),), (), (("stop", ()),), (("move", (0.0, 1.0)),),
                       (), (("move", (0.1, 0.0)),), ()]


def test_api_entry_point_builds_the_example_machine(tmp_path):
    it, checked = api.machine_interpreter([str(EXAMPLES / "marxbot")], pmodel="marXbotBase")
    assert it is not None and it.machine.name == "SMovement"
    assert it.cycle({"obstacle": None}) == (("move", (0.1, 0.0)),)
    missing, checked = api.machine_interpreter([str(EXAMPLES / "marxbot")], name="Nope")
    assert missing is None
    assert [d.code.id for d in checked.report.diagnostics] == ["E-MACHINE"]
    assert "SMovement" in checked.report.diagnostics[0].hint
