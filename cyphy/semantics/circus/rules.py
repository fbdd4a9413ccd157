"""The paper's semantic rules (section 6): a p-model with its platform mapping → CyPhyCircus.

One function per rule, named for it, with the rule's number in its docstring; the rules read
the elaborated model (device equations already renamed to their instances) and the mapping's
syntax tree, and build the AST of :mod:`cyphy.semantics.circus.ast`. ``../shared/spec/
semantics.md`` records the rules in words, and where they are ours rather than the paper's.

Nothing here prints: the text, LaTeX and Isabelle printers in :mod:`cyphy.backends` do.
"""

from __future__ import annotations

from dataclasses import field
from typing import Iterable

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.model.elements import ElaboratedModel, Sensor
from cyphy.records import record
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.apart import RULE_ACTIONS, claim_apart, derived_names, global_names
from cyphy.semantics.circus.names import NameTable, capitalised
from cyphy.semantics.circus.values import (constant_type, literal, si_units, type_of,
                                          value_expr, within)
from cyphy.semantics.dynamics.equations import mapping_renamer

TIME = "t"  # the time variable of equations; CyPhyCircus's own, not declared
TIMER = "timer"
REGISTER_CHANNELS = ("registerRead", "registerWrite", "tock")
RECEIVE_LOOP = "Y"  # the recursion variable of ReceiveFromDModel

#: Where the program departs from the paper's rules, in words every printer states (the
#: text and LaTeX as comments, the Isabelle theories in their header).
DEVIATIONS = (
    "ReceiveFromDModel receives the d-model's calls one after the other, in any number and "
    "order, until the cycle's first tock (mu Y . (AFromDModel ; Y [] BFromDModel ; Y [] "
    "tock -> Skip)); the main action then waits for the cycle's other cycle - 1 tocks. The "
    "paper interleaves the receivers (AFromDModel ||| BFromDModel) under Wait(cycle): an "
    "interleaving with empty name sets discards the calls' updates (utp-main c9122f14, "
    "utp_circus_parallel.thy:846-847, the merge at :18-26), and the first tock cuts it off "
    "without a final state, so no call would reach the p-model's state.",
    "Evolve also states the kinematic tree's equations of motion (one joint effort "
    "J_tau = M(q) a + h(q, v) per joint) and, for each joint whose parent is a fixed root, "
    "a zero parent twist and twist rate (J_pV = J_pA = 0): the paper's rules leave the "
    "joints' efforts and a fixed root's motion unconstrained.",
    "Init assigns, besides the timer and the private inputs no equation determines (the "
    "spec's Rule 2: declared initial value, else 0), what a scenario starts (gen "
    "--scenario: any state variable its [init] names, a number assigned, an interval "
    "[lo, hi] as the specification statement x : [true, lo <= x' <= hi]); the Isabelle "
    "dialects, which hold the ODEs' states and running integrals as state where the paper "
    "quantifies them afresh in each Evolve (exists PLocal), start them at 0, their declared "
    "or the scenario's values.",
)


class SemanticsError(Exception):
    """A mapping the rules cannot translate; the message and hint say why."""

    def __init__(self, message: str, span: Span, hint: str) -> None:
        super().__init__(message)
        self.message, self.span, self.hint = message, span, hint


@record(frozen=True, slots=False)
class Service:
    """What the d-model's platform declares for a mapped name: parameter (or value) types."""

    name: str
    params: tuple[c.Binding, ...] = ()


@record(frozen=True, slots=False)
class DModel:
    """What the rules need of the d-model: its module name, cycle restriction and the
    parameters of the platform's operations, events (typed or not) and variables."""

    module: str
    cycle_restriction: tuple[ex.Expr, ...] = ()
    operations: dict[str, Service] = field(default_factory=dict)
    events: dict[str, Service] = field(default_factory=dict)
    variables: dict[str, Service] = field(default_factory=dict)


