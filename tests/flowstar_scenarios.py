"""Flow* scenarios of ``examples/dcmotor``'s motor bench that several tests and
``benchmarks/bench_reach_horizon.py`` share: the scenario's head (model, elements, initial
intervals, environment), the controller tables written from a short description, and the
problem built from a scenario file (asserting that it loads and builds without errors)."""

from __future__ import annotations

import json
from pathlib import Path

#: ``examples/dcmotor``'s scenario: the motor stops when the range finder sees the obstacle.
SAMPLED_STOP = Path(__file__).resolve().parent.parent / "examples" / "dcmotor" / "sampled_stop.toml"
#: The motor and the range finder of the bench; ``str.format`` fills the horizon, the motor's
#: initial speed, the obstacle's initial distance and how that distance evolves.
MOTOR_HEAD = """model = "DCMotorBase"
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


def sampled_stop(folder: Path, name: str, *edits: tuple[str, str]) -> Path:
    """:data:`SAMPLED_STOP` without its ``max_jumps`` (the horizon decides how many jumps),
    with each (old, new) edit made (``old`` must be there), written as ``folder/NAME.toml``."""
    text = SAMPLED_STOP.read_text().replace("max_jumps = 25\n", "")
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = folder / f"{name}.toml"
    path.write_text(text)
    return path


def controller(initial: str, states: dict[str, list[str]],
               transitions: list[tuple[str, str, str]]) -> str:
    """A scenario's ``[controller]`` table: each state with its calls, each transition as
    (from, to, when), in the order given (the first ``when`` that holds wins)."""
    lines = ["[controller]", f'initial = "{initial}"']
    for name, calls in states.items():
        lines += [f"[controller.states.{name}]", f"calls = {json.dumps(calls)}"]
    for source, target, when in transitions:
        lines += ["[[controller.transitions]]", f'from = "{source}"', f'to = "{target}"',
                  f'when = "{when}"']
    return "\n".join(lines) + "\n"


#: Cruise (drive(8)) and coast (drive(6)) on the range finder's event, back and forth: an
#: obstacle that never comes near makes the automaton jump at every cycle.
CRUISE_COAST = controller("cruise", {"cruise": ["drive(8)"], "coast": ["drive(6)"]},
                          [("cruise", "coast", "near"), ("coast", "cruise", "not near")])

#: Cruise, then coast without calls (the inputs are held) once near, then stop once no
#: longer near.
CRUISE_COAST_STOP = controller(
    "cruise", {"cruise": ["drive(8)"], "coast": [], "stopped": ["stop()"]},
    [("cruise", "coast", "near"), ("coast", "stopped", "not near")])


def scenario_problem(folder: Path, scenario_path: Path):  # -> Problem
    """The problem of the model in ``folder`` under the scenario, which must load and build
    without errors."""
    # lazy: benchmarks/bench_reach_horizon.py reads the texts only, in a process that
    # times others
    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.build import build_problem
    from cyphy.verify.flowstar.scenario import load_scenario

    report = Report()
    scenario = load_scenario(scenario_path, report)
    assert scenario is not None, report.diagnostics
    problem, _ = build_problem([folder], scenario, report)
    assert problem is not None and not report.has_errors, report.diagnostics
    return problem
