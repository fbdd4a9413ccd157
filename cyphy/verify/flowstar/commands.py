"""``cyphy gen --flowstar`` and ``cyphy reach``: library functions the CLI calls (no printing
here, no exits)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Sequence

from cyphy.diagnostics import Report, Span
from cyphy.pipeline.generated import Generated
from cyphy.verify.flowstar.build import build_problem
from cyphy.verify.flowstar.export import output_name, render
from cyphy.verify.flowstar.printer import NotExpressible
from cyphy.verify.flowstar.scenario import EXPORT, SCENARIO, load_scenario

if TYPE_CHECKING:
    from cyphy.verify.flowstar.problem import Problem


def generate(paths: Sequence[str | Path], scenario_path: str | None, model: str | None = None,
             search_paths: tuple[str, ...] = (), consts: dict[str, object] | None = None,
             machine: str | None = None, default_inertial: str | None = None
             ) -> tuple[Generated, "Problem | None"]:
    """The Flow* model of the p-model under the scenario, as ``NAME.model`` (NAME from the
    scenario's file name), and the problem it renders (None on errors), which
    :func:`cyphy.verify.flowstar.check.check` decomposes, splits and runs. ``machine`` names the
    d-model's state machine that is the controller when the scenario has no ``[controller]``;
    ``default_inertial`` (``"sdf"``) wins over the scenario's ``default_inertial``."""
    report = Report()
    if scenario_path is None:
        report.report(SCENARIO, "the Flow* export needs a scenario", Span.unknown("<command>"),
                      "give --scenario FILE (the scenario format: docs/commands/reach.md)")
        return Generated(report), None
    scenario = load_scenario(scenario_path, report)
    if scenario is None:
        text = Path(scenario_path).read_text(encoding="utf-8", errors="replace") \
            if Path(scenario_path).is_file() else ""
        return Generated(report, {scenario_path: text}), None
    if model is not None:
        scenario.model = model
    if machine is not None:
        if scenario.states:
            report.report(SCENARIO, f"--machine {machine}: the scenario has a [controller], "
                          "which is the controller", scenario.span("controller"),
                          "remove the [controller] table to use the machine")
            return Generated(report, {scenario_path: scenario.text}), None
        scenario.machine = machine
    scenario.consts.update(consts or {})
    if default_inertial is not None:
        scenario.default_inertial = default_inertial
    problem, sources = build_problem(paths, scenario, report, search_paths)
    if problem is None or report.has_errors:
        return Generated(report, sources), None
    name = output_name(scenario_path)
    disjuncts = problem.disjuncts()
    try:
        if len(disjuncts) == 1:
            files = {f"{name}.model": render(problem, name)}
        else:  # Flow* checks one conjunction per model
            files = {f"{name}_{k + 1}.model": render(d, f"{name}_{k + 1}")
                     for k, d in enumerate(disjuncts)}
    except NotExpressible as err:  # what the checks while building did not foresee
        report.report(EXPORT, f"the automaton cannot be written for Flow*: {err}",
                      scenario.span("unsafe"), "the scenario format: docs/commands/reach.md")
        return Generated(report, sources), None
    return Generated(report, sources, files), problem