@record(frozen=False, slots=False)
class Context:
    """The inputs of the rules and the names they hand out."""

    model: ElaboratedModel
    mapping: ast.PlatformMapping
    dmodel: DModel
    names: NameTable
    system_name: str
    tscale: float | None = None
    ports: dict[tuple[str, ...], str] = field(default_factory=dict)
    motion: tuple[ex.Expr, ...] = ()  # the kinematic tree's equations of motion (build.py)
    given: dict[str, tuple[float, float]] = field(default_factory=dict)  # a scenario's [init]
    actions: set[str] = field(default_factory=lambda: set(RULE_ACTIONS))  # named so far

    def action_name(self, base: str) -> str:
        """``base``, or ``base_2``, ``base_3``… when an action already has it: names built from
        mapped names (``<Event>ToDModel``, ``<Op>Call``, ``<Op>FromDModel``) can repeat a
        rule's own (an input event ``send`` makes ``SendToDModel``) or each other (events
        ``near`` and ``Near``), and two definitions of one name are ambiguous in the text and
        rejected by Isabelle."""
        return claim_apart(base, self.actions)


# --------------------------------------------------------------------------- Rule 1


def rule1_program(ctx: Context) -> c.Program:
    """Rule 1: global constants ``cycle : ℕ`` and ``tscale : ℝ`` (positive, with the
    d-model's cycle restriction and a fixed ``tscale`` if given), the channels, the d-model
    process ``D`` (opaque here: :mod:`cyphy.semantics.circus.build` writes it from the
    d-model's state machine, :mod:`cyphy.semantics.circus.dmodel`), the p-model process ``P``
    (Rule 2) and
    ``N = (D ⟦ registerRead, registerWrite, tock ⟧ P) \\ {registerRead, registerWrite, tock}``."""
    cycle, tscale = ex.Name(("cycle",)), ex.Name(("tscale",))
    where: list[ex.Expr] = [ex.BinOp(">", cycle, ex.Num("0")),
                            ex.BinOp(">", tscale, ex.Num("0"))]
    where.extend(ctx.dmodel.cycle_restriction)
    if ctx.tscale is not None:
        where.append(ex.BinOp("==", tscale, ex.Num(repr(float(ctx.tscale)))))
    globals_ = c.AxDef((c.Binding("cycle", c.NAT), c.Binding("tscale", c.REAL)), tuple(where))
    process = rule2_pmodel_process(ctx)
    taken = global_names(process)
    dmodel = c.OpaqueProcess(claim_apart(ctx.dmodel.module, taken))
    taken |= derived_names(dmodel.name)
    system = c.ProcessDef(claim_apart(ctx.system_name, taken), c.PHide(
        c.PParallel(c.PRef(dmodel.name), REGISTER_CHANNELS, c.PRef(process.name)),
        REGISTER_CHANNELS))
    return c.Program(globals_, channels(ctx), dmodel, process, system,
                     functions(process))


def channels(ctx: Context) -> tuple[c.ChannelDecl, ...]:
    """Rule 1's channels: ``tock``; ``registerRead`` with one variant per input event mapping
    (a boolean, and the event's value if typed); ``registerWrite`` with one variant per
    operation, output event and variable mapping (their arguments or value)."""
    reads, writes = [], []
    for m in ctx.mapping.events:
        service = ctx.dmodel.events.get(m.name, Service(m.name))
        types = tuple(b.type for b in service.params)
        if m.direction == "input":
            reads.append(c.ChannelVariant(m.name, (c.BOOL, *types)))
        else:
            writes.append(c.ChannelVariant(m.name, types))
    for op in ctx.mapping.operations:
        service = ctx.dmodel.operations.get(op.name, Service(op.name))
        writes.append(c.ChannelVariant(op.name, tuple(b.type for b in service.params)))
    for v in ctx.mapping.variables:
        service = ctx.dmodel.variables.get(v.name, Service(v.name))
        writes.append(c.ChannelVariant(v.name, tuple(b.type for b in service.params)))
    return (c.ChannelDecl("tock", ()), c.ChannelDecl("registerRead", tuple(reads)),
            c.ChannelDecl("registerWrite", tuple(writes)))


def functions(process: c.BasicProcess) -> tuple[c.FunctionDecl, ...]:
    """The uninterpreted functions the process applies (library functions such as
    ``ScrewAxis``), with their arities, so that every printer can declare them."""
    arities: dict[str, int] = {}
    for node in c.walk(process):
        if isinstance(node, ex.Call) and isinstance(node.func, ex.Name):
            arities.setdefault(node.func.text, len(node.args))
    return tuple(c.FunctionDecl(n, arities[n]) for n in sorted(arities))


# --------------------------------------------------------------------------- Rule 2


