"""``D`` written out for a machine whose states lead back to each other through clock guards
(``since(c) >= 5``, the clock reset on the way): within one cycle the clock reads 0 after its
reset, so ``Fast → Slow → Fast`` cannot happen in the same cycle. The cycle is unrolled with
that knowledge (:mod:`cyphy.semantics.circus.path_facts`); before, the unrolling followed the
loop, ``D`` was refused ("a loop of transitions without exec", ``W-SEMANTICS-DMODEL``) and the
theory held no machine.

The model: ``tests/data/clock_pulse`` (the machine and its mapping) over the motor bench of
``examples/dcmotor``. Its first cycle reads ``near``, so the theory writes the cycle out
rather than the automaton. Oracles: ``simulate`` (the model's equations and the machine's
interpreter, never the theory) for ``animate`` (the theory's text), and the speeds the
machine demands, read off the trajectory."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cyphy import expr as ex
from conftest import needs_flowstar
from dmodel_runs import animated_as_simulated, bench, run_json, written_session
from cyphy.cli import main
from cyphy.semantics.circus.path_facts import Facts

DATA = Path(__file__).parent / "data" / "clock_pulse"

SCENARIO = """model = "DCMotorBase"
horizon = 1.6
tscale = 0.1
[init]
Motor_av = 0
Motor_i = 0
Motor_int1 = 0
Motor_theta = 0
Shaft_theta = 0
Shaft_v = 0
Range_distance = {distance}
[environment]
Range_distance = "-2"
"""


def _model(folder: Path, distance: float) -> tuple[Path, Path]:
    return bench(folder, DATA, SCENARIO.format(distance=distance))


def _run(command: str, target: Path, scenario: Path) -> dict:
    """``simulate`` or ``animate`` over 1.6 s, 33 samples (every 0.05 s), JSON."""
    return run_json(command, target, scenario, 33)


@pytest.mark.parametrize("dialect", ("utp", "axiomatic"))
@pytest.mark.parametrize("distance", [10.0, 0.5])  # never near; near from the start
def test_clock_loop_is_written_and_animates_as_simulate_runs_it(
        tmp_path: Path, dialect: str, distance: float) -> None:
    folder, scenario = _model(tmp_path / "bench", distance)
    theory = written_session(folder, scenario, dialect, tmp_path / "thy")
    assert "PulseSoftwareStart" in theory and "PulseSoftware_c" in theory
    columns, rows = animated_as_simulated(tmp_path / "thy", folder, scenario, 33)
    # independent of both: the demand is 10 rad/s for 5 cycles (0.5 s), then 4, then 10
    # again; or 0 from the first cycle when something is near at the start
    speed = rows[:, columns.index("Motor_av")]
    t = rows[:, 0]
    if distance > 5:
        assert speed[(t > 0.3) & (t < 0.55)].min() > 8  # fast
        assert speed[(t > 0.8) & (t < 1.0)].max() < 5   # slow
        assert speed[(t > 1.3) & (t < 1.55)].min() > 8  # fast again
    else:
        assert np.max(np.abs(speed)) < 1e-9


def _n(text: str) -> ex.Name:
    return ex.Name((text,))


def test_facts_fold_exactly_and_leave_the_unknown_open() -> None:
    c, near, x = _n("D_c"), _n("D_near"), _n("D_x")
    facts = Facts().assigned("D_c", ex.Num("0"))
    assert facts.value(ex.BinOp(">=", c, ex.Num("5"))) is False
    # exact: 0.1 + 0.2 == 0.3 over the reals (in floats it is not)
    tenths = ex.BinOp("+", ex.Num("0.1"), ex.Num("0.2"))
    assert Facts().value(ex.BinOp("==", tenths, ex.Num("0.3"))) is True
    unknown = ex.BinOp("==", near, ex.Bool(True))
    assert facts.value(unknown) is None
    assert facts.value(ex.BinOp("/\\", ex.BinOp(">=", c, ex.Num("5")), unknown)) is False
    assert facts.value(ex.BinOp("\\/", ex.BinOp("<", c, ex.Num("5")), unknown)) is True
    assert facts.value(ex.BinOp("/\\", ex.BinOp("<", c, ex.Num("5")), unknown)) is None
    # a guard taken tells its tests; one refused, when a single test, the opposite
    taken = facts.taken(ex.BinOp("/\\", ex.BinOp(">=", x, ex.Num("1")),
                                 ex.UnaryOp("not", unknown)))
    assert taken.value(unknown) is False and taken.value(x) is None
    assert facts.refused(unknown).value(unknown) is False
    # an assignment that does not fold forgets; division by zero is not folded
    assert facts.assigned("D_c", x).value(c) is None
    assert Facts().value(ex.BinOp("/", ex.Num("1"), ex.Num("0"))) is None


# the motor and the range finder alone (the shaft's own states left out), the obstacle
# starting anywhere in [5, 5.1]
REACH = SCENARIO.replace("horizon = 1.6", "horizon = 1.5").replace(
    'model = "DCMotorBase"\n', 'model = "DCMotorBase"\nelements = '
    '["DCMotorBase::Bench::Shaft::Motor", "DCMotorBase::Bench::Range"]\n').replace(
    "Shaft_theta = 0\nShaft_v = 0\n", "").replace(
    "{distance}", "[5, 5.1]") + """[unsafe]
constraints = ["Motor_av >= {bound}"]
[flowstar]
step = 0.01
order = 6
remainder = 1e-2
cutoff = 1e-12
precision = 53
max_jumps = 40
"""


@pytest.mark.parametrize("bound, verdict", [(16, "SAFE"), (12.5, "UNSAFE")])
@needs_flowstar
def test_reach_compiles_the_machine_with_its_counter(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], bound: float, verdict: str) -> None:
    """The machine counts its switches in ``n``, which nothing reads: the automaton leaves it
    out (it had a mode per count: refused past 5000 configurations), and its first cycle
    reads ``near``, decided on the initial box (never near in it: Fast, exact). The speed
    overshoots 10 rad/s to about 12.8 before the first switch to 4, and later peaks are
    lower: below 16 (SAFE), above 12.5 (UNSAFE), as ``simulate`` shows from each end of the
    box."""
    folder, _ = _model(tmp_path / "bench", 5.0)
    scenario = tmp_path / "reach.toml"
    scenario.write_text(REACH.format(bound=bound))
    for start in (5.0, 5.1):
        point = tmp_path / f"point{start}.toml"
        point.write_text(SCENARIO.format(distance=start).replace("horizon = 1.6",
                                                                  "horizon = 1.5"))
        speed = np.array(_run("simulate", folder, point)["columns"]["Motor_av"])
        assert 12.6 < speed.max() < 13.5
    capsys.readouterr()
    code = main(["reach", str(folder), "--scenario", str(scenario), "--jobs", "1",
                 "--timeout", "240", "-o", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert (code, out.split(":")[0]) == ({"SAFE": 0, "UNSAFE": 1}[verdict], verdict), out
    assert "the first cycle reads near at the initial state: on the initial set it ends " \
        "in Fast (exact)" in out
