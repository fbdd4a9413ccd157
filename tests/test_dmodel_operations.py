"""Operation definitions in the theory's ``D`` when the cycle is written out
(:mod:`cyphy.semantics.circus.dmodel_cycle`): a call runs the operation inline, its
parameters, variables and clocks fields of D's state set at the call, the caller waiting
with the rest of its action while the operation rests or is cut by ``exec``/``wait``, and
the operation's top-level final state returning to it in the same cycle. Before, such a
machine had no ``D`` ("D for typed events does not run operation definitions",
``W-SEMANTICS-DMODEL``).

Oracles: ``simulate`` (the machine's interpreter and the model's equations, never the
theory) for ``animate`` (the theory's text), and the demands worked out by hand from the
cycle rules of ``cyphy/semantics/machines/cycle.py``; and, on small machines, the
interpreter stepped directly against D's actions run on the same random events.

A machine without operation definitions keeps its ``D`` byte for byte: checked by
``python3 benchmarks/compare_outputs.py main HEAD`` (the examples and the corpus) and by
the other ``tests/test_dmodel_*.py`` files, which compare ``D``'s text."""

from __future__ import annotations

import random
import shutil
from pathlib import Path

import numpy as np
import pytest

from cyphy import api
from dmodel_runs import RunD, animated_as_simulated, bench, written_session
from test_dmodel_clock_loop import SCENARIO as CLOCK_PULSE_SCENARIO
from cyphy.cli import main
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import machines_of
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel_cycle import cycle_process
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter
from cyphy.semantics.machines.interpreters import interpreter_for

DATA = Path(__file__).parent / "data" / "op_pulse"

# the clock-pulse bench's scenario over 3 s: the obstacle at {distance} m closing at 2 m/s
SCENARIO = CLOCK_PULSE_SCENARIO.replace("horizon = 1.6", "horizon = 3.0")

# The demand each cycle (0.1 s) sets, worked out by hand from the rules, the obstacle at
# 5 m closing at 2 m/s (near, range <= 1, from t = 2.0 s: cycle 20):
#  0-2  Ramp(10, 3) from Fast's entry: Up, k = 1, 2, 3: 10/3, 20/3, 10; c's exec cuts cycle 2
#  3-5  #h, Hold (top; during 10), since(h) = 0, 1, 2: 10 (e re-enters Hold: 10 twice)
#  6-8  since(h) = 3: d calls Kick(5): 5, wait(2): cut twice; cycle 8 sends 10 and returns
#       twice (Kick, then Ramp), Fast's entry ends (rounds + 1), its during sends 10 again
#  9-11 Fast rested: during 10, t3 calls Kick(1): 1, cut, cut; cycle 11 sends 2, returns,
#       t3 enters Slow: Ramp(4, 2), Up, k = 1: 2
# 12-18 k = 2: 4, c cuts; Hold 4, 4, 4; since(h) = 3: Kick(2): 2, cut; cycle 18 sends 4,
#       returns to Slow's entry (nothing after the call: Slow rests, exec t4 waits)
# 19-21 t4 to Fast: Ramp(10, 3): 10/3, 20/3, 10 (near from cycle 20: b and c ignore it)
# 22-24 Hold: during 10, then d holds at once (near): Kick(5): 5, cut, cut; cycle 24 sends
#       10 and returns (Fast's during: 10 again)
# 25-   Fast rested, near: t5 to Done: 0
DEMANDS = [10 / 3, 20 / 3, 10, 10, 10, 10, 5, 5, 10, 1, 1, 2, 4, 4, 4, 4, 2, 2, 4,
           10 / 3, 20 / 3, 10, 5, 5, 10] + [0] * 5


