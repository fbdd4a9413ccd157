"""From checked files to a CyPhyCircus program: choose the mapping, read what the rules need
of the d-model, elaborate the p-model, and apply Rule 1 (which applies the others)."""

from __future__ import annotations

from dataclasses import replace

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report, Span
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.scopes import Scopes, is_pmodel
from cyphy.lang.workspace import Workspace
from cyphy.model.choose import require_constants
from cyphy.model.default_inertial import apply_default_inertial
from cyphy.model.elaborate import elaborate_pmodel
from cyphy.model.elements import ElaboratedModel
from cyphy.model.machines import select_machines
from cyphy.records import record
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel import dmodel_process
from cyphy.semantics.circus.dmodel_cycle import cycle_process
from cyphy.semantics.circus.names import NameTable
from cyphy.semantics.circus.rules import Context, DModel, SemanticsError, Service, rule1_program
from cyphy.semantics.circus.values import type_of
from cyphy.semantics.circus.walk import action_nodes
from cyphy.semantics.dynamics.equations import fixed_root_twists, motion, port_index
from cyphy.semantics.dynamics.errors import DynamicsError
from cyphy.semantics.machines.cycle import MACHINE, MachineError, MachineInterpreter
from cyphy.semantics.machines.interpreters import interpreter_for, machine_constants
from cyphy.semantics.machines.parallel import compile_module
from cyphy.wellformed.platform_services import Platform, platform_of
from cyphy.wellformed.registry import WFContext

NO_MAPPING = codes.code("E-MAPPING", codes.E,
                        "no platform mapping to give a semantics to")
NO_PDF = codes.code("E-PDF", codes.E, "the LaTeX output cannot be typeset to PDF")
UNTRANSLATABLE = codes.code("E-SEMANTICS", codes.E,
                            "the mapping cannot be translated to CyPhyCircus")
OPAQUE_DMODEL = codes.code("W-SEMANTICS-DMODEL", codes.W,
                           "the d-model's state machine cannot be written as the process D")
NO_MOTION = codes.code("W-SEMANTICS-MOTION", codes.W,
                       "Evolve leaves out the equations of motion of the kinematic tree")
UNASSIGNED_INIT = codes.code("W-SCENARIO-INIT", codes.W,
                             "a scenario's initial value names no state that Init can start")


def started_by_init(actions: "tuple[c.ActionDef, ...] | list[c.ActionDef]") -> set[str]:
    """The variables ``Init`` assigns or starts in a specification's box."""
    out: set[str] = set()
    for d in actions:
        if d.name == "Init":
            for n in action_nodes(d.body):
                out.update(n.targets if isinstance(n, c.Assign) else
                           n.frame if isinstance(n, c.Spec) else ())
    return out


@record(frozen=True, slots=False)
class SemanticsOptions:
    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of N (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] | None = None
    default_inertial: str | None = None  # "sdf": massless links get SDF's defaults (a warning)
    machine: str | None = None  # the d-model's machine D is written from (default: as simulate)
    # a scenario's [init]: name → (low, high), a point when low == high; Init starts there
    initial: dict[str, tuple[float, float]] | None = None


@record(frozen=False, slots=False)
class Semantics:
    program: c.Program
    names: NameTable
    mapping: ast.PlatformMapping
    model: ElaboratedModel | None = None  # what Evolve's equations come from (for solving)
    scenario: object | None = None  # the scenario whose [init] Init starts (api.semantics)