def rule2_pmodel_process(ctx: Context) -> c.BasicProcess:
    """Rule 2: the p-model process ``P``: constants, the state schema ``PState`` (private
    and visible variables), the local schema ``PLocal``, ``Init``, the actions of Rules 3-5
    and of the output mappings, ``Evolve`` and the main action
    ``Init ; μ X • (SendToDModel ; ReceiveFromDModel ; Wait(cycle - 1) ; timer := 0 ;
    (Evolve △ (timer ≥ cycle × tscale)) ; X)``: ours where the paper has
    ``(ReceiveFromDModel △ Wait(cycle))``, whose updates are lost
    (:func:`receive_until_tock`)."""
    name = ctx.model.name
    consts = constants(ctx)
    state = state_schema(ctx)
    local = local_schema(ctx)
    actions: list[c.ActionDef] = [init_action(ctx, state)]
    actions.extend(rule3_send_to_dmodel(ctx))
    actions.extend(receive_from_dmodel(ctx))
    actions.append(evolve(ctx, state, local))
    timer = ex.Name((TIMER,))
    cycle_length = ex.BinOp("*", ex.Name(("cycle",)), ex.Name(("tscale",)))
    main = c.Seq((c.Call("Init"), c.Mu("X", c.Seq((
        c.Call("SendToDModel"),
        c.Call("ReceiveFromDModel"),
        c.Wait(ex.BinOp("-", ex.Name(("cycle",)), ex.Num("1"))),
        c.Assign((TIMER,), (ex.Num("0"),)),
        c.InterruptCond(c.Call("Evolve"), ex.BinOp(">=", timer, cycle_length)),
        c.Call("X"))))))
    declared = {p.mangled: si_units(p.initial) for _, device in _device_elements(ctx.model)
                for p in device.of_kind(ast.DeclKind.LOCAL) if p.initial is not None}
    fields = {f.name for f in state.fields}
    given = {n: v for n, v in ctx.given.items() if n not in fields}  # locals, integrals
    initial = {**declared, **{n: literal(lo) for n, (lo, hi) in given.items() if lo == hi}}
    ranges = tuple((n, literal(lo), literal(hi)) for n, (lo, hi) in sorted(given.items())
                   if lo != hi)
    return c.BasicProcess(name, consts, state, local, tuple(actions), main,
                          tuple(sorted(initial.items())), ranges)


def constants(ctx: Context) -> tuple[c.Constant, ...]:
    """Rule 2's constants: those of every block of the p-model (per instance, after
    instantiation) and of the mapping, with their values, or open (a parameter of the
    model) when they have none; library constants only where an equation uses them."""
    out: list[c.Constant] = []
    for e, device in _device_elements(ctx.model):
        for p in device.of_kind(ast.DeclKind.CONST):
            qualified = f"{e.name}::{p.name}"
            ctx.names.claim(qualified, p.mangled)
            if e.definition:
                ctx.names.define(qualified, f"{e.definition}::{p.name}")
            value = value_expr(p.value) if p.value is not None else None
            out.append(c.Constant(p.mangled, type_of(p.type), value, qualified))
    own = {q for q in (x.origin for x in out)}
    for qualified, value in sorted(ctx.model.constants.items()):
        if qualified in own or not qualified.startswith(ctx.model.name + "::"):
            continue
        mangled = ctx.names.mangle(qualified, qualified.split("::")[1:])
        out.append(c.Constant(mangled, constant_type(value), value_expr(value), qualified))
    for owner, decl in _mapping_constants(ctx.mapping):
        qualified = f"{ctx.mapping.name}::{owner}::{decl.name}" if owner \
            else f"{ctx.mapping.name}::{decl.name}"
        mangled = ctx.names.mangle(qualified, [owner or ctx.mapping.name, decl.name])
        value = si_units(decl.value) if decl.value is not None else None
        out.append(c.Constant(mangled, type_of(decl.type), value, qualified))
    return tuple(out)


def state_schema(ctx: Context) -> c.Schema:
    """Rule 2's ``PState``: ``timer`` and the inputs of actuators and joints and outputs of
    sensors are private; the inputs of sensors and outputs of actuators and joints are
    visible (and, ours, InOut ports). Every variable is a function of time."""
    fields = [c.SchemaField(TIMER, c.REAL)]
    ctx.names.claim(TIMER, TIMER)
    for e, device in _device_elements(ctx.model):
        sensor = type(e) is Sensor  # an Actuator is a Sensor subclass
        for p in device.of_kind(ast.DeclKind.INPUT, ast.DeclKind.OUTPUT, ast.DeclKind.INOUT):
            ctx.names.claim(f"{e.name}.{p.name}", p.mangled)
            visible = (p.kind is ast.DeclKind.INOUT
                       or (p.kind is ast.DeclKind.INPUT) == sensor)
            fields.append(c.SchemaField(p.mangled, type_of(p.type), visible))
    return c.Schema(f"{ctx.model.name}State", tuple(fields))


