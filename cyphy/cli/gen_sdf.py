"""``cyphy gen --sdf``: SDF 1.6 for Gazebo and other simulators."""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING

from cyphy.cli.options import const_values
from cyphy.cli.target import Target

if TYPE_CHECKING:
    from cyphy.api import Generated


def _sdf_pose(text: str) -> tuple[float, float, float, float, float, float]:
    parts = text.split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 6 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected six finite numbers x,y,z,roll,pitch,yaw, "
                                         f"not {text!r}")
    return values  # type: ignore[return-value]


def _sdf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--sdf options")
    group.add_argument("--pose", type=_sdf_pose, default=(0.0,) * 6,
                       metavar="x,y,z,roll,pitch,yaw",
                       help="pose of the model in the world (metres, radians; default zeros)")
    group.add_argument("--short-names", action="store_true",
                       help="RoboTool's coded names (1-Wheel, 1--wheel) instead of readable ones")
    group.add_argument("--target", dest="sdf_target",
                       choices=("gazebo", "coppeliasim", "pybullet", "drake"), default="gazebo",
                       help="coppeliasim: RoboTool's CoppeliaSim conventions (coded names, "
                       "sensor poses turned by Ry(pi/2)); pybullet: trees only (split "
                       "trees, joints that close loops left out, gearboxes as revolute "
                       "joints, each reported); drake: what Drake's parser loads (no "
                       "<axis><initial_position>, a warning when it was not 0)")
    group.add_argument("--gazebo-model", metavar="DIR",
                       help="write a Gazebo model folder DIR (model.config, model.sdf)")
    group.add_argument("--split-trees", action="store_true",
                       help="links that form several trees: a <world> with one <model> per "
                       "tree, which PyBullet loads (it refuses a model with several roots)")


def _sdf_run(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import SdfGenOptions, generate_sdf

    if args.gazebo_model is not None:
        if args.output is not None:
            sys.stderr.write("cyphy gen: error: give either -o or --gazebo-model\n")
            raise SystemExit(2)
        if args.split_trees or args.sdf_target == "pybullet":
            sys.stderr.write("cyphy gen: error: a Gazebo model folder holds one model: "
                             "--split-trees and --target pybullet write a world\n")
            raise SystemExit(2)
        args.output = args.gazebo_model
    options = SdfGenOptions(args.model, const_values(args), tuple(args.path), tuple(args.pose),
                            args.short_names, args.sdf_target, args.gazebo_model is not None,
                            args.split_trees)
    return generate_sdf(args.paths, options)


TARGETS = {"sdf": Target(_sdf_run, "SDF 1.6 for Gazebo and other simulators (the paper's "
                            "section 5)", _sdf_options)}