def build_semantics(ws: Workspace, resolution: Resolution, report: Report,
                    options: SemanticsOptions = SemanticsOptions()) -> Semantics | None:
    """The CyPhyCircus program of one platform mapping of the given files, or None with
    the reason reported."""
    chosen = _choose_mapping(ws, report, options.mapping)
    if chosen is None:
        return None
    file, mapping = chosen
    wf = WFContext(ws, resolution, report)
    found = wf.scopes.lookup(file, mapping.pmodel, is_pmodel)
    pm = found[0] if found else None
    pm_file = wf.file_of(pm) if pm is not None else None
    if pm is None or pm_file is None:
        report.report(NO_MAPPING, f"the p-model {'::'.join(mapping.pmodel)} of mapping "
                      f"{mapping.name} is not among the files", mapping.pmodel_span,
                      "give the p-model's file or folder too")
        return None
    model = elaborate_pmodel(ws, resolution, report, pm, pm_file, options.consts or {})
    if model is not None and options.default_inertial is not None:

        apply_default_inertial(model, report, options.default_inertial)
    if report.has_errors:
        return None
    platform = platform_of(wf, mapping)
    dmodel = _dmodel(mapping, platform)

    equations_of_motion = _motion(model, report, {i.name for f in ws.files.values()
                                                  for i in f.items
                                                  if isinstance(i, ast.PModel)})
    if report.has_errors:
        return None
    ctx = Context(model, mapping, dmodel, NameTable(),
                  options.system_name or mapping.name, options.tscale,
                  port_index(model), equations_of_motion, dict(options.initial or {}))
    try:
        program = rule1_program(ctx)
    except SemanticsError as err:
        report.report(UNTRANSLATABLE, err.message, err.span, err.hint)
        return None
    dprocess = _dmodel_process(ws, resolution, report, mapping, program, options.machine,
                               machine_constants(options.consts))
    if report.has_errors:
        return None
    if dprocess is not None:
        program = replace(program, dmodel=dprocess)
    return Semantics(program, ctx.names, mapping, model)


def _dmodel_process(ws: Workspace, resolution: Resolution, report: Report,
                    mapping: ast.PlatformMapping, program: c.Program,
                    name: str | None, consts: dict[str, object]) -> c.BasicProcess | None:
    """``D`` from the state machine that controls the mapped p-model (``name``, else the
    one its module runs, as ``simulate`` and ``reach`` choose it), compiled as they compile
    it; None, the d-model left opaque, when the files have no machine (said in every
    output) or, with a warning at the machine, when it cannot be written yet; None with an
    error when the machine asked for by ``name`` is not among the files. ``consts`` gives
    the machine's constants left open (``--const``, a scenario's ``[consts]``), as
    simulate and reach take them."""

    files = list(ws.user_files())
    machines, (message, hint) = select_machines(files, resolution, mapping.pmodel[-1], name)
    if not machines:
        if name is not None:  # asked for by name: no semantics without it
            report.report(MACHINE, message, mapping.span, hint)
        elif "several" in message:
            report.report(OPAQUE_DMODEL, f"the d-model process is left opaque: {message}",
                          mapping.span, hint)
        return None
    machine = machines[0]
    channels = {ch.name: ch for ch in program.channels}
    reads = {v.tag: v.types for v in channels["registerRead"].variants if v.tag is not None}
    writes = {v.tag: v.types for v in channels["registerWrite"].variants
              if v.tag is not None}
    try:
        interpreters = []
        for machine in machines:
            interpreters.append(interpreter_for(machine, files, resolution, Scopes(ws), consts,
                                                mapping.pmodel[-1], leave_open=True))
        # values no automaton holds (typed events, open constants): the cycle written out
        if _reads_typed(interpreters) or any(i.open for i in interpreters):
            return cycle_process(program.dmodel.name, interpreters, reads, writes)
        # the module's machines together (the product), as simulate and reach run them
        try:
            automaton = compile_module(interpreters)
        except MachineError as no_automaton:
            # a first cycle that reads the inputs, or too many configurations: the cycle
            # written out reads the events before its first cycle, as simulate runs it
            try:
                return cycle_process(program.dmodel.name, interpreters, reads, writes)
            except MachineError as no_cycle:  # its reason, the one that applies, first
                raise MachineError(f"{no_cycle.message} (nor can the automaton hold it: "
                                   f"{no_automaton.message})", no_cycle.span,
                                   no_cycle.hint) from None
        return dmodel_process(program.dmodel.name, automaton, reads, writes)
    except MachineError as err:
        report.report(OPAQUE_DMODEL, f"the d-model process is left opaque: state machine "
                      f"{machine.name}: {err.message}", err.span, err.hint)
        return None
    except ValueError as err:
        report.report(OPAQUE_DMODEL, f"the d-model process is left opaque: state machine "
                      f"{machine.name} calls {err}, which the mapping does not map with "
                      "these arguments", machine.decl.span,
                      f"map {err} in {mapping.name}")
        return None


