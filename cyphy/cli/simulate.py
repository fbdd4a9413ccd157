"""``cyphy simulate``: the model's equations integrated with SciPy, optionally under a
scenario's controller or the d-model's state machine."""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
from pathlib import Path

from cyphy.cli.options import (const_options, const_values, default_inertial_option,
                               finite_float, gravity_option, path_option)
from cyphy.diagnostics import Report, render_text
from cyphy.outputs import OutputError, write_file


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    simulate = sub.add_parser(
        "simulate",
        help="integrate the model's equations of motion and devices (SciPy)",
        description="Integrate the explicit ODEs that `cyphy solve` derives (the kinematic "
        "tree's equations of motion included) with SciPy's solve_ivp, and write the "
        "trajectories: t, then one column per state and output. With --numeric the "
        "kinematic tree is integrated alone, with the numeric articulated-body algorithm; "
        "its inputs are then the joint efforts <Joint>_tau.",
    )
    simulate.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    simulate.add_argument("--model", metavar="NAME", help="the p-model to simulate")
    simulate.add_argument("--scenario", metavar="FILE",
                          help="a Flow* scenario (TOML, as for gen --flowstar): its "
                          "[controller] runs at the d-model cycle, its [environment] drives "
                          "the sensor inputs, its [init] intervals start at their midpoints; "
                          "without [controller] the d-model's state machine runs")
    simulate.add_argument("--machine", metavar="NAME",
                          help="the d-model's state machine that is the controller when the "
                          "scenario has no [controller]")
    simulate.add_argument("--t-end", type=finite_float, metavar="T",
                          help="simulated time in seconds (default 1, or the scenario's "
                          "horizon)")
    simulate.add_argument("--init", action="append", default=[], metavar="NAME=VALUE",
                          help="initial value of a state (default 0); repeatable")
    simulate.add_argument("--input", action="append", default=[], metavar="NAME=EXPR",
                          help="an input as an expression of t, e.g. 'Motor_das=10*sin(t)' "
                          "(default 0); repeatable")
    simulate.add_argument("--method", default=None,
                          choices=("LSODA", "BDF", "Radau", "RK45", "DOP853", "RK23"),
                          help="solve_ivp's method (default: DOP853, explicit, unless the "
                          "model is stiff at the start, then BDF with the analytic Jacobian); "
                          "the choice is noted on stderr")
    simulate.add_argument("--rtol", type=finite_float, default=1e-6, help="relative tolerance")
    simulate.add_argument("--atol", type=finite_float, default=1e-9, help="absolute tolerance")
    simulate.add_argument("--samples", type=int, default=201,
                          help="output instants over [0, T] (default 201)")
    simulate.add_argument("--numeric", action="store_true",
                          help="the kinematic tree alone, with the articulated-body algorithm")
    simulate.add_argument("--format", choices=("csv", "json"), default="csv")
    simulate.add_argument("-o", "--output", metavar="FILE", help="write here, not to stdout")
    simulate.add_argument("--plot", metavar="FILE.png", help="also plot to this PNG")
    simulate.add_argument("--plot-var", action="append", default=[], metavar="NAME",
                          help="a column to plot (repeatable; default the first 8)")
    gravity_option(simulate)
    default_inertial_option(simulate)
    const_options(simulate)
    path_option(simulate)


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy, SciPy)
    from cyphy.api import SimulateOptions, simulate
    from cyphy.backends import simulate as sim

    def pairs(items: list[str], option: str) -> dict[str, str] | None:
        out = {}
        for item in items:
            name, sep, value = item.partition("=")
            if not sep or not name.strip():
                sys.stderr.write(f"cyphy simulate: error: {option} takes NAME=VALUE, not "
                                 f"'{item}'\n")
                return None
            out[name.strip()] = value.strip()
        return out

    init, inputs = pairs(args.init, "--init"), pairs(args.input, "--input")
    if init is None or inputs is None:
        return 2
    try:
        values = {k: float(v) for k, v in init.items()}
    except ValueError:
        sys.stderr.write("cyphy simulate: error: --init takes a number: NAME=0.5\n")
        return 2
    bad = [f"{k}={v}" for k, v in values.items() if not math.isfinite(v)]
    if bad:
        sys.stderr.write(f"cyphy simulate: error: --init {bad[0]}: not a finite number\n")
        return 2
    if args.machine is not None and args.scenario is None:
        sys.stderr.write("cyphy simulate: error: --machine needs --scenario (a scenario "
                         "without [controller])\n")
        return 2
    if args.t_end is None:
        args.t_end = _scenario_horizon(args.scenario) if args.scenario else 1.0
    if not args.t_end > 0 or args.samples < 2:
        sys.stderr.write("cyphy simulate: error: --t-end must be positive and --samples at "
                         "least 2\n")
        return 2
    try:  # the budget for the smallest trajectory: time and one column (refined later)
        sim.check_memory(args.samples, 1)
    except sim.OptionError as err:
        sys.stderr.write(f"cyphy simulate: error: {err.message} ({err.hint})\n")
        return 2
    settings = sim.SimulationOptions(args.t_end, values, inputs, args.method, args.rtol,
                                     args.atol, args.samples,
                                     sim.progress_to_stderr if sys.stderr.isatty() else None)
    result = simulate(args.paths, SimulateOptions(args.model, const_values(args), tuple(args.path),
                                                  settings, args.numeric, args.scenario,
                                                  args.gravity, machine=args.machine,
                                                  default_inertial=args.default_inertial,
                                                  floating_base=args.floating_base))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.elaboration.check.sources)))
    if result.trajectory is None or result.report.has_errors:
        return 1
    if result.idle_machines:
        idle = result.idle_machines
        which = f"machine {idle[0]} is" if len(idle) == 1 else f"machines {', '.join(idle)} are"
        sys.stderr.write(f"cyphy simulate: the d-model's {which} not run: a machine runs "
                         "under --scenario (its tscale and initial values); this is the "
                         "p-model alone, its inputs as --input gives them, else 0\n")
    if result.numeric:
        sys.stderr.write("cyphy simulate: the kinematic tree alone (articulated-body "
                         "algorithm): the other devices' equations are not simulated\n")
    sys.stderr.write(f"cyphy simulate: integrated with {result.trajectory.method} "
                     f"({result.trajectory.reason}; --method to change), dynamics by "
                     f"{result.trajectory.engine}\n")
    text = (sim.to_json if args.format == "json" else sim.to_csv)(result.trajectory)
    code = 0
    if args.output:
        code = _keep(Path(args.output), text)
    else:
        sys.stdout.write(text)
    if args.plot:
        try:
            png = sim.plot(result.trajectory, args.plot_var)
        except sim.SimulationError as err:
            sys.stderr.write(f"cyphy simulate: error: {err.message} ({err.hint})\n")
            return 1
        code = _keep(Path(args.plot), png) or code
    return code


def _keep(target: Path, content: str | bytes) -> int:
    """Write a result atomically; when that fails after all (the disk filled during the
    run), save it in a temporary file rather than lose it, and say where (exit 1)."""
    try:
        write_file(target, content)
        return 0
    except OutputError as err:
        fd, rescue = tempfile.mkstemp(prefix="cyphy-", suffix=target.suffix)
        with os.fdopen(fd, "wb") as stream:
            stream.write(content.encode("utf-8") if isinstance(content, str) else content)
        sys.stderr.write(f"cyphy simulate: error: {err}; the result is saved in {rescue}\n")
        return 1


def _scenario_horizon(path: str) -> float:
    """The scenario's horizon, or 1 when the file cannot be read (simulate reports why)."""
    # lazy: --help imports every command module; these pull in the model
    from cyphy.verify.flowstar.scenario import load_scenario

    scenario = load_scenario(path, Report(), needs_unsafe=False)
    return scenario.horizon if scenario is not None else 1.0
