"""``cyphy gen --flowstar``: a Flow* hybrid automaton of the model under a scenario."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from cyphy.cli.options import (GEN_INERTIAL, const_values, default_inertial_option,
                               gen_scenario_option)
from cyphy.cli.target import Target

if TYPE_CHECKING:
    from cyphy.api import Generated


def _flowstar_gen(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model
    from cyphy.verify.flowstar.commands import generate

    return generate(args.paths, args.scenario, args.model, tuple(args.path), const_values(args),
                    args.machine, args.default_inertial)[0]


def _scenario_option(parser: argparse.ArgumentParser) -> None:
    gen_scenario_option(parser)
    if not any("--machine" in a.option_strings for a in parser._actions):
        parser.add_argument("--machine", metavar="NAME",
                            help="the d-model's state machine: the process D of the "
                            "semantics (--cyphycircus, --latex, --isabelle) is written from it, "
                            "and (--flowstar) it is the controller when the scenario has no "
                            "[controller]")
    default_inertial_option(parser, GEN_INERTIAL)


TARGETS = {"flowstar": Target(_flowstar_gen, "a Flow* 2.1.0 hybrid automaton of the model "
                                "under a controller scenario (needs --scenario)",
                                _scenario_option)}