def _reads_typed(interpreters: list[MachineInterpreter]) -> bool:
    """Whether a machine reads a typed input event (then ``D`` is
    :mod:`~cyphy.semantics.circus.dmodel_cycle`'s, not the automaton's)."""
    return any(d.type is not None for i in interpreters
               for d in i.machine.platform.input_events.values())


def _motion(model: ElaboratedModel, report: Report, pmodels: set[str]
            ) -> tuple[ex.Expr, ...]:
    """The kinematic tree's equations of motion for ``Evolve``: the very equations ``cyphy
    solve`` assembles by default, the root fixed to the world and gravity −9.81 m/s² along the
    model's z (the semantics has no option for either: the axiomatic Isabelle dialect reduces
    the same default equations), after the zero parent twist and rate of every joint on a
    root link (:func:`~cyphy.semantics.dynamics.equations.fixed_root_twists`). A tree that has none (a link without mass, a loop, more
    joints than the symbolic limit) leaves them out with a warning: the rest of the semantics
    does not depend on them."""

    twists = tuple(e.expr for e in fixed_root_twists(model))  # the root is fixed: pV = pA = 0
    try:
        return twists + tuple(e.expr for e in motion(model))
    except DynamicsError as err:
        # Not a tree without motion: the p-models' constants that place and weigh its
        # links have no values (a part that does not instantiate one, P1). The devices'
        # constants stay open in the theory, as its `consts`.
        if not require_constants(model, report, "Evolve's equations of motion",
                                 owners=pmodels):
            return twists
        report.report(NO_MOTION, f"Evolve has no equations of motion: {err.message}", err.span,
                      err.hint)
        return twists


def _choose_mapping(ws: Workspace, report: Report, wanted: str | None
                    ) -> tuple[ast.SourceFile, ast.PlatformMapping] | None:
    mappings = [(f, i) for f in ws.user_files() for i in f.items
                if isinstance(i, ast.PlatformMapping)]
    named = [(f, m) for f, m in mappings if f.path in ws.named]
    mappings = named or mappings
    if wanted is not None:
        mappings = [(f, m) for f, m in mappings
                    if wanted in (m.name, m.pmodel[-1], "::".join(m.pmodel))]
    where = Span.unknown(ws.targets[0] if ws.targets else "<input>")
    if not mappings:
        report.report(NO_MAPPING, "no platform mapping" +
                      (f" named {wanted}" if wanted else "") + " among the files", where,
                      "give the mapping file (map M dmodel D to pmodel P {…}) and the files "
                      "of its p-model and d-model")
        return None
    if len(mappings) > 1:
        names = ", ".join(m.name for _, m in mappings)
        report.report(NO_MAPPING, f"several platform mappings: {names}", where,
                      "choose one with --model NAME")
        return None
    return mappings[0]


def _dmodel(mapping: ast.PlatformMapping, platform: Platform | None) -> DModel:
    """The module name, cycle restriction and service signatures; without a d-model
    (S1 reported it) the mapping alone gives untyped services."""
    if platform is None:
        return DModel("::".join(mapping.dmodel))
    restriction = tuple(_cycle_equation(d.expr) for d in platform.module.cycle_defs)
    dm = DModel(platform.module.name, restriction)
    for name, s in platform.operations.items():
        params = s.decl.params if isinstance(s.decl, ast.OperationSig) else ()
        dm.operations[name] = Service(name, tuple(c.Binding(p.name, type_of(p.type))
                                                  for p in params))
    for name, s in platform.events.items():
        typ = s.decl.type
        dm.events[name] = Service(name, () if typ is None else
                                  (c.Binding(name, type_of(typ)),))
    for name, s in platform.variables.items():
        dm.variables[name] = Service(name, (c.Binding(name, type_of(s.decl.type)),))
    return dm


def _cycle_equation(e: ex.Expr) -> ex.Expr:
    """``cycleDef cycle == 1`` states the restriction itself; a bare value means
    ``cycle == value``."""
    if isinstance(e, ex.BinOp) and e.op in ("==", "<", "<=", ">", ">=", "!="):
        return e
    return ex.BinOp("==", ex.Name(("cycle",)), e)
