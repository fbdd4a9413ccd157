"""``cyphy gen --urdf`` and ``--mjcf``: the model as trees of links."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from cyphy.cli.options import const_values
from cyphy.cli.target import Target
from cyphy.outputs import default_output_dir

if TYPE_CHECKING:
    from cyphy.api import Generated, TreeGenOptions


def _tree_options(args: argparse.Namespace) -> "TreeGenOptions":
    """The options of ``--urdf`` and ``--mjcf``: mesh paths are written relative to the
    output folder, so it is fixed here as ``_gen`` will choose it."""
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import TreeGenOptions

    output = args.output or str(default_output_dir(args.paths, args.target))
    return TreeGenOptions(args.model, const_values(args), tuple(args.path), output,
                          getattr(args, "urdf_package", None),
                          getattr(args, "mjcf_free_base", False))


def _urdf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--urdf options")
    group.add_argument("--urdf-package", metavar="NAME",
                       help="mesh paths as package://NAME/<path in the model folder> (ROS), "
                       "instead of relative to the output folder")


def _urdf_run(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import generate_urdf

    return generate_urdf(args.paths, _tree_options(args))


def _mjcf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--mjcf options")
    group.add_argument("--mjcf-free-base", action="store_true",
                       help="give each tree's root a free joint (a mobile robot) instead of "
                       "fixing it to the world")


def _mjcf_run(args: argparse.Namespace) -> "Generated":
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import generate_mjcf

    return generate_mjcf(args.paths, _tree_options(args))


TARGETS = {
    "urdf": Target(_urdf_run, "URDF 1.0 for ROS, PyBullet and Pinocchio: one file per "
                   "tree of links, loops cut", _urdf_options),
    "mjcf": Target(_mjcf_run, "MuJoCo MJCF: the trees of links as bodies, a motor per "
                   "driven joint, loops closed by equality constraints", _mjcf_options),
}
