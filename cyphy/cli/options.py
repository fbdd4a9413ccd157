"""The options several commands share (model paths, constants, gravity, inertia defaults)
and the values they parse to: one definition each, so every command spells them alike."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Sequence


def common_options(parser: argparse.ArgumentParser, default: object) -> None:
    """Options of every command, accepted before and after its name (a subcommand's copy
    does not override what was given before it)."""
    parser.add_argument("-q", "--quiet", action="store_true", default=default,
                        help="print errors only: no warnings, progress or summary lines")
    parser.add_argument("--warnings-as-errors", action="store_true", default=default,
                        help="exit with status 1 when there are warnings (gen writes nothing)")


def path_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--path", action="append", default=[], metavar="DIR",
                        help="another folder of model files to resolve names against")
    # Every command that reads models takes --path, and so the limit on copies.
    parser.add_argument("--max-copies", type=positive_int, metavar="N",
                        help="most copies that index ranges may make in one model (default "
                        "100000, or $CYPHY_MAX_COPIES)")


def const_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--const", action="append", default=[], metavar="NAME=VALUE",
                        help="value of a constant, which wins over the model's own (NAME may be "
                        "qualified: Treel::HEIGHT; one the model lacks is an error); "
                        "repeatable")
    parser.add_argument("--consts", metavar="FILE",
                        help="constant values from a TOML or JSON file (NAME = VALUE)")


def const_values(args: argparse.Namespace) -> dict[str, object]:
    if not args.const and not args.consts:
        return {}
    # lazy: --help imports every command module; these pull in the model (Lark, NumPy)
    from cyphy.model.constants import ConstantsError, parse_const_options

    try:
        return parse_const_options(args.const, args.consts)
    except ConstantsError as err:
        sys.stderr.write(f"cyphy: error: {err}\n")
        raise SystemExit(2) from None


def finite_float(text: str) -> float:
    """A number option: ``nan`` and ``inf`` are refused here rather than reaching the
    integrator, Flow*'s timeout or the camera."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{text}'") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: '{text}'")
    return value


def positive_float(text: str) -> float:
    """A finite positive number (``--tscale``, ``--timeout``): zero, a negative value or a NaN
    would become an inconsistent axiom beside ``tscale > 0``, or a run that never ends."""
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be finite and positive, not {text}")
    return value


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: '{text}'") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {value}")
    return value


def _gravity(text: str) -> tuple[float, float, float]:
    """``--gravity 0,0,-1.62`` as three floats (argparse reports a bad value, exit 2)."""
    parts = text.split(",")
    try:
        x, y, z = (float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not three numbers x,y,z") from None
    if not all(math.isfinite(v) for v in (x, y, z)):
        raise argparse.ArgumentTypeError(f"'{text}' is not three finite numbers x,y,z")
    return (x, y, z)


def gravity_option(parser: argparse.ArgumentParser) -> None:
    """``--gravity`` and ``--floating-base``: how the kinematic tree meets the world."""
    parser.add_argument("--gravity", type=_gravity, metavar="X,Y,Z",
                        help="gravity in m/s² in the model frame (default 0,0,-9.81)")
    parser.add_argument("--floating-base", action="store_true",
                        help="free the root link (six coordinates <Root>_x, _y, _z, _yaw, "
                        "_pitch, _roll, no contact) instead of fixing it to the world")


def gen_scenario_option(parser: argparse.ArgumentParser) -> None:
    """``gen --scenario``, shared by Flow* and the semantic generators (added once)."""
    if any("--scenario" in a.option_strings for a in parser._actions):
        return
    parser.add_argument("--scenario", metavar="FILE",
                        help="a scenario, the TOML file simulate and reach read: "
                        "(--flowstar) the controller scenario; (--cyphycircus, --latex, "
                        "--isabelle) Init starts the state at its [init] values, and its "
                        "[consts], tscale, machine and model apply unless given as options")


GEN_INERTIAL = "(--flowstar, --cyphycircus, --latex, --isabelle: Evolve's equations of motion) "


def default_inertial_option(parser: argparse.ArgumentParser, note: str = "") -> None:
    if any("--default-inertial" in a.option_strings for a in parser._actions):
        return
    parser.add_argument("--default-inertial", choices=("sdf",), metavar="sdf",
                        help=f"{note}give links without inertial information SDFormat's "
                        "defaults (1 kg, identity inertia), as Gazebo does, with a warning "
                        "each (default: they stay without mass, an E-DYNAMICS error when a "
                        "joint moves them)")


def joined_values(argv: Sequence[str]) -> list[str]:
    """``--pose -1,0,0,0,0,0`` as ``--pose=-1,…``: argparse takes a value that starts with
    ``-`` and is not a plain number for an option, and would refuse the pose."""
    out: list[str] = []
    for i, arg in enumerate(argv):
        if i > 0 and argv[i - 1] == "--pose" and arg.startswith("-") and "," in arg:
            out[-1] = f"--pose={arg}"
        else:
            out.append(arg)
    return out
