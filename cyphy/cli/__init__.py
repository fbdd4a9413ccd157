"""The ``cyphy`` command line: arguments in, rendered diagnostics and an exit status out.

Heavy libraries are imported by the subcommands that need them, so ``cyphy --help`` and
``cyphy check`` start fast. Exit status: 0 no errors (warnings allowed), 1 errors, 2 usage,
70 an internal error (a bug), 130 interrupted. Diagnostics go to stderr.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Callable, NoReturn, Sequence

if TYPE_CHECKING:
    from cyphy.api import Generated, SemanticsGenOptions, TreeGenOptions


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="cyphy",
        description="Read RoboSim models (.pm, .rst, .rsm) and check or translate them.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    check = sub.add_parser(
        "check",
        help="parse, resolve and check model files",
        description="Parse the model files (a folder means every model file in it), resolve "
        "names across them and the built-in physmod library, and report every problem.",
    )
    check.add_argument("paths", nargs="*", metavar="PATH", help="model file or folder")
    check.add_argument("--list-rules", action="store_true",
                       help="list the well-formedness conditions checked, and exit")
    check.add_argument("--syntax-only", action="store_true", help="stop after parsing")
    check.add_argument("--format", choices=("text", "json"), default="text",
                       help="diagnostic format (default: text)")
    _path_option(check)
    _const_options(check)
    _consistency_options(check)
    show = sub.add_parser(
        "show",
        help="print the elaborated model",
        description="Elaborate one p-model (parts instantiated, indexed blocks replicated, "
        "constants evaluated, poses composed) and print it as a tree or as JSON.",
    )
    show.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    show.add_argument("--model", metavar="NAME", help="the p-model to show")
    show.add_argument("--dmodel", action="store_true",
                      help="show the d-model instead: modules, controllers and state machines")
    _const_options(show)
    show.add_argument("--format", choices=("text", "json", "dot", "svg"), default="text",
                      help="text (default), json, or the kinematic graph: dot (Graphviz's "
                      "language) or svg (drawn by Graphviz's dot)")
    _path_option(show)
    solve = sub.add_parser(
        "solve",
        help="reduce the model's equations to explicit ODEs (SymPy)",
        description="Assemble the equations of a p-model (optionally with the effect of one "
        "mapping operation), reduce them to explicit first-order ODEs x' = f(x, u, p) and, "
        "for linear systems with constant inputs and known constants, give the closed form.",
    )
    solve.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    solve.add_argument("--model", metavar="NAME", help="the p-model to solve")
    solve.add_argument("--element", action="append", default=[], metavar="QUALIFIED",
                       help="only this element and what it contains (repeatable), e.g. "
                       "marXbotBase::Core::LHinge::LMotor")
    solve.add_argument("--mapping-call", metavar="CALL",
                       help="add the effect of a mapping operation, e.g. 'move(0.1, 0)'")
    _gravity_option(solve)
    _default_inertial_option(solve)
    _const_options(solve)
    solve.add_argument("--format", choices=("text", "latex", "json"), default="text")
    _path_option(solve)
    simulate = sub.add_parser(
        "simulate",
        help="integrate the model's equations of motion and devices (SciPy)",
        description="Integrate the explicit ODEs that `cyphy solve` derives (the kinematic "
        "tree's equations of motion included) with SciPy's solve_ivp, and write the "
        "trajectories: t, then one column per state and output. With --numeric the "
        "kinematic tree is integrated alone, with the numeric articulated-body algorithm; "
        "its inputs are then the joint efforts <Joint>_tau.",
    )
    simulate.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    simulate.add_argument("--model", metavar="NAME", help="the p-model to simulate")
    simulate.add_argument("--scenario", metavar="FILE",
                          help="a Flow* scenario (TOML, as for gen --flowstar): its "
                          "[controller] runs at the d-model cycle, its [environment] drives "
                          "the sensor inputs, its [init] intervals start at their midpoints; "
                          "without [controller] the d-model's state machine runs")
    simulate.add_argument("--machine", metavar="NAME",
                          help="the d-model's state machine that is the controller when the "
                          "scenario has no [controller]")
    simulate.add_argument("--t-end", type=_finite_float, metavar="T",
                          help="simulated time in seconds (default 1, or the scenario's "
                          "horizon)")
    simulate.add_argument("--init", action="append", default=[], metavar="NAME=VALUE",
                          help="initial value of a state (default 0); repeatable")
    simulate.add_argument("--input", action="append", default=[], metavar="NAME=EXPR",
                          help="an input as an expression of t, e.g. 'Motor_das=10*sin(t)' "
                          "(default 0); repeatable")
    simulate.add_argument("--method", default="LSODA",
                          choices=("LSODA", "BDF", "Radau", "RK45", "DOP853"),
                          help="solve_ivp's method (default LSODA, stiff-capable)")
    simulate.add_argument("--rtol", type=_finite_float, default=1e-6, help="relative tolerance")
    simulate.add_argument("--atol", type=_finite_float, default=1e-9, help="absolute tolerance")
    simulate.add_argument("--samples", type=int, default=201,
                          help="output instants over [0, T] (default 201)")
    simulate.add_argument("--numeric", action="store_true",
                          help="the kinematic tree alone, with the articulated-body algorithm")
    simulate.add_argument("--format", choices=("csv", "json"), default="csv")
    simulate.add_argument("-o", "--output", metavar="FILE", help="write here, not to stdout")
    simulate.add_argument("--plot", metavar="FILE.png", help="also plot to this PNG")
    simulate.add_argument("--plot-var", action="append", default=[], metavar="NAME",
                          help="a column to plot (repeatable; default the first 8)")
    _gravity_option(simulate)
    _default_inertial_option(simulate)
    _const_options(simulate)
    _path_option(simulate)
    gen = sub.add_parser(
        "gen",
        help="generate files for simulators and provers",
        description="Check the model and, when it has no errors, generate the chosen artefact. "
        "Without -o the files go beside the model, in RoboTool's folder names (sdf-gen/, "
        "cpc-gen/, isabelle-gen/, flowstar-gen/; ours urdf-gen/, mjcf-gen/). A model with errors "
        "writes nothing.",
    )
    gen.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    targets = gen.add_mutually_exclusive_group(required=True)
    for target, (_, flag_help, _) in GENERATORS.items():
        targets.add_argument(f"--{target}", dest="target", action="store_const", const=target,
                             help=flag_help)
    gen.add_argument("-o", "--output", metavar="DIR", help="output folder")
    gen.add_argument("--model", metavar="NAME", help="the p-model (or mapping) to generate for")
    gen.add_argument("--format", choices=("text", "json"), default="text",
                     help="json: print one JSON document (files written, diagnostics) on "
                     "stdout instead of text")
    _const_options(gen)
    _path_option(gen)
    for _, _, add_options in GENERATORS.values():
        add_options(gen)
    _add_reach(sub)
    _add_view(sub)
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="print cyphy's version and exit")
    _common_options(parser, False)
    for command in sub.choices.values():  # also after the command: `cyphy check -q …`
        _common_options(command, argparse.SUPPRESS)
    return parser


def _add_view(sub: argparse._SubParsersAction) -> None:
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
    view.add_argument("--elevation", type=_finite_float, metavar="DEG",
                      help="the camera's elevation, overriding --view's")
    view.add_argument("--azimuth", type=_finite_float, metavar="DEG",
                      help="the camera's azimuth, overriding --view's")
    _const_options(view)
    _path_option(view)


def _view(args: argparse.Namespace) -> int:
    from pathlib import Path

    from cyphy.api import ViewRequest, view
    from cyphy.diagnostics import render_text
    from cyphy.outputs import OutputError, write_file

    import math

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
    generated, _ = view(args.paths, ViewRequest(args.model, _consts(args), tuple(args.path),
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


#: The largest joint position ``view --set`` takes: beyond it a pose's coordinates lose
#: every digit that a picture shows (1e300 overflowed the projection).
MAX_POSITION = 1e6


class _Version(argparse.Action):
    """``--version``, reading the package metadata only when asked (it costs a start)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: object, option_string: str | None = None) -> None:
        import cyphy

        sys.stdout.write(f"cyphy {cyphy.__version__}\n")
        parser.exit()


