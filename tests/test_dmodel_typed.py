"""The theory's ``D`` for a machine that reads a typed input event
(:mod:`cyphy.semantics.circus.dmodel_cycle`): the held-out ranger (``$echo?seen``, then a
junction tests ``seen >= close``) and a follower whose call's argument is the value read
(``$echo?d`` then ``$roll(d * k)``), in both Isabelle dialects. The theories' structure is
read from their text; ``cyphy animate`` runs them and is compared with an independent
reference: the p-model's equations written out by hand below (the ranger's cart, motor and
IR sensor) integrated with SciPy, sampled each cycle by the machine's interpreter
(``MachineInterpreter``) driven by hand with the event the mapping gives."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

from cyphy import api
from cyphy import expr as ex
from cyphy.cli import main
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.build import build_semantics
from cyphy.verify.animate.animation import animate

HERE = Path(__file__).parent
RANGER = HERE / "data" / "heldout" / "ranger"
FOLLOW = HERE / "data" / "typed_follow"
RANGER_PATHS = [RANGER]
FOLLOW_PATHS = [RANGER / "RangerBase.rsm", FOLLOW]
TSCALE = 0.1  # approach.toml: one d-model time unit is 0.1 s, cycle = 1
DIALECTS = ("utp", "axiomatic")


def _generate(paths: list[Path], folder: Path, dialect: str) -> tuple[Path, str, list]:
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions(dialect=dialect))
    assert not generated.report.has_errors, generated.report.diagnostics
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in generated.files.items():
        (folder / name).write_text(text)
    theory = next(t for n, t in generated.files.items() if n.endswith(".thy")
                  and "Prelude" not in n)
    return folder, theory, list(generated.report.diagnostics)


def _definition(theory: str, name: str) -> str:
    start = theory.index(f'  "{name} = ')
    return theory[start:theory.index("\n", start)]


# ---------------------------------------------------------------- the theory's structure

@pytest.mark.parametrize("dialect", DIALECTS)
def test_ranger_d_reads_the_value_binds_it_and_guards_on_it(tmp_path: Path,
                                                            dialect: str) -> None:
    """D is stated (no W-SEMANTICS-DMODEL): its state holds the event's value and the
    machine's variable; Read takes both fields of registerRead; the transition that reads
    $echo?seen assigns the value to seen; the junction's guards test seen against close
    (1.0); the halt sends roll(0); check-theory finds nothing wrong."""
    folder, theory, diagnostics = _generate(RANGER_PATHS, tmp_path / dialect, dialect)
    assert not [d for d in diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert "  RangerSoftware_echo_value :: real\n" in theory
    assert "  RangerSoftware_seen :: real\n" in theory
    read = _definition(theory, "RangerSoftwareRead")
    step = _definition(theory, "RangerSoftwareStep")
    if dialect == "utp":
        assert "registerRead_echo?(echo_in)?(echo_value_in) \\<^bold>\\<rightarrow> " \
            "((RangerSoftware_echo, RangerSoftware_echo_value) :=\\<^sub>C " \
            "(\\<guillemotleft>echo_in\\<guillemotright>, " \
            "\\<guillemotleft>echo_value_in\\<guillemotright>))" in read
        assert "(RangerSoftware_seen :=\\<^sub>C &RangerSoftware_echo_value)" in step
        assert "(&RangerSoftware_echo =\\<^sub>u true)" in step
        assert "(&RangerSoftware_seen \\<ge>\\<^sub>u \\<guillemotleft>1.0\\<guillemotright>)" \
            in step
        assert "registerWrite_roll!(\\<guillemotleft>0.0\\<guillemotright>)" in step
    else:
        assert "registerRead_echo\\<^bold>?(echo_in, echo_value_in) \\<rightarrow> " \
            "((RangerSoftware_echo, RangerSoftware_echo_value) := " \
            "(echo_in, echo_value_in))" in read
        assert "(RangerSoftware_seen := RangerSoftware_echo_value)" in step
        assert "(RangerSoftware_echo = True)" in step
        assert "(RangerSoftware_seen \\<ge> 1.0)" in step
        assert "registerWrite_roll\\<^bold>!(0.0)" in step
    # the binding comes before the guard that reads it: the junction is passed in the cycle
    assert step.index("RangerSoftware_echo_value") < step.index("1.0")
    assert main(["check-theory", str(folder)]) == 0


def test_ranger_d_is_the_machine_cycle_by_hand() -> None:
    """The AST of D, against the machine read by hand: Init starts at the initial junction
    (node 0) with seen = 0; the first cycle enters Rolling (node 1), calling roll(0.4);
    from Rolling with echo the value is bound and the junction Look (node 2) goes to
    Halted (node 3, roll(0)) when seen >= 1.0, back into Rolling (its entry: roll(0.4))
    when seen < 1.0; from Look (rested in only if neither held) the same tests."""
    checked = api.check([RANGER], api.CheckOptions(neighbours_as_targets=True))
    sem = build_semantics(checked.workspace, checked.resolution, checked.report)
    assert sem is not None and isinstance(sem.program.dmodel, c.BasicProcess)
    d = sem.program.dmodel
    actions = {a.name: a.body for a in d.actions}
    assert [f.name for f in d.state.fields] == ["RangerSoftware_mode", "RangerSoftware_echo",
                                                "RangerSoftware_echo_value",
                                                "RangerSoftware_seen"]
    assert actions["RangerSoftwareInit"] == c.Assign(
        tuple(f.name for f in d.state.fields),
        (ex.Num("0"), ex.Bool(False), ex.Num("0"), ex.Num("0.0")))

    def name(text: str) -> ex.Name:
        return ex.Name((text,))

    def roll(v: str) -> c.Action:
        return c.Prefix(c.Comm("registerWrite", "roll", (c.Out(ex.Num(v)),)), c.Skip())

    def mode(n: str) -> c.Action:
        return c.Assign(("RangerSoftware_mode",), (ex.Num(n),))

    def at(n: str) -> ex.Expr:
        return ex.BinOp("==", name("RangerSoftware_mode"), ex.Num(n))

    near = ex.BinOp(">=", name("RangerSoftware_seen"), ex.Num("1.0"))
    far = ex.BinOp("<", name("RangerSoftware_seen"), ex.Num("1.0"))
    # entering Look in a cycle from Rolling: Halted (its entry), or Rolling again (its
    # entry; the exec transition waits), or resting at Look when neither guard holds
    look = c.Cond(near, c.Seq((roll("0.0"), mode("3"))), c.Cond(far, roll("0.4"), mode("2")))
    from_rolling = c.Cond(ex.BinOp("==", name("RangerSoftware_echo"), ex.Bool(True)),
                          c.Seq((c.Assign(("RangerSoftware_seen",),
                                          (name("RangerSoftware_echo_value"),)), look)),
                          c.Skip())
    from_look = c.Cond(near, c.Seq((roll("0.0"), mode("3"))),
                       c.Cond(far, c.Seq((roll("0.4"), mode("1"))), c.Skip()))
    assert actions["RangerSoftwareStart"] == c.Seq((roll("0.4"), mode("1")))
    assert actions["RangerSoftwareStep"] == c.Cond(at("1"), from_rolling,
                                                   c.Cond(at("2"), from_look, c.Skip()))


@pytest.mark.parametrize("dialect", DIALECTS)
def test_the_value_flows_into_the_calls_argument(tmp_path: Path, dialect: str) -> None:
    """``$echo?d`` then ``$roll(d * k)``: the call's argument is the expression over D's
    state (d times 0.5), not a literal."""
    folder, theory, diagnostics = _generate(FOLLOW_PATHS, tmp_path / dialect, dialect)
    assert not [d for d in diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    step = _definition(theory, "FollowSoftwareStep")
    if dialect == "utp":
        assert "registerWrite_roll!((&FollowSoftware_d * \\<guillemotleft>0.5" \
            "\\<guillemotright>))" in step
    else:
        assert "registerWrite_roll\\<^bold>!((FollowSoftware_d * 0.5))" in step
    assert main(["check-theory", str(folder)]) == 0


# ---------------------------------------------------------------- the reference, by hand

def _reference(machine_paths: list[Path], mapping_low: float, t_end: float, samples: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times, the cart's position and the motor's demand: RangerBase's equations by hand
    (the LinearSpeedControlMotor's PI loop and electrics driving the 0.5 kg cart along the
    rail, the IR sensor 1 m from the wall), the machine's interpreter run at the start of
    each cycle with ``echo`` present (carrying the reading) when the reading is at least
    ``mapping_low`` V, a ``roll(v)`` setting the demand; sampled at the ends of cycles
    (after the cycle's calls), as animate samples them."""
    from scipy.integrate import solve_ivp

    R, L, Kf, Ke, b, Kp, Ki = 1.0, 0.02, 2.0, 2.0, 0.2, 10.0, 20.0
    mass = 0.5

    def voltage(theta: float) -> float:
        return 0.3 / ((1.0 - theta) + 0.01) + 0.0

    interpreter, checked = api.machine_interpreter(machine_paths)
    assert interpreter is not None, checked.report.diagnostics
    interpreter.reset()
    demand = 0.0
    y = np.zeros(4)  # theta, v, i, integral of the speed error

    def rates(_t: float, s: np.ndarray) -> list[float]:
        theta, v, i, _ = s
        e = demand - v
        return [v, (Kf * i - b * v) / mass, (Kp * e + Ki * s[3] - R * i - Ke * v) / L, e]

    times, thetas, demands = [], [], []
    cycles = int(round(t_end / TSCALE))
    for k in range(cycles + 1):
        reading = voltage(y[0])
        event = reading if reading >= mapping_low else None
        for name, args in interpreter.cycle({"echo": event}):
            assert name == "roll"
            demand = args[0]
        times.append(k * TSCALE)
        thetas.append(y[0])
        demands.append(demand)
        if k < cycles:
            sol = solve_ivp(rates, (k * TSCALE, (k + 1) * TSCALE), y, method="LSODA",
                            rtol=1e-10, atol=1e-12)
            y = sol.y[:, -1]
    return np.array(times), np.array(thetas), np.array(demands)


