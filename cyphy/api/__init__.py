"""The library entry points behind the CLI: values in, results with diagnostics out.

Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from cyphy import codes, collector, progress
from cyphy.deep import deep
from cyphy.diagnostics import Report, Span
from cyphy.lang.placement import check_placement
from cyphy.lang.resolve import Resolution, check_scopes
from cyphy.lang.workspace import Workspace, load_workspace

if TYPE_CHECKING:  # the model needs NumPy and SciPy: `cyphy check` must not import them
    from cyphy.model.elements import ElaboratedModel
    from cyphy.semantics.machines.cycle import MachineInterpreter


@dataclass(frozen=True)
class CheckOptions:
    syntax_only: bool = False
    search_paths: tuple[str, ...] = ()
    wellformedness: bool = True
    consts: dict[str, object] = field(default_factory=dict)
    neighbours_as_targets: bool = False  # check the files the given ones use, too
    value_checks: bool = True  # V1-V5 (geometry, inertia, meshes): what simulators need
    consistency: bool = False  # also C1-C5 on the platform mappings (imports Z3)
    z3_timeout_ms: int | None = None  # per Z3 query; None: the checks' default


@dataclass
class CheckResult:
    workspace: Workspace
    report: Report
    resolution: Resolution | None = None
    sources: dict[str, str] = field(default_factory=dict)


@deep
def check(paths: Sequence[str | Path], options: CheckOptions = CheckOptions()) -> CheckResult:
    """Parse the files (or folders) and, unless ``syntax_only``, resolve names and check the
    scope conditions. Diagnostics of library files are never reported."""
    with collector.paused():  # the syntax tree and the resolution tables all stay alive
        result = _front_end(paths, options)
    if options.consistency and result.resolution is not None:
        _check_consistency(result.workspace, result.resolution, result.report, options)
    return result


def _front_end(paths: Sequence[str | Path], options: CheckOptions) -> CheckResult:
    ws, report = load_workspace(paths, options.search_paths)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    if options.neighbours_as_targets:
        ws.targets = _with_dependencies(ws)
    check_placement(ws.user_files(), report)
    progress.stage("resolving names")
    result.resolution = check_scopes(ws, report)
    if options.wellformedness:
        from cyphy.wellformed import RULES, WFContext, check_wellformed

        only = None if options.value_checks else {i for i in RULES if not i.startswith("V")}
        check_wellformed(WFContext(ws, result.resolution, report, dict(options.consts),
                                   z3=options.consistency), only)
    return result


def _check_consistency(ws: Workspace, resolution: Resolution, report: Report,
                       options: CheckOptions) -> None:
    from cyphy.semantics.consistency import DEFAULT_TIMEOUT_MS, check_consistency

    check_consistency(ws, resolution, report, options.consts,
                      options.z3_timeout_ms or DEFAULT_TIMEOUT_MS)


@dataclass
class Generated:
    """What a generator produced: files by relative path, in writing order. ``files`` is
    empty when the model has errors (the report says which), so nothing gets written."""

    report: Report
    sources: dict[str, str] = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)


def _with_dependencies(ws: Workspace) -> list[str]:
    """The given files and every (non-library) file they use, transitively: what a
    generator translates with them, so what must be resolved and checked with them. Files
    that merely sit in the same folder (another robot's p-model) are left out."""
    item_file = {id(item): f.path for f in ws.files.values() for item in f.items}
    library = {f.path for pkg in ws.packages.values() if pkg.builtin for f in pkg.files}
    targets = list(ws.targets)
    while True:
        ws.targets = targets
        resolution = check_scopes(ws, Report())
        used = {item_file[id(d)] for d in resolution.targets.values() if id(d) in item_file}
        new = sorted(used - set(targets) - library)
        if not new:
            return targets
        targets = targets + new


@deep
def machine_interpreter(paths: Sequence[str | Path], name: str | None = None,
                        consts: dict[str, object] | None = None,
                        search_paths: tuple[str, ...] = (), pmodel: str | None = None
                        ) -> tuple["MachineInterpreter | None", CheckResult]:
    """The d-model's state machine under RoboSim's cycle semantics, ready to run (the
    sampled controller of a simulation), with the operation definitions it calls: the
    machine ``name``, else the one the controller of the module mapped onto ``pmodel``
    runs, else the only one. None (with diagnostics,
    code ``E-MACHINE`` for what is not a check) when the files have errors or there is no
    single machine to run."""
    from cyphy.diagnostics import Span
    from cyphy.lang.scopes import Scopes
    from cyphy.model.machines import select_machine
    from cyphy.semantics.machines.cycle import MACHINE, MachineError, interpreter_for

    checked = check(paths, CheckOptions(search_paths=search_paths))
    report = checked.report
    if report.has_errors or checked.resolution is None:
        return None, checked
    machine, (message, hint) = select_machine(list(checked.workspace.user_files()),
                                              checked.resolution, pmodel, name)
    if machine is None:
        report.report(MACHINE, message, Span.unknown(str(next(iter(paths), "<input>"))), hint)
        return None, checked
    try:
        return interpreter_for(machine, list(checked.workspace.user_files()),
                               checked.resolution, Scopes(checked.workspace), consts,
                               pmodel), checked
    except MachineError as err:
        report.report(MACHINE, f"state machine {machine.name}: {err.message}", err.span,
                      err.hint)
        return None, checked


@dataclass(frozen=True)
class ElaborateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    despite_value_errors: bool = False  # `cyphy show`: elaborate a model with V1-V5/E-EVAL
    # Links without inertial information get these defaults ("sdf": SDFormat's), with a
    # warning each (cyphy.model.default_inertial); None: they stay without mass.
    default_inertial: str | None = None


@dataclass
class ElaborateResult:
    check: CheckResult
    model: "ElaboratedModel | None"

    @property
    def report(self) -> Report:
        return self.check.report


@deep
def elaborate(paths: Sequence[str | Path], options: ElaborateOptions = ElaborateOptions()
              ) -> ElaborateResult:
    """Check the files, then elaborate one p-model. The model is None when the files have
    errors (generation must not run on them) or no p-model can be chosen."""
    from cyphy.model.elaborate import elaborate as run

    checked = check(paths, CheckOptions(search_paths=options.search_paths))
    if checked.resolution is None or (checked.report.has_errors and not (
            options.despite_value_errors
            and all(_value_error(d) for d in checked.report.errors))):
        return ElaborateResult(checked, None)
    model = run(checked.workspace, checked.resolution, checked.report, options.model,
                options.consts)  # type: ignore[arg-type]
    if model is not None and options.default_inertial is not None:
        from cyphy.model.default_inertial import apply_default_inertial

        apply_default_inertial(model, checked.report, options.default_inertial)
    return ElaborateResult(checked, model)


def _value_error(d: Any) -> bool:
    """Whether an error concerns only values (``V1``-``V5``, ``E-EVAL``): the model can
    still be elaborated and shown, with the error reported; generators refuse it."""
    import re

    return d.code.id == "E-EVAL" or re.fullmatch(r"V\d+", d.code.id) is not None


class UsageError(ValueError):
    """An option that names nothing in the model (``solve --element Nope::X``): the caller's
    mistake, not the model's, so not a diagnostic; the CLI exits with status 2."""


def unknown_elements(model: "ElaboratedModel", elements: Sequence[str]) -> str | None:
    """Why some of ``elements`` (qualified names) name no element with equations of
    ``model``, or None when each names one (or contains some)."""
    from cyphy.diagnostics import did_you_mean

    names = {e.name for e in [*model.joints, *model.unconnected, *model.sensors,
                              *model.actuators]}
    for q in elements:
        if not any(n == q or n.startswith(q + "::") for n in names):
            return (f"'{q}' names no element of {model.name}; "
                    + (did_you_mean(q, names) or f"qualified names start with "
                       f"{model.name}::"))
    return None


@dataclass(frozen=True)
class SolveOptions:
    model: str | None = None
    elements: tuple[str, ...] = ()
    mapping_call: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    closed_form: bool = True
    gravity: tuple[float, float, float] | None = None  # default −9.81 m/s² along z
    default_inertial: str | None = None  # see ElaborateOptions
    floating_base: bool = False  # the root bodies free (six coordinates each), not fixed


@dataclass
class SolveResult:
    elaboration: ElaborateResult
    system: Any = None  # cyphy.semantics.dynamics.equations.System
    reduced: Any = None  # cyphy.semantics.dynamics.reduce.Reduced
    closed_form: dict[str, Any] | None = None

    @property
    def report(self) -> Report:
        return self.elaboration.report


@deep
def solve(paths: Sequence[str | Path], options: SolveOptions = SolveOptions()) -> SolveResult:
    """Assemble the model's equations (optionally with one mapping call), reduce them to
    explicit ODEs with SymPy and, where SymPy finds one, give the closed form."""
    from cyphy.semantics.dynamics.reduce import closed_form, reduce_system, report_obstacles
    from cyphy.semantics.dynamics.equations import AssemblyError, assemble, mapping_operation

    elaborated = elaborate(paths, ElaborateOptions(
        options.model, options.consts, options.search_paths,
        default_inertial=options.default_inertial))
    result = SolveResult(elaborated)
    model = elaborated.model
    if model is None:
        return result
    report = elaborated.report
    unknown = unknown_elements(model, options.elements)
    if unknown:
        raise UsageError(unknown)
    try:
        mapping, call, params = (None, None, ())
        if options.mapping_call is not None:
            mapping, call, params = mapping_operation(
                elaborated.check.workspace, elaborated.check.resolution, model,
                options.mapping_call)
        result.system = assemble(model, list(options.elements) or None, mapping, call, params,
                                 options.gravity, definitions=True,
                                 floating_base=options.floating_base)
    except AssemblyError as err:
        from cyphy.semantics.dynamics.equations import ASSEMBLY

        report.report(getattr(err, "code", ASSEMBLY), err.message, err.span, err.hint)
        return result
    result.reduced = reduce_system(result.system)
    report_obstacles(result.reduced, report)
    free = [p for p in result.reduced.parameters if result.system.parameters.get(p) is None]
    if options.closed_form and not free and result.reduced.states \
            and not result.reduced.obstacles and not result.reduced.definitions:
        inputs = {f"der_{n}": 0 for n in result.system.inputs}
        result.closed_form = closed_form(result.reduced, inputs)
    return result


@dataclass(frozen=True)
class SimulateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    simulation: Any = None  # cyphy.backends.simulate.SimulationOptions (defaults when None)
    numeric: bool = False  # the kinematic tree alone, articulated-body algorithm
    scenario: str | None = None  # a Flow* scenario whose controller and environment run
    gravity: tuple[float, float, float] | None = None  # default −9.81 m/s² along z
    controller: Any = None  # with a scenario: a Controller run instead of its [controller]
    machine: str | None = None  # with a scenario without [controller]: the d-model machine
    default_inertial: str | None = None  # see ElaborateOptions (wins over the scenario's)
    floating_base: bool = False  # the root bodies free (six coordinates each), not fixed


@dataclass
class SimulateResult:
    elaboration: ElaborateResult
    trajectory: Any = None  # cyphy.backends.simulate.Trajectory
    numeric: bool = False  # whether the numeric (tree-only) path ran

    @property
    def report(self) -> Report:
        return self.elaboration.report


@deep
def simulate(paths: Sequence[str | Path], options: SimulateOptions = SimulateOptions()
             ) -> SimulateResult:
    """Integrate the model's explicit ODEs (``cyphy solve``'s, the equations of motion as
    named definitions, for trees of any size) with SciPy, or, with ``numeric``, the
    kinematic tree alone with the numeric articulated-body algorithm. With a ``scenario``
    (TOML, as for ``gen --flowstar``), its ``[controller]`` runs at the d-model cycle, its
    environment drives the sensor inputs and its ``[init]`` intervals start at their
    midpoints. A
    ``controller`` (:class:`cyphy.backends.simulate.Controller`, e.g. a state-machine
    interpreter) replaces the ``[controller]`` table; its calls must be among those the
    table's states issue, whose effects the scenario's problem solves. A scenario without
    ``[controller]`` runs the d-model's state machine (``machine`` names it when there are
    several), as ``reach`` does: its interpreter is the controller, one cycle per
    ``cycle × tscale`` seconds, and the mapping's operations give its calls' effects."""
    from cyphy.backends import simulate as sim
    from cyphy.semantics.dynamics import rigid_body as dynamics
    from cyphy.semantics.dynamics.equations import ASSEMBLY, AssemblyError

    if options.scenario is not None:
        return _simulate_scenario(paths, options)
    elaborated = elaborate(paths, ElaborateOptions(
        options.model, options.consts, options.search_paths,
        default_inertial=options.default_inertial))
    result = SimulateResult(elaborated)
    model = elaborated.model
    if model is None:
        return result
    report = elaborated.report
    settings = options.simulation or sim.SimulationOptions()
    try:
        numeric = options.numeric
        gravity = options.gravity or dynamics.STANDARD_GRAVITY
        several = options.floating_base or any(
            dynamics.DOF.get(dynamics.joint_kind(j), 1) > 1 for j in model.joints)
        if numeric or several:  # ZYX Euler angles must not start at their singularity
            tree = dynamics.kinematic_tree(model, gravity, options.floating_base)
            dynamics.euler_singularity(tree, [float(settings.init.get(name, 0.0))
                                              for name in tree.coordinates("theta")])
            if numeric:
                result.numeric = True
                result.trajectory = sim.simulate_tree(tree, settings)
                return result
        from cyphy.semantics.dynamics.reduce import reduce_system, report_obstacles
        from cyphy.semantics.dynamics.equations import assemble

        reduced = reduce_system(assemble(model, gravity=options.gravity, definitions=True,
                                         floating_base=options.floating_base))
        if reduced.obstacles:
            report_obstacles(reduced, report)
            return result
        result.trajectory = sim.simulate_reduced(reduced, settings)
    except AssemblyError as err:
        report.report(getattr(err, "code", ASSEMBLY), err.message, err.span, err.hint)
    except sim.SimulationError as err:
        hint = err.hint
        if err.message.startswith("constants without a value"):
            qualified = sorted({f"{e.definition.split('::')[-1]}::{p.name}"
                                for e in [*model.joints, *model.sensors, *model.actuators]
                                if e.device is not None and e.definition
                                for p in e.device.ports if p.mangled in err.message}
                               & set(model.missing))
            if qualified:
                hint = "give them values: " + " ".join(f"--const {n}=VALUE" for n in qualified)
        span = getattr(model.pmodel, "span", None) or Span.unknown(str(paths[0]))
        if isinstance(err, sim.OptionError):
            report.report(codes.OPTION, err.message, Span.unknown("<command line>"), hint)
        else:
            report.report(sim.SIMULATE, err.message, span, hint)
    return result


def _simulate_scenario(paths: Sequence[str | Path], options: SimulateOptions
                       ) -> SimulateResult:
    """The scenario's problem as ``gen --flowstar`` builds it (reduced ODEs with the
    environment, the effects of each state's calls, the events' predicates), integrated
    cycle by cycle under the ``[controller]`` table, or the d-model's state machine run by
    its interpreter (:mod:`cyphy.semantics.machines.cycle`) when the scenario has none."""
    import dataclasses

    from cyphy.backends import simulate as sim
    from cyphy.verify.flowstar.controller import CallEffects, ScenarioController
    from cyphy.verify.flowstar.export import build_problem
    from cyphy.verify.flowstar.scenario import SCENARIO, load_scenario

    report = Report()
    empty = ElaborateResult(CheckResult(None, report), None)  # type: ignore[arg-type]
    scenario = load_scenario(options.scenario, report,  # type: ignore[arg-type]
                             needs_unsafe=False)
    if scenario is None:
        return SimulateResult(empty)
    if options.model is not None:
        scenario.model = options.model
    if options.machine is not None:
        if scenario.states:
            report.report(SCENARIO, f"--machine {options.machine}: the scenario has a "
                          "[controller], which is the controller", scenario.span("controller"),
                          "remove the [controller] table to use the machine")
            empty.check.sources[scenario.path] = scenario.text
            return SimulateResult(empty)
        scenario.machine = options.machine
    scenario.consts.update(options.consts)
    if options.default_inertial is not None:
        scenario.default_inertial = options.default_inertial
    problem, sources = build_problem(paths, scenario, report, options.search_paths)
    empty.check.sources.update(sources)
    if problem is None:
        return SimulateResult(empty)
    settings = options.simulation or sim.SimulationOptions(t_end=scenario.horizon)
    init = {n: (lo + hi) / 2 for n, (lo, hi) in scenario.init.items()}
    init = {n: v for n, v in init.items() if n in problem.states}
    init.update(settings.init)
    settings = dataclasses.replace(settings, init=init)
    result = SimulateResult(empty)
    try:
        controller = options.controller or problem.machine or ScenarioController(scenario)
        effects = CallEffects(problem.call_effects, scenario.consts, problem.operation_effects)

        def events(_t: float, values: dict[str, float]) -> dict[str, object]:
            import sympy

            subs = {sympy.Symbol(n, real=True): v for n, v in values.items()}
            return {name: (True if bool(pred.xreplace(subs)) else None)
                    for name, pred in problem.events.items()}

        reduced = dataclasses.make_dataclass("Problem", ["states", "rhs", "inputs", "outputs"])(
            problem.states, problem.rhs, problem.inputs, problem.outputs)
        result.trajectory = sim.simulate_reduced(
            reduced, settings, controller, effects, scenario.period, events,
            getattr(controller, "observable", frozenset()))
    except sim.OptionError as err:
        report.report(codes.OPTION, err.message, Span.unknown("<command line>"), err.hint)
    except (sim.SimulationError, ValueError) as err:
        report.report(sim.SIMULATE, getattr(err, "message", str(err)),
                      scenario.span("controller"), getattr(err, "hint", ""))
    return result


@dataclass(frozen=True)
class SemanticsGenOptions:
    """Options of the generators built on the CyPhyCircus semantics (``--cyphycircus``,
    ``--latex``, ``--isabelle``)."""

    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of the whole system (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pdf: bool = False  # --latex: also typeset with pdflatex
    namesets: bool = False  # --isabelle: keep interleaved updates with a name-set partition
    dialect: str = "utp"  # --isabelle: "utp" (utp-main 2020) or "axiomatic" (Ax_CyPhyCircus)
    elements: tuple[str, ...] = ()  # --isabelle axiomatic: the elements Evolve's ODE covers
    default_inertial: str | None = None  # see ElaborateOptions


@deep
def semantics(paths: Sequence[str | Path], options: SemanticsGenOptions = SemanticsGenOptions()
              ) -> tuple[CheckResult, Any]:
    """Check the files (and the files they use) and apply the paper's rules to the chosen
    platform mapping: ``(check result, Semantics or None)``."""
    from cyphy.semantics.circus.build import SemanticsOptions, build_semantics

    # The value checks concern geometry and inertia, which the semantics does not use.
    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts),
                                        neighbours_as_targets=True, value_checks=False))
    if checked.report.has_errors or checked.resolution is None:
        return checked, None
    built = build_semantics(checked.workspace, checked.resolution, checked.report,
                            SemanticsOptions(options.mapping, options.system_name,
                                             options.tscale, dict(options.consts),
                                             options.default_inertial))
    return checked, built


