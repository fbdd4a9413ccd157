"""``cyphy gen --isabelle``, ``--cyphycircus``, ``--latex``: the CyPhyCircus semantics of a
platform mapping, as an Isabelle/UTP session, text or LaTeX."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from typing import TYPE_CHECKING

from cyphy.cli.options import (GEN_INERTIAL, const_values, default_inertial_option,
                               gen_scenario_option, positive_float)
from cyphy.cli.target import Target

if TYPE_CHECKING:
    from cyphy.api import Generated, SemanticsGenOptions


def _semantics_options(parser: argparse.ArgumentParser) -> None:
    """Options of the CyPhyCircus semantics that every semantic generator shares (added
    once, whichever generator asks first)."""
    if not any("--machine" in a.option_strings for a in parser._actions):  # shared: Flow*'s
        parser.add_argument("--machine", metavar="NAME",
                            help="the d-model's state machine: the process D of the semantics "
                            "(--cyphycircus, --latex, --isabelle) is written from it, and "
                            "(--flowstar) it is the controller when the scenario has no "
                            "[controller]")
    gen_scenario_option(parser)
    if "--tscale" in parser._option_string_actions:
        return
    parser.add_argument("--tscale", type=positive_float, metavar="X",
                        help="fix tscale, the length of a d-model time unit in seconds "
                        "(finite and positive)")
    parser.add_argument("--name", type=_system_name, metavar="N",
                        help="the name of the whole system (default: the mapping's); an "
                        "identifier: a letter, then letters, digits and single underscores")
    default_inertial_option(parser, GEN_INERTIAL)


def _system_name(text: str) -> str:
    """``--name``: an identifier, since it is printed into theories, comments and Z names
    (``*)`` in it would end an Isabelle comment)."""
    # lazy: --help imports every command module; these pull in the model
    from cyphy.backends.isabelle.names import is_identifier

    if not is_identifier(text):
        raise argparse.ArgumentTypeError(
            f"'{text}' is not an identifier (a letter, then letters, digits and single "
            "underscores, not ending in one)")
    return text


def _isabelle_options(parser: argparse.ArgumentParser) -> None:
    _semantics_options(parser)
    parser.add_argument("--isabelle-dialect", choices=("utp", "axiomatic"), default="utp",
                        help="utp: utp-main's 2020 Circus with closure lemmas (default); "
                        "axiomatic: Ax_CyPhyCircus, Evolve as explicit ODEs (SymPy), into "
                        "isabelle-ax-gen/")
    parser.add_argument("--isabelle-element", action="append", default=[],
                        metavar="QUALIFIED",
                        help="with --isabelle-dialect axiomatic: reduce only the equations "
                        "of this element and what it contains (repeatable), as `cyphy solve "
                        "--element`")


def _isabelle(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import generate_isabelle

    if args.isabelle_element and args.isabelle_dialect != "axiomatic":
        sys.stderr.write("cyphy gen: error: --isabelle-element needs --isabelle-dialect "
                         "axiomatic (the utp dialect keeps every equation)\n")
        raise SystemExit(2)
    options = _semantics_gen_options(args)
    if args.isabelle_dialect == "axiomatic":
        args.default_folder = "isabelle-axiomatic"  # beside isabelle-gen/, never mixed in
        options = replace(options, dialect="axiomatic",
                          elements=tuple(args.isabelle_element))
    return generate_isabelle(args.paths, options)


def _semantics_gen_options(args: argparse.Namespace) -> "SemanticsGenOptions":
    """The options of every generator built on the semantics, from the parsed arguments
    (``--pdf`` is added by its own target)."""
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import SemanticsGenOptions

    return SemanticsGenOptions(args.model, args.name, args.tscale, const_values(args),
                               tuple(args.path), pdf=getattr(args, "pdf", False),
                               default_inertial=args.default_inertial,
                               machine=getattr(args, "machine", None),
                               scenario=getattr(args, "scenario", None))


def _latex_options(parser: argparse.ArgumentParser) -> None:
    _semantics_options(parser)
    parser.add_argument("--pdf", action="store_true",
                        help="with --latex, also typeset the document with pdflatex")


def _gen_semantics(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import generate_cyphycircus

    return generate_cyphycircus(args.paths, "text" if args.target == "cyphycircus"
                                else "latex", _semantics_gen_options(args))


TARGETS = {
    "isabelle": Target(_isabelle, "an Isabelle/UTP session of the CyPhyCircus semantics of a "
                       "platform mapping (isabelle-gen/)", _isabelle_options),
    "cyphycircus": Target(_gen_semantics, "the CyPhyCircus semantics of a platform mapping, "
                          "as text", _semantics_options),
    "latex": Target(_gen_semantics, "the CyPhyCircus semantics as LaTeX for the CZT tools",
                    _latex_options),
}