def _columns(animation, names: list[str]) -> dict[str, np.ndarray]:  # type: ignore[no-untyped-def]
    rows = np.array(animation.rows)
    return {n: rows[:, animation.columns.index(n)] for n in names}


@pytest.mark.parametrize("dialect", DIALECTS)
def test_ranger_animated_halts_where_the_machine_by_hand_halts(tmp_path: Path,
                                                               dialect: str) -> None:
    """Over approach.toml's 3 s: the cart rolls at 0.4 m/s demanded until the reading the
    event carries reaches 1.0 V (the cart within 0.29 m of the wall), then the demand is 0
    and the cart stops short of the wall; animate's position and demand agree with the
    reference at every cycle within 1e-4."""
    folder, _, _ = _generate(RANGER_PATHS, tmp_path / dialect, dialect)
    t_end, samples = 3.0, 31  # one sample per cycle
    anim = animate(folder, t_end, consts={"tscale": TSCALE}, samples=samples)
    got = _columns(anim, ["t", "Carriage_theta", "Push_dls"])
    times, theta, demand = _reference([RANGER], 0.4, t_end, samples)
    assert np.allclose(got["t"], times)
    inner = times < t_end - 1e-9  # the last instant: before that cycle's calls in both
    assert np.max(np.abs(got["Carriage_theta"] - theta)) < 1e-4
    assert np.max(np.abs(got["Push_dls"][inner] - demand[inner])) < 1e-4
    halted = np.flatnonzero(demand == 0.0)
    assert halted.size and 1.5 < times[halted[0]] < 2.5  # the halt happens, mid-run
    assert np.all(demand[:halted[0]] == 0.4) and np.all(demand[halted[0]:] == 0.0)
    assert 0.71 <= theta[halted[0]] and theta[-1] < 0.8  # seen >= 1.0 V, short of the wall


