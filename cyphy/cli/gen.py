"""``cyphy gen``: check the model and, when it has no errors, write one target's files.

Each target lives in its own module (``gen_sdf``, ``gen_trees``, ``gen_flowstar``,
``gen_semantics``) as a ``TARGETS`` table of :class:`cyphy.cli.target.Target`; a new target is
a new module named in :data:`TARGET_MODULES`.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from pathlib import Path

from cyphy.cli.options import const_options, path_option
from cyphy.cli.target import Target
from cyphy.diagnostics import diagnostics_json, render_text
from cyphy.outputs import OutputError, default_output_dir, write_all

#: The modules holding ``cyphy gen``'s targets, in the order ``--help`` lists them.
TARGET_MODULES = ("gen_sdf", "gen_trees", "gen_flowstar", "gen_semantics")


def _generators() -> dict[str, Target]:
    """Every target by its flag, from the modules of :data:`TARGET_MODULES`."""
    table: dict[str, Target] = {}
    for name in TARGET_MODULES:
        table.update(importlib.import_module(f"cyphy.cli.{name}").TARGETS)
    return table


#: ``cyphy gen`` targets: flag → :class:`Target` (generator, flag help, options).
GENERATORS: dict[str, Target] = _generators()


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    gen = sub.add_parser(
        "gen",
        help="generate files for simulators and provers",
        description="Check the model and, when it has no errors, generate the chosen artefact. "
        "Without -o the files go beside the model, in RoboTool's folder names (sdf-gen/, "
        "cpc-gen/, isabelle-gen/, flowstar-gen/; ours urdf-gen/, mjcf-gen/). A model with errors "
        "writes nothing.",
    )
    gen.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    targets = gen.add_mutually_exclusive_group(required=True)
    for target, (_, flag_help, _) in GENERATORS.items():
        targets.add_argument(f"--{target}", dest="target", action="store_const", const=target,
                             help=flag_help)
    gen.add_argument("-o", "--output", metavar="DIR", help="output folder")
    gen.add_argument("--model", metavar="NAME", help="the p-model (or mapping) to generate for")
    gen.add_argument("--format", choices=("text", "json"), default="text",
                     help="json: print one JSON document (files written, diagnostics) on "
                     "stdout instead of text")
    const_options(gen)
    path_option(gen)
    for _, _, add_options in GENERATORS.values():
        add_options(gen)


def run(args: argparse.Namespace) -> int:
    stray = _options_of_other_targets(args)
    if stray:
        sys.stderr.write(f"cyphy gen: error: {stray}\n")
        return 2
    run, _, _ = GENERATORS[args.target]
    generated = run(args)
    diagnostics = generated.report.diagnostics
    as_json = getattr(args, "format", "text") == "json"
    if diagnostics and not as_json:
        sys.stderr.write(render_text(diagnostics, dict(generated.sources)))
    refused = args.warnings_as_errors and any(d.severity.value == "WARNING"
                                              for d in diagnostics)
    written: list[Path] = []
    problem = None
    if generated.report.has_errors or not generated.files or refused:
        problem = "nothing written: the model has " + ("warnings (--warnings-as-errors)"
                                                       if refused else "errors")
    else:
        folder = getattr(args, "default_folder", args.target)  # a generator may choose
        out_dir = Path(args.output) if args.output else default_output_dir(args.paths, folder)
        try:
            written = write_all(generated.files, out_dir)
        except OutputError as err:
            problem = f"error: {err}"
    if as_json:  # one document on stdout: what was written and every diagnostic
        sys.stdout.write(json.dumps({"written": [str(p) for p in written], "error": problem,
                                     "diagnostics": diagnostics_json(diagnostics)},
                                    indent=2) + "\n")
    elif problem:
        sys.stderr.write(f"cyphy gen: {problem}\n")
    elif not args.quiet:
        for path in written:
            sys.stdout.write(f"wrote {path}\n")
    return 1 if problem else generated.report.exit_code


def _options_of_other_targets(args: argparse.Namespace) -> str | None:
    """Why the command line is wrong when it sets an option that only other targets take
    (``--split-trees`` with ``--cyphycircus``), which would otherwise be silently ignored.
    Each target's options are found by letting it add them to a scratch parser."""
    owners: dict[str, list[str]] = {}
    flags: dict[str, str] = {}
    defaults: dict[str, object] = {}
    for target, (_, _, add_options) in GENERATORS.items():
        scratch = argparse.ArgumentParser(add_help=False)
        add_options(scratch)
        for action in scratch._actions:
            owners.setdefault(action.dest, []).append(target)
            flags[action.dest] = action.option_strings[0]
            defaults[action.dest] = action.default
    for dest, targets in owners.items():
        if args.target not in targets and getattr(args, dest, None) != defaults[dest]:
            takes = ", ".join(f"--{t}" for t in targets)
            return f"{flags[dest]} is an option of {takes}, not of --{args.target}"
    return None