def _common_options(parser: argparse.ArgumentParser, default: object) -> None:
    """Options of every command, accepted before and after its name (a subcommand's copy
    does not override what was given before it)."""
    parser.add_argument("-q", "--quiet", action="store_true", default=default,
                        help="print errors only: no warnings, progress or summary lines")
    parser.add_argument("--warnings-as-errors", action="store_true", default=default,
                        help="exit with status 1 when there are warnings (gen writes nothing)")


def _gen(args: argparse.Namespace) -> int:
    from pathlib import Path

    from cyphy.diagnostics import render_text
    from cyphy.outputs import OutputError, default_output_dir, write_all

    stray = _options_of_other_targets(args)
    if stray:
        sys.stderr.write(f"cyphy gen: error: {stray}\n")
        return 2
    run, _, _ = GENERATORS[args.target]
    generated = run(args)
    diagnostics = generated.report.diagnostics
    as_json = getattr(args, "format", "text") == "json"
    if diagnostics and not as_json:
        sys.stderr.write(render_text(diagnostics, dict(generated.sources)))
    refused = args.warnings_as_errors and any(d.severity.value == "WARNING"
                                              for d in diagnostics)
    written: list[Path] = []
    problem = None
    if generated.report.has_errors or not generated.files or refused:
        problem = "nothing written: the model has " + ("warnings (--warnings-as-errors)"
                                                       if refused else "errors")
    else:
        folder = getattr(args, "default_folder", args.target)  # a generator may choose
        out_dir = Path(args.output) if args.output else default_output_dir(args.paths, folder)
        try:
            written = write_all(generated.files, out_dir)
        except OutputError as err:
            problem = f"error: {err}"
    if as_json:  # one document on stdout: what was written and every diagnostic
        import json

        from cyphy.diagnostics import diagnostics_json

        sys.stdout.write(json.dumps({"written": [str(p) for p in written], "error": problem,
                                     "diagnostics": diagnostics_json(diagnostics)},
                                    indent=2) + "\n")
    elif problem:
        sys.stderr.write(f"cyphy gen: {problem}\n")
    elif not args.quiet:
        for path in written:
            sys.stdout.write(f"wrote {path}\n")
    return 1 if problem else generated.report.exit_code


