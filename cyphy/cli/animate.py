"""``cyphy animate SESSION_DIR``: run a generated Isabelle/UTP session from its text alone
(``D`` and ``P`` synchronised on their channels, ``Evolve`` integrated with SciPy)."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from cyphy.cli.options import finite_float

if TYPE_CHECKING:
    from cyphy.verify.animate.errors import AnimateError


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    animate = sub.add_parser(
        "animate", help="run a generated Isabelle/UTP session (its text alone)",
        description="Read a session that cyphy gen --isabelle wrote (ROOT and theories, "
        "never the model), run its composition N = (D [| cs |] P) \\ cs from Init, "
        "integrating Evolve's equations with SciPy between the cycle's tocks, and write "
        "every state variable's trajectory and the events D and P exchanged. Both "
        "dialects (utp, axiomatic).")
    animate.add_argument("session", metavar="SESSION_DIR", help="the session's folder")
    animate.add_argument("--t-end", type=finite_float, default=None, metavar="T",
                         help="simulated time in seconds (default the scenario's horizon, "
                         "else 1)")
    animate.add_argument("--scenario", metavar="FILE",
                         help="the TOML scenario simulate and reach read: its [consts] and "
                         "world inputs ([environment] from [init]) as --const and --input "
                         "would give them (those options win), its tscale when the theory "
                         "leaves it open, its horizon as --t-end")
    animate.add_argument("--input", action="append", default=[], metavar="NAME=EXPR",
                         help="a world input of the p-model (a state no equation or action "
                         "sets, e.g. a sensor's distance) as an expression of t and the state: "
                         "'Range_distance=3-2*t'; repeatable")
    animate.add_argument("--const", action="append", default=[], metavar="NAME=VALUE",
                         help="a value for one of the theory's constants (an open one, such as "
                         "tscale, or a defined one to override), by its theory name or by "
                         "RoboSim's as simulate takes it (lv, SpeedControlMotor::R); repeatable")
    animate.add_argument("--samples", type=int, default=201,
                         help="output instants over [0, T] (default 201)")
    animate.add_argument("--format", choices=("csv", "json"), default="csv")
    animate.add_argument("-o", "--output", metavar="FILE", help="write here, not to stdout")
    animate.add_argument("--plot", metavar="FILE.png", help="also plot to this PNG")
    animate.add_argument("--plot-var", action="append", default=[], metavar="NAME",
                         help="a column to plot (repeatable; default the integrated states)")


def _error(message: str) -> int:
    sys.stderr.write(f"cyphy animate: error: {message}\n")
    return 2


def _report(err: "AnimateError") -> int:
    sys.stderr.write(f"{err.where()}: ERROR {err.code}: {err.message}\n")
    if err.hint:
        sys.stderr.write(f"  hint: {err.hint}\n")
    return err.status


def _note(names: list[str], noun: str, what: str) -> None:
    """One stderr line naming what the output leaves out or holds (the first six)."""
    if names:
        shown = ", ".join(names[:6]) + (", …" if len(names) > 6 else "")
        sys.stderr.write(f"cyphy animate: {len(names)} {noun}{'s' if len(names) != 1 else ''}"
                         f" {what}: {shown}\n")


def _pairs(items: list[str], option: str) -> dict[str, str] | str:
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            return f"{option} takes NAME=VALUE, not '{item}'"
        out[name.strip()] = value.strip()
    return out


def run(args: argparse.Namespace) -> int:
    # lazy: the reader (lark), SymPy and SciPy load when the command runs, not for --help
    from cyphy.outputs import OutputError, write_file
    from cyphy.verify.animate.animation import animate
    from cyphy.verify.animate.errors import AnimateError
    from cyphy.verify.animate.output import plot, to_csv, to_json

    inputs, consts = _pairs(args.input, "--input"), _pairs(args.const, "--const")
    if isinstance(inputs, str):
        return _error(inputs)
    if isinstance(consts, str):
        return _error(consts)
    values: dict[str, float] = {}
    for name, text in consts.items():
        truth = {"true": 1.0, "false": 0.0}.get(text.strip().lower())  # a Boolean constant's
        try:
            values[name] = float(text) if truth is None else truth
        except ValueError:
            return _error(f"--const {name}={text}: not a number")
        if not math.isfinite(values[name]):
            return _error(f"--const {name}={text}: not a finite number")
    # lazy: the scenario reader, only when a command runs (SymPy inside, at its own call)
    from cyphy.verify.animate import scenario as scenario_file
    values = scenario_file.theory_values(values, Path(args.session))
    scenario_consts: dict[str, float] = {}
    rates: dict[str, tuple[str, float]] = {}
    if args.scenario:
        try:
            given = scenario_file.read(Path(args.scenario), Path(args.session))
        except AnimateError as err:
            return _report(err)
        rates = {k: v for k, v in given.state_dependent.items() if k not in inputs}
        inputs = {**given.inputs, **inputs}
        scenario_consts = dict(given.consts)
        if given.tscale is not None:
            scenario_consts["tscale"] = given.tscale
        if args.t_end is None and given.horizon is not None:
            args.t_end = given.horizon
    if args.t_end is None:
        args.t_end = 1.0
    if not args.t_end > 0:
        return _error(f"--t-end {args.t_end:g}: the time must be above 0")
    if args.samples < 2:
        return _error("--samples must be at least 2")
    try:
        animation = animate(Path(args.session), args.t_end, inputs, values, args.samples,
                            scenario_consts, rates)
        text = (to_json if args.format == "json" else to_csv)(animation)
        png = plot(animation, args.plot_var) if args.plot else None
    except AnimateError as err:
        return _report(err)
    try:
        if args.output:
            write_file(Path(args.output), text)
        else:
            sys.stdout.write(text)
        if png is not None:
            write_file(Path(args.plot), png)
    except OutputError as err:
        sys.stderr.write(f"cyphy animate: error: {err}\n")
        return 1
    _note(animation.undetermined, "state variable", "that no equation determines left out "
          "(world inputs not given with --input, forces the equations leave open)")
    _note(animation.held, "world input", "not given with --input held at 0 (the axiomatic "
          "theory lets them start anywhere and move at any rate)")
    return 0
