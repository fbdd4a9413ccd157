"""``cyphy check``: parse, resolve and check model files, and report every problem."""

from __future__ import annotations

import argparse
import sys

from cyphy import codes
from cyphy.cli.options import const_options, path_option, positive_int, const_values
from cyphy.diagnostics import render_json, render_text


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    check = sub.add_parser(
        "check",
        help="parse, resolve and check model files",
        description="Parse the model files (a folder means every model file in it), resolve "
        "names across them and the built-in physmod library, and report every problem.",
    )
    check.add_argument("paths", nargs="*", metavar="PATH", help="model file or folder")
    check.add_argument("--list-rules", action="store_true",
                       help="list the well-formedness conditions checked, and exit")
    check.add_argument("--syntax-only", action="store_true", help="stop after parsing")
    check.add_argument("--format", choices=("text", "json"), default="text",
                       help="diagnostic format (default: text)")
    path_option(check)
    const_options(check)
    _consistency_options(check)


def _consistency_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--consistency", action="store_true",
                        help="also check what the platform mappings' equations mean, with Z3 "
                        "(C1-C5: solutions exist and are unique, typed events have values, "
                        "predicates can hold and fail, no conflicting writers)")
    parser.add_argument("--z3-timeout", type=positive_int, metavar="MS",
                        help="time limit of each Z3 query in milliseconds (default 10000); "
                        "a query that runs out is reported as C-UNKNOWN")


def _list_rules() -> int:
    """Every condition ``cyphy check`` checks: the scope and typing conditions S1-S5, which
    name resolution and typing check as they go, then the registered rules."""
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.wellformed import RULES

    for code in (codes.S1, codes.S2, codes.S3, codes.S4, codes.S5):
        sys.stdout.write(f"{code.id:<7} {code.severity.value:<7} {code.summary}\n")
    for r in RULES.values():
        sys.stdout.write(f"{r.id:<7} {r.code.severity.value:<7} {r.summary}\n")
    return 0


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import CheckOptions, check

    if args.list_rules:
        return _list_rules()
    if not args.paths:
        sys.stderr.write("cyphy check: error: give at least one PATH\n")
        return 2
    if args.syntax_only and args.consistency:
        sys.stderr.write("cyphy check: error: --consistency needs names resolved: drop "
                         "--syntax-only\n")
        return 2

    result = check(args.paths, CheckOptions(args.syntax_only, tuple(args.path),
                                            consts=const_values(args),
                                            consistency=args.consistency,
                                            z3_timeout_ms=args.z3_timeout))
    diagnostics = result.report.diagnostics
    if args.format == "json":  # the document asked for: the command's output
        sys.stdout.write(render_json(diagnostics))
    else:  # diagnostics go to stderr, as every command's do
        sys.stderr.write(render_text(diagnostics, dict(result.sources)))
        errors = sum(1 for d in diagnostics if d.severity.value == "ERROR")
        warnings = len(diagnostics) - errors
        files = len(result.workspace.targets)
        if not args.quiet:
            sys.stderr.write(f"{files} file{'s' if files != 1 else ''} checked: "
                             f"{errors} error{'s' if errors != 1 else ''}, "
                             f"{warnings} warning{'s' if warnings != 1 else ''}\n")
    return result.report.exit_code
