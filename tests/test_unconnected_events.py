"""An event no connection carries to the machine never occurs for it (RoboChart's rule, and
what STM11's warning says), in every command that runs the machine.

The motor bench (``examples/dcmotor``) cruises at 10 rad/s until the range finder reads
1 m, then stops for good (the obstacle starts at 3 m and approaches at 2 m/s: the stop
comes at t = 1.0 s or 1.1 s). With ``connection Bench on near to ctrl on near`` deleted,
``near`` never reaches the machine, so the motor cruises for the whole run: ``simulate``,
``reach`` (Flow*), the theory's ``D`` and ``animate`` (which reads only the theory) each
show it, and the model with the connection is their control.
"""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import pytest

from conftest import EXAMPLES, needs_flowstar
from cyphy.cli import main

CONNECTION = "\tconnection Bench on near to ctrl on near (_async)\n"
STOPS_AT = 1.1  # the latest sample at which the connected machine stops


def _bench(tmp_path: Path, connected: bool) -> Path:
    folder = tmp_path / ("connected" if connected else "unconnected")
    shutil.copytree(EXAMPLES / "dcmotor", folder, ignore=shutil.ignore_patterns("*-gen"))
    if not connected:
        software = folder / "DCMotorSoftware.rsm"
        text = software.read_text(encoding="utf-8")
        assert text.count(CONNECTION) == 1
        software.write_text(text.replace(CONNECTION, ""), encoding="utf-8")
    return folder


def _final(rows: list[dict[str, str]], column: str) -> float:
    return float(rows[-1][column])


@pytest.mark.parametrize("connected", [True, False])
def test_simulate_never_delivers_an_unconnected_event(tmp_path, capsys, connected):
    folder = _bench(tmp_path, connected)
    out = tmp_path / "run.csv"
    assert main(["simulate", str(folder), "--scenario", str(folder / "sampled_stop.toml"),
                 "-o", str(out), "-q"]) == 0
    rows = list(csv.DictReader(out.open(encoding="utf-8")))
    assert float(rows[-1]["t"]) == pytest.approx(2.0)
    # cruising: the PI loop holds 10 rad/s; stopped at 1.1 s: the speed decays to ~0
    if connected:
        assert abs(_final(rows, "Motor_av")) < 0.5
    else:
        assert _final(rows, "Motor_av") == pytest.approx(10.0, abs=0.05)
    check = main(["check", str(folder)])
    err = capsys.readouterr().err
    assert check == 0 and ("STM11" in err) != connected
    if not connected:
        assert "the event never occurs for the machine" in err


def test_the_theory_reads_and_drops_an_unconnected_event(tmp_path):
    """``D`` takes ``registerRead.near`` (``P`` offers it every cycle) and drops it: its
    automaton has the one mode Cruise, and no step reads ``near``."""
    theories = {}
    for connected in (True, False):
        out = tmp_path / f"thy-{connected}"
        assert main(["gen", str(_bench(tmp_path, connected)), "--isabelle", "-o", str(out),
                     "-q"]) == 0
        theories[connected] = next(out.glob("*_CyPhyCircus.thy")).read_text(encoding="utf-8")
    dropped = r'"DCMotorSoftwareRead = (registerRead_near?(near_in) \<^bold>\<rightarrow> Skip)"'
    assert dropped in theories[False] and dropped not in theories[True]
    assert "DCMotorSoftware_near" in theories[True]
    assert "DCMotorSoftware_near" not in theories[False]


