"""The d-model process ``D`` (issue 26): written from the d-model's state machine as the
automaton ``simulate`` and ``reach`` run, checked against the cycle semantics of the
dcmotor's machine derived by hand; a machine ``D`` cannot express is a warning at the
machine, the process left opaque."""

from __future__ import annotations

from pathlib import Path

from cyphy import api
from dmodel_runs import RunD
from cyphy import expr as ex
from cyphy.backends.circus.text import CircusText
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.build import build_semantics

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
DCMOTOR = EXAMPLES / "dcmotor"


def _semantics(paths: list[Path]):  # type: ignore[no-untyped-def]
    checked = api.check(paths, api.CheckOptions(neighbours_as_targets=True))
    assert not checked.report.has_errors, checked.report.diagnostics
    return build_semantics(checked.workspace, checked.resolution, checked.report), checked


def test_dcmotor_d_is_the_speed_machine_by_hand() -> None:
    """SSpeed (DCMotorSoftware.rsm) under RoboSim's cycle semantics, by hand: the first cycle
    enters Cruise, whose entry calls drive(wref = 10); every later cycle in Cruise takes the
    exec transition to the junction and returns to Cruise (drive(10) again) unless near,
    when t3 calls stop() and rests in Stopped, where nothing changes the actuator (stop()
    repeated). So two modes: Cruise (drive 10) → Stopped (stop) on near."""
    sem, _ = _semantics([DCMOTOR / "Mapping.rsm"])
    d = sem.program.dmodel
    assert isinstance(d, c.BasicProcess) and d.name == "DCMotorSoftware"
    text = CircusText()
    acts = {a.name: text.action(a.body) for a in d.actions}
    mode, near = "DCMotorSoftware_mode", "DCMotorSoftware_near"
    assert [f.name for f in d.state.fields] == [mode, near]
    assert acts["DCMotorSoftwareInit"] == f"{mode}, {near} := 0, false"
    assert acts["DCMotorSoftwareRead"] == f"registerRead.near?near_in → {near} := near_in"
    assert acts["DCMotorSoftwareStep"] == \
        f"if {mode} = 0 ∧ {near} = true then {mode} := 1 else Skip"
    assert acts["DCMotorSoftwareWrite"] == (
        f"if {mode} = 0 then registerWrite.drive!10.0 → Skip else if {mode} = 1 then "
        "registerWrite.stop → Skip else Skip")
    wait = c.Wait(ex.Name(("cycle",)))
    call = {n: c.Call(f"DCMotorSoftware{n}") for n in ("Init", "Read", "Step", "Write")}
    assert d.main == c.Seq((call["Init"], call["Read"], call["Write"], wait, c.Mu("X", c.Seq((
        call["Read"], call["Step"], call["Write"], wait, c.Call("X"))))))
    # N composes D (no longer opaque) with P, as the spec's Structure says
    assert sem.program.system.body == c.PHide(c.PParallel(
        c.PRef("DCMotorSoftware"), ("registerRead", "registerWrite", "tock"),
        c.PRef("DCMotorBase")), ("registerRead", "registerWrite", "tock"))


