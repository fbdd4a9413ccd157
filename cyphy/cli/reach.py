"""``cyphy reach``: the model under a scenario exported for Flow*, run, and one verdict."""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

from cyphy.cli.options import (const_options, const_values, default_inertial_option, path_option,
                               positive_float)
from cyphy.diagnostics import render_text
from cyphy.outputs import OutputError, write_all
from cyphy.verify.flowstar import limits


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    reach = sub.add_parser(
        "reach",
        help="check a scenario's unsafe set with Flow*: SAFE, UNSAFE or UNKNOWN",
        description="Export the model under the scenario as for `gen --flowstar`, run Flow* "
        "on it and print one line: SAFE, UNSAFE or UNKNOWN with the reason, Flow*'s time "
        "and the model's path. Exit status: 0 SAFE, 1 UNSAFE, 3 UNKNOWN, 2 errors.",
    )
    reach.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    reach.add_argument("--scenario", metavar="FILE", required=True,
                       help="the controller scenario (TOML)")
    reach.add_argument("--flowstar-bin", metavar="PATH",
                       help="the Flow* executable (default: $CYPHY_FLOWSTAR, the one "
                       ".ci/install built, or flowstar on PATH)")
    reach.add_argument("--timeout", type=positive_float, metavar="SECONDS",
                       help="give up (UNKNOWN) when a Flow* run takes longer")
    reach.add_argument("--split", type=limits.boxes, default=1, metavar="N",
                       help="split the initial set into N boxes along its widest state, one "
                       "Flow* run each (default 1; a run ending UNKNOWN is retried with "
                       "4 boxes unless --no-auto-split)")
    reach.add_argument("--no-auto-split", action="store_true",
                       help="do not retry an UNKNOWN run (finer settings, smaller boxes)")
    reach.add_argument("--jobs", type=int, metavar="N",
                       help="Flow* runs at a time (default: the number of cores)")
    reach.add_argument("-o", "--output", metavar="DIR",
                       help="keep the Flow* model in DIR, and in runs/ each model Flow* ran "
                       "(default: a temporary folder, removed at the end)")
    reach.add_argument("--keep", action="store_true",
                       help="keep the temporary folder with the Flow* models, and print its "
                       "path")
    reach.add_argument("--model", metavar="NAME", help="the p-model")
    reach.add_argument("--machine", metavar="NAME",
                       help="the d-model's state machine that is the controller when the "
                       "scenario has no [controller]")
    default_inertial_option(reach)
    const_options(reach)
    path_option(reach)


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (Lark, NumPy, SymPy)
    from cyphy.verify.flowstar.commands import generate
    from cyphy.verify.flowstar.check import check
    from cyphy.verify.flowstar.locate import find_flowstar
    from cyphy.verify.flowstar.verdict import FlowstarMissing

    try:
        binary = find_flowstar(args.flowstar_bin)
    except FlowstarMissing as err:
        sys.stderr.write(f"cyphy reach: error: {err}\n")
        return 2
    if args.split < 1 or (args.jobs is not None and args.jobs < 1):
        sys.stderr.write("cyphy reach: error: --split and --jobs take a positive number\n")
        return 2
    generated, problem = generate(args.paths, args.scenario, args.model, tuple(args.path),
                                  const_values(args), args.machine, args.default_inertial)
    if generated.report.diagnostics:
        sys.stderr.write(render_text(generated.report.diagnostics, dict(generated.sources)))
    if generated.report.has_errors or not generated.files or problem is None:
        sys.stderr.write("cyphy reach: nothing checked: the model or scenario has errors\n")
        return 2
    # Never beside the inputs, which may be read-only (the corpus): -o, else a scratch folder
    out_dir = Path(args.output) if args.output else Path(tempfile.mkdtemp(prefix="cyphy-reach-"))
    kept = args.output is not None or args.keep
    try:
        model = write_all(generated.files, out_dir)[0]
        result = check(problem, model.stem, binary, args.timeout, args.split,
                       not args.no_auto_split, args.jobs)
        if kept:
            write_all(result.runs, out_dir)  # the models Flow* ran (parts, boxes, rungs)
    except (FlowstarMissing, OutputError) as err:
        sys.stderr.write(f"cyphy reach: error: {err}\n")
        return 2
    finally:
        if not kept:
            shutil.rmtree(out_dir, ignore_errors=True)
    where = f"; model {model}" if kept else ""
    line = f"{result.verdict}: {result.reason} (Flow* runs {result.seconds:.1f} s{where})\n"
    stream = sys.stderr if result.verdict == "ERROR" else sys.stdout
    stream.write(line)
    if result.witness is not None:
        stream.write("the trajectory (time, event, controller state, state):\n")
        stream.write("\n".join(result.witness.lines(result.names)) + "\n")
    if result.details and (len(result.details) > 1 or result.verdict != "SAFE"):
        stream.write("Flow* runs:\n" + "\n".join(result.details) + "\n")
    return result.exit_code