@pytest.mark.parametrize("dialect", DIALECTS)
def test_follower_animated_demand_is_the_reading_times_k(tmp_path: Path,
                                                         dialect: str) -> None:
    """The follower's demand at each cycle is 0.5 × the reading at that cycle's start, in
    the theory as in the reference; the position agrees within 1e-4."""
    folder, _, _ = _generate(FOLLOW_PATHS, tmp_path / dialect, dialect)
    t_end = 1.5
    anim = animate(folder, t_end, consts={"tscale": TSCALE}, samples=16)
    got = _columns(anim, ["t", "Carriage_theta", "Push_dls", "Eye_voltage"])
    times, theta, demand = _reference(FOLLOW_PATHS, 0.2, t_end, 16)
    inner = times < t_end - 1e-9
    assert np.max(np.abs(got["Carriage_theta"] - theta)) < 1e-4
    assert np.max(np.abs(got["Push_dls"][inner] - demand[inner])) < 1e-4
    # from the second cycle on, the demand is half the reading taken at that cycle's start
    readings = 0.3 / (1.0 - theta + 0.01)
    assert np.allclose(demand[1:], 0.5 * readings[1:], atol=1e-9)
    assert demand[1] > 0.14 and theta[-1] > 0.1  # the cart moves


def test_a_typed_machine_d_cannot_write_is_refused_with_the_reason(tmp_path: Path) -> None:
    """A vector of truth values in a machine that reads a typed event: D stays opaque with
    the reason at the declaration (W-SEMANTICS-DMODEL), and gen still writes the rest."""
    software = (FOLLOW / "FollowSoftware.rsm").read_text()
    vector = software.replace("\tvar d: real = 0\n",
                              "\tvar d: real = 0\n\tvar w: vector(boolean, 2)\n")
    assert vector != software
    (tmp_path / "FollowSoftware.rsm").write_text(vector)
    (tmp_path / "Mapping.rsm").write_text((FOLLOW / "Mapping.rsm").read_text())
    checked = api.check([RANGER / "RangerBase.rsm", tmp_path],
                        api.CheckOptions(neighbours_as_targets=True))
    sem = build_semantics(checked.workspace, checked.resolution, checked.report)
    assert sem is not None and isinstance(sem.program.dmodel, c.OpaqueProcess)
    [warning] = [d for d in checked.report.diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert "SFollow" in warning.message and "D holds a vector of numbers" in warning.message
    assert warning.span.line == vector.splitlines().index("\tvar w: vector(boolean, 2)") + 1


# ---------------------------------------------------------------- a second construction

HELDOUT = HERE / "data" / "heldout"


def _typed_variant(model: Path, event: str, folder: Path) -> Path:
    """The held-out ``model`` with its input event ``event`` typed (``event e: real``, the
    mapping's ``? r`` carrying the sensor reading its predicate tests) and the machines
    unchanged: they only test the event's occurrence, so they behave as the untyped
    model's, whose ``D`` is the automaton's."""
    folder.mkdir(parents=True)
    for f in model.glob("*.rsm"):
        text = f.read_text()
        typed = text.replace(f"\tevent {event}\n", f"\tevent {event}: real\n")
        found = re.search(rf"\tinput event {event} \{{\n\t\tpredicate ((\S+) [<>]= \S+)\n", typed)
        if found:
            typed = typed.replace(found[0], f"\tinput event {event} ? r {{\n\t\tpredicate "
                                  f"{found[1]}\n\t\tequation r == {found[2]}\n")
        (folder / f.name).write_text(typed)
    assert (folder / "Mapping.rsm").read_text().count(f"input event {event} ? r") == 1
    return folder


@pytest.mark.parametrize("model, event, scenario, samples", [
    ("lift", "atTop", "cycle.toml", 71),    # entry/during/exit, a junction, a clock
    ("tracks", "near", "clear.toml", 21),   # a composite state, a clock, an int argument
    ("rover", "near", "bump.toml", 21),     # two machines in the module
])
def test_typed_variant_animates_as_the_automaton_d_of_the_untyped_model(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], model: str, event: str,
        scenario: str, samples: int) -> None:
    """One machine through both constructions: with the event typed, D is the cycle
    written out; untyped, the automaton (the product of the module's machines for the
    rover). Run by ``cyphy animate`` with the model's scenario, every state of the p-model
    agrees at every sample."""
    typed = _typed_variant(HELDOUT / model, event, tmp_path / "typed")
    runs = {}
    for name, folder in (("typed", typed), ("untyped", HELDOUT / model)):
        out = tmp_path / f"{name}-thy"
        assert main(["gen", "--isabelle", str(folder), "--scenario",
                     str(HELDOUT / model / scenario), "-o", str(out), "-q"]) == 0
        theory = next(out.glob("*_CyPhyCircus.thy")).read_text()
        assert ("Start = " in theory) == (name == "typed")  # which construction
        assert main(["check-theory", str(out)]) == 0
        capsys.readouterr()
        assert main(["animate", str(out), "--scenario", str(HELDOUT / model / scenario),
                     "--samples", str(samples), "--format", "json", "-q"]) == 0
        doc = json.loads(capsys.readouterr().out)
        runs[name] = {col: np.array([row[i] for row in doc["rows"]], dtype=float)
                      for i, col in enumerate(doc["columns"])
                      if "Software_" not in col}  # D's own state is named apart
    assert runs["typed"].keys() == runs["untyped"].keys() and len(runs["typed"]) > 10
    for col, values in runs["untyped"].items():
        assert np.max(np.abs(runs["typed"][col] - values)) < 1e-9, col


