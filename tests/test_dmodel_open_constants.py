"""A machine's constant without a value (the paper's open constant: the model is a family)
in the theory's ``D``: declared as a constant of the theory (``consts <D>_fast :: real``, as
the p-model's open constants are) and read where the machine reads it, so the theory holds
the machine for every value. Before, ``D`` was left opaque (``W-SEMANTICS-DMODEL``) and the
theory held no machine.

The model: ``tests/data/clock_pulse`` (the motor bench of ``examples/dcmotor`` under a machine
that alternates a fast and a slow speed every 5 cycles), with ``fast`` left open, ``slow``
computed from it and a variable starting at it. Oracle: ``simulate`` of the same machine with the value written in its
source (the interpreter, never the theory), against ``animate`` of the open theory given that
value with ``--const``."""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from cyphy import api
from conftest import CORPUS, needs_corpus
from test_dmodel_clock_loop import SCENARIO as CLOCK_PULSE_SCENARIO
from cyphy.cli import main

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(__file__).parent / "data" / "clock_pulse"

SCENARIO = CLOCK_PULSE_SCENARIO.format(distance=10.0)  # the motor bench, 1.6 s, never near
CLOSED = ("const fast: real = 10.0", "const slow: real = 4.0")


def _model(folder: Path, fast: str, slow: str) -> Path:
    """The bench with the machine's two speed constants declared as given."""
    folder.mkdir()
    shutil.copy(ROOT / "examples" / "dcmotor" / "DCMotorBase.rsm", folder)
    for source in DATA.glob("*.rsm"):
        text = source.read_text()
        if CLOSED[0] in text:
            text = text.replace(CLOSED[0], fast).replace(CLOSED[1], slow)
        (folder / source.name).write_text(text)
    return folder


