"""Decisive Flow* verdicts (issue 28): jumps without duplicates, exports that keep
precision, falsification before and after Flow*, bounded settings, verdicts for all time.
Known answers come from brute-force enumeration, from arithmetic on Flow*'s steps, and from
trajectories worked out independently (closed forms, SciPy) of the automaton cyphy writes."""

from __future__ import annotations

import itertools
import re
import subprocess
from pathlib import Path

import pytest

from conftest import EXAMPLES, flowstar_binary, needs_flowstar
from cyphy.diagnostics import Report
from cyphy.verify.flowstar.export import build_problem, render
from cyphy.verify.flowstar.guards import targets
from cyphy.verify.flowstar.scenario import load_scenario
from cyphy.verify.flowstar.syntax import parse_model

DCMOTOR = EXAMPLES / "dcmotor"

HEAD = """model = "DCMotorBase"
elements = ["DCMotorBase::Bench::Shaft::Motor", "DCMotorBase::Bench::Range"]
horizon = {horizon}
tscale = 0.1
[init]
Motor_av = {av}
Motor_i = 0
Motor_int1 = 0
Motor_theta = 0
Range_distance = {distance}
[environment]
Range_distance = "{env}"
"""

# Re-issue drive(8) while near; the transition to slow on the same event comes second, so
# it is never taken (the first `when` that holds wins): every cycle stays in fast.
SELF = HEAD + """[controller]
initial = "fast"
[controller.states.fast]
calls = ["drive(8)"]
[controller.states.slow]
calls = ["drive(2)"]
[[controller.transitions]]
from = "fast"
to = "fast"
when = "near"
[[controller.transitions]]
from = "fast"
to = "slow"
when = "near"
[[controller.transitions]]
from = "slow"
to = "fast"
when = "near"
[unsafe]
constraints = ["Motor_av >= 20"]
"""


def _problem(tmp_path: Path, text: str, name: str = "s"):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    report = Report()
    scenario = load_scenario(path, report)
    assert scenario is not None, report.diagnostics
    problem, _ = build_problem([DCMOTOR], scenario, report)
    assert problem is not None and not report.has_errors, report.diagnostics
    return problem


def _flowpipes(text: str, cwd: Path) -> int:
    proc = subprocess.run([str(flowstar_binary())], input=text, capture_output=True,
                          text=True, cwd=cwd, timeout=300)
    out = re.sub(r"\x1b\[[0-9;]*m", "", proc.stdout)
    m = re.search(r"Computation completed: (\d+) flowpipe", out)
    assert m, out + proc.stderr
    return int(m.group(1))


# --------------------------------------------------------------------------- 1. jumps

@pytest.mark.parametrize("transitions", [
    [("B", (("a", False), ("b", False)))],  # stay: not (a and b), once overlapping cubes
    [("A", (("n", False),)), ("B", (("f", False),))],  # a self-transition before another
    [("B", (("a", False),)), ("C", (("b", False),)), ("B", (("c", True),))],
    [("A", (("a", True), ("b", False))), ("C", (("a", False),)), ("A", (("b", True),))],
])
def test_guards_are_disjoint_and_follow_the_first_transition_that_holds(transitions):
    """Brute force over every combination of the events: exactly one cube of one target
    holds, and that target is the first transition's whose literals hold (else A stays)."""
    events = sorted({e for _, lits in transitions for e, _ in lits})
    out = targets("A", transitions)
    assert len({t for t, _ in out}) == len(out)  # one guard per target
    for combo in itertools.product((False, True), repeat=len(events)):
        value = dict(zip(events, combo))
        expected = next((t for t, lits in transitions
                         if all(value[e] != neg for e, neg in lits)), "A")
        holding = [t for t, cubes in out for cube in cubes
                   if all(value[e] != neg for e, neg in cube)]
        assert holding == [expected], (combo, out)


def test_a_self_transition_and_the_stay_are_one_unguarded_jump(tmp_path):
    problem = _problem(tmp_path, SELF.format(horizon=0.5, av=0, distance="[0.95, 1.05]",
                                             env="0"))
    model = parse_model(render(problem, "self"))
    out_of_fast = [j for j in model.jumps if j.source == "fast"]
    assert [(j.target, len(j.guard)) for j in out_of_fast] == [("fast", 1)]  # timer only


@needs_flowstar
def test_flowstar_computes_one_path_on_a_machine_with_a_self_transition(tmp_path):
    """The range straddles the event's threshold: with a duplicate self-jump (`near` and
    the stay's `not near` both admit the enclosure) Flow* doubled its flowpipes at every
    cycle (1112 flowpipes over 0.5 s, 94 s). One path is 5 cycles of 11 flowpipes (10
    steps of 0.01 s and the step ending on the guard `timer = 0.1`) and the last one."""
    problem = _problem(tmp_path, SELF.format(horizon=0.5, av=0, distance="[0.95, 1.05]",
                                             env="0"))
    assert _flowpipes(render(problem, "self"), tmp_path) == 5 * 11 + 1