def local_schema(ctx: Context) -> c.Schema:
    """Rule 2's ``PLocal``: the local variables of every p-model block and of every
    mapping element (``LHinge_theta``, ``move_dsl``)."""
    fields = []
    for e, device in _device_elements(ctx.model):
        for p in device.of_kind(ast.DeclKind.LOCAL):
            ctx.names.claim(f"{e.name}.{p.name}", p.mangled)
            fields.append(c.SchemaField(p.mangled, type_of(p.type)))
    for owner, decl in _mapping_locals(ctx.mapping):
        qualified = f"{ctx.mapping.name}::{owner}::{decl.name}"
        fields.append(c.SchemaField(ctx.names.mangle(qualified, [owner, decl.name]),
                                    type_of(decl.type)))
    return c.Schema(f"{ctx.model.name}Local", tuple(fields))


def init_action(ctx: Context, state: c.Schema) -> c.ActionDef:
    """Rule 2's ``Init`` (ours where the paper is silent): ``timer := 0`` and every private
    input that no equation or relation of the model determines (the actuator inputs the
    software sets) gets its declared initial value, or 0 if it is a scalar (a vector
    input without a declared initial value is left to the first ``Evolve``). A scenario's
    ``[init]`` (``ctx.given``) wins for every scalar state field it names, visible ones
    too (a sensor's reading of the world): a number is assigned, an interval ``[lo, hi]``
    is the specification statement ``x : [true, lo ≤ x' ≤ hi]`` after the assignment
    (any start in the box, as Flow* reads it)."""
    determined = _determined_by_relations(ctx.model)
    private = {f.name for f in state.fields if not f.visible}
    targets, values = [TIMER], [ex.Num("0")]
    for e, device in _device_elements(ctx.model):
        for p in device.of_kind(ast.DeclKind.INPUT):
            if p.mangled not in private or p.mangled in determined:
                continue
            typ = type_of(p.type)
            if p.initial is not None:
                targets.append(p.mangled)
                values.append(si_units(p.initial))
            elif not isinstance(typ, c.TSeq):
                targets.append(p.mangled)
                values.append(ex.Bool(False) if typ == c.BOOL else ex.Num("0"))
    scalar = {f.name for f in state.fields if f.type == c.REAL}
    ranges: list[tuple[str, ex.Expr, ex.Expr]] = []
    for name, (lo, hi) in sorted(ctx.given.items()):
        if name not in scalar:
            continue  # a local (the process's ``initial``) or no state: reported by the caller
        if lo != hi:
            ranges.append((name, literal(lo), literal(hi)))
        elif name in targets:
            values[targets.index(name)] = literal(lo)
        else:
            targets.append(name)
            values.append(literal(lo))
    body: c.Action = c.Assign(tuple(targets), tuple(values))
    if ranges:
        body = c.Seq((body, within(ranges)))
    return c.ActionDef("Init", (), body)


def evolve(ctx: Context, state: c.Schema, local: c.Schema) -> c.ActionDef:
    """Rule 2's ``Evolve``: ``[Λ PState | ∃ PLocal • e1 ∧ … ∧ en ∧ timer' = 1]``: every
    equation of every device instance (indexed ones once per index) and every relation on
    containment, in model order, then (ours, issue 16) the kinematic tree's equations of
    motion, one ``<Joint>_tau = M(q)·a + h(q, v)`` per joint in tree order, which tie each
    joint's effort to the accelerations of the bodies it moves."""
    equations: list[ex.Expr] = []
    for _, device in _device_elements(ctx.model):
        equations.extend(si_units(e) for e in device.equations)
    equations.extend(si_units(r) for r in ctx.model.relations)
    equations.extend(si_units(m) for m in ctx.motion)
    equations.append(ex.BinOp("==", ex.Derivative(ex.Name((TIMER,))), ex.Num("1")))
    return c.ActionDef("Evolve", (), c.Evolution(state.name, local.name if local.fields
                                                 else None, tuple(equations)))


# --------------------------------------------------------------------------- Rules 3-5