def _options_of_other_targets(args: argparse.Namespace) -> str | None:
    """Why the command line is wrong when it sets an option that only other targets take
    (``--split-trees`` with ``--cyphycircus``), which would otherwise be silently ignored.
    Each target's options are found by letting it add them to a scratch parser."""
    owners: dict[str, list[str]] = {}
    flags: dict[str, str] = {}
    defaults: dict[str, object] = {}
    for target, (_, _, add_options) in GENERATORS.items():
        scratch = argparse.ArgumentParser(add_help=False)
        add_options(scratch)
        for action in scratch._actions:
            owners.setdefault(action.dest, []).append(target)
            flags[action.dest] = action.option_strings[0]
            defaults[action.dest] = action.default
    for dest, targets in owners.items():
        if args.target not in targets and getattr(args, dest, None) != defaults[dest]:
            takes = ", ".join(f"--{t}" for t in targets)
            return f"{flags[dest]} is an option of {takes}, not of --{args.target}"
    return None


#: ``cyphy gen`` targets: flag → (generator, flag help, function adding the target's options).
#: A generator takes the parsed arguments and returns a :class:`cyphy.api.Generated`.
GENERATORS: dict[str, tuple[Callable[[argparse.Namespace], "Generated"], str,
                            Callable[[argparse.ArgumentParser], None]]] = {}


def _sdf_pose(text: str) -> tuple[float, float, float, float, float, float]:
    import math

    parts = text.split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 6 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected six finite numbers x,y,z,roll,pitch,yaw, "
                                         f"not {text!r}")
    return values  # type: ignore[return-value]


def _joined_values(argv: Sequence[str]) -> list[str]:
    """``--pose -1,0,0,0,0,0`` as ``--pose=-1,…``: argparse takes a value that starts with
    ``-`` and is not a plain number for an option, and would refuse the pose."""
    out: list[str] = []
    for i, arg in enumerate(argv):
        if i > 0 and argv[i - 1] == "--pose" and arg.startswith("-") and "," in arg:
            out[-1] = f"--pose={arg}"
        else:
            out.append(arg)
    return out


def _sdf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--sdf options")
    group.add_argument("--pose", type=_sdf_pose, default=(0.0,) * 6,
                       metavar="x,y,z,roll,pitch,yaw",
                       help="pose of the model in the world (metres, radians; default zeros)")
    group.add_argument("--short-names", action="store_true",
                       help="RoboTool's coded names (1-Wheel, 1--wheel) instead of readable ones")
    group.add_argument("--target", dest="sdf_target",
                       choices=("gazebo", "coppeliasim", "pybullet"), default="gazebo",
                       help="coppeliasim: RoboTool's CoppeliaSim conventions (coded names, "
                       "sensor poses turned by Ry(pi/2)); pybullet: trees only (split "
                       "trees, joints that close loops left out, gearboxes as revolute "
                       "joints, each reported)")
    group.add_argument("--gazebo-model", metavar="DIR",
                       help="write a Gazebo model folder DIR (model.config, model.sdf)")
    group.add_argument("--split-trees", action="store_true",
                       help="links that form several trees: a <world> with one <model> per "
                       "tree, which PyBullet loads (it refuses a model with several roots)")


def _sdf_run(args: argparse.Namespace) -> "Generated":
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
    options = SdfGenOptions(args.model, _consts(args), tuple(args.path), tuple(args.pose),
                            args.short_names, args.sdf_target, args.gazebo_model is not None,
                            args.split_trees)
    return generate_sdf(args.paths, options)


GENERATORS["sdf"] = (_sdf_run, "SDF 1.6 for Gazebo and other simulators (the paper's "
                     "section 5)", _sdf_options)
def _tree_options(args: argparse.Namespace) -> "TreeGenOptions":
    """The options of ``--urdf`` and ``--mjcf``: mesh paths are written relative to the
    output folder, so it is fixed here as ``_gen`` will choose it."""
    from cyphy.api import TreeGenOptions
    from cyphy.outputs import default_output_dir

    output = args.output or str(default_output_dir(args.paths, args.target))
    return TreeGenOptions(args.model, _consts(args), tuple(args.path), output,
                          getattr(args, "urdf_package", None),
                          getattr(args, "mjcf_free_base", False))


