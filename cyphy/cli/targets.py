"""The output paths of a command line, checked before the command does any work: a long
simulation or Flow* run must not end in an output that cannot be written."""

from __future__ import annotations

import argparse
from pathlib import Path

from cyphy.outputs import OutputError, check_target, default_output_dir

#: Each command's output options: argparse destination, option as shown, and whether it
#: names a folder (else a file).
OUTPUTS: dict[str, tuple[tuple[str, str, bool], ...]] = {
    "simulate": (("output", "-o", False), ("plot", "--plot", False)),
    "animate": (("output", "-o", False), ("plot", "--plot", False)),
    "view": (("output", "-o", False),),
    "gen": (("output", "-o", True), ("gazebo_model", "--gazebo-model", True)),
    "reach": (("output", "-o", True),),
}


def output_problem(args: argparse.Namespace) -> str | None:
    """Why one of the command's output paths cannot be written, or None. ``gen`` without
    ``-o`` writes beside the first model: that folder is checked too."""
    chosen = [(option, Path(getattr(args, dest)), folder)
              for dest, option, folder in OUTPUTS.get(args.command, ())
              if getattr(args, dest, None)]
    if args.command == "gen" and not chosen and args.paths and Path(args.paths[0]).exists():
        chosen.append(("the default output folder",
                       default_output_dir(args.paths, args.target), True))
    for option, path, folder in chosen:
        try:
            check_target(path, folder)
        except OutputError as err:
            return f"{option} {path}: {err}"
    return None
