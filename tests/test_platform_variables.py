"""A machine that writes a platform variable (``speed = v`` with ``var speed`` in an interface
the machine ``requires`` and the robotic platform ``provides``), so that the mapping's
``variable speed { … }`` is reached in every artefact: ``check``, ``simulate`` (against a
hand derivation of the PI-controlled DC motor), ``gen --isabelle`` (both dialects: D's
``registerWrite_speed``, P's ``SpeedFromDModel``), ``check-theory``, ``animate`` against
``simulate``, and ``reach`` with the real Flow*. The model (tests/data/pvars/): a wheel on
a stand whose motor's demand is ``speed``; the machine writes ``speed = slow`` (5 rad/s),
then, four cycles later, ``speed = 2 * speed`` (reading the last value written: 10 rad/s).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import needs_flowstar
from cyphy import api
from cyphy.cli import main
from test_heldout import (WHEEL_MOTOR, _animate_cli, _by_cycles, _reach, _session, _simulate,
                          _speed_motor)

PVARS = Path(__file__).parent / "data" / "pvars"
SW = "WheelSoftware.rsm"


def _by_hand(t_end: float, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """The rotor and wheel by hand: the demand 5 rad/s from the first cycle, 10 rad/s from
    the cycle since(C) >= 4 (t = 0.4 s, one time unit 0.1 s); state (av, i, ∫e, wheel's
    speed); the hinge carries the motor's torque and the wheel's inertia (iyy 0.001)."""
    def decide(k: int, _x: np.ndarray, _u: float | None) -> float:
        return 10.0 if k >= 4 else 5.0

    def rates(u: float) -> Any:
        motor = _speed_motor(WHEEL_MOTOR, u)
        return lambda x: [*motor(x), (WHEEL_MOTOR["Kt"] * x[1] - WHEEL_MOTOR["b"] * x[0])
                          / 0.001]
    return _by_cycles(t_end, samples, [0, 0, 0, 0], 0.1, rates, decide)


def _copy(tmp_path: Path, edits: dict[str, tuple[str, str]]) -> Path:
    """The model copied with ``edits`` (file → (old, new), old occurring once)."""
    folder = tmp_path / "pvars"
    shutil.copytree(PVARS, folder)
    for file, (old, new) in edits.items():
        text = (folder / file).read_text()
        assert text.count(old) == 1, old
        (folder / file).write_text(text.replace(old, new))
    return folder


def _check(folder: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, list[dict[str, Any]]]:
    capsys.readouterr()
    code = main(["check", "--format", "json", str(folder)])
    return code, json.loads(capsys.readouterr().out)


def test_the_model_checks_clean(capsys: pytest.CaptureFixture[str]) -> None:
    """Today's fault: ``speed = slow`` was STM5, "unknown name 'speed'"."""
    code, diags = _check(PVARS, capsys)
    assert (code, diags) == (0, [])