def _urdf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--urdf options")
    group.add_argument("--urdf-package", metavar="NAME",
                       help="mesh paths as package://NAME/<path in the model folder> (ROS), "
                       "instead of relative to the output folder")


def _urdf_run(args: argparse.Namespace) -> "Generated":
    from cyphy.api import generate_urdf

    return generate_urdf(args.paths, _tree_options(args))


GENERATORS["urdf"] = (_urdf_run, "URDF 1.0 for ROS, PyBullet and Pinocchio: one file per "
                      "tree of links, loops cut", _urdf_options)


def _mjcf_options(gen: argparse.ArgumentParser) -> None:
    group = gen.add_argument_group("--mjcf options")
    group.add_argument("--mjcf-free-base", action="store_true",
                       help="give each tree's root a free joint (a mobile robot) instead of "
                       "fixing it to the world")


def _mjcf_run(args: argparse.Namespace) -> "Generated":
    from cyphy.api import generate_mjcf

    return generate_mjcf(args.paths, _tree_options(args))


GENERATORS["mjcf"] = (_mjcf_run, "MuJoCo MJCF: the trees of links as bodies, a motor per "
                      "driven joint, loops closed by equality constraints", _mjcf_options)


def _flowstar_gen(args: argparse.Namespace) -> "Generated":
    from cyphy.verify.flowstar.commands import generate

    return generate(args.paths, args.scenario, args.model, tuple(args.path), _consts(args),
                    args.machine, args.default_inertial)[0]


def _scenario_option(parser: argparse.ArgumentParser) -> None:
    if not any("--scenario" in a.option_strings for a in parser._actions):
        parser.add_argument("--scenario", metavar="FILE",
                            help="(--flowstar) the controller scenario, a TOML file")
    if not any("--machine" in a.option_strings for a in parser._actions):
        parser.add_argument("--machine", metavar="NAME",
                            help="(--flowstar) the d-model's state machine that is the "
                            "controller when the scenario has no [controller]")
    _default_inertial_option(parser, _GEN_INERTIAL)


GENERATORS["flowstar"] = (_flowstar_gen, "a Flow* 2.1.0 hybrid automaton of the model under "
                          "a controller scenario (needs --scenario)", _scenario_option)


def _add_reach(sub: argparse._SubParsersAction) -> None:
    reach = sub.add_parser(
        "reach",
        help="check a scenario's unsafe set with Flow*: SAFE, UNSAFE or UNKNOWN",
        description="Export the model under the scenario as for `gen --flowstar`, run Flow* "
        "on it and print one line: SAFE, UNSAFE or UNKNOWN with the reason, Flow*'s time "
        "and the model's path. Exit status: 0 SAFE, 1 UNSAFE, 3 UNKNOWN, 2 errors.",
    )
    reach.add_argument("paths", nargs="+", metavar="PATH", help="model file or folder")
    reach.add_argument("--scenario", metavar="FILE", required=True,
                       help="the controller scenario (TOML)")
    reach.add_argument("--flowstar-bin", metavar="PATH",
                       help="the Flow* executable (default: $CYPHY_FLOWSTAR, the one .ci/install "
                       "built, or flowstar on PATH)")
    reach.add_argument("--timeout", type=_finite_float, metavar="SECONDS",
                       help="give up (UNKNOWN) when a Flow* run takes longer")
    reach.add_argument("--split", type=int, default=1, metavar="N",
                       help="split the initial set into N boxes along its widest state, one "
                       "Flow* run each (default 1; a run ending UNKNOWN is retried with "
                       "4 boxes unless --no-auto-split)")
    reach.add_argument("--no-auto-split", action="store_true",
                       help="do not retry an UNKNOWN run on smaller boxes")
    reach.add_argument("--jobs", type=int, metavar="N",
                       help="Flow* runs at a time (default: the number of cores)")
    reach.add_argument("-o", "--output", metavar="DIR",
                       help="keep the Flow* model in DIR (default: a temporary folder, "
                       "removed at the end)")
    reach.add_argument("--keep", action="store_true",
                       help="keep the temporary folder with the Flow* model, and print its "
                       "path")
    reach.add_argument("--model", metavar="NAME", help="the p-model")
    reach.add_argument("--machine", metavar="NAME",
                       help="the d-model's state machine that is the controller when the "
                       "scenario has no [controller]")
    _default_inertial_option(reach)
    _const_options(reach)
    _path_option(reach)