def rule3_send_to_dmodel(ctx: Context) -> list[c.ActionDef]:
    """Rule 3: ``SendToDModel`` interleaves one action per input event mapping (Rule 4);
    a single mapping is that action alone; none gives ``Skip``."""
    defs = [rule4_input_event(ctx, m) for m in ctx.mapping.events if m.direction == "input"]
    calls = [c.Call(d.name) for d in defs]
    body: c.Action = c.Skip() if not calls else calls[0] if len(calls) == 1 \
        else c.Interleave(tuple(calls))
    return [*defs, c.ActionDef("SendToDModel", (), body)]


def rule4_input_event(ctx: Context, m: ast.EventMapping) -> c.ActionDef:
    """Rule 4: ``<Event>ToDModel ≙ if pred then Then(m) else Else(m)`` with the mapping's
    predicates (conjoined) translated.

    The paper's else-branch is ``registerRead.e!false → Skip``. For a typed event the
    channel carries ``bool × T``, so that communication would be ill-typed; ours (the spec
    is silent) offers every value, ``□ p : {p : T | true} • registerRead.e!false!p → Skip``:
    the value of an event that did not occur is left unconstrained, and no default value
    has to be invented for given sets."""
    preds = [translate(ctx, m, p.expr) for p in m.predicates]
    cond = ex.conjunction(preds) if preds else ex.Bool(True)
    return c.ActionDef(ctx.action_name(f"{capitalised(m.name)}ToDModel"), (),
                       c.Cond(cond, rule5_then_branch(ctx, m), _not_occurred(ctx, m)))


def _event_value(ctx: Context, m: ast.EventMapping) -> c.Binding | None:
    """The bound variable that carries a typed event's value (``None`` if untyped)."""
    service = ctx.dmodel.events.get(m.name, Service(m.name))
    if not service.params:
        return None
    return c.Binding(m.param or service.params[0].name, service.params[0].type)


def _register_read(m: ast.EventMapping, occurred: bool, value: c.Binding | None) -> c.Action:
    """``registerRead.e!occurred[!p] → Skip``."""
    fields = (c.Out(ex.Bool(occurred)),)
    if value is not None:
        fields += (c.Out(ex.Name((value.name,))),)
    return c.Prefix(c.Comm("registerRead", m.name, fields), c.Skip())


def _not_occurred(ctx: Context, m: ast.EventMapping) -> c.Action:
    """Rule 4's else-branch: ``registerRead.e!false``, with any value if typed."""
    value = _event_value(ctx, m)
    if value is None:
        return _register_read(m, False, None)
    return c.IndexedExtChoice(value, c.Exists((), ()),  # true
                              _register_read(m, False, value))


def rule5_then_branch(ctx: Context, m: ast.EventMapping) -> c.Action:
    """Rule 5: an untyped event communicates ``registerRead.e!true``; a typed one offers
    an external choice over the values ``{p | ∃ locals • equations}``."""
    value = _event_value(ctx, m)
    if value is None:
        return _register_read(m, True, None)
    where = c.Exists(_locals_bindings(ctx, m),
                     tuple(translate(ctx, m, e.expr) for e in m.equations))
    return c.IndexedExtChoice(value, where, _register_read(m, True, value))


# --------------------------------------------------------------------------- outputs


def receive_from_dmodel(ctx: Context) -> list[c.ActionDef]:
    """Rule 2's ``ReceiveFromDModel``: one action per output event, operation and variable
    mapping, received until the cycle's first tock (:func:`receive_until_tock`; the paper
    interleaves them, ``MoveFromDModel ||| StopFromDModel``); ``tock → Skip`` if there are
    none."""
    defs: list[c.ActionDef] = []
    receivers: list[str] = []
    for op in ctx.mapping.operations:
        found = operation_mapping(ctx, op)
        defs.extend(found)
        receivers.append(found[-1].name)
    for m in ctx.mapping.events:
        if m.direction == "output":
            defs.append(output_event_mapping(ctx, m))
            receivers.append(defs[-1].name)
    for v in ctx.mapping.variables:
        defs.append(variable_mapping(ctx, v))
        receivers.append(defs[-1].name)
    return [*defs, c.ActionDef("ReceiveFromDModel", (), receive_until_tock(receivers))]