def _model(folder: Path, distance: float) -> tuple[Path, Path]:
    return bench(folder, DATA, SCENARIO.format(distance=distance))


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
@pytest.mark.parametrize("distance", [5.0, 0.5])  # near from cycle 20; near from the start
def test_operations_are_written_and_animate_as_simulate_runs_them(
        tmp_path: Path, dialect: str, distance: float) -> None:
    folder, scenario = _model(tmp_path / "bench", distance)
    theory = written_session(folder, scenario, dialect, tmp_path / "thy")
    # the operations' parameters, variables and clocks are D's fields
    for name in ("Ramp_w", "Ramp_n", "Ramp_k", "Ramp_top", "Ramp_h", "Kick_v"):
        assert f"OpPulseSoftware_{name}" in theory, name
    columns, rows = animated_as_simulated(tmp_path / "thy", folder, scenario, 61)
    # independent of both: the demand in each cycle (two samples a cycle), by hand
    demand = rows[:, columns.index("Motor_das")]
    want = DEMANDS if distance > 1 else [0] * 30
    assert np.allclose(demand[:60:2], want, atol=1e-9), list(np.round(demand[:60:2], 3))
    assert np.allclose(demand[1:60:2], want, atol=1e-9)


# ----------------------------------------------------------------- D against the interpreter

INTERFACES = """\
interface OutI { go(x: real) halt() }
interface InI { event near event val: real }
"""

CONTEXT = " input context { uses InI }\n output context { requires OutI }\n"

#: Small machines, each with what it exercises; all read near (and val) every cycle.
MACHINES = {
    # a call in the during action of a rested state: after a return in the same cycle the
    # caller's during does not run again, its exec transitions are enabled (it had rested);
    # after a return in a later cycle its during runs again
    "during": """
operation Tick(x: real) {
""" + CONTEXT + """ var n: real = x
 initial j0
 state W { during n = n + 1; $go(n) }
 final F
 transition a { from j0 to W }
 transition b { from W to F condition $near \\/ n >= x + 2 action $go(-n) }
}
stm M {
""" + CONTEXT + """ var s: real = 0
 initial i0
 state A { during s = s + 1; Tick(s); $go(100 + s) }
 state B { entry $halt() }
 transition t0 { from i0 to A }
 transition t1 { from A to B exec condition s >= 4 }
 transition t2 { from B to A exec condition not $near }
}
""",
    # nested calls, a typed event bound inside the operation, its clock, exec and wait in
    # its actions, the caller's action going on after the call (a transition's)
    "nested": """
operation Inner(y: real) {
""" + CONTEXT + """ var got: real = 0
 clock H
 initial j0
 state S { entry #H }
 final F
 transition a { from j0 to S action $go(y); exec; $go(y + 1) }
 transition b { from S to F exec condition $val?got /\\ since(H) >= 1 action $go(got * y) }
 transition c { from S to S exec condition since(H) < 3 /\\ not $val action wait(2); $go(since(H)) }
}
operation Outer(x: real) {
""" + CONTEXT + """ initial j0
 final F
 transition a { from j0 to F action Inner(x + 1); $go(x) }
}
stm M {
""" + CONTEXT + """ var k: real = 1
 clock C
 initial i0
 state A { entry k = k + 1 }
 state B { }
 transition t0 { from i0 to A condition $near action Outer(k); $go(since(C)) }
 transition t1 { from i0 to B condition not $near }
 transition t2 { from A to B exec action Inner(k * 10); #C }
 transition t3 { from B to A exec condition $near action Outer(since(C)) }
}
""",
    # an operation whose during action and junction run every cycle it rests, a Boolean
    # parameter, returning through a junction into a composite state's initial junction
    "composite": """
operation Pick(up: boolean, v: real) {
""" + CONTEXT + """ var m: real = 0
 initial j0
 junction J
 state Wait { during m = m + v; $go(m) }
 final F
 transition a { from j0 to J }
 transition b { from J to Wait condition up }
 transition c { from J to F condition not up action $halt() }
 transition d { from Wait to F exec condition m >= 3 * v }
}
stm M {
""" + CONTEXT + """ initial i0
 state Outer {
  initial k0
  state In1 { entry Pick(true, 1) }
  state In2 { entry Pick(false, 5); $go(55) }
  transition u0 { from k0 to In1 }
  transition u1 { from In1 to In2 exec condition $near }
  transition u2 { from In2 to In1 exec }
 }
 transition t0 { from i0 to Outer }
}
""",
}