def _reach(args: argparse.Namespace) -> int:
    from pathlib import Path

    from cyphy.diagnostics import render_text
    from cyphy.verify.flowstar.commands import generate
    from cyphy.verify.flowstar.check import check
    from cyphy.verify.flowstar.locate import find_flowstar
    import shutil
    import tempfile

    from cyphy.verify.flowstar.verdict import FlowstarMissing
    from cyphy.outputs import OutputError, write_all

    try:
        binary = find_flowstar(args.flowstar_bin)
    except FlowstarMissing as err:
        sys.stderr.write(f"cyphy reach: error: {err}\n")
        return 2
    if args.split < 1 or (args.jobs is not None and args.jobs < 1):
        sys.stderr.write("cyphy reach: error: --split and --jobs take a positive number\n")
        return 2
    generated, problem = generate(args.paths, args.scenario, args.model, tuple(args.path),
                                  _consts(args), args.machine, args.default_inertial)
    if generated.report.diagnostics:
        sys.stderr.write(render_text(generated.report.diagnostics, dict(generated.sources)))
    if generated.report.has_errors or not generated.files or problem is None:
        sys.stderr.write("cyphy reach: nothing checked: the model or scenario has errors\n")
        return 2
    # Never beside the inputs, which may be read-only (the corpus): -o, else a scratch folder
    out_dir = Path(args.output) if args.output else Path(tempfile.mkdtemp(prefix="cyphy-reach-"))
    kept = args.output is not None or args.keep
    try:
        model = write_all(generated.files, out_dir)[0]
        result = check(problem, model.stem, binary, args.timeout, args.split,
                       not args.no_auto_split, args.jobs)
    except (OutputError, FlowstarMissing) as err:
        sys.stderr.write(f"cyphy reach: error: {err}\n")
        return 2
    finally:
        if not kept:
            shutil.rmtree(out_dir, ignore_errors=True)
    where = f"; model {model}" if kept else ""
    line = f"{result.verdict}: {result.reason} (Flow* runs {result.seconds:.1f} s{where})\n"
    stream = sys.stderr if result.verdict == "ERROR" else sys.stdout
    stream.write(line)
    if result.witness is not None:
        stream.write("the trajectory (time, event, controller state, state):\n")
        stream.write("\n".join(result.witness.lines(result.names)) + "\n")
    if len(result.details) > 1 or result.verdict != "SAFE":
        stream.write("Flow* runs:\n" + "\n".join(result.details) + "\n")
    return result.exit_code

def _semantics_options(parser: argparse.ArgumentParser) -> None:
    """Options of the CyPhyCircus semantics that every semantic generator shares (added
    once, whichever generator asks first)."""
    if "--tscale" in parser._option_string_actions:
        return
    parser.add_argument("--tscale", type=_tscale, metavar="X",
                        help="fix tscale, the length of a d-model time unit in seconds "
                        "(finite and positive)")
    parser.add_argument("--name", type=_system_name, metavar="N",
                        help="the name of the whole system (default: the mapping's); an "
                        "identifier: a letter, then letters, digits and single underscores")
    _default_inertial_option(parser, _GEN_INERTIAL)


def _tscale(text: str) -> float:
    """``--tscale``: a finite positive number. Any other value would become the axiom
    ``tscale = X`` beside ``tscale > 0`` (or a NaN no prover reads): inconsistent axioms, from
    which every lemma follows."""
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{text}'") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be finite and positive, not {text}")
    return value


def _system_name(text: str) -> str:
    """``--name``: an identifier, since it is printed into theories, comments and Z names
    (``*)`` in it would end an Isabelle comment)."""
    from cyphy.backends.isabelle.names import is_identifier

    if not is_identifier(text):
        raise argparse.ArgumentTypeError(
            f"'{text}' is not an identifier (a letter, then letters, digits and single "
            "underscores, not ending in one)")
    return text