def test_a_machine_d_cannot_express_is_a_warning_at_the_machine(tmp_path: Path) -> None:
    """A typed input event in a machine with a matrix variable: the automaton models events
    as present or absent only, and the cycle written out (dmodel_cycle.py) holds numbers,
    Booleans and vectors of numbers."""
    (tmp_path / "DCMotorBase.rsm").write_text((DCMOTOR / "DCMotorBase.rsm").read_text())
    mapping = (DCMOTOR / "Mapping.rsm").read_text()
    (tmp_path / "Mapping.rsm").write_text(mapping.replace(
        "input event near {\n\t\tpredicate Bench::Range.range <= 1.0\n",
        "input event near ? d {\n\t\tpredicate Bench::Range.range <= 1.0\n"
        "\t\tequation d == Bench::Range.range\n"))
    software = (DCMOTOR / "DCMotorSoftware.rsm").read_text()
    software = software.replace("event near\n", "event near: real\n")
    (tmp_path / "DCMotorSoftware.rsm").write_text(software)
    sem, checked = _semantics([tmp_path / "Mapping.rsm"])
    assert sem is not None and isinstance(sem.program.dmodel, c.BasicProcess)  # flat: written
    vector = software.replace("\tconst wref: real = 10.0\n",
                              "\tconst wref: real = 10.0\n\tvar w: matrix(real, 2, 2)\n")
    assert vector != software
    (tmp_path / "DCMotorSoftware.rsm").write_text(vector)
    sem, checked = _semantics([tmp_path / "Mapping.rsm"])
    assert sem is not None and isinstance(sem.program.dmodel, c.OpaqueProcess)
    [warning] = [d for d in checked.report.diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert "variable w is not a number" in warning.message and "SSpeed" in warning.message
    assert warning.span.file.endswith("DCMotorSoftware.rsm")
    assert warning.span.line == vector.splitlines().index("\tvar w: matrix(real, 2, 2)") + 1


def test_gen_machine_option_chooses_d_and_an_unknown_one_is_an_error(tmp_path: Path,
                                                                     capsys) -> None:
    """--machine picks the machine D is written from, as for simulate and reach: the
    marXbot's SStop (stop on obstacle, for good) has two modes, SMovement (the default, the
    one its module runs) turns after the stop; a machine not among the files is E-MACHINE,
    nothing written."""
    from cyphy.cli import main

    marxbot = EXAMPLES / "marxbot"
    assert main(["gen", "--cyphycircus", str(marxbot), "--machine", "SStop", "-o",
                 str(tmp_path / "stop")]) == 0
    text = (tmp_path / "stop" / "M.cpc").read_text()
    assert ("marXbotSoftwareStep ≙ if marXbotSoftware_mode = 0 ∧ marXbotSoftware_obstacle "
            "= true then marXbotSoftware_mode := 1 else Skip\n") in text
    assert main(["gen", "--cyphycircus", str(marxbot), "-o", str(tmp_path / "default")]) == 0
    turning = (tmp_path / "default" / "M.cpc").read_text()
    assert "registerWrite.move!0.0!0.5" in turning and "registerWrite.move!0.0!0.5" not in text
    capsys.readouterr()
    assert main(["gen", "--cyphycircus", str(marxbot), "--machine", "Nope", "-o",
                 str(tmp_path / "none")]) == 1
    assert "E-MACHINE" in capsys.readouterr().err and not (tmp_path / "none").exists()


# ------------------------------------------------------------ D run against the interpreter


def _effect(previous: tuple, calls: tuple) -> tuple:
    """What the actuators hold after a cycle: the calls it made, else the last ones (a
    cycle without calls leaves them as they were)."""
    return calls or previous


def test_d_writes_what_the_machine_interpreter_calls_cycle_by_cycle() -> None:
    """D, run on random event sequences, leaves the actuators as RoboSim's cycle semantics
    (the machine's interpreter, stepped directly) does, for the dcmotor's SSpeed and the
    marXbot's SMovement (clocks: it turns for a number of cycles after each stop)."""
    import random

    from cyphy.semantics.machines.cycle import MachineInterpreter

    for folder, module, machine in ((DCMOTOR, "DCMotorSoftware", None),
                                    (EXAMPLES / "marxbot", "marXbotSoftware", None)):
        sem, _ = _semantics([folder / "Mapping.rsm"])
        d = sem.program.dmodel
        assert isinstance(d, c.BasicProcess) and d.name == module
        events = [f.name[len(module) + 1:] for f in d.state.fields[1:]]
        rng = random.Random(26)
        for _ in range(20):
            interpreter, _checked = api.machine_interpreter(
                [folder], machine, pmodel=sem.program.pmodel.name)
            assert isinstance(interpreter, MachineInterpreter)
            runner = RunD(d)
            want = got = ()
            for k in range(40):
                present = {e: rng.random() < 0.3 for e in events}
                calls = interpreter.cycle({e: True if v else None for e, v in present.items()})
                want = _effect(want, tuple((n, tuple(a)) for n, a in calls))
                got = _effect(got, runner.cycle(present, first=k == 0))
                assert got == want, (folder.name, k)