def receive_until_tock(receivers: list[str]) -> c.Action:
    """``μ Y • (AFromDModel ; Y □ BFromDModel ; Y □ tock → Skip)``: the calls of one cycle,
    in any number and order, each applied after the one before, until the cycle's first
    ``tock`` ends the loop.

    A deviation from the paper (which interleaves the receivers, ``A ||| B``, interrupted by
    ``Wait(cycle)``): an interleaving with empty name sets restores the state from before it
    at its end (utp-main c9122f14, utp/utp_circus_parallel.thy:846-847, the merge at
    :18-26), it ends only when every branch has ended though a cycle calls one operation,
    and an interrupted action has no final state, so no call would ever reach the
    p-model's state. In the sequence here every update persists, and the tock that ends the
    software's cycle ends the loop normally; the main action then waits for the cycle's
    other ``cycle - 1`` tocks."""
    tock = c.Prefix(c.Comm("tock", None, ()), c.Skip())
    branches = tuple(c.Seq((c.Call(n), c.Call(RECEIVE_LOOP))) for n in receivers)
    return c.Mu(RECEIVE_LOOP, c.ExtChoice((*branches, tock))) if branches else tock


def operation_mapping(ctx: Context, op: ast.OperationMapping) -> list[c.ActionDef]:
    """``OpCall(x1..xn)`` (the mapping's effect) and
    ``OpFromDModel ≙ registerWrite.op?x1..?xn → OpCall(x1..xn)``."""
    service = ctx.dmodel.operations.get(op.name, Service(op.name))
    call_name = ctx.action_name(f"{capitalised(op.name)}Call")
    call = c.ActionDef(call_name, service.params, effect(ctx, op))
    trigger = c.Comm("registerWrite", op.name, tuple(c.In(b.name) for b in service.params))
    args = tuple(ex.Name((b.name,)) for b in service.params)
    receive = c.ActionDef(ctx.action_name(f"{capitalised(op.name)}FromDModel"), (),
                          c.Prefix(trigger, c.Call(call_name, args)))
    return [call, receive]


def output_event_mapping(ctx: Context, m: ast.EventMapping) -> c.ActionDef:
    """An output event: ``registerWrite.e?p → effect`` (typed) or
    ``registerWrite.e → effect``."""
    service = ctx.dmodel.events.get(m.name, Service(m.name))
    fields = tuple(c.In(m.param or b.name) for b in service.params)
    return c.ActionDef(ctx.action_name(f"{capitalised(m.name)}FromDModel"), (),
                       c.Prefix(c.Comm("registerWrite", m.name, fields), effect(ctx, m)))


def variable_mapping(ctx: Context, v: ast.VariableMapping) -> c.ActionDef:
    """A variable: ``registerWrite.v?v → effect`` (the new value is bound to ``v``)."""
    return c.ActionDef(ctx.action_name(f"{capitalised(v.name)}FromDModel"), (),
                       c.Prefix(c.Comm("registerWrite", v.name, (c.In(v.name),)),
                                effect(ctx, v)))


def effect(ctx: Context, m: ast.OperationMapping | ast.EventMapping | ast.VariableMapping
           ) -> c.Action:
    """The effect of an output mapping: for equations, the specification statement
    ``w : [true, ∃ locals • equations]`` whose frame ``w`` is the actuator inputs the
    equations constrain; for actions, the action translated; ``Skip`` when empty."""
    if m.actions:
        return _statements(ctx, m, [s for a in m.actions for s in a.statements])
    if not m.equations:
        return c.Skip()
    equations = tuple(translate(ctx, m, e.expr) for e in m.equations)
    ports = set(ctx.ports.values())
    frame = tuple(sorted({n for e in equations for n in c.names_in(e) if n in ports},
                         key=_order(ctx)))
    return c.Spec(frame, ex.Bool(True), c.Exists(_locals_bindings(ctx, m), equations))


def _statements(ctx: Context, m: ast.OperationMapping | ast.EventMapping
                | ast.VariableMapping, statements: list[ast.Statement]) -> c.Action:
    out: list[c.Action] = []
    for s in statements:
        if isinstance(s, ast.Assign):
            target = translate(ctx, m, s.target)
            if not isinstance(target, ex.Name):
                raise SemanticsError("the target of this assignment is not an input of the "
                                     "p-model", s.span, "assign to a port such as "
                                     "Core::LHinge::LMotor.das")
            out.append(c.Assign((target.text,), (translate(ctx, m, s.value),)))
        elif isinstance(s, ast.SkipStatement):
            out.append(c.Skip())
        else:
            raise SemanticsError("a mapping action can only assign p-model inputs (PMap11)",
                                 s.span, "replace the call by the assignments it stands for")
    return out[0] if len(out) == 1 else c.Seq(tuple(out)) if out else c.Skip()


