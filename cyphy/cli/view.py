"""``cyphy view``: one p-model drawn headless as a PNG."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from cyphy.cli.options import const_options, const_values, finite_float, path_option
from cyphy.diagnostics import render_text
from cyphy.outputs import OutputError, write_file

#: The largest joint position ``view --set`` takes: beyond it a pose's coordinates lose
#: every digit that a picture shows (1e300 overflowed the projection).
MAX_POSITION = 1e6


def add_parser(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    view = sub.add_parser(
        "view",
        help="draw the robot in 3D (PNG)",
        description="Draw one p-model headless: every body at its pose, link frames (x red, "
        "y green, z blue), joint axes (dashed magenta); links and bodies at the same place "
        "with the same shape (V5) in red. A model with errors draws nothing.",
    )
    view.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    view.add_argument("--model", metavar="NAME", help="the p-model to draw")
    view.add_argument("-o", "--output", metavar="FILE.png",
                      help="the picture (default: <Model>.png in the current folder)")
    view.add_argument("--set", action="append", default=[], metavar="JOINT=VALUE",
                      dest="positions", help="a joint's position (radians or metres; the "
                      "joint's qualified, simple or exported name); repeatable")
    view.add_argument("--view", choices=("iso", "front", "side", "top"), default="iso",
                      help="the camera: iso (default), front (along +y), side (along -x), "
                      "top (down)")
    view.add_argument("--elevation", type=finite_float, metavar="DEG",
                      help="the camera's elevation, overriding --view's")
    view.add_argument("--azimuth", type=finite_float, metavar="DEG",
                      help="the camera's azimuth, overriding --view's")
    const_options(view)
    path_option(view)


def run(args: argparse.Namespace) -> int:
    # lazy: --help imports every command module; these pull in the model (NumPy)
    from cyphy.api import ViewRequest, view

    positions: dict[str, float] = {}
    for text in args.positions:
        name, _, value = text.partition("=")
        try:
            positions[name.strip()] = float(value)
        except ValueError:
            sys.stderr.write(f"cyphy view: error: --set {text}: expected JOINT=NUMBER\n")
            return 2
        if not math.isfinite(positions[name.strip()]) or \
                abs(positions[name.strip()]) > MAX_POSITION:
            sys.stderr.write(f"cyphy view: error: --set {text}: a joint position is a finite "
                             f"number of radians or metres, at most {MAX_POSITION:g} in size "
                             "(further cannot be drawn)\n")
            return 2
    if args.output is not None and not args.output.endswith(".png"):
        sys.stderr.write("cyphy view: error: -o names a .png file\n")
        return 2
    generated, _ = view(args.paths, ViewRequest(args.model, const_values(args), tuple(args.path),
                                                positions, args.view, args.elevation,
                                                args.azimuth))
    if generated.report.diagnostics:
        sys.stderr.write(render_text(generated.report.diagnostics, dict(generated.sources)))
    if generated.report.has_errors or not generated.files:
        sys.stderr.write("cyphy view: nothing drawn: the model has errors\n")
        return 1
    ((name, png),) = generated.files.items()
    target = Path(args.output) if args.output else Path(name)
    try:
        written = write_file(target, png)
    except OutputError as err:
        sys.stderr.write(f"cyphy view: error: {err}\n")
        return 1
    sys.stdout.write(f"wrote {written}\n")
    return generated.report.exit_code