def _interpreter(tmp_path: Path, text: str, consts: dict[str, object] | None = None,
                 leave_open: bool = False) -> MachineInterpreter:
    """The machine ``M`` of ``text`` as the commands set it up (its operation definitions,
    ``consts`` given, the constants without a value left open if ``leave_open``)."""
    f = tmp_path / "m.rst"
    f.write_text(INTERFACES + text, encoding="utf-8")
    result = api.check([str(f)])
    assert not result.report.has_errors, [d.message for d in result.report.diagnostics]
    files = list(result.workspace.user_files())
    (m,) = [m for m in machines_of(files, result.resolution) if m.name == "M"]
    return interpreter_for(m, files, result.resolution, Scopes(result.workspace), consts,
                           leave_open=leave_open)


READS = {"near": (c.BOOL,), "val": (c.BOOL, c.REAL)}
WRITES: dict[str, tuple[c.Type, ...]] = {"go": (c.REAL,), "halt": ()}
@pytest.mark.parametrize("name", sorted(MACHINES))
def test_d_calls_what_the_interpreter_calls_cycle_by_cycle(tmp_path: Path, name: str) -> None:
    it = _interpreter(tmp_path, MACHINES[name])
    d = cycle_process("D", [it], READS, WRITES)
    rng = random.Random(18)
    places = set()
    for _ in range(30):
        it.reset()
        runner = RunD(d)
        for k in range(25):
            events = {"near": True if rng.random() < 0.3 else None,
                      "val": round(rng.uniform(-2, 2), 2) if rng.random() < 0.5 else None}
            want = it.cycle(events)
            got = runner.cycle(events, first=k == 0)
            assert [(n, pytest.approx(a)) for n, a in want] == list(got), (name, k)
            places.add((it.running, len(it.stack), it.node))
    # the runs went inside the operations (nested ones too)
    assert any(depth > 0 for _, depth, _ in places)
    if name == "nested":
        assert any(depth == 2 for _, depth, _ in places)


def test_a_recursive_chain_of_calls_is_refused_with_the_reason(tmp_path: Path) -> None:
    it = _interpreter(tmp_path, """
operation Ping(n: real) {
""" + CONTEXT + """ initial j0
 state S { entry Pong(n - 1) }
 final F
 transition a { from j0 to S condition n > 0 }
 transition b { from j0 to F condition n <= 0 }
 transition c { from S to F }
}
operation Pong(n: real) {
""" + CONTEXT + """ initial j0
 final F
 transition a { from j0 to F action Ping(n) }
}
stm M {
""" + CONTEXT + """ initial i0
 state A { entry Ping(3) }
 transition t0 { from i0 to A }
}
""")
    with pytest.raises(MachineError, match="Ping is called again while it runs "
                       r"\(M → Ping → Pong → Ping\): D holds one copy of an operation's "
                       "variables, so a recursive chain of calls is not written"):
        cycle_process("D", [it], READS, WRITES)


def test_an_operation_s_open_constant_is_a_constant_of_the_theory(tmp_path: Path) -> None:
    """An operation's own constant without a value is named as its fields are
    (``D_Go_gain``, from ``Go::gain``), the machine's as before (``D_lim``); D with the
    constants set runs as the interpreter given their values does."""
    text = """
operation Go(x: real) {
""" + CONTEXT + """ const gain: real
 initial j0
 final F
 transition a { from j0 to F action $go(x * gain) }
}
stm M {
""" + CONTEXT + """ const lim: real
 var s: real = 0
 initial i0
 state A { during s = s + 1; Go(s) }
 state B { entry $halt() }
 transition t0 { from i0 to A }
 transition t1 { from A to B exec condition s >= lim }
}
"""
    d = cycle_process("D", [_interpreter(tmp_path, text, leave_open=True)], READS, WRITES)
    assert [(k.name, k.origin) for k in d.constants] == [("D_lim", "M::lim"),
                                                          ("D_Go_gain", "Go::gain")]
    given = _interpreter(tmp_path, text, {"lim": 3, "gain": 2.5})
    runner = RunD(d)
    runner.state.update({"D_lim": 3.0, "D_Go_gain": 2.5})
    got = [runner.cycle({}, first=k == 0) for k in range(6)]
    assert got == [given.cycle({}) for _ in range(6)]
    # by hand: A's during sets s = 1, 2, 3, Go sends go(2.5 s); t1 (exec) then takes B
    assert got == [(("go", (2.5,)),), (("go", (5.0,)),), (("go", (7.5,)), ("halt", ())),
                   (), (), ()]


