"""``cyphy solve``: the model's equations reduced to explicit ODEs (SymPy)."""

from __future__ import annotations

import argparse
import sys

from cyphy.cli.options import (const_options, const_values, default_inertial_option,
                               gravity_option, path_option)
from cyphy.diagnostics import render_text


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    solve = sub.add_parser(
        "solve",
        help="reduce the model's equations to explicit ODEs (SymPy)",
        description="Assemble the equations of a p-model (optionally with the effect of one "
        "mapping operation), reduce them to explicit first-order ODEs x' = f(x, u, p) and, "
        "for linear systems with constant inputs and known constants, give the closed form.",
    )
    solve.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    solve.add_argument("--model", metavar="NAME", help="the p-model to solve")
    solve.add_argument("--element", action="append", default=[], metavar="QUALIFIED",
                       help="only this element and what it contains (repeatable), e.g. "
                       "marXbotBase::Core::LHinge::LMotor")
    solve.add_argument("--mapping-call", metavar="CALL",
                       help="add the effect of a mapping operation, e.g. 'move(0.1, 0)'")
    gravity_option(solve)
    default_inertial_option(solve)
    const_options(solve)
    solve.add_argument("--format", choices=("text", "latex", "json"), default="text")
    path_option(solve)


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy, SymPy)
    from cyphy.api import SolveOptions, UsageError, solve
    from cyphy.backends.odes import odes_to_json, odes_to_latex, odes_to_text

    options = SolveOptions(args.model, tuple(args.element), args.mapping_call, const_values(args),
                           tuple(args.path), gravity=args.gravity,
                           default_inertial=args.default_inertial,
                           floating_base=args.floating_base)
    try:
        result = solve(args.paths, options)
    except UsageError as err:
        sys.stderr.write(f"cyphy solve: error: --element {err}\n")
        return 2
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.elaboration.check.sources)))
    if result.reduced is None or (result.reduced.obstacles and not result.reduced.states):
        return 1
    render = {"text": odes_to_text, "latex": odes_to_latex, "json": odes_to_json}
    sys.stdout.write(render[args.format](result.reduced, result.closed_form))
    return result.report.exit_code
