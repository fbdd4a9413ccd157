"""``cyphy lsp``: the language server for editors, over stdin and stdout (:mod:`cyphy.lsp`)."""

from __future__ import annotations

import argparse
import sys

from cyphy.cli.options import path_option


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    lsp = sub.add_parser(
        "lsp",
        help="run the language server (for editors) over stdin and stdout",
        description="Serve the Language Server Protocol over stdin and stdout: diagnostics "
        "as 'cyphy check' gives them, go to definition, references, hover, completion and "
        "the outline of RoboSim files. Editors start it; see docs/editors.md.",
    )
    path_option(lsp)


def run(args: argparse.Namespace) -> int:
    try:  # lazy: pygls is an optional extra, and --help must not import it
        from cyphy.lsp.server import serve
    except ImportError as err:
        sys.stderr.write(f"cyphy lsp: error: the language server needs pygls and lsprotocol "
                         f"({err}); install them with: pip install 'cyphy[lsp]'\n")
        return 1
    serve(tuple(args.path))
    return 0