@deep
def generate_cyphycircus(paths: Sequence[str | Path], target: str,
                         options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """``target`` ``"text"``: ``<N>.cpc`` (Unicode, reads like the paper's Figure 18);
    ``"latex"``: ``<N>.tex`` with ``cyphycircus.sty`` (and ``<N>.pdf`` with ``pdf``). Both
    with the names table ``<N>.names.json``."""
    import json

    checked, built = semantics(paths, options)
    result = Generated(checked.report, checked.sources)
    if built is None or checked.report.has_errors:
        return result
    stem = built.program.system.name
    if target == "text":
        from cyphy.backends.circus.text import program_to_text

        result.files[f"{stem}.cpc"] = program_to_text(built.program)
    else:
        from cyphy.backends.circus.latex import STYLE, program_to_latex

        document = program_to_latex(built.program)
        result.files[f"{stem}.tex"] = document
        result.files["cyphycircus.sty"] = STYLE
        if options.pdf:
            from cyphy.backends.circus.pdf import PdfError, typeset

            try:
                result.files[f"{stem}.pdf"] = typeset(document, {"cyphycircus.sty": STYLE})
            except PdfError as err:
                from cyphy.semantics.circus.build import NO_PDF

                checked.report.report(NO_PDF, str(err), built.mapping.span, err.hint)
                result.files.clear()
                return result
    table = dict(built.names.items())
    result.files[f"{stem}.names.json"] = json.dumps(table, indent=2, sort_keys=True) + "\n"
    return result


@dataclass(frozen=True)
class SdfGenOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pose: tuple[float, float, float, float, float, float] = (0.0,) * 6
    short_names: bool = False
    target: str = "gazebo"  # or "coppeliasim"
    gazebo_model: bool = False  # files model.sdf and model.config instead of <Model>.sdf
    split_trees: bool = False  # a <world> with one <model> per tree of links


@deep
def generate_sdf(paths: Sequence[str | Path], options: SdfGenOptions = SdfGenOptions()
                 ) -> Generated:
    """SDF 1.6 for one p-model (``cyphy gen --sdf``): ``<Model>.sdf`` and the name table
    ``<Model>.names.json``, or, for a Gazebo model folder, ``model.sdf``, ``model.config``
    and the table. No files when the model has errors or constants without values."""
    from cyphy.backends.robot_formats.sdf_xml import model_config, names_json, to_xml
    from cyphy.semantics.sdf.rules import SdfOptions, translate

    checked, generated, model = _geometric_model(paths, options.model, options.consts,
                                                 options.search_paths, "SDF generation")
    if model is None:
        return generated
    document = translate(model, checked.workspace, checked.report,
                         SdfOptions(options.pose, options.short_names, options.target,
                                    options.split_trees))
    text = to_xml(document.root)
    if options.gazebo_model:
        generated.files = {"model.sdf": text, "model.config": model_config(model.name),
                           f"{model.name}.names.json": names_json(document.names)}
    else:
        generated.files = {f"{model.name}.sdf": text,
                           f"{model.name}.names.json": names_json(document.names)}
    return generated


def _geometric_model(paths: Sequence[str | Path], name: str | None,
                     consts: dict[str, object], search_paths: tuple[str, ...], purpose: str
                     ) -> tuple[CheckResult, Generated, "ElaboratedModel | None"]:
    """Check the files and elaborate one p-model for a geometric export (SDF, URDF, MJCF,
    pictures): the model is None when the files have errors or a constant that geometry
    needs has no value (constants only the equations use may stay without one)."""
    from cyphy.model.elaborate import choose_pmodel, elaborate_pmodel, require_constants
    from cyphy.semantics.sdf.rules import unvalued

    checked = check(paths, CheckOptions(search_paths=search_paths, consts=dict(consts)))
    generated = Generated(checked.report, checked.sources)
    if checked.report.has_errors or checked.resolution is None:
        return checked, generated, None
    chosen = choose_pmodel(checked.workspace, name, checked.report)
    if chosen is None:
        return checked, generated, None
    model = elaborate_pmodel(checked.workspace, checked.resolution, checked.report, *chosen,
                             consts)  # type: ignore[arg-type]
    if unvalued(model):  # only constants that SDF needs must have values
        needed = {n: spans for n, spans in model.missing.items()
                  if not _device_constant(model, n)} or model.missing
        model.missing = needed
        require_constants(model, checked.report, purpose)
    if checked.report.has_errors:
        return checked, generated, None
    return checked, generated, model


@dataclass(frozen=True)
class TreeGenOptions:
    """Options of the tree exports (``--urdf``, ``--mjcf``)."""

    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    output: str | None = None  # the output folder, to write mesh paths relative to it
    package: str | None = None  # mesh paths as package://PACKAGE/… (URDF)
    free_base: bool = False  # MJCF: each tree's root gets a free joint


@deep
def robot(paths: Sequence[str | Path], options: TreeGenOptions, target: str
          ) -> tuple[Generated, Any, Any]:
    """The checked model as trees of links for ``target`` (``urdf``, ``mjcf``):
    ``(generated, robot or None, elaborated model)``. A mesh outside the model's folder is
    V2's warning, reported by the check for every target."""
    from cyphy.semantics.sdf.robot_tree import build_robot

    checked, generated, model = _geometric_model(paths, options.model, options.consts,
                                                 options.search_paths,
                                                 f"{target.upper()} generation")
    if model is None:
        return generated, None, None
    built = build_robot(model, checked.workspace, checked.report, target)
    return generated, built, model


def _mesh_paths(options: TreeGenOptions, model: "ElaboratedModel") -> Any:
    """Mesh paths as the export names them: from the output folder to the model's."""
    import os

    from cyphy.backends.robot_formats.urdf import MeshPaths

    folder = Path(model.pmodel.span.file).resolve().parent
    out = Path(options.output).resolve() if options.output else folder
    return MeshPaths(Path(os.path.relpath(folder, out)).as_posix(), options.package)


@deep
def generate_urdf(paths: Sequence[str | Path], options: TreeGenOptions = TreeGenOptions()
                  ) -> Generated:
    """URDF 1.0 (``cyphy gen --urdf``): ``<Model>.urdf``, or one ``<Model>__<Root>.urdf`` per
    tree of links, and the name table. Loops are cut as for ``--target pybullet``."""
    from cyphy.backends.robot_formats.sdf_xml import names_json, to_xml
    from cyphy.backends.robot_formats.urdf import robot_to_urdf

    generated, built, model = robot(paths, options, "urdf")
    if built is None:
        return generated
    report = generated.report
    files = robot_to_urdf(built, _mesh_paths(options, model), report, model.pmodel.span)
    if report.has_errors:
        return generated
    generated.files = {name: to_xml(node) for name, node in files.items()}
    generated.files[f"{built.name}.names.json"] = names_json(_names(built))
    return generated


@deep
def generate_mjcf(paths: Sequence[str | Path], options: TreeGenOptions = TreeGenOptions()
                  ) -> Generated:
    """MuJoCo's MJCF (``cyphy gen --mjcf``): ``<Model>.xml`` with every tree of links, a
    motor per driven joint, loops closed by equality constraints; and the name table."""
    from cyphy.backends.robot_formats.mjcf import robot_to_mjcf
    from cyphy.backends.robot_formats.sdf_xml import names_json, to_xml

    generated, built, model = robot(paths, options, "mjcf")
    if built is None:
        return generated
    report = generated.report
    root = robot_to_mjcf(built, _mesh_paths(options, model), report, model.pmodel.span,
                         options.free_base)
    if report.has_errors:
        return generated
    generated.files = {f"{built.name}.xml": to_xml(root),
                       f"{built.name}.names.json": names_json(_names(built))}
    return generated


@dataclass(frozen=True)
class ViewRequest:
    """``cyphy view``: which model, its joints' positions (joint → radians or metres; the
    exported name, the qualified name with or without the p-model, or a simple name that
    only one joint has) and the camera."""

    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    positions: dict[str, float] = field(default_factory=dict)
    view: str = "iso"
    elevation: float | None = None
    azimuth: float | None = None


@deep
def view(paths: Sequence[str | Path], request: ViewRequest = ViewRequest()
         ) -> tuple[Generated, Any]:
    """The picture of one p-model (``cyphy view``): ``(generated with <Model>.png, the
    Picture with the bodies' image positions)``; nothing when the model has errors."""
    from cyphy.backends.show.view import ViewOptions, render
    from cyphy.semantics.sdf.robot_tree import build_robot
    from cyphy.wellformed.values import coincident

    checked, generated, model = _geometric_model(paths, request.model, request.consts,
                                                 request.search_paths, "the picture")
    if model is None:
        return generated, None
    # Cuts and other tree warnings concern the exports, not the picture: not reported.
    built = build_robot(model, checked.workspace, Report(), "urdf")
    positions = _joint_positions(built, request.positions, generated.report, model)
    if generated.report.has_errors:
        return generated, None
    highlighted = {e.name for pair in coincident(model) for e in pair}
    picture = render(built, positions, highlighted, ViewOptions(
        request.view, request.elevation, request.azimuth))
    generated.files = {f"{built.name}.png": picture.png}
    return generated, picture


def _joint_positions(built: Any, given: dict[str, float], report: Report,
                     model: "ElaboratedModel") -> dict[str, float]:
    """``--set`` names to the exported joint names; an unknown or ambiguous name is an
    error (E-VIEW-JOINT) that lists the joints."""
    from cyphy.backends.show.view import UNKNOWN_JOINT

    joints = [j for j in built.joints() if j.kind != "fixed"]
    out: dict[str, float] = {}
    for name, value in given.items():
        found = [j for j in joints if name in (j.name, j.qualified)
                 or j.qualified.endswith("::" + name)]
        if len(found) != 1:
            why = "no joint" if not found else f"{len(found)} joints"
            report.report(UNKNOWN_JOINT, f"--set {name}: {why} of {model.name} has that name",
                          model.pmodel.span, "name one of: "
                          + ", ".join(j.qualified for j in joints) or "(it has no joints)")
            continue
        out[found[0].name] = value
    return out


def _names(built: Any) -> dict[str, str]:
    """Exported link and joint names → qualified RoboSim names."""
    table = {link.name: link.qualified for link in built.links().values()}
    table.update((j.name, j.qualified) for j in built.joints())
    return table


def _device_constant(model: "ElaboratedModel", name: str) -> bool:
    """Whether a missing constant (``IR::a``) is a constant of a device's definition: the
    equations need it, SDF only if an annotation uses it."""
    definition, _, const = name.rpartition("::")
    return any(e.definition == definition and e.device is not None
               and e.device.port(const) is not None
               for e in [*model.joints, *model.sensors, *model.actuators])


@deep
def generate_isabelle(paths: Sequence[str | Path],
                      options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """The Isabelle session of one platform mapping: ``ROOT``, the prelude, the theory, a
    README and the names table. Files are empty when the model has errors. Interleavings
    that discard state updates are reported as warnings (W-INTERLEAVE)."""
    from cyphy.backends.isabelle.theory import (LOSSY_INTERLEAVING, UNTRANSLATABLE,
                                                IsabelleError, IsabelleOptions,
                                                generate_session)

    checked, built = semantics(paths, options)
    generated = Generated(checked.report, dict(checked.sources))
    report = checked.report
    if built is None or report.has_errors:
        return generated
    span = built.mapping.span
    from cyphy.backends.isabelle.axioms import INCONSISTENT_AXIOMS, unsatisfiable_axioms

    why = unsatisfiable_axioms(built.program.globals)
    if why is not None:
        report.report(INCONSISTENT_AXIOMS, why, span,
                      "check the d-model's cycle restriction and --tscale: a theory with "
                      "inconsistent axioms proves anything")
        return generated
    try:
        if options.dialect == "axiomatic":
            session = _axiomatic_session(built, options, report)
            if session is None:
                return generated
        else:
            session = generate_session(built.program, built.names,
                                       IsabelleOptions(options.namesets),
                                       options.system_name)
    except IsabelleError as err:
        where = err.span if err.span is not None and err.span.line > 0 else span
        if err.shapes:
            from cyphy import codes

            report.report(codes.S3, f"{err} (Isabelle's state is scalar: each equation "
                          "between vectors or matrices is written per component)", where,
                          "give both sides the same size (a m x n matrix equals only a m x n "
                          "one; a product needs the left's columns to equal the right's rows)")
        else:
            report.report(UNTRANSLATABLE, str(err), where,
                          "this construct cannot be written in Isabelle/UTP yet; the text and "
                          "LaTeX printers (--cyphycircus, --latex) show it")
        return generated
    for found in session.lossy:
        if session.namesets_applied and found.partition:
            continue
        branches = " ||| ".join(found.branches)
        updated = ", ".join(sorted(found.updated))
        if found.partition:  # (not applied: --isabelle-namesets was not given)
            hint = ("this follows the paper; --isabelle-namesets writes the interleaving with "
                    "a name-set partition, as the branches update disjoint variables")
        else:  # offer no option that cannot help
            hint = ("this follows the paper; no name-set partition keeps the updates: the "
                    f"branches all may update {', '.join(sorted(found.overlap))}")
        report.report(LOSSY_INTERLEAVING,
                      f"{found.action} ≙ {branches} interleaves with empty name sets: the "
                      f"updates of {updated} are discarded when it ends", span, hint)
    generated.files = session.files
    return generated


def _axiomatic_session(built: Any, options: SemanticsGenOptions, report: Report) -> Any:
    """The Ax_CyPhyCircus session, with Evolve reduced to explicit ODEs (SymPy); None when
    the equations cannot be reduced (E-ISABELLE-ODE reported)."""
    from cyphy.backends.isabelle.ax_theory import generate_ax_session
    from cyphy.backends.isabelle.theory import IsabelleOptions
    from cyphy.semantics.circus import ast as c
    from cyphy.semantics.circus.namesets import action_nodes

    pm = built.program.pmodel
    evolutions = [n for d in pm.actions for n in action_nodes(d.body)
                  if isinstance(n, c.Evolution)]
    odes = None
    if evolutions:
        from cyphy.semantics.dynamics.evolve_odes import explicit_odes

        odes = explicit_odes(built.model, evolutions[0], {f.name for f in pm.state.fields},
                             options.elements, report, built.mapping.span)
        if odes is None:
            return None
    return generate_ax_session(built.program, built.names, odes,
                               IsabelleOptions(options.namesets), options.system_name,
                               options.elements)
