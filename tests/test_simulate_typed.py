"""``cyphy simulate`` with a state machine that reads typed input events (``event echo: real``
mapped as ``input event echo ? r { predicate … equation r == … }``, read as ``$echo?seen``):
the machine runs on its interpreter (the automaton models events as present or absent only),
and a present event carries the value its mapping's equations give the parameter at the
cycle's instant (spec semantics.md, Rule 5: ``registerRead.echo!true!p``).

Every trajectory is checked against the cart's equations written out and integrated here
with SciPy, the machine's decisions taken by hand from the IR curve, not against cyphy."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from cyphy.cli import main

RANGER = Path(__file__).parent / "data" / "heldout" / "ranger"

#: The cart's linear motor (RangerBase.rsm) and the cart's mass (the prismatic joint moves
#: the Cart link alone: 0.5 kg; gravity is along z, across the rail).
MOTOR = {"R": 1.0, "L": 0.02, "Kf": 2.0, "Ke": 2.0, "b": 0.2, "Kp": 10.0, "Ki": 20.0}
MASS = 0.5


def voltage(theta: float) -> float:
    """The IR curve, a/(distance + b) + c, with the wall 1 m ahead: distance = 1 − θ."""
    return 0.3 / (1.0 - theta + 0.01) + 0.0


def _cart_by_hand(t_end: float, samples: int, decide: Callable[[int, float], float | None]
                  ) -> tuple[np.ndarray, np.ndarray]:
    """θ of the cart under a sampled speed demand: at each cycle k (t = 0.1·k)
    ``decide(k, θ)`` gives the demand dls (None: the one before stays; before any, 0), held
    until the next cycle. The motor: e = dls − v, V = Kp e + Ki ∫e, L i' = V − R i − Ke v,
    F = Kf i − b v; the cart: m v' = F, θ' = v. State (θ, v, i, ∫e)."""
    from scipy.integrate import solve_ivp

    m = MOTOR

    def rates(dls: float) -> Callable[[float, np.ndarray], list[float]]:
        def f(_t: float, x: np.ndarray) -> list[float]:
            theta, v, i, z = x
            e = dls - v
            force = m["Kf"] * i - m["b"] * v
            return [v, force / MASS, (m["Kp"] * e + m["Ki"] * z - m["R"] * i - m["Ke"] * v)
                    / m["L"], e]
        return f

    grid = np.linspace(0.0, t_end, samples)
    x, dls, rows = np.zeros(4), 0.0, []
    for k in range(round(t_end / 0.1)):
        t0, t1 = 0.1 * k, 0.1 * (k + 1)
        demand = decide(k, float(x[0]))
        dls = dls if demand is None else demand
        inside = [min(max(t, t0), t1) for t in grid if t0 - 1e-12 <= t < t1 - 1e-12]
        sol = solve_ivp(rates(dls), (t0, t1), x, t_eval=[*inside, t1], rtol=1e-11,
                        atol=1e-13, method="DOP853")
        rows += list(sol.y[0][:-1])
        x = sol.y[:, -1]
    return grid, np.array(rows + [x[0]])


def _simulate(model: Path, *argv: str) -> dict[str, np.ndarray]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["simulate", str(model), "--scenario", str(model / "approach.toml"),
                     "--format", "json", "-q", *argv]) == 0
    doc = json.loads(out.getvalue())
    return {"t": np.array(doc["t"]), **{k: np.array(v) for k, v in doc["columns"].items()}}


def _variant(tmp_path: Path, edits: dict[str, list[tuple[str, str]]]) -> Path:
    """The ranger with text replaced in some of its files."""
    folder = tmp_path / "model"
    folder.mkdir()
    for f in RANGER.iterdir():
        text = f.read_text()
        for old, new in edits.get(f.name, []):
            assert old in text, (f.name, old)
            text = text.replace(old, new)
        (folder / f.name).write_text(text)
    return folder


# ------------------------------------------------------------------------------ ranger
THROUGH_LOCAL = [("\t\tpredicate Rail::Carriage::Eye.voltage >= 0.4\n"
                  "\t\tequation r == Rail::Carriage::Eye.voltage\n",
                  "\t\tvar w: real\n\t\tpredicate w >= 0.4\n"
                  "\t\tequation w == Rail::Carriage::Eye.voltage\n\t\tequation r == w\n")]


@pytest.mark.parametrize("edits", [{}, {"Mapping.rsm": THROUGH_LOCAL}],
                         ids=["as-written", "predicate-and-value-through-a-local"])
def test_ranger_stops_at_the_cycle_the_reading_first_reaches_close(
        tmp_path: Path, edits: dict[str, list[tuple[str, str]]]) -> None:
    """The cart rolls at 0.4 m/s; from θ ≥ 0.26 (voltage ≥ 0.4) echo occurs every cycle
    carrying the voltage, and SRanger halts at the first cycle it reads ``seen >= close``
    (1.0 V: θ ≥ 0.71). Before this change simulate refused the model (E-FLOWSTAR, "the
    automaton models events as present or absent"). The second mapping reads the voltage
    into a local w that both the predicate and the value read."""
    model = _variant(tmp_path, edits) if edits else RANGER
    stopped: list[int] = []

    def decide(k: int, theta: float) -> float | None:
        if k == 0:
            return 0.4  # i0 → Rolling: roll(cruise)
        if stopped or voltage(theta) < 0.4:  # halted, or no echo: Rolling stays
            return None
        if voltage(theta) >= 1.0:  # Look → Halted: roll(0)
            stopped.append(k)
            return 0.0
        return 0.4  # Look → Rolling: its entry calls roll(cruise) again

    t, theta = _cart_by_hand(3.0, 31, decide)
    simulated = _simulate(model, "--samples", "31")
    chosen = _simulate(model, "--samples", "31", "--machine", "SRanger")  # named: the same
    assert np.array_equal(chosen["Carriage_theta"], simulated["Carriage_theta"])
    assert np.allclose(simulated["t"], t)
    assert np.max(np.abs(simulated["Carriage_theta"] - theta)) < 1e-6
    # the stop: cycle 19 (t = 1.9 s), the first with a reading of 1 V or more
    assert stopped == [19]
    k = int(np.argmin(np.abs(t - 1.9)))
    assert voltage(simulated["Carriage_theta"][k - 1]) < 1.0 <= \
        voltage(simulated["Carriage_theta"][k])
    assert simulated["Carriage_v"][k] == pytest.approx(0.3977, abs=1e-3)  # still cruising
    assert float(np.max(np.abs(simulated["Carriage_v"][t >= 2.5]))) < 0.03  # stopped
    assert 0.75 < simulated["Carriage_theta"][-1] < 0.76  # 0.24 m before the wall
    # the value matters: with seen = 1 at every echo the cart would stop at the first one
    # (θ ≥ 0.26, t ≈ 0.8 s); with seen left at 0, never
    assert simulated["Carriage_theta"][int(np.argmin(np.abs(t - 1.2)))] > 0.4


# ------------------------------------------------------------------------------ follow
FOLLOW_SOFTWARE = """package rangerSoftware

interface MoveI {
	roll(v: real)
}

interface GapI {
	event gap: real
}

module RangerSoftware {
	cycleDef cycle == 1
	robotic platform Cart {
		provides MoveI
		uses GapI
	}
	cref ctrl = Follower
	connection Cart on gap to ctrl on gap (_async)
}

controller Follower {
	cycleDef cycle == 1
	uses GapI
	requires MoveI
	sref sm = SFollow
	connection Follower on gap to sm on gap
}

stm SFollow {
	cycleDef cycle == 1
	const k: real = 0.8, keep: real = 0.3
	var d: real = 0
	input context { uses GapI }
	output context { requires MoveI }
	initial i0
	state Tracking { }
	transition t0 { from i0 to Tracking }
	transition t1 { from Tracking to Tracking exec condition $gap?d action $roll(k * (d - keep)) }
}
"""

FOLLOW_MAPPING = """package rangerMapping

import rangerBase::*
import rangerSoftware::*

map RangerMapping dmodel RangerSoftware to pmodel RangerBase {
	operation roll {
		equation Rail::Carriage::Push.dls == v
	}
	input event gap ? d {
		var w: real
		predicate Rail::Carriage::Eye.voltage >= 0.2
		equation w == Rail::Carriage::Eye.voltage
		equation d == 0.3 / w - 0.01
	}
}
"""


def test_an_event_value_through_a_mapping_local_sets_the_call_argument(
        tmp_path: Path) -> None:
    """SFollow reads the gap to the wall each cycle (``$gap?d``, d recovered from the IR
    voltage through the mapping's local w: d = 0.3/w − 0.01 = 1 − θ) and demands
    ``roll(k·(d − keep))``: the cart closes to 0.3 m from the wall at a speed proportional
    to the gap. A wrong value (the voltage, or True) gives another trajectory."""
    folder = _variant(tmp_path, {})
    (folder / "RangerSoftware.rsm").write_text(FOLLOW_SOFTWARE)
    (folder / "Mapping.rsm").write_text(FOLLOW_MAPPING)
    capture = io.StringIO()
    with contextlib.redirect_stderr(capture):
        assert main(["check", str(folder)]) == 0, capture.getvalue()

    def decide(k: int, theta: float) -> float | None:
        if k == 0:
            return None  # the first cycle enters Tracking: no call, the demand stays 0
        return 0.8 * ((1.0 - theta) - 0.3)  # voltage(θ) ≥ 0.2 always: gap occurs

    t, theta = _cart_by_hand(3.0, 31, decide)
    simulated = _simulate(folder, "--samples", "31")
    assert np.allclose(simulated["t"], t)
    assert np.max(np.abs(simulated["Carriage_theta"] - theta)) < 1e-6
    assert simulated["Carriage_theta"][1] == 0.0  # no call before t = 0.1
    assert 0.55 < simulated["Carriage_theta"][-1] < 0.7  # closing on 0.7, never past
    assert float(np.max(simulated["Carriage_theta"])) < 0.7


# ------------------------------------------------------------------------------ refusals
EQUATION = "\t\tequation r == Rail::Carriage::Eye.voltage\n"


@pytest.mark.parametrize("equations, why", [
    ("\t\tequation r * r == Rail::Carriage::Eye.voltage\n", "its equations allow 2 values"),
    ("\t\tvar w: real\n\t\tequation r + w == Rail::Carriage::Eye.voltage\n",
     "its equations leave it open"),
    # r written twice (r == v, r == v + 1) is check's PMap16 (tests/test_mutants.py); this
    # contradiction is one check cannot see: r == v and r == v + 1 in another form
    (EQUATION + "\t\tequation r - 1 == Rail::Carriage::Eye.voltage\n",
     "its equations have no solution"),
], ids=["two-roots", "open-local", "contradiction"])
def test_a_value_the_equations_do_not_determine_is_refused_at_the_mapping(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], equations: str, why: str) -> None:
    """The machine reads one value: equations that allow two (±√v), leave the parameter
    open (a local that nothing fixes) or none (the theory's choice over an empty set is
    Stop) are refused at the event's mapping (code, place, hint), exit 1, nothing written.
    ``check`` accepts all three (they are well-formed)."""
    folder = _variant(tmp_path, {"Mapping.rsm": [(EQUATION, equations)]})
    line = next(i for i, s in enumerate((folder / "Mapping.rsm").read_text().splitlines(), 1)
                if "input event echo" in s)
    assert main(["check", str(folder)]) == 0
    out = tmp_path / "sim.csv"
    capsys.readouterr()
    code = main(["simulate", str(folder), "--scenario", str(folder / "approach.toml"),
                 "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 1 and not out.exists() and "Traceback" not in err
    assert f"Mapping.rsm:{line}:2: ERROR E-FLOWSTAR: the value of the input event echo is " \
        f"not determined by mapping RangerMapping: {why}, and the machine reads one" in err, err
    assert "hint: give the parameter of echo one value" in err


@pytest.mark.parametrize("edits, where, message", [
    ({"RangerSoftware.rsm": [("event echo: real", "event echo: vector(real, 2)"),
                             ("var seen: real = 0", "var seen: vector(real, 2)"),
                             ("seen >= close", "seen[1] >= close"),
                             ("seen < close", "seen[1] < close")]},
     ("RangerSoftware.rsm", "$echo?seen"),
     "the input event echo carries a vector(real, 2): simulate computes an event's value "
     "as one number"),
    ({"Mapping.rsm": [(EQUATION, "\t\tequation r == [| Rail::Carriage::Eye.voltage, 0 |]\n")]},
     ("Mapping.rsm", "input event echo"),
     "the value of the input event echo: the equation r == [|Eye_voltage, 0|] is not "
     "between numbers"),
], ids=["vector-event", "vector-equation"])
def test_a_value_that_is_not_one_number_is_refused(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], edits: dict[str, list[tuple[str, str]]],
        where: tuple[str, str], message: str) -> None:
    """A vector-typed event (which check accepts), or a real one given a vector (check
    accepts it too, today): refused with the place, not an internal error."""
    folder = _variant(tmp_path, edits)
    text = (folder / where[0]).read_text().splitlines()
    line = next(i for i, s in enumerate(text, 1) if where[1] in s)
    column = text[line - 1].index(where[1]) + 1 if where[1].startswith("$") else 2
    capsys.readouterr()
    code = main(["simulate", str(folder), "--scenario", str(folder / "approach.toml"),
                 "-o", str(tmp_path / "sim.csv")])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" not in err and "internal error" not in err
    assert f"{where[0]}:{line}:{column}: ERROR E-FLOWSTAR: {message}" in err, err
    assert not (tmp_path / "sim.csv").exists()


def test_flowstar_still_refuses_typed_events_and_names_simulate(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = _variant(tmp_path, {"approach.toml": [
        ("[init]", '[unsafe]\nconstraints = ["Carriage_theta >= 1"]\n\n[init]')]})
    capsys.readouterr()
    code = main(["gen", str(folder), "--flowstar", "--scenario",
                 str(folder / "approach.toml"), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 1 and not (tmp_path / "out").exists() and "Traceback" not in err
    assert "RangerSoftware.rsm:32:1: ERROR E-FLOWSTAR: state machine SRanger: the typed " \
        "input event echo cannot be written for Flow*" in err
    assert "hint: `cyphy simulate` runs this machine with the events' values" in err


REVERSE = """
controller Reverse {
	cycleDef cycle == 1
	requires MoveI
	sref sm = SBack
}

stm SBack {
	cycleDef cycle == 1
	clock C
	output context { requires MoveI }
	initial i0
	state Wait { }
	state Back {
		entry $roll(-0.2)
	}
	transition t0 { from i0 to Wait }
	transition t1 { from Wait to Back exec condition since(C) >= 25 }
}
"""


def test_a_module_with_a_typed_reader_runs_all_its_machines_on_the_interpreter(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A second controller (SBack, no events: it backs the cart off at 0.2 m/s from cycle
    25) beside SRanger: the module's machines run together every cycle, on the
    interpreter, SRanger's calls then SBack's; before this change the module was refused
    as SRanger alone was (its automaton could not be compiled, so neither the product)."""
    folder = _variant(tmp_path, {"RangerSoftware.rsm": [
        ("\tcref ctrl = Ranger\n", "\tcref ctrl = Ranger\n\tcref back = Reverse\n")]})
    with (folder / "RangerSoftware.rsm").open("a") as f:
        f.write(REVERSE)
    assert main(["check", str(folder)]) == 0, capsys.readouterr().err
    stopped: list[int] = []

    def decide(k: int, theta: float) -> float | None:
        if k == 0:
            return 0.4
        if k == 25:
            return -0.2  # SRanger rests in Halted (no call): SBack's call holds
        if stopped or voltage(theta) < 0.4:
            return None
        if voltage(theta) >= 1.0:
            stopped.append(k)
            return 0.0
        return 0.4

    t, theta = _cart_by_hand(4.0, 41, decide)
    simulated = _simulate(folder, "--samples", "41", "--t-end", "4")
    assert stopped == [19]
    assert np.max(np.abs(simulated["Carriage_theta"] - theta)) < 1e-6
    assert simulated["Carriage_v"][-1] == pytest.approx(-0.2, abs=0.02)  # backing off


def test_the_documented_ranger_run_prints_what_the_page_shows(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """docs/commands/simulate.md shows the ranger's run in a plain block (test_docs runs
    its pages in a copy of examples/, which has no tests/data): run here from the checkout."""
    import re
    import shlex

    root = Path(__file__).resolve().parent.parent
    page = (root / "docs" / "commands" / "simulate.md").read_text()
    block = re.search(r"```text\n\$ (cyphy simulate tests/data/heldout/ranger[^\n]*)\n"
                      r"(.*?)```", page, re.S)
    assert block is not None
    argv = shlex.split(block[1])[1:]
    argv = [str(root / a) if a.startswith("tests/") else a for a in argv]
    argv[argv.index("-o") + 1] = str(tmp_path / "ranger.csv")
    capsys.readouterr()
    assert main(argv) == 0
    assert capsys.readouterr().err.splitlines() == block[2].splitlines()
    first = (tmp_path / "ranger.csv").read_bytes()
    assert first.count(b"\n") == 32  # header and 31 rows
    assert main(argv) == 0 and (tmp_path / "ranger.csv").read_bytes() == first  # byte-identical


def test_a_machine_failing_on_a_value_at_run_time_is_reported_at_its_statement(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A value the machine cannot use (here 1/(seen − seen) once echo occurs, at t = 0.8 s)
    stops the run with E-MACHINE at the expression, exit 1, nothing written: it was an
    internal error (a MachineError escaped simulate)."""
    folder = _variant(tmp_path, {"RangerSoftware.rsm": [
        ("transition t3 { from Look to Rolling condition seen < close }",
         "transition t3 { from Look to Rolling condition seen < close action "
         "$roll(1 / (seen - seen)) }")]})
    text = (folder / "RangerSoftware.rsm").read_text().splitlines()
    line = next(i for i, s in enumerate(text, 1) if "1 / (seen - seen)" in s)
    capsys.readouterr()
    code = main(["simulate", str(folder), "--scenario", str(folder / "approach.toml"),
                 "-o", str(tmp_path / "sim.csv")])
    err = capsys.readouterr().err
    assert code == 1 and "internal error" not in err and not (tmp_path / "sim.csv").exists()
    assert f"RangerSoftware.rsm:{line}:" in err and "ERROR E-MACHINE: state machine SRanger: " \
        in err, err