def _run(args: list[str], samples: int = 33) -> dict:
    """``simulate`` or ``animate``, JSON; samples every 0.05 s (0.1 s for the marXbot's
    2.5 s): on the cycle's ticks, so both report the same instants."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main([*args, "--samples", str(samples), "--format", "json", "-q"]) == 0
    return json.loads(out.getvalue())


def _session(folder: Path, dialect: str, scenario: Path, out: Path) -> tuple[str, str, list]:
    generated = api.generate_isabelle([folder], api.SemanticsGenOptions(
        dialect=dialect, scenario=str(scenario)))
    assert not generated.report.has_errors
    out.mkdir()
    for name, text in generated.files.items():
        (out / name).write_text(text)
    theory = next(t for n, t in generated.files.items() if n.endswith(".thy")
                  and "Prelude" not in n)
    return theory, generated.files["names.tsv"], [d.code.id for d in
                                                  generated.report.diagnostics]


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
def test_open_constant_is_a_constant_of_the_theory_and_animates_as_the_model_runs(
        tmp_path: Path, dialect: str) -> None:
    scenario = tmp_path / "pulse.toml"
    scenario.write_text(SCENARIO)
    family = _model(tmp_path / "family", "const fast: real", "const slow: real = fast * 0.4")
    machine = family / "PulseSoftware.rsm"  # and a variable that starts at the open value
    text = machine.read_text()
    assert "entry $drive(fast)" in text and "var n: int = 0" in text
    machine.write_text(text.replace("entry $drive(fast)", "entry $drive(top)").replace(
        "var n: int = 0", "var n: int = 0\n\tvar top: real = fast"))
    theory, names, codes = _session(family, dialect, scenario, tmp_path / "thy")
    assert "W-SEMANTICS-DMODEL" not in codes and "STM15" in codes, codes
    # declared open, read by D: the calls carry it, the derived speed as its expression
    assert "consts PulseSoftware_fast :: real" in theory
    assert "PulseSoftwareStep" in theory and "PulseSoftware_fast * 0.4" in theory
    assert "PulseSoftware_slow" not in theory  # computed from fast where it is read
    assert "PulseSoftware_top" in theory  # a variable of D, starting at fast (Init)
    assert "Pulse::fast\tPulseSoftware_fast\tPulseSoftware_fast\t" in names
    assert main(["check-theory", str(tmp_path / "thy")]) == 0

    # two members of the family; the value by the theory's name, or by RoboSim's (as
    # simulate takes it, names.tsv relating the two)
    for value, name in ((10.0, "PulseSoftware_fast"), (6.5, "fast")):
        anim = _run(["animate", str(tmp_path / "thy"), "--scenario", str(scenario),
                     "--const", f"{name}={value}"])
        member = _model(tmp_path / f"member{value}", f"const fast: real = {value}",
                        f"const slow: real = {value * 0.4}")
        sim = _run(["simulate", str(member), "--scenario", str(scenario)])
        columns, rows = anim["columns"], np.array(anim["rows"])
        assert np.allclose(rows[:, 0], sim["t"])
        for col in ("Motor_av", "Motor_i"):
            gap = np.max(np.abs(rows[:, columns.index(col)] - sim["columns"][col]))
            assert gap < 1e-5, (value, col, gap)
    # the members differ: the value reached the motor
    assert np.max(np.abs(np.array(sim["columns"]["Motor_av"]) - np.array(
        _run(["simulate", str(tmp_path / "member10.0"), "--scenario", str(scenario)])
        ["columns"]["Motor_av"]))) > 1.0


def test_animate_asks_for_the_open_constant(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    scenario = tmp_path / "pulse.toml"
    scenario.write_text(SCENARIO)
    family = _model(tmp_path / "family", "const fast: real", "const slow: real = 4.0")
    _session(family, "utp", scenario, tmp_path / "thy")
    assert main(["animate", str(tmp_path / "thy"), "--scenario", str(scenario), "-q",
                 "-o", str(tmp_path / "a.csv")]) == 1
    err = capsys.readouterr().err
    assert "E-ANIMATE-CONST" in err and "PulseSoftware_fast" in err
    assert not (tmp_path / "a.csv").exists()


def test_an_open_vector_constant_is_refused_with_the_reason(tmp_path: Path) -> None:
    family = _model(tmp_path / "family", "const fast: real, gains: vector(real, 2)",
                    "const slow: real = 4.0 + gains[1]")
    generated = api.generate_isabelle([family], api.SemanticsGenOptions())
    opaque = [d for d in generated.report.diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert opaque and "open constant (no value) gains is not a number or a Boolean" in \
        opaque[0].message, [d.message for d in opaque]


def test_a_loop_closed_only_by_an_open_guard_is_refused_with_a_hint(tmp_path: Path) -> None:
    """``since(c) >= pause`` with ``pause`` open: for ``pause <= 0`` the way back from Slow to
    Fast is taken in the same cycle, without end; the unrolling cannot tell, and says which
    constants would decide it."""
    family = _model(tmp_path / "family", "const fast: real = 10.0, pause: real",
                    "const slow: real = 4.0")
    machine = family / "PulseSoftware.rsm"
    machine.write_text(machine.read_text().replace("since(c) >= 5", "since(c) >= pause")
                       .replace("since(c) < 5", "since(c) < pause"))
    generated = api.generate_isabelle([family], api.SemanticsGenOptions())
    opaque = [d for d in generated.report.diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert opaque and "passes more than" in opaque[0].message, [d.message for d in opaque]
    assert "give the open constants (pause) values (--const)" in opaque[0].hint
    given = api.generate_isabelle([family], api.SemanticsGenOptions(consts={"pause": 5.0}))
    assert "W-SEMANTICS-DMODEL" not in [d.code.id for d in given.report.diagnostics]


@needs_corpus
def test_robotools_marxbot_machine_is_in_its_theory_with_its_open_constants(
        tmp_path: Path) -> None:
    """RoboTool's own marXbot (the corpus, used in place): its ``SMovement`` declares ``PI``,
    ``lv`` and ``av`` without values and calls ``move(0, av)`` without ``$``. Its theory now
    holds the machine, and those three stay open; animated with the values
    ``examples/marxbot/corpus_smovement.toml`` gives them (matched by ``names.tsv``), the
    motors run as ``simulate`` runs the model (the scenario's obstacle starts at
    one point, and the hinges' efforts are left to the axiomatic theory, whose own state they
    are)."""
    text = (ROOT / "examples" / "marxbot" / "corpus_smovement.toml").read_text()
    text = text.replace("Proximity1_distance = [0.25, 0.26]", "Proximity1_distance = 0.255")
    point = tmp_path / "point.toml"  # simulate's: the efforts held at 0 as world inputs
    point.write_text(text)
    text = text.replace("LHinge_tau = { value = 0 }\n", "").replace(
        "RHinge_tau = { value = 0 }\n", "")
    assert "0.255" in text and "LHinge_tau = {" not in text
    scenario = tmp_path / "smovement.toml"
    scenario.write_text(text)
    family = tmp_path / "family.toml"  # the same, without the machine's values: left open
    values = "PI = 3.141592653589793\nlv = 0.1\nav = 0.5\n"
    assert values in text
    family.write_text(text.replace(values, ""))
    marxbot = CORPUS / "marXbot"
    theory, names, codes = _session(marxbot, "axiomatic", family, tmp_path / "thy")
    assert "W-SEMANTICS-DMODEL" not in codes, codes
    for k in ("PI", "lv", "av"):
        assert f"consts marXbotSoftware_{k} :: real" in theory, k
        assert f"SMovement::{k}\tmarXbotSoftware_{k}" in names
    assert main(["check-theory", str(tmp_path / "thy")]) == 0
    anim = _run(["animate", str(tmp_path / "thy"), "--scenario", str(scenario)], 26)
    sim = _run(["simulate", str(marxbot), "--scenario", str(point)], 26)
    columns, rows = anim["columns"], np.array(anim["rows"])
    assert np.allclose(rows[:, 0], sim["t"])
    for col in ("LMotor_av", "RMotor_av", "LMotor_i", "RMotor_theta"):
        gap = np.max(np.abs(rows[:, columns.index(col)] - sim["columns"][col]))
        assert gap < 1e-6, (col, gap)
    assert max(sim["columns"]["LMotor_av"]) > 4  # it drives (lv reached the motors)


def test_an_open_boolean_constant_is_given_as_true_or_false(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``const enabled: boolean`` left open and read in a guard (``$near \\/ not enabled``
    stops the motor): a Boolean constant of the theory, compared with true where the guard
    reads it. ``animate`` and ``simulate`` both take ``--const enabled=true`` (or false); a
    value other than 0 or 1 is refused."""
    scenario = tmp_path / "pulse.toml"
    scenario.write_text(SCENARIO)
    family = _model(tmp_path / "family", "const fast: real = 10.0, enabled: boolean",
                    "const slow: real = 4.0")
    machine = family / "PulseSoftware.rsm"
    t3 = "transition t3 { from Fast to Done condition $near }"
    assert t3 in machine.read_text()
    machine.write_text(machine.read_text().replace(
        t3, "transition t3 { from Fast to Done condition $near \\/ not enabled }"))
    theory, _, codes = _session(family, "utp", scenario, tmp_path / "thy")
    assert "W-SEMANTICS-DMODEL" not in codes and "consts PulseSoftware_enabled :: bool" in theory
    peaks = {}
    for value in ("true", "false"):
        anim = _run(["animate", str(tmp_path / "thy"), "--scenario", str(scenario),
                     "--const", f"enabled={value}"])
        sim = _run(["simulate", str(family), "--scenario", str(scenario),
                    "--const", f"enabled={value}"])
        speed = np.array(anim["rows"])[:, anim["columns"].index("Motor_av")]
        assert np.max(np.abs(speed - sim["columns"]["Motor_av"])) < 1e-5, value
        peaks[value] = speed.max()
    assert peaks["true"] > 8 and peaks["false"] < 1e-9  # disabled: stopped at once
    capsys.readouterr()
    assert main(["animate", str(tmp_path / "thy"), "--scenario", str(scenario), "-q",
                 "--const", "enabled=2"]) == 2
    assert "a Boolean constant takes true or false" in capsys.readouterr().err
    # simulate refuses a value of the wrong kind, rather than sending true as 1.0
    for given, said in (("enabled=2", "the constant enabled is a boolean, not 2"),
                        ("fast=true", "the constant fast is a number, not true")):
        assert main(["simulate", str(family), "--scenario", str(scenario), "-q",
                     "--const", given, "-o", str(tmp_path / "s.csv")]) == 1
        assert said in capsys.readouterr().err
    assert not (tmp_path / "s.csv").exists()


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
@pytest.mark.parametrize("kind, embedding, bad", [("int", "real_of_int", "6.5"),
                                                  ("nat", "real", "-3")])
