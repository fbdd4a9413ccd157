"""``cyphy check-theory SESSION_DIR``: the static check of an Isabelle session (not Isabelle)."""

from __future__ import annotations

import argparse
import sys

DESCRIPTION = (
    "A static check of an Isabelle session folder (ROOT and its theories), NOT Isabelle: it "
    "proves nothing and cannot say whether a proof succeeds. It reports, with file:line, what "
    "Isabelle2020 with utp-main c9122f14 is known to reject: plain HOL merged into a UTP "
    "theory without recall_syntax and the terms that then parse two ways; names declared "
    "twice or used before their declaration; terms that do not type-check against a "
    "signature table read from the library sources (both cyphy dialects); reserved words "
    "bound as names; proofs citing facts nothing defines, and closure lemmas not citing "
    "their definition. Exit 0: nothing found; 1: findings (or unreadable theories); 2: no "
    "session to read.")


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "check-theory", help="statically check an Isabelle session (not Isabelle)",
        description=DESCRIPTION)
    parser.add_argument("folder", metavar="SESSION_DIR",
                        help="the session folder (with ROOT), e.g. what gen --isabelle wrote")
    return parser


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from cyphy.verify.theory.check import check_session
    from cyphy.verify.theory.session import SessionError

    folder = Path(args.folder)
    try:
        result = check_session(folder)
    except SessionError as err:
        sys.stderr.write(f"cyphy check-theory: error: {err}\n")
        return 2
    for finding in result.findings:
        sys.stdout.write(finding.render() + "\n")
    noun = "theory" if result.theories == 1 else "theories"
    if result.findings:
        sys.stdout.write(f"{folder}: {len(result.findings)} problem"
                         f"{'s' if len(result.findings) != 1 else ''} in {result.theories} "
                         f"{noun} (static check, not Isabelle)\n")
        return 1
    sys.stdout.write(f"{folder}: session {result.session.name if result.session else '?'}, "
                     f"{result.theories} {noun}: no problem found (static check, not "
                     "Isabelle)\n")
    return 0
