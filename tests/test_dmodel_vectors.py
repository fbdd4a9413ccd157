"""Vector variables in the theory's ``D`` written out: one field per entry
(``<D>_speeds_1``, ``<D>_speeds_2``), an entry read or written at a constant index, a whole
vector assigned at once (every entry in one assignment, so ``speeds = (|speeds[2],
speeds[1]|)`` swaps). Before, ``D`` was left opaque ("variable speeds is not a number or a
Boolean") whenever the cycle had to be written out (typed events, a first cycle that reads
the inputs, open constants).

The model: the clock-pulse bench (``tests/data/clock_pulse``: its first cycle reads ``near``,
so ``D`` is written out) whose two speeds live in a vector that the transitions change.
Oracles: ``simulate`` (the interpreter) for ``animate`` (the theory's text), and the demands
worked out by hand from the machine."""

from __future__ import annotations

from pathlib import Path

import pytest

from cyphy import api
from dmodel_runs import animated_as_simulated, bench, run_json, written_session
from test_dmodel_clock_loop import SCENARIO

DATA = Path(__file__).parent / "data" / "clock_pulse"
EDITS = (
    ("var n: int = 0", "var n: int = 0\n\tvar speeds: vector(real, 2) = (|fast, slow|)"),
    ("entry $drive(fast)", "entry $drive(speeds[1])"),
    ("entry $drive(slow)", "entry $drive(speeds[2])"),
    ("action n = n + 1; #c }", "action n = n + 1; speeds[2] = speeds[2] + 1; #c }"),
    ("not $near action #c }", "not $near action speeds = (|speeds[2], speeds[1]|) * 1.5; #c }"),
)


def _vector_bench(tmp_path: Path) -> tuple[Path, Path]:
    folder, scenario = bench(tmp_path / "bench", DATA, SCENARIO.format(distance=10.0)
                             .replace("horizon = 1.6", "horizon = 3.2"))
    machine = folder / "PulseSoftware.rsm"
    text = machine.read_text()
    for old, new in EDITS:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    machine.write_text(text)
    return folder, scenario


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
def test_vector_variables_animate_as_simulate_runs_them(tmp_path: Path, dialect: str) -> None:
    folder, scenario = _vector_bench(tmp_path)
    theory = written_session(folder, scenario, dialect, tmp_path / "thy")
    assert "PulseSoftware_speeds_1" in theory and "PulseSoftware_speeds_2" in theory
    animated_as_simulated(tmp_path / "thy", folder, scenario, 65, ("Motor_av", "Motor_i"))
    # by hand: Fast drives speeds[1], Slow speeds[2]; Fast → Slow adds 1 to speeds[2], and
    # Slow → Fast swaps the two and scales them by 1.5 (at once: the swap reads the old ones)
    # (10, 4) → 10; (10, 5) → 5; (7.5, 15) → 7.5; (7.5, 16) → 16; (24, 11.25) → 24;
    # (24, 12.25) → 12.25; (18.375, 36) → 18.375
    anim = run_json("animate", tmp_path / "thy", scenario, 65)
    demands = [e["value"] for e in anim["events"] if e["channel"] == "registerWrite_drive"]
    changes = [v for i, v in enumerate(demands) if i == 0 or v != demands[i - 1]]
    assert changes == [10.0, 5.0, 7.5, 16.0, 24.0, 12.25, 18.375]


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
def test_a_constant_vector_read_in_guards(tmp_path: Path, dialect: str) -> None:
    """``const gains: vector(real, 2)`` with a value, read at constant indices in the guards
    (``since(c) >= gains[2] + 1``): each entry is its number, so the unrolling knows the clock
    guards as before. Before, the entry stayed an index of a literal, the unrolling could not
    fold it, and D was refused as a loop without exec."""
    folder, scenario = bench(tmp_path / "bench", DATA, SCENARIO.format(distance=10.0))
    machine = folder / "PulseSoftware.rsm"
    text = machine.read_text()
    for old, new in (("const slow: real = 4.0",
                      "const slow: real = 4.0, gains: vector(real, 2) = (|10.0, 4.0|)"),
                     ("entry $drive(fast)", "entry $drive(gains[1])")):
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    machine.write_text(text.replace("since(c) >= 5", "since(c) >= gains[2] + 1")
                       .replace("since(c) < 5", "since(c) < gains[2] + 1"))
    written_session(folder, scenario, dialect, tmp_path / "thy")
    animated_as_simulated(tmp_path / "thy", folder, scenario, 33, ("Motor_av", "Motor_i"))


@pytest.mark.parametrize("declaration, entry, reason", [
    ("var speeds: vector(boolean, 2)", "entry $drive(fast)", "D holds a vector of numbers"),
    ("var speeds: vector(real, 2)", "entry $drive(norm(speeds))",
     "the function norm takes or gives vectors or matrices"),
    ("var speeds: vector(real, 2)", "entry $drive(speeds[3])",
     "entries at a constant index from 1 to 2"),
    ("var speeds: vector(real, 2)", "entry $drive(speeds[n])",
     "entries at a constant index from 1 to 2"),
])
def test_what_d_cannot_write_of_a_vector_is_refused_with_the_reason(
        tmp_path: Path, declaration: str, entry: str, reason: str) -> None:
    folder, _ = bench(tmp_path / "bench", DATA, SCENARIO.format(distance=10.0))
    machine = folder / "PulseSoftware.rsm"
    machine.write_text(machine.read_text().replace(
        "var n: int = 0", f"var n: int = 0\n\t{declaration}").replace(
        "entry $drive(fast)", entry))
    generated = api.generate_isabelle([folder], api.SemanticsGenOptions())
    opaque = [d for d in generated.report.diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert opaque and reason in opaque[0].message, [d.message for d in
                                                    generated.report.diagnostics]


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
def test_library_functions_in_guards_and_calls(tmp_path: Path, dialect: str) -> None:
    """``abs`` and ``sqrt`` (the library's, which HOL has) in a guard over the clock and in a
    call's argument over a variable: applied in ``D`` as the interpreter applies them.
    Before, ``D`` was left opaque ("'abs' has no value in the machine")."""
    folder, scenario = bench(tmp_path / "bench", DATA, SCENARIO.format(distance=10.0)
                             .replace("horizon = 1.6", "horizon = 3.2"))
    machine = folder / "PulseSoftware.rsm"
    text = machine.read_text()
    for old, new in (("entry $drive(fast)", "entry $drive(sqrt(fast * fast) + abs(n - 3))"),
                     ("Fast to Slow condition since(c) >= 5",
                      "Fast to Slow condition abs(since(c) - 2.5) >= 2.5"),
                     ("Fast to Fast condition since(c) < 5",
                      "Fast to Fast condition abs(since(c) - 2.5) < 2.5")):
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    machine.write_text(text)
    written_session(folder, scenario, dialect, tmp_path / "thy")
    animated_as_simulated(tmp_path / "thy", folder, scenario, 65, ("Motor_av", "Motor_i"))
    # by hand: Fast demands 10 + |n - 3|, n counting the moves to Slow so far; Slow 4
    anim = run_json("animate", tmp_path / "thy", scenario, 65)
    demands = [e["value"] for e in anim["events"] if e["channel"] == "registerWrite_drive"]
    changes = [v for i, v in enumerate(demands) if i == 0 or v != demands[i - 1]]
    fast = [10.0 + abs(n - 3) for n in range(len(changes))]
    assert changes == [x for pair in zip(fast, [4.0] * len(fast)) for x in pair][:len(changes)]
    assert len(changes) >= 8