def test_a_whole_open_constant_stays_whole_in_the_theory(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], dialect: str, kind: str,
        embedding: str, bad: str) -> None:
    """``const fast: int`` (or ``nat``) left open: the theory's constant has the declared
    type, so its family is the model's (held as a real it admitted 6.5), and D embeds it in
    the reals where it computes with it (HOL has no implicit coercion: Real.thy's
    ``real_of_int`` and ``real``), in the calls and in a variable's initial value. Animated
    with ``--const fast=7`` it runs as ``simulate`` runs the model with 7 written in; a value
    the declared type cannot take is refused by ``animate`` (exit 2, nothing written)."""
    scenario = tmp_path / "pulse.toml"
    scenario.write_text(SCENARIO)
    family = _model(tmp_path / "family", f"const fast: {kind}", "const slow: real = fast * 0.4")
    machine = family / "PulseSoftware.rsm"
    machine.write_text(machine.read_text().replace("entry $drive(fast)", "entry $drive(top)")
                       .replace("var n: int = 0", "var n: int = 0\n\tvar top: real = fast"))
    theory, names, codes = _session(family, dialect, scenario, tmp_path / "thy")
    assert "W-SEMANTICS-DMODEL" not in codes, codes
    assert f"consts PulseSoftware_fast :: {kind}" in theory
    assert f"(({embedding} PulseSoftware_fast) * 0.4)" in theory  # the slow speed, a real
    init = next(line for line in theory.splitlines() if "PulseSoftwareInit =" in line)
    assert f"({embedding} PulseSoftware_fast)" in init  # top starts at fast, a real
    assert "PulseSoftware_fast :: real" not in theory
    assert main(["check-theory", str(tmp_path / "thy")]) == 0

    anim = _run(["animate", str(tmp_path / "thy"), "--scenario", str(scenario),
                 "--const", "fast=7"])
    member = _model(tmp_path / "member", f"const fast: {kind} = 7", "const slow: real = 2.8")
    member_machine = member / "PulseSoftware.rsm"
    member_machine.write_text(member_machine.read_text().replace(
        "entry $drive(fast)", "entry $drive(top)").replace(
        "var n: int = 0", "var n: int = 0\n\tvar top: real = fast"))
    sim = _run(["simulate", str(member), "--scenario", str(scenario)])
    columns, rows = anim["columns"], np.array(anim["rows"])
    for col in ("Motor_av", "Motor_i"):
        gap = np.max(np.abs(rows[:, columns.index(col)] - sim["columns"][col]))
        assert gap < 1e-5, (col, gap)
    assert max(sim["columns"]["Motor_av"]) > 1.0  # the value reached the motor

    capsys.readouterr()
    out = tmp_path / "bad.csv"
    assert main(["animate", str(tmp_path / "thy"), "--scenario", str(scenario), "-q",
                 "--const", f"fast={bad}", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "E-ANIMATE-OPTION" in err and f"declared {kind}" in err, err
    assert not out.exists()


def test_a_packages_open_constant_is_named_by_its_package(tmp_path: Path) -> None:
    """``const fast: real`` declared by the package, not the machine: ``names.tsv`` gives its
    full RoboSim name (``pulseSoftware::fast``, it gave the bare ``fast``), and ``animate``
    takes the value by that name or the bare one, running as ``simulate`` runs the model
    with the value written in."""
    scenario = tmp_path / "pulse.toml"
    scenario.write_text(SCENARIO)

    def package_level(folder: Path, value: str) -> Path:
        _model(folder, "", "const slow: real = 4.0")
        machine = folder / "PulseSoftware.rsm"
        machine.write_text(machine.read_text().replace(
            "interface SpeedI {", f"const fast: real{value}\n\ninterface SpeedI {{", 1))
        return folder

    family = package_level(tmp_path / "family", "")
    theory, names, codes = _session(family, "utp", scenario, tmp_path / "thy")
    assert "W-SEMANTICS-DMODEL" not in codes and "STM15" in codes, codes
    assert "consts PulseSoftware_fast :: real" in theory
    assert "pulseSoftware::fast\tPulseSoftware_fast\t" in names, names
    sim = _run(["simulate", str(package_level(tmp_path / "member", " = 7.0")), "--scenario",
                str(scenario)])
    for name in ("pulseSoftware::fast", "fast"):
        anim = _run(["animate", str(tmp_path / "thy"), "--scenario", str(scenario),
                     "--const", f"{name}=7"])
        speed = np.array(anim["rows"])[:, anim["columns"].index("Motor_av")]
        assert np.max(np.abs(speed - sim["columns"]["Motor_av"])) < 1e-5, name
    assert max(sim["columns"]["Motor_av"]) > 1.0