PULSE = HERE / "data" / "typed_pulse"


def test_actions_that_end_cycles_run_as_the_automaton_d_runs_them(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``wait(3)`` inside an entry action and ``exec`` inside a transition's action: the
    rest of the action resumes in a later cycle (a mode of its own in D). Typed, D is the
    cycle written out; untyped (the same machine, the event's value dropped), the
    automaton: animated on the ranger's cart for 3 s, position and demand agree at every
    cycle, and the demands are the machine's: 0.4, three cycles later 0.2, then 0.3 when
    echo occurs, 0.05 and Rest's 0.1 in the next cycle."""
    untyped = tmp_path / "untyped"
    untyped.mkdir()
    for f in PULSE.glob("*.rsm"):
        text = f.read_text().replace("event echo: real", "event echo")
        text = text.replace("input event echo ? r {", "input event echo {")
        text = re.sub(r"\n\t\tequation r == .*", "", text)
        (untyped / f.name).write_text(text)
    runs = {}
    for name, folder in (("typed", PULSE), ("untyped", untyped)):
        out = tmp_path / f"{name}-thy"
        assert main(["gen", "--isabelle", str(RANGER / "RangerBase.rsm"), str(folder), "-o",
                     str(out), "-q"]) == 0
        assert ("PulseSoftwareStart = " in (out / "RangerBase_CyPhyCircus.thy").read_text()) \
            == (name == "typed")
        assert main(["check-theory", str(out)]) == 0
        anim = animate(out, 3.0, consts={"tscale": TSCALE}, samples=31)
        runs[name] = _columns(anim, ["Carriage_theta", "Push_dls"])
    for col, values in runs["untyped"].items():
        assert np.max(np.abs(runs["typed"][col] - values)) < 1e-9, col
    assert list(np.round(runs["typed"]["Push_dls"][:7], 9)) == [0.4, 0.4, 0.4, 0.2, 0.3, 0.1,
                                                                   0.1]


def _simulated(paths: list[Path], t_end: float, samples: int) -> dict[str, np.ndarray]:
    """``cyphy simulate``'s trajectories (the model's equations and the machine's
    interpreter, never the theory), JSON on stdout, under approach.toml (tscale 0.1, the
    cart at rest at the start: the theory's Init)."""
    out = io.StringIO()
    argv = ["simulate", *map(str, paths), "--scenario", str(RANGER / "approach.toml"),
            "--t-end", str(t_end), "--samples", str(samples), "--format", "json", "-q"]
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    doc = json.loads(out.getvalue())
    return {"t": np.array(doc["t"]), **{k: np.array(v) for k, v in doc["columns"].items()}}


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("paths, t_end, samples", [
    (RANGER_PATHS, 3.0, 31),     # the halt at t = 1.9 s
    (FOLLOW_PATHS, 1.5, 16),     # the demand the reading times k
])
def test_animate_agrees_with_simulate(tmp_path: Path, dialect: str, paths: list[Path],
                                      t_end: float, samples: int) -> None:
    """The theory's D, animated, and ``cyphy simulate`` (the machine on its interpreter,
    the event carrying the mapping's value) give the same cart: every state both report
    within 1e-6 at every sample."""
    folder, _, _ = _generate(paths, tmp_path / dialect, dialect)
    anim = animate(folder, t_end, consts={"tscale": TSCALE}, samples=samples)
    sim = _simulated(paths, t_end, samples)
    rows = np.array(anim.rows)
    assert np.allclose(rows[:, 0], sim["t"])
    common = [c for c in anim.columns[1:] if c in sim]
    assert {"Carriage_theta", "Carriage_v", "Push_i", "Eye_voltage"} <= set(common)
    for col in common:
        assert np.max(np.abs(rows[:, anim.columns.index(col)] - sim[col])) < 1e-6, col


MIXED = HERE / "data" / "typed_mixed"


@pytest.mark.parametrize("dialect", DIALECTS)
def test_mixed_types_check(tmp_path: Path, dialect: str) -> None:
    """An ``int`` variable in real arithmetic (``0.1 * n``), a Boolean variable under
    ``not``, ``since(C)`` under ``cycleDef cycle == 2``: D holds the numbers as reals (UTP
    expressions do not convert int to real), the clock's count times 2, and the theory
    passes check-theory (an int-typed field there was a type error)."""
    folder, theory, diagnostics = _generate([RANGER / "RangerBase.rsm", MIXED],
                                            tmp_path / dialect, dialect)
    assert not [d for d in diagnostics if d.code.id == "W-SEMANTICS-DMODEL"]
    assert "  SmokeSoftware_n :: real\n" in theory and "  SmokeSoftware_seen :: bool\n" in theory
    step = _definition(theory, "SmokeSoftwareStep")
    if dialect == "utp":
        assert "((&SmokeSoftware_C * \\<guillemotleft>2.0\\<guillemotright>) \\<ge>\\<^sub>u 4)" \
            in step
        assert "(\\<not> (&SmokeSoftware_seen =\\<^sub>u true))" in step
    else:
        assert "((SmokeSoftware_C * 2.0) \\<ge> 4)" in step
        assert "(\\<not> (SmokeSoftware_seen = True))" in step
    assert main(["check-theory", str(folder)]) == 0