@pytest.mark.parametrize("old, new, code, message", [
    # the interface is not required: speed is no name of the machine's
    ("output context { requires SpeedI }", "output context { }", "STM5",
     "unknown name 'speed': the platform's variable speed (interface SpeedI) is not required "
     "by SWheel"),
    # the platform does not provide it: nothing would hold the value
    ("\t\tprovides SpeedI\n", "\t\tvar level: real\n", "STM5",
     "the robotic platform Wheel of module WheelSoftware does not provide the variable speed"),
    # the value's type is not the variable's
    ("entry speed = slow", "entry speed = true", "STM8",
     "speed is a number, but it is given a boolean"),
    # one entry of a vector platform variable: a write is one output with the whole value
    ("entry speed = slow", "entry speed = slow ; pair[1] = 1", "STM5",
     "one part of the platform variable pair cannot be written alone"),
    # a constant of the interface is not assigned (today's error)
    ("var speed: real", "const speed: real = 1", "STM5", "unknown name 'speed'"),
])
def test_faults_are_refused_at_the_assignment(old: str, new: str, code: str, message: str,
                                              tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    folder = _copy(tmp_path, {SW: (old, new)})
    text = (folder / SW).read_text().replace("\tvar speed: real\n",
                                             "\tvar speed: real\n\tvar pair: vector(real, 2)\n")
    (folder / SW).write_text(text)
    text = (folder / SW).read_text()
    line = text[:text.index("entry speed = ")].count("\n") + 1
    status, diags = _check(folder, capsys)
    assert status == 1
    found = [d for d in diags if d["code"] == code and Path(d["span"]["file"]).name == SW
             and d["span"]["line"] == line]
    assert found and message in found[0]["message"], diags
    assert all(d["hint"] for d in diags)


def test_simulate_follows_the_machine_and_the_hand_derivation() -> None:
    simulated = _simulate(PVARS, PVARS / "spin.toml", "--samples", "11")
    t, want = _by_hand(1.0, 11)
    assert np.allclose(simulated["t"], t)
    assert np.max(np.abs(simulated["Motor_av"] - want[:, 0])) < 1e-4
    assert np.max(np.abs(simulated["Axle_v"] - want[:, 3])) < 1e-3
    # the demand is the variable mapping's effect: das = speed, 5 then 10 from t = 0.4
    assert np.allclose(simulated["Motor_e"] + simulated["Motor_av"],
                       np.where(t < 0.4 - 1e-9, 5.0, 10.0))


def test_the_dollar_form_names_the_same_variable(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """``$speed = slow`` and ``$speed = 2 * $speed`` (RoboSim's ``$`` for the platform's
    elements): the same run. It checked clean before, then failed in ``simulate``
    ("only a variable or one entry of a vector can be assigned")."""
    folder = _copy(tmp_path, {SW: ("entry speed = 2 * speed", "entry $speed = 2 * $speed")})
    text = (folder / SW).read_text().replace("entry speed = slow", "entry $speed = slow")
    (folder / SW).write_text(text)
    assert _check(folder, capsys) == (0, [])
    simulated = _simulate(folder, folder / "spin.toml", "--samples", "11")
    _t, want = _by_hand(1.0, 11)
    assert np.max(np.abs(simulated["Motor_av"] - want[:, 0])) < 1e-4


def test_an_interface_initial_value_is_read_before_the_first_write(tmp_path: Path) -> None:
    """``var speed: real = 3`` and ``speed = speed + 2``: the first demand is 5 rad/s, as
    before (reading a variable never written gives the interface's initial value)."""
    folder = _copy(tmp_path, {SW: ("var speed: real", "var speed: real = 3")})
    text = (folder / SW).read_text().replace("entry speed = slow", "entry speed = speed + 2")
    (folder / SW).write_text(text)
    simulated = _simulate(folder, folder / "spin.toml", "--samples", "11")
    _t, want = _by_hand(1.0, 11)
    assert np.max(np.abs(simulated["Motor_av"] - want[:, 0])) < 1e-4


def test_an_unmapped_variable_is_shared_memory(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """PMap3 lets a platform variable go unmapped: a write of it reaches no actuator (the
    machine keeps its value for later reads) and D does not write it to P."""
    folder = _copy(tmp_path, {SW: ("\tvar speed: real\n", "\tvar speed: real\n\tvar count: int\n")})
    text = (folder / SW).read_text().replace("entry speed = 2 * speed",
                                             "entry speed = 2 * speed ; count = count + 1")
    (folder / SW).write_text(text)
    assert _check(folder, capsys) == (0, [])
    simulated = _simulate(folder, folder / "spin.toml", "--samples", "11")
    _t, want = _by_hand(1.0, 11)
    assert np.max(np.abs(simulated["Motor_av"] - want[:, 0])) < 1e-4
    capsys.readouterr()
    assert main(["simulate", str(folder), "--scenario", str(folder / "spin.toml"),
                 "--format", "json", "-q"]) == 0
    events = json.loads(capsys.readouterr().out)["events"]
    assert events == [{"t": 0.4, "name": "count", "values": [1.0]}]  # recorded, not applied
    out = tmp_path / "gen"
    _session(folder, out, "utp")
    theory = (out / "WheelBase_CyPhyCircus.thy").read_text()
    assert "registerWrite_speed" in theory and "registerWrite_count" not in theory


@pytest.mark.parametrize("dialect", ["utp", "axiomatic"])
def test_the_theory_writes_the_variable_and_animates_like_simulate(
        dialect: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder, _err = _session(PVARS, tmp_path / dialect, dialect)
    theory = next(folder.glob("*.thy"), None)
    text = "".join(p.read_text() for p in folder.glob("*.thy"))
    assert theory is not None
    # D's Write sends the value, P's ReceiveFromDModel takes it into the variable mapping
    write = next(line for line in text.splitlines() if '"WheelSoftwareWrite = ' in line)
    assert write.count("registerWrite_speed") == 5 and "10.0" in write
    receive = next(line for line in text.splitlines() if '"SpeedFromDModel = ' in line)
    assert "registerWrite_speed" in receive and "Motor_das" in receive
    assert "SpeedFromDModel" in next(line for line in text.splitlines()
                                     if '"ReceiveFromDModel = ' in line)
    assert api.check_theory(folder).exit_code == 0
    animated, calls = _animate_cli(folder, PVARS / "spin.toml", 11, capsys)
    simulated = _simulate(PVARS, PVARS / "spin.toml", "--samples", "11")
    for name in ("Motor_av", "Motor_i", "Axle_v", "Axle_theta"):
        scale = float(np.max(np.abs(simulated[name])))
        assert np.max(np.abs(animated[name] - simulated[name])) / scale < 1e-4, name
    assert calls[0] == (0.0, "speed", 5.0) and (0.4, "speed", 10.0) in calls


@needs_flowstar
@pytest.mark.parametrize("bound, verdict, status", [(12, "SAFE", 0), (11, "UNSAFE", 1)])
def test_reach_brackets_the_hand_derived_peak(bound: float, verdict: str, status: int,
                                              tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """The real Flow* over 1 s: the rotor's speed derived by hand peaks at 11.27 rad/s."""
    _t, want = _by_hand(1.0, 101)
    assert 11.0 < float(np.max(want[:, 0])) < 12.0
    code, said, out = _reach(PVARS, PVARS / "spin.toml",
                             {"Motor_av >= 12": f"Motor_av >= {bound}"}, tmp_path, capsys)
    assert (code, said) == (status, verdict), out


def test_an_operation_definition_writes_the_variable(tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """``Double()``, an operation definition that requires SpeedI, writes ``speed = 2 *
    speed``: the caller's cycle outputs it as the machine's own write would be."""
    folder = _copy(tmp_path, {SW: ("entry speed = 2 * speed\n", "entry Double()\n")})
    with (folder / SW).open("a") as f:
        f.write("\noperation Double() {\n\toutput context { requires SpeedI }\n\tinitial j0\n"
                "\tfinal F\n\ttransition a { from j0 to F action speed = 2 * speed }\n}\n")
    assert _check(folder, capsys) == (0, [])
    simulated = _simulate(folder, folder / "spin.toml", "--samples", "11")
    _t, want = _by_hand(1.0, 11)
    assert np.max(np.abs(simulated["Motor_av"] - want[:, 0])) < 1e-4


def test_two_machines_sharing_a_variable_one_reading_it_are_refused(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A second machine of the controller writes ``speed`` while SWheel reads it: each
    interpreter (and each automaton of the product) keeps its own value, so the run is
    refused with the reason, not given wrong values."""
    folder = _copy(tmp_path, {SW: ("\tsref sm = SWheel\n", "\tsref sm = SWheel\n"
                                   "\tsref idle = SIdle\n")})
    with (folder / SW).open("a") as f:
        f.write("\nstm SIdle {\n\tcycleDef cycle == 1\n\toutput context { requires SpeedI }\n"
                "\tinitial i0\n\tstate Off { entry speed = 0 }\n"
                "\ttransition t0 { from i0 to Off }\n}\n")
    assert _check(folder, capsys) == (0, [])
    code = main(["simulate", str(folder), "--scenario", str(folder / "spin.toml"), "-q"])
    err = capsys.readouterr().err
    assert code != 0 and "Traceback" not in err
    assert "SWheel and SIdle both use the platform variable speed" in err, err
    generated = api.generate_isabelle([folder], api.SemanticsGenOptions())
    assert any("both use the platform variable speed" in d.message
               for d in generated.report.diagnostics)


@pytest.mark.parametrize("target, write, receive", [
    ("--cyphycircus", "registerWrite.speed!10.0", "SpeedFromDModel ≙ registerWrite.speed?speed"),
    ("--latex", "registerWrite\\_speed!10\\decimalpoint 0",
     "SpeedFromDModel \\circdef registerWrite\\_speed?speed"),
])
def test_the_text_and_latex_printers_write_the_variable(
        target: str, write: str, receive: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["gen", str(PVARS), target, "-o", str(tmp_path), "-q"]) == 0
    text = "".join(p.read_text() for p in tmp_path.iterdir() if p.suffix in (".cpc", ".tex"))
    assert write in text and receive in text
