"""``cyphy show``: the elaborated p-model (text, JSON, Graphviz) or the d-model."""

from __future__ import annotations

import argparse
import sys

from cyphy.cli.options import const_options, path_option, const_values
from cyphy.diagnostics import render_text


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    show = sub.add_parser(
        "show",
        help="print the elaborated model",
        description="Elaborate one p-model (parts instantiated, indexed blocks replicated, "
        "constants evaluated, poses composed) and print it as a tree or as JSON.",
    )
    show.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    show.add_argument("--model", metavar="NAME", help="the p-model to show")
    show.add_argument("--dmodel", action="store_true",
                      help="show the d-model instead: modules, controllers and state machines")
    const_options(show)
    show.add_argument("--format", choices=("text", "json", "dot", "svg"), default="text",
                      help="text (default), json, or the kinematic graph: dot (Graphviz's "
                      "language) or svg (drawn by Graphviz's dot)")
    path_option(show)


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import ElaborateOptions, elaborate
    from cyphy.backends.show.pmodel import model_to_json, model_to_text

    if args.dmodel:
        return _show_dmodel(args)
    consts = const_values(args)
    result = elaborate(args.paths, ElaborateOptions(args.model, consts, tuple(args.path),
                                                    despite_value_errors=True))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.check.sources)))
    if result.model is None:
        return 1
    if args.format in ("dot", "svg"):
        # lazy: --help imports every command module; these pull in the model (NumPy)
        from cyphy.backends.show.graph import GraphvizMissing, dot_to_svg, model_to_dot

        out = model_to_dot(result.model)
        if args.format == "svg":
            try:
                out = dot_to_svg(out)
            except GraphvizMissing as err:
                sys.stderr.write(f"cyphy show: error: {err}\n")
                return 2
    else:
        out = model_to_json(result.model) if args.format == "json" \
            else model_to_text(result.model)
    sys.stdout.write(out)
    return result.report.exit_code


def _show_dmodel(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import CheckOptions, check
    from cyphy.backends.show.dmodel import dmodel_to_dict, dmodel_to_json, dmodel_to_text
    from cyphy.lang import ast
    from cyphy.model.machines import machines_of

    result = check(args.paths, CheckOptions(search_paths=tuple(args.path),
                                            consts=const_values(args)))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.sources)))
    if result.resolution is None:
        return 1
    files = list(result.workspace.user_files())
    # Errors stop the show only where the d-model is (a p-model beside it does not matter).
    dmodel_files = {f.path for f in files if any(isinstance(
        i, (ast.Module, ast.Controller, ast.StateMachine, ast.Interface)) for i in f.items)}
    if any(d.span.file in dmodel_files or d.span.file not in result.sources
           for d in result.report.errors):
        return 1
    data = dmodel_to_dict(files, result.resolution,
                          machines_of(files, result.resolution, operations=True))
    if not (data["modules"] or data["controllers"] or data["machines"]):
        sys.stderr.write("cyphy show: error: no module, controller or state machine in the "
                         "files\n")
        return 1
    sys.stdout.write(dmodel_to_json(data) if args.format == "json" else dmodel_to_text(data))
    return 0