@pytest.mark.parametrize("connected", [True, False])
def test_animate_of_the_theory_agrees_with_simulate(tmp_path, connected):
    """``animate`` runs the generated session alone (no model): the composition of ``D``
    and ``P`` does not deadlock on the dropped event, and the motor's speed at 2 s is the
    simulator's."""
    folder = _bench(tmp_path, connected)
    scenario = str(folder / "sampled_stop.toml")
    session, anim, run = tmp_path / "thy", tmp_path / "anim.csv", tmp_path / "run.csv"
    assert main(["gen", str(folder), "--isabelle", "-o", str(session), "-q"]) == 0
    assert main(["animate", str(session), "--scenario", scenario, "-o", str(anim), "-q"]) == 0
    assert main(["simulate", str(folder), "--scenario", scenario, "-o", str(run), "-q"]) == 0
    animated = list(csv.DictReader(anim.open(encoding="utf-8")))
    simulated = list(csv.DictReader(run.open(encoding="utf-8")))
    assert _final(animated, "Motor_av") == pytest.approx(_final(simulated, "Motor_av"),
                                                         abs=1e-3)
    stops = [r for r in animated if "registerWrite_stop" in r["events"]]
    assert bool(stops) == connected
    if connected:
        assert float(stops[0]["t"]) <= STOPS_AT + 1e-9


@needs_flowstar
@pytest.mark.parametrize("connected", [True, False])
def test_reach_proves_the_cruise_of_an_unconnected_machine(tmp_path, capsys, connected):
    """Flow*: the shaft turns less than 15 rad in 2 s when the motor stops at 1.1 s (about
    11 rad), more when it cruises (about 19.5 rad): SAFE with the connection, UNSAFE (a
    witness) without it; the automaton without it has no jump."""
    folder = _bench(tmp_path, connected)
    scenario = folder / "theta.toml"
    text = (folder / "sampled_stop.toml").read_text(encoding="utf-8")
    scenario.write_text(text.replace('"Motor_av >= 20"', '"Motor_theta >= 15"'),
                        encoding="utf-8")
    status = main(["reach", str(folder), "--scenario", str(scenario), "-q"])
    out = capsys.readouterr().out
    assert out.startswith("SAFE" if connected else "UNSAFE"), out
    assert status == (0 if connected else 1)
    exported = tmp_path / "fs"
    assert main(["gen", str(folder), "--flowstar", "--scenario", str(scenario), "-o",
                 str(exported), "-q"]) == 0
    model = next(exported.glob("*.model")).read_text(encoding="utf-8")
    assert ("Cruise -> Stopped" in model) == connected


MODULE = """\
interface SenseI { event near }
interface GoI { go() }
module Mod {
  robotic platform P { uses SenseI provides GoI }
  cref c = Ctrl
  connection P on near to c on near
}
controller Ctrl {
  uses SenseI requires GoI
  sref a = M
  stm B {
    input context { uses SenseI }
    output context { requires GoI }
    initial i0 state S {} state T { entry $go() }
    transition t0 { from i0 to S }
    transition t1 { from S to T exec condition $near }
  }
  connection Ctrl on near to a on near
}
stm M {
  input context { uses SenseI }
  output context { requires GoI }
  initial i0 state S {} state T { entry $go() }
  transition t0 { from i0 to S }
  transition t1 { from S to T exec condition $near }
}
"""


def test_one_module_connects_the_event_to_one_machine_and_not_the_other(tmp_path):
    """The controller passes near to its machine ``a`` (M) and not to B: the same event,
    read by two identical machines of one controller, moves M and never B; the warning is
    B's alone."""
    from cyphy import api
    from cyphy.model.machines import select_machine
    from cyphy.semantics.machines.cycle import MachineInterpreter

    f = tmp_path / "m.rst"
    f.write_text(MODULE, encoding="utf-8")
    checked = api.check([str(f)])
    found = [(d.code.id, d.span.line) for d in checked.report.diagnostics]
    assert found == [("STM11", 16)], [d.message for d in checked.report.diagnostics]
    files = list(checked.workspace.user_files())
    calls = {}
    for name in ("M", "B"):
        machine, _ = select_machine(files, checked.resolution, None, name)
        assert machine is not None
        it = MachineInterpreter(machine)
        calls[name] = [it.cycle({"near": True}) for _ in range(3)]
    assert calls["M"] == [(), (("go", ()),), ()]
    assert calls["B"] == [(), (), ()]