def _isabelle_options(parser: argparse.ArgumentParser) -> None:
    _semantics_options(parser)
    parser.add_argument("--isabelle-namesets", action="store_true",
                        help="write interleavings whose branches update disjoint variables "
                        "with that name-set partition, so their updates are kept")
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
    from dataclasses import replace

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
    (``--pdf`` and ``--isabelle-namesets`` are each added by their own target)."""
    from cyphy.api import SemanticsGenOptions

    return SemanticsGenOptions(args.model, args.name, args.tscale, _consts(args),
                               tuple(args.path), pdf=getattr(args, "pdf", False),
                               namesets=getattr(args, "isabelle_namesets", False),
                               default_inertial=args.default_inertial)


GENERATORS["isabelle"] = (_isabelle, "an Isabelle/UTP session of the CyPhyCircus semantics "
                          "of a platform mapping (isabelle-gen/)", _isabelle_options)

def _solve(args: argparse.Namespace) -> int:
    from cyphy.api import SolveOptions, UsageError, solve
    from cyphy.backends.odes import odes_to_json, odes_to_latex, odes_to_text
    from cyphy.diagnostics import render_text

    options = SolveOptions(args.model, tuple(args.element), args.mapping_call, _consts(args),
                           tuple(args.path), gravity=args.gravity,
                           default_inertial=args.default_inertial,
                           floating_base=args.floating_base)
    try:
        result = solve(args.paths, options)
    except UsageError as err:
        sys.stderr.write(f"cyphy solve: error: --element {err}\n")
        return 2
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.elaboration.check.sources)))
    if result.reduced is None:
        return 1
    render = {"text": odes_to_text, "latex": odes_to_latex, "json": odes_to_json}
    sys.stdout.write(render[args.format](result.reduced, result.closed_form))
    return result.report.exit_code


def _simulate(args: argparse.Namespace) -> int:
    from cyphy.api import SimulateOptions, simulate
    from cyphy.backends import simulate as sim
    from cyphy.diagnostics import render_text

    def pairs(items: list[str], option: str) -> dict[str, str] | None:
        out = {}
        for item in items:
            name, sep, value = item.partition("=")
            if not sep or not name.strip():
                sys.stderr.write(f"cyphy simulate: error: {option} takes NAME=VALUE, not "
                                 f"'{item}'\n")
                return None
            out[name.strip()] = value.strip()
        return out

    init, inputs = pairs(args.init, "--init"), pairs(args.input, "--input")
    if init is None or inputs is None:
        return 2
    try:
        values = {k: float(v) for k, v in init.items()}
    except ValueError:
        sys.stderr.write("cyphy simulate: error: --init takes a number: NAME=0.5\n")
        return 2
    import math

    bad = [f"{k}={v}" for k, v in values.items() if not math.isfinite(v)]
    if bad:
        sys.stderr.write(f"cyphy simulate: error: --init {bad[0]}: not a finite number\n")
        return 2
    if args.machine is not None and args.scenario is None:
        sys.stderr.write("cyphy simulate: error: --machine needs --scenario (a scenario "
                         "without [controller])\n")
        return 2
    if args.t_end is None:
        args.t_end = _scenario_horizon(args.scenario) if args.scenario else 1.0
    if not args.t_end > 0 or args.samples < 2:
        sys.stderr.write("cyphy simulate: error: --t-end must be positive and --samples at "
                         "least 2\n")
        return 2
    try:  # the budget for the smallest trajectory: time and one column (refined later)
        sim.check_memory(args.samples, 1)
    except sim.OptionError as err:
        sys.stderr.write(f"cyphy simulate: error: {err.message} ({err.hint})\n")
        return 2
    settings = sim.SimulationOptions(args.t_end, values, inputs, args.method, args.rtol,
                                     args.atol, args.samples,
                                     sim.progress_to_stderr if sys.stderr.isatty() else None)
    result = simulate(args.paths, SimulateOptions(args.model, _consts(args), tuple(args.path),
                                                  settings, args.numeric, args.scenario,
                                                  args.gravity, machine=args.machine,
                                                  default_inertial=args.default_inertial,
                                                  floating_base=args.floating_base))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.elaboration.check.sources)))
    if result.trajectory is None or result.report.has_errors:
        return 1
    if result.numeric:
        sys.stderr.write("cyphy simulate: the kinematic tree alone (articulated-body "
                         "algorithm): the other devices' equations are not simulated\n")
    text = (sim.to_json if args.format == "json" else sim.to_csv)(result.trajectory)
    code = 0
    if args.output:
        code = _keep(Path(args.output), text)
    else:
        sys.stdout.write(text)
    if args.plot:
        try:
            png = sim.plot(result.trajectory, args.plot_var)
        except sim.SimulationError as err:
            sys.stderr.write(f"cyphy simulate: error: {err.message} ({err.hint})\n")
            return 1
        code = _keep(Path(args.plot), png) or code
    return code


def _keep(target: Path, content: str | bytes) -> int:
    """Write a result atomically; when that fails after all (the disk filled during the
    run), save it in a temporary file rather than lose it, and say where (exit 1)."""
    import tempfile

    from cyphy.outputs import OutputError, write_file

    try:
        write_file(target, content)
        return 0
    except OutputError as err:
        fd, rescue = tempfile.mkstemp(prefix="cyphy-", suffix=target.suffix)
        with os.fdopen(fd, "wb") as stream:
            stream.write(content.encode("utf-8") if isinstance(content, str) else content)
        sys.stderr.write(f"cyphy simulate: error: {err}; the result is saved in {rescue}\n")
        return 1


def _scenario_horizon(path: str) -> float:
    """The scenario's horizon, or 1 when the file cannot be read (simulate reports why)."""
    from cyphy.diagnostics import Report
    from cyphy.verify.flowstar.scenario import load_scenario

    scenario = load_scenario(path, Report(), needs_unsafe=False)
    return scenario.horizon if scenario is not None else 1.0