# --------------------------------------------------------------------------- expressions


def translate(ctx: Context, owner: ast.OperationMapping | ast.EventMapping
              | ast.VariableMapping, e: ex.Expr) -> ex.Expr:
    """A mapping expression in CyPhyCircus names: element paths become the ports they
    name (``Core::LHinge::LMotor.das`` → ``LMotor_das``), locals and constants of the
    element get their mangled names, quantities their SI values; parameters stay."""

    _bound_apart(ctx, owner)
    names = {d.name: f"{ctx.mapping.name}::{d.name}" for d in ctx.mapping.declarations}
    names.update({d.name: f"{ctx.mapping.name}::{owner.name}::{d.name}"
                  for d in owner.declarations})
    scoped: dict[str, ex.Expr] = {n: ex.Name((m,)) for n, q in names.items()
                                  if (m := ctx.names.get(q)) is not None}
    return si_units(ex.transform(e, mapping_renamer(ctx.model, ctx.ports, scoped)))


def _bound_apart(ctx: Context, owner: ast.OperationMapping | ast.EventMapping
                 | ast.VariableMapping) -> None:
    """Refuse a parameter (an operation's, a typed event's value, a mapped variable) named as
    the semantics names a port or constant (``Motor_das``): parameters stay as they are in
    the translated equations, so ``LMotor.das == Motor_das`` would read
    ``Motor_das = Motor_das``, and the call would set nothing."""
    if isinstance(owner, ast.OperationMapping):
        service = ctx.dmodel.operations.get(owner.name, Service(owner.name))
        bound, what = [b.name for b in service.params], "parameter"
    elif isinstance(owner, ast.EventMapping):
        value = _event_value(ctx, owner)
        bound, what = ([value.name] if value is not None else []), "value"
    else:
        bound, what = [owner.name], "variable"
    for name in bound:
        if (taken := ctx.names.owner(name)) is not None:
            raise SemanticsError(
                f"the {what} '{name}' of {owner.name} has the name that the semantics gives "
                f"to {taken}: in the mapping's equations the two could not be told apart",
                owner.span, f"rename '{name}' (in the d-model and in this mapping)")


# --------------------------------------------------------------------------- helpers


def _device_elements(model: ElaboratedModel) -> Iterable[tuple[object, object]]:
    """Each element with behaviour and its device, in model order, each device once."""
    seen: set[str] = set()
    for e in [*model.joints, *model.unconnected, *model.actuators, *model.sensors,
              *model.links]:
        device = e.device
        if device is not None and device.prefix not in seen:
            seen.add(device.prefix)
            yield e, device


def _mapping_constants(mapping: ast.PlatformMapping
                       ) -> Iterable[tuple[str | None, ast.VarDecl]]:
    for d in mapping.declarations:
        if d.kind is ast.DeclKind.CONST:
            yield None, d
    for m in [*mapping.operations, *mapping.events, *mapping.variables]:
        for d in m.declarations:
            if d.kind is ast.DeclKind.CONST:
                yield m.name, d


def _mapping_locals(mapping: ast.PlatformMapping) -> Iterable[tuple[str, ast.VarDecl]]:
    for m in [*mapping.operations, *mapping.events, *mapping.variables]:
        for d in m.declarations:
            if d.kind is not ast.DeclKind.CONST:
                yield m.name, d


def _locals_bindings(ctx: Context, m: ast.OperationMapping | ast.EventMapping
                     | ast.VariableMapping) -> tuple[c.Binding, ...]:
    return tuple(c.Binding(ctx.names.lookup(f"{ctx.mapping.name}::{m.name}::{d.name}"),
                           type_of(d.type))
                 for d in m.declarations if d.kind is not ast.DeclKind.CONST)


def _determined_by_relations(model: ElaboratedModel) -> set[str]:
    return {n.text for r in model.relations for n in r.walk() if isinstance(n, ex.Name)}


def _order(ctx: Context):  # type: ignore[no-untyped-def]
    """Frame names in the order their ports appear in the model."""
    rank = {name: i for i, name in enumerate(ctx.ports.values())}
    return lambda n: rank.get(n, len(rank))