def test_gen_leaves_d_opaque_at_a_recursive_call_with_the_reason(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Kick calling Ramp back (Ramp → Kick → Ramp): the warning is at the call, with the
    cycle construction's reason first (the automaton's, which cannot hold the machine
    either, after it), and the theory is still written, ``D`` opaque."""
    folder, _ = _model(tmp_path / "bench", 5.0)
    software = folder / "OpPulseSoftware.rsm"
    text = software.read_text()
    software.write_text(text.replace("wait(2); $drive(v * 2) }", "wait(2); Ramp(v, 1) }"))
    line = next(n for n, s in enumerate(software.read_text().splitlines(), 1)
                if "Ramp(v, 1)" in s)
    assert main(["gen", str(folder), "--isabelle", "-o", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert f"OpPulseSoftware.rsm:{line}:57: WARNING W-SEMANTICS-DMODEL: the d-model process " \
        "is left opaque: state machine OpPulse: Ramp is called again while it runs (OpPulse " \
        "→ Ramp → Kick → Ramp): D holds one copy of an operation's variables, so a " \
        "recursive chain of calls is not written (nor can the automaton hold it: the first " \
        "cycle of OpPulse depends on its inputs" in err, err
    assert "hint: write the repetition as a loop of transitions with exec" in err
    theory = next((tmp_path / "out").glob("*_CyPhyCircus.thy")).read_text()
    assert "OpPulseSoftwareStep" not in theory


# ----------------------------------------------------------------- two machines of a module

ROVER = Path(__file__).parent / "data" / "heldout" / "rover"


def _rover(folder: Path) -> Path:
    """The held-out rover with ``tests/data/op_rover``'s software: both machines call
    operation definitions, each its own ``Hold``."""
    folder.mkdir()
    for name in ("Mapping.rsm", "RoverBase.rsm", "bump.toml"):
        shutil.copy(ROVER / name, folder)
    shutil.copy(DATA.parent / "op_rover" / "RoverSoftware.rsm", folder)
    return folder


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
def test_two_machines_calling_operations_animate_as_simulate_runs_them(
        tmp_path: Path, dialect: str) -> None:
    folder = _rover(tmp_path / "rover")
    theory = written_session(folder, folder / "bump.toml", dialect, tmp_path / "thy")
    # each machine's operations have fields of their own (both call a Hold)
    for name in ("SDrive_Spin_s", "SDrive_Hold_H", "SScan_Swing_side", "SScan_Hold_H"):
        assert f"RoverSoftware_{name}" in theory, name
    columns, _ = animated_as_simulated(tmp_path / "thy", folder, folder / "bump.toml", 21, ())
    assert {"LMotor_av", "RMotor_av", "Pan_av"} <= set(columns)


def test_two_machines_d_calls_what_the_interpreters_call_cycle_by_cycle(
        tmp_path: Path) -> None:
    from cyphy.semantics.machines.parallel import ModuleInterpreter
    from test_dmodel_process import _semantics

    folder = _rover(tmp_path / "rover")
    sem, _ = _semantics([folder / "Mapping.rsm"])
    d = sem.program.dmodel
    assert isinstance(d, c.BasicProcess)
    rng = random.Random(28)
    for _ in range(10):
        interpreter, _checked = api.machine_interpreter([folder], pmodel="RoverBase")
        assert isinstance(interpreter, ModuleInterpreter)
        runner = RunD(d)
        for k in range(40):
            events = {"near": True if rng.random() < 0.3 else None}
            want = interpreter.cycle(events)
            assert [(n, pytest.approx(a)) for n, a in want] == \
                list(runner.cycle(events, first=k == 0)), k