def _gravity(text: str) -> tuple[float, float, float]:
    """``--gravity 0,0,-1.62`` as three floats (argparse reports a bad value, exit 2)."""
    import math

    parts = text.split(",")
    try:
        x, y, z = (float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not three numbers x,y,z") from None
    if not all(math.isfinite(v) for v in (x, y, z)):
        raise argparse.ArgumentTypeError(f"'{text}' is not three finite numbers x,y,z")
    return (x, y, z)


_GEN_INERTIAL = "(--flowstar, --cyphycircus, --latex, --isabelle: Evolve's equations of motion) "


def _default_inertial_option(parser: argparse.ArgumentParser, note: str = "") -> None:
    if any("--default-inertial" in a.option_strings for a in parser._actions):
        return
    parser.add_argument("--default-inertial", choices=("sdf",), metavar="sdf",
                        help=f"{note}give links without inertial information SDFormat's "
                        "defaults (1 kg, identity inertia), as Gazebo does, with a warning "
                        "each (default: they stay without mass, an E-DYNAMICS error when a "
                        "joint moves them)")


def _gravity_option(parser: argparse.ArgumentParser) -> None:
    """``--gravity`` and ``--floating-base``: how the kinematic tree meets the world."""
    parser.add_argument("--gravity", type=_gravity, metavar="X,Y,Z",
                        help="gravity in m/s² in the model frame (default 0,0,-9.81)")
    parser.add_argument("--floating-base", action="store_true",
                        help="free the root link (six coordinates <Root>_x, _y, _z, _yaw, "
                        "_pitch, _roll, no contact) instead of fixing it to the world")


def _path_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--path", action="append", default=[], metavar="DIR",
                        help="another folder of model files to resolve names against")
    # Every command that reads models takes --path, and so the limit on copies.
    parser.add_argument("--max-copies", type=_positive_int, metavar="N",
                        help="most copies that index ranges may make in one model (default "
                        "100000, or $CYPHY_MAX_COPIES)")


def _const_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--const", action="append", default=[], metavar="NAME=VALUE",
                        help="value of a constant that has none (NAME may be qualified: "
                        "Treel::HEIGHT); repeatable")
    parser.add_argument("--consts", metavar="FILE",
                        help="constant values from a TOML or JSON file (NAME = VALUE)")


def _consts(args: argparse.Namespace) -> dict[str, object]:
    if not args.const and not args.consts:
        return {}
    from cyphy.model.constants import ConstantsError, parse_const_options

    try:
        return parse_const_options(args.const, args.consts)
    except ConstantsError as err:
        sys.stderr.write(f"cyphy: error: {err}\n")
        raise SystemExit(2) from None


def _show(args: argparse.Namespace) -> int:
    from cyphy.api import ElaborateOptions, elaborate
    from cyphy.backends.show.pmodel import model_to_json, model_to_text
    from cyphy.diagnostics import render_text

    if args.dmodel:
        return _show_dmodel(args)
    consts = _consts(args)
    result = elaborate(args.paths, ElaborateOptions(args.model, consts, tuple(args.path),
                                                    despite_value_errors=True))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.check.sources)))
    if result.model is None:
        return 1
    if args.format in ("dot", "svg"):
        from cyphy.backends.show.graph import GraphvizMissing, dot_to_svg, model_to_dot

        out = model_to_dot(result.model)
        if args.format == "svg":
            try:
                out = dot_to_svg(out)
            except GraphvizMissing as err:
                sys.stderr.write(f"cyphy show: error: {err}\n")
                return 2
    else:
        out = model_to_json(result.model) if args.format == "json" \
            else model_to_text(result.model)
    sys.stdout.write(out)
    return result.report.exit_code


def _show_dmodel(args: argparse.Namespace) -> int:
    from cyphy.api import CheckOptions, check
    from cyphy.backends.show.dmodel import dmodel_to_dict, dmodel_to_json, dmodel_to_text
    from cyphy.diagnostics import render_text
    from cyphy.lang import ast
    from cyphy.model.machines import machines_of

    result = check(args.paths, CheckOptions(search_paths=tuple(args.path),
                                            consts=_consts(args)))
    diagnostics = result.report.diagnostics
    if diagnostics:
        sys.stderr.write(render_text(diagnostics, dict(result.sources)))
    if result.resolution is None:
        return 1
    files = list(result.workspace.user_files())
    # Errors stop the show only where the d-model is (a p-model beside it does not matter).
    dmodel_files = {f.path for f in files if any(isinstance(
        i, (ast.Module, ast.Controller, ast.StateMachine, ast.Interface)) for i in f.items)}
    if any(d.span.file in dmodel_files or d.span.file not in result.sources
           for d in result.report.errors):
        return 1
    data = dmodel_to_dict(files, result.resolution,
                          machines_of(files, result.resolution, operations=True))
    if not (data["modules"] or data["controllers"] or data["machines"]):
        sys.stderr.write("cyphy show: error: no module, controller or state machine in the "
                         "files\n")
        return 1
    sys.stdout.write(dmodel_to_json(data) if args.format == "json" else dmodel_to_text(data))
    return 0


def _consistency_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--consistency", action="store_true",
                        help="also check what the platform mappings' equations mean, with Z3 "
                        "(C1-C5: solutions exist and are unique, typed events have values, "
                        "predicates can hold and fail, no conflicting writers)")
    parser.add_argument("--z3-timeout", type=_positive_int, metavar="MS",
                        help="time limit of each Z3 query in milliseconds (default 10000); "
                        "a query that runs out is reported as C-UNKNOWN")


