"""The ``cyphy`` command line: arguments in, rendered diagnostics and an exit status out.

Each command is a module ``cyphy.cli.<command>`` with ``add_parser(subparsers)`` and
``run(args) -> int``, named once in :data:`COMMANDS`; the options several commands share are in
:mod:`cyphy.cli.options`, ``cyphy gen``'s targets in :mod:`cyphy.cli.gen`. Heavy libraries are
imported by the commands that need them, when they run, so ``cyphy --help`` and ``cyphy check``
start fast. Exit status: 0 no errors (warnings allowed), 1 errors, 2 usage, 70 an internal error
(a bug), 130 interrupted. Diagnostics go to stderr.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from types import ModuleType
from typing import NoReturn, Sequence

import cyphy
from cyphy import collector, interrupts, progress
from cyphy.cli.options import common_options, joined_values
from cyphy.cli.targets import output_problem
from cyphy.deep import run_deep, where_too_deep
from cyphy.diagnostics import RENDERING

#: The commands, in the order ``--help`` lists them: each the module ``cyphy.cli.<name>``.
COMMANDS = ("check", "show", "solve", "simulate", "gen", "reach", "view", "lsp", "check_theory",
            "animate")


def _command_module(name: str) -> ModuleType:
    return importlib.import_module(f"cyphy.cli.{name.replace('-', '_')}")  # check-theory


#: The options of ``cyphy`` itself that may come before the command and take no value.
_LEADING_FLAGS = frozenset({"-q", "--quiet", "--warnings-as-errors"})


def _chosen(argv: Sequence[str]) -> str | None:
    """The command ``argv`` names, when nothing but :data:`_LEADING_FLAGS` comes before it;
    None for anything else (``--help``, ``--version``, an unknown or misspelt command), which
    the whole parser then answers."""
    for arg in argv:
        if arg not in _LEADING_FLAGS:
            return next((name for name in COMMANDS if name.replace("_", "-") == arg), None)
    return None


def _parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The command line's parser; given the arguments, with only the subparser of the command
    they name (building every command's options and importing its module cost a tenth of
    ``cyphy check``'s start-up): that command's help, errors and values are the same."""
    parser = argparse.ArgumentParser(
        prog="cyphy",
        description="Read RoboSim models (.pm, .rst, .rsm) and check or translate them.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    chosen = None if argv is None else _chosen(argv)
    for name in COMMANDS if chosen is None else (chosen,):
        _command_module(name).add_parser(sub)
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="print cyphy's version and exit")
    common_options(parser, False)
    for command in sub.choices.values():  # also after the command: `cyphy check -q …`
        common_options(command, argparse.SUPPRESS)
    return parser


class _Version(argparse.Action):
    """``--version``, reading the package metadata only when asked (it costs a start)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: object, option_string: str | None = None) -> None:
        sys.stdout.write(f"cyphy {cyphy.__version__}\n")
        parser.exit()


def run() -> NoReturn:
    """The ``cyphy`` command: :func:`main`, then the exit without the interpreter's teardown.
    Freeing a large model object by object, and the final collection before it, take seconds
    on a 10,000-link model; everything has been written and closed by then, and the standard
    streams are flushed here (mypy ends the same way).

    NumPy's OpenBLAS starts a thread per core at import, and they spin: 0.1 s of processor
    time on every command that imports NumPy, for matrices of 3x3 to a few hundred rows, which
    one thread multiplies faster than several can share. A user's own setting wins."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    collector.keep_frozen()  # the command's results live until os._exit: never collected
    try:
        interrupts.raise_on_sigterm()
        progress.start()
        try:  # deeply nested models need a deep stack (cyphy/deep.py)
            code = run_deep(main, progress.tick)
        finally:
            progress.finish()
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:  # `cyphy show … | head`: the reader has gone
        pass
    except KeyboardInterrupt as err:  # Ctrl-C or SIGTERM while waiting, or while flushing
        code = interrupts.exit_status(err)
    os._exit(code)


def main(argv: Sequence[str] | None = None) -> int:
    given = joined_values(sys.argv[1:] if argv is None else argv)
    args = _parser(given).parse_args(given)
    if getattr(args, "max_copies", None):
        os.environ["CYPHY_MAX_COPIES"] = str(args.max_copies)  # read by cyphy.limits
    RENDERING.quiet, RENDERING.warnings_seen, RENDERING.usage_errors = args.quiet, 0, 0
    if (problem := output_problem(args)) is not None:  # before any long work
        sys.stderr.write(f"cyphy {args.command}: error: {problem}\n")
        return 2
    code = _command(args)
    if code == 1 and RENDERING.usage_errors:  # a value given on the command line is wrong
        return 2
    if code == 0 and args.warnings_as_errors and RENDERING.warnings_seen:
        sys.stderr.write(f"cyphy: error: {RENDERING.warnings_seen} warning"
                         f"{'s' if RENDERING.warnings_seen != 1 else ''} "
                         "(--warnings-as-errors)\n")
        return 1
    return code


def _command(args: argparse.Namespace) -> int:
    """The chosen command's exit status; what it raises becomes a status too."""
    try:
        code: int = _command_module(args.command).run(args)
        return code
    except KeyboardInterrupt:
        return 130
    except RecursionError as err:
        sys.stderr.write(TOO_DEEP.replace("error: ", "error: " + where_too_deep(err), 1))
        return 1
    except Exception as err:  # a bug of ours: say so plainly, without a traceback
        sys.stderr.write(f"cyphy: internal error ({type(err).__name__}: {err}); please report "
                         "it with the model that caused it (set CYPHY_TRACEBACK=1 for "
                         "details)\n")
        if os.environ.get("CYPHY_TRACEBACK"):
            raise
        return 70


TOO_DEEP = ("cyphy: error: the model nests too deeply (expressions, blocks or parts nested "
            "thousands of levels deep)\n")


if __name__ == "__main__":
    sys.exit(main())