def _finite_float(text: str) -> float:
    """A number option: ``nan`` and ``inf`` are refused here rather than reaching the
    integrator, Flow*'s timeout or the camera."""
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{text}'") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: '{text}'")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: '{text}'") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {value}")
    return value


def _list_rules() -> int:
    """Every condition ``cyphy check`` checks: the scope and typing conditions S1-S5, which
    name resolution and typing check as they go, then the registered rules."""
    from cyphy import codes
    from cyphy.wellformed import RULES

    for code in (codes.S1, codes.S2, codes.S3, codes.S4, codes.S5):
        sys.stdout.write(f"{code.id:<7} {code.severity.value:<7} {code.summary}\n")
    for r in RULES.values():
        sys.stdout.write(f"{r.id:<7} {r.code.severity.value:<7} {r.summary}\n")
    return 0


def _check(args: argparse.Namespace) -> int:
    from cyphy.api import CheckOptions, check
    from cyphy.diagnostics import render_json, render_text

    if args.list_rules:
        return _list_rules()
    if not args.paths:
        sys.stderr.write("cyphy check: error: give at least one PATH\n")
        return 2
    if args.syntax_only and args.consistency:
        sys.stderr.write("cyphy check: error: --consistency needs names resolved: drop "
                         "--syntax-only\n")
        return 2

    result = check(args.paths, CheckOptions(args.syntax_only, tuple(args.path),
                                            consts=_consts(args),
                                            consistency=args.consistency,
                                            z3_timeout_ms=args.z3_timeout))
    diagnostics = result.report.diagnostics
    if args.format == "json":  # the document asked for: the command's output
        sys.stdout.write(render_json(diagnostics))
    else:  # diagnostics go to stderr, as every command's do
        sys.stderr.write(render_text(diagnostics, dict(result.sources)))
        errors = sum(1 for d in diagnostics if d.severity.value == "ERROR")
        warnings = len(diagnostics) - errors
        files = len(result.workspace.targets)
        if not args.quiet:
            sys.stderr.write(f"{files} file{'s' if files != 1 else ''} checked: "
                             f"{errors} error{'s' if errors != 1 else ''}, "
                             f"{warnings} warning{'s' if warnings != 1 else ''}\n")
    return result.report.exit_code


def run() -> NoReturn:
    """The ``cyphy`` command: :func:`main`, then the exit without the interpreter's teardown.
    Freeing a large model object by object, and the final collection before it, take seconds
    on a 10,000-link model; everything has been written and closed by then, and the standard
    streams are flushed here (mypy ends the same way)."""
    from cyphy import interrupts, progress
    from cyphy.deep import run_deep

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
    from cyphy.diagnostics import RENDERING

    args = _parser().parse_args(_joined_values(sys.argv[1:] if argv is None else argv))
    if getattr(args, "max_copies", None):
        os.environ["CYPHY_MAX_COPIES"] = str(args.max_copies)  # read by cyphy.limits
    RENDERING.quiet, RENDERING.warnings_seen, RENDERING.usage_errors = args.quiet, 0, 0
    from cyphy.cli.targets import output_problem

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
        if args.command == "check":
            return _check(args)
        if args.command == "show":
            return _show(args)
        if args.command == "solve":
            return _solve(args)
        if args.command == "simulate":
            return _simulate(args)
        if args.command == "gen":
            return _gen(args)
        if args.command == "reach":
            return _reach(args)
        if args.command == "view":
            return _view(args)
    except KeyboardInterrupt:
        return 130
    except RecursionError:
        sys.stderr.write(TOO_DEEP)
        return 1
    except Exception as err:  # a bug of ours: say so plainly, without a traceback
        sys.stderr.write(f"cyphy: internal error ({type(err).__name__}: {err}); please report "
                         "it with the model that caused it (set CYPHY_TRACEBACK=1 for "
                         "details)\n")
        if os.environ.get("CYPHY_TRACEBACK"):
            raise
        return 70
    return 2


TOO_DEEP = ("cyphy: error: the model nests too deeply (expressions, blocks or parts nested "
            "thousands of levels deep)\n")


def _latex_options(parser: argparse.ArgumentParser) -> None:
    _semantics_options(parser)
    parser.add_argument("--pdf", action="store_true",
                        help="with --latex, also typeset the document with pdflatex")


def _gen_semantics(args: argparse.Namespace) -> "Generated":
    from cyphy.api import generate_cyphycircus

    return generate_cyphycircus(args.paths, "text" if args.target == "cyphycircus"
                                else "latex", _semantics_gen_options(args))


GENERATORS["cyphycircus"] = (
    _gen_semantics, "the CyPhyCircus semantics of a platform mapping, as text", _semantics_options)
GENERATORS["latex"] = (
    _gen_semantics, "the CyPhyCircus semantics as LaTeX for the CZT tools", _latex_options)


if __name__ == "__main__":
    sys.exit(main())
