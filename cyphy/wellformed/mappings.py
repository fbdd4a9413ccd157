"""Platform mappings: PMap1-PMap12.

A platform mapping ``map M dmodel Module to pmodel P {…}`` says how the services of the robotic
platform of a d-model module (its operations, events and variables) are realised by the sensors
and actuators of a p-model. The conditions below are those of ``wellformedness.md``; the
services of a platform are those of ``notation.md`` B: operations of the interfaces it
*provides* (or declares itself), events of the interfaces it *uses* (or declares itself) and the
variables of its ``var`` lists.

Name resolution (S1) has already reported names that do not resolve; these checks only judge
what the resolved names are, and stay silent about what they cannot resolve.
"""


from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Code, Severity, did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import type_to_notation
from cyphy.lang.resolve import steps_of
from cyphy.wellformed.mapping_names import (
    ACT_IN, ACT_OUT, CONST, DVAR, OPERATION, OTHER, PARAM, PREDICATE_READS, SENSOR_IN, SENSOR_OUT,
    TIME, UNKNOWN, Access, Names, Ref, access_of, pmodel_of_part,
)
from cyphy.wellformed.platform_services import (
    MemberMapping, Platform, Service, Site, in_user_file, kind_of, label_of, members_of,
    service_of, sites,
)
from cyphy.wellformed.registry import WFContext, rule

# ---------------------------------------------------------------------------------------------
# PMap1, PMap2: the mapped p-model is fully connected


def _joints_in_links(pm: ast.PModel) -> Iterator[ast.Block]:
    for link in pm.blocks:
        if link.kind is ast.BlockKind.LINK:
            for j in link.blocks:
                if j.kind is ast.BlockKind.JOINT:
                    yield j


@rule("PMap1", "in a mapped p-model every joint of a link has a flexible connection")
def check_PMap1_joints_connected(ctx: WFContext) -> None:
    """In the p-model of a platform mapping, every joint contained in a link of that p-model
    has a flexible connection (``flexibly connected to L``): a joint that moves nothing
    cannot be simulated."""
    seen: set[int] = set()
    for site in sites(ctx):
        pm = site.pmodel
        if pm is None:
            continue
        for link in pm.blocks:
            if link.kind is not ast.BlockKind.LINK:
                continue
            for joint in link.blocks:
                if joint.kind is not ast.BlockKind.JOINT or joint.flexible or id(joint) in seen:
                    continue
                seen.add(id(joint))
                where: object = joint if in_user_file(ctx, joint) else site.mapping.pmodel_span
                others = [b.name for b in pm.blocks
                          if b.kind is ast.BlockKind.LINK and b is not link]
                others += [f"<link> in {p.name}" for p in pm.parts]
                target = others[0] if others else "<link>"
                ctx.error("PMap1", where,
                          f"joint {joint.name} of link {link.name} in p-model {pm.name} (mapped "
                          f"by {site.mapping.name}) has no flexible connection",
                          f"add 'flexibly connected to {target}' to joint {joint.name}: a "
                          "mapped p-model must connect every joint")


@rule("PMap2", "in a mapped p-model every joint of a part is connected")
def check_PMap2_part_joints_connected(ctx: WFContext) -> None:
    """Every joint of a part of the mapped p-model (at any depth) is connected: by a flexible
    connection inside the part's p-model, or by a ``joint J flexibly connected to …`` clause
    of the part (or of a part enclosing it)."""
    seen: set[tuple[int, str]] = set()
    for site in sites(ctx):
        pm, pm_file = site.pmodel, site.pmodel_file
        if pm is None or pm_file is None:
            continue
        for top in pm.parts:
            for path, inner, joint in _part_joints(ctx, top, pm_file, (), set(), set()):
                key = (id(top), f"{path}/{joint.name}")
                if key in seen:
                    continue
                seen.add(key)
                where: object = top if in_user_file(ctx, top) else site.mapping.pmodel_span
                ctx.error("PMap2", where,
                          f"joint {joint.name} of part {path} (p-model {inner.name}) is not "
                          f"connected in the mapped p-model {pm.name}",
                          f"add 'joint {joint.name} flexibly connected to <link>' to part "
                          f"{top.name}, or 'flexibly connected to <link>' to the joint in "
                          f"p-model {inner.name}")


def _part_joints(ctx: WFContext, part: ast.Part, file: ast.SourceFile,
                 outer_path: tuple[str, ...], outer_clauses: set[str], visiting: set[int]
                 ) -> Iterator[tuple[str, ast.PModel, ast.Block]]:
    """Unconnected joints of ``part`` and of its nested parts, with the part path."""
    target = pmodel_of_part(ctx, part, file)
    if target is None or id(target[0]) in visiting:
        return  # S1 or S5 reported it
    inner, inner_file = target
    path = outer_path + (part.name,)
    clauses = outer_clauses | {c.joint for c in part.flexible}
    for joint in _joints_in_links(inner):
        if not joint.flexible and joint.name not in clauses:
            yield "::".join(path), inner, joint
    for nested in inner.parts:
        yield from _part_joints(ctx, nested, inner_file, path, clauses,
                                visiting | {id(inner)})


# ---------------------------------------------------------------------------------------------
# PMap3, PMap4: mappings and platform services correspond


@rule("PMap3", "there is a mapping for every event and operation of the robotic platform")
def check_PMap3_every_service_mapped(ctx: WFContext) -> None:
    """There is a mapping for every event and every operation of the d-model's robotic
    platform (events of the interfaces it uses and its own; operations of the interfaces it
    provides and its own). Variables may be left unmapped: they are then shared memory of the
    controllers."""
    for site in sites(ctx):
        platform = site.platform
        if platform is None:
            continue
        m = site.mapping
        mapped_ops = {o.name for o in m.operations}
        mapped_events = {e.name for e in m.events}
        for name, service in platform.operations.items():
            if name not in mapped_ops:
                ctx.error("PMap3", m,
                          f"mapping {m.name} has no mapping for {service.label} of robotic "
                          f"platform {platform.platform.name} (from {service.origin})",
                          f"add 'operation {name} {{ equation … }}' to mapping {m.name}")
        for name, service in platform.events.items():
            if name in mapped_events:
                continue
            direction = platform.direction(name)
            decl = service.decl
            param = f" ? {name[0]}" if isinstance(decl, ast.EventDecl) and decl.type else ""
            if direction == "output":
                example = f"'output event {name}{param} {{ equation … }}'"
            else:
                example = f"'input event {name}{param} {{ predicate … }}'"
                if direction is None:
                    example += f" (or 'output event {name}{param} {{ … }}' if the software " \
                               "sends it)"
            ctx.error("PMap3", m,
                      f"mapping {m.name} has no mapping for {service.label} of robotic "
                      f"platform {platform.platform.name} (from {service.origin})",
                      f"add {example} to mapping {m.name}")


@rule("PMap4", "every mapping is for a variable, event or operation of the robotic platform")
def check_PMap4_mapped_services_exist(ctx: WFContext) -> None:
    """Every operation, event and variable mapping names an operation, event or variable of
    the d-model's robotic platform (operations of provided interfaces, events of used
    interfaces, variables of ``var`` lists, or the platform's own)."""
    for site in sites(ctx):
        platform = site.platform
        if platform is None:
            continue
        pname = platform.platform.name
        for member in members_of(site.mapping):
            kind = kind_of(member)
            table = platform.of_kind(kind)
            if member.name in table:
                if isinstance(member, ast.EventMapping):
                    _check_event_direction(ctx, platform, member)
                continue
            hint = _unknown_service_hint(platform, member.name, table, kind)
            ctx.error("PMap4", member,
                      f"robotic platform {pname} of d-model {platform.module.name} has no "
                      f"{kind} '{member.name}' for the mapping of {label_of(member)}", hint)


def _check_event_direction(ctx: WFContext, platform: Platform,
                           member: ast.EventMapping) -> None:
    """An event the module's connections send from the platform to the software is an input
    event (its mapping observes sensors); one they send to the platform is an output event
    (its mapping drives actuators). Mapped the other way, the mapping means nothing."""
    way = platform.direction(member.name)
    if way is None or way == member.direction:
        return
    towards = "from the platform to the software" if way == "input" else \
        "from the software to the platform"
    ctx.error("PMap4", member,
              f"the mapping of {label_of(member)} is for an {member.direction} event, but "
              f"module {platform.module.name} connects {member.name} {towards}",
              f"write '{way} event {member.name}'")


def _unknown_service_hint(platform: Platform, name: str, table: dict[str, Service],
                          kind: str) -> str:
    other = platform.find(name)
    if other is None:
        return did_you_mean(name, table) or (
            f"its {kind}s are: {', '.join(sorted(table)) or '(none)'}")
    article = "an" if other.kind[0] in "aeiou" else "a"
    if other.kind == "constant":
        return f"{name} is a constant of {other.origin}: constants are not mapped"
    if platform.of_kind(other.kind).get(name) is other:  # mappable, as another kind
        keyword = "input event" if other.kind == "event" else other.kind
        return f"{name} is {article} {other.kind} (of {other.origin}): write " \
            f"'{keyword} {name} {{ … }}'"
    return f"{name} is {article} {other.kind} of the {other.origin}: " + (
        "operations come from provided interfaces" if other.kind == "operation"
        else "events come from used interfaces")


# ---------------------------------------------------------------------------------------------
# PMap5, PMap6: the shape of one mapping


@rule("PMap5", "an event mapping declares a parameter iff the event is typed")
def check_PMap5_event_parameter(ctx: WFContext) -> None:
    """An input or output event mapping declares a parameter (``input event e ? v``) if and
    only if the event is typed, and the parameter has the event's type (it does by
    construction: the parameter is declared with no type of its own)."""
    for site in sites(ctx):
        for member in site.mapping.events:
            service = service_of(site, member)
            if service is None or not isinstance(service.decl, ast.EventDecl):
                continue  # PMap4
            typed = service.decl.type is not None
            if typed and member.param is None:
                ctx.error("PMap5", member,
                          f"event {member.name} is typed ({type_to_notation(service.decl.type)}) but "
                          f"the mapping of {label_of(member)} declares no parameter for its value",
                          f"write '{member.direction} event {member.name} ? {member.name[0]} "
                          "{ … }' and define the parameter with equations")
            elif not typed and member.param is not None:
                ctx.error("PMap5", member.param_span or member.span,
                          f"event {member.name} is untyped but the mapping of {label_of(member)} "
                          f"declares parameter '{member.param}'",
                          f"remove '? {member.param}', or give event {member.name} a type in "
                          f"{service.origin}")


@rule("PMap6", "a mapping is given by actions or by equations, at least one, not both")
def check_PMap6_actions_or_equations(ctx: WFContext) -> None:
    """A mapping is given by actions or by equations: at least one, not both. An untyped
    input event mapping is given by its predicate alone (PMap12); a typed one also needs
    equations or actions for its parameter. Predicates belong to input event mappings only."""
    for site in sites(ctx):
        for member in members_of(site.mapping):
            label = label_of(member)
            is_input = isinstance(member, ast.EventMapping) and member.direction == "input"
            if member.equations and member.actions:
                ctx.error("PMap6", member.actions[0],
                          f"the mapping of {label} has both equations and actions",
                          "give it either equations (a relation the p-model satisfies) or "
                          "actions (assignments), not both")
            elif not member.equations and not member.actions:
                if not is_input:
                    ctx.error("PMap6", member,
                              f"the mapping of {label} has neither equations nor actions",
                              f"say how {member.name} acts on the p-model, e.g. "
                              "'equation <actuator>.<input> == …'")
                elif isinstance(member, ast.EventMapping) and _typed(site, member):
                    ctx.error("PMap6", member,
                              f"the mapping of {label} gives no equations or actions for the "
                              f"value of event {member.name}",
                              f"add 'equation {member.param or 'v'} == …' over sensor outputs")
            if not is_input:
                for p in member.predicates:
                    ctx.error("PMap6", p,
                              f"the mapping of {label} has a predicate; only input event "
                              "mappings have one",
                              "state the mapping with equations or actions, not a predicate")


def _typed(site: Site, member: ast.EventMapping) -> bool:
    """Whether the mapped event is typed (when the event is unknown, whether the mapping
    says so by declaring a parameter)."""
    service = service_of(site, member)
    if service is not None and isinstance(service.decl, ast.EventDecl):
        return service.decl.type is not None
    return member.param is not None


# ---------------------------------------------------------------------------------------------
# PMap7-PMap10: what each kind of mapping reads and writes


def _fix(member: MemberMapping, ref: Ref, writing: bool) -> str:
    block = ref.block
    if ref.category in (SENSOR_OUT, SENSOR_IN) and not (
            isinstance(member, ast.EventMapping) and member.direction == "input"):
        return "sensor readings reach the software only through input event mappings"
    if ref.category in (ACT_IN, ACT_OUT) and isinstance(member, ast.EventMapping) and \
            member.direction == "input":
        return "actuators are driven by operation, output event and variable mappings; an " \
            "input event mapping only observes sensor outputs"
    if ref.category == SENSOR_IN and block is not None:
        outs = [p.name for p in ref.ports if p.kind in (ast.DeclKind.OUTPUT, ast.DeclKind.INOUT)]
        return f"read an output of sensor {block.name} instead ({', '.join(outs) or 'none'})"
    if ref.category == ACT_OUT and block is not None:
        ins = [p.name for p in ref.ports if p.kind in (ast.DeclKind.INPUT, ast.DeclKind.INOUT)]
        return f"set an input of actuator {block.name} instead ({', '.join(ins) or 'none'})"
    if ref.category == OTHER:
        return "a mapping reaches the p-model only through sensor outputs and actuator inputs"
    if writing and ref.category == PARAM:
        return "the parameter is given by the software: copy it to a 'var' to change it"
    if writing and ref.category == DVAR:
        return "the variable is written by the software: read it only"
    if writing and ref.category in (CONST, TIME):
        return "constants and time cannot be assigned: declare a 'var'"
    if writing and ref.category == SENSOR_OUT:
        return "sensor outputs are computed by the p-model: read them only"
    return "use a local ('var') instead"


def _check_access(ctx: WFContext, site: Site, member: MemberMapping) -> None:
    access = access_of(member)
    names = Names(ctx, site, member)
    label = label_of(member)

    def report(ref: Ref, verb: str, writing: bool) -> None:
        ctx.error(access.rule, ref.span,
                  f"the mapping of {label} {verb} {ref.what} ({ref.text}); {access.summary}",
                  _fix(member, ref, writing))

    both = access.reads | access.writes
    for eq in member.equations:
        refs = list(names.refs(eq.expr))
        for ref in refs:
            if ref.category not in both:
                report(ref, "mentions", False)
        _check_equation_writes(ctx, access, member, eq, refs)
    for action in member.actions:
        for s in action.statements:
            if isinstance(s, ast.Assign):
                reads: list[ex.Expr] = [s.value]
                if steps_of(s.target) is not None:
                    ref = names.classify(s.target)
                    if ref.category not in access.writes | {UNKNOWN}:
                        report(ref, "assigns", True)
                    for node in s.target.walk():
                        if isinstance(node, ex.Index):
                            reads.extend(node.args)
                else:
                    reads.append(s.target)
                for e in reads:
                    for ref in names.refs(e):
                        if ref.category not in access.reads:
                            report(ref, "reads", False)
            elif isinstance(s, ast.CallStatement):
                for ref in names.refs(s.call):
                    if ref.category not in access.reads:
                        report(ref, "reads", False)


def _check_equation_writes(ctx: WFContext, access: Access, member: MemberMapping,
                           eq: ast.Equation, refs: list[Ref]) -> None:
    """An equation relates what the mapping writes to what it reads: one that mentions
    nothing the mapping may write (``equation S.range == 2.0`` in an input event mapping)
    constrains what it may only read, a sensor output or the software's parameter."""
    if any(r.category in access.writes | {UNKNOWN} for r in refs) or \
            any(r.category not in access.reads for r in refs):
        return  # it sets something, or mentions what it may not (reported above)
    read = next((r for r in refs if r.category not in _NOT_STATE), None)
    if read is None and not refs:
        return
    what = f"{read.what} ({read.text})" if read is not None else "only constants"
    ctx.error(access.rule, eq, f"an equation of the mapping of {label_of(member)} sets nothing "
              f"the mapping may write: it constrains {what}; {access.summary}",
              "relate it to a local ('var') or to what the mapping drives, or make it the "
              "predicate" if isinstance(member, ast.EventMapping) and member.direction == "input"
              else "relate it to an actuator input or a local ('var')")


#: Names that are no state of the robot or the software: an equation over them alone is odd,
#: but it is the constant's, not the mapping's, business (PMap7-PMap10 name the state).
_NOT_STATE = frozenset({CONST, TIME, OPERATION, UNKNOWN})


def _check_kind(ctx: WFContext, kind: str) -> None:
    for site in sites(ctx):
        for member in members_of(site.mapping):
            direction = member.direction if isinstance(member, ast.EventMapping) else None
            if (direction or kind_of(member)) == kind:
                _check_access(ctx, site, member)


@rule("PMap7", "an input event mapping reads sensor outputs, locals and constants")
def check_PMap7_input_event_access(ctx: WFContext) -> None:
    """An input event mapping reads sensor outputs, its locals and constants, and writes its
    locals and (if typed) its parameter: it observes the p-model and never drives it (an
    actuator port, a sensor input or a joint variable in its equations or actions is an
    error)."""
    _check_kind(ctx, "input")


@rule("PMap8", "an output event mapping reads its parameter and writes actuator inputs")
def check_PMap8_output_event_access(ctx: WFContext) -> None:
    """An output event mapping reads its parameter, locals and constants, and writes actuator
    inputs and its locals (no sensor port, actuator output or joint variable)."""
    _check_kind(ctx, "output")


@rule("PMap9", "an operation mapping reads its parameters and writes actuator inputs")
def check_PMap9_operation_access(ctx: WFContext) -> None:
    """An operation mapping reads the operation's parameters, its locals and constants, and
    writes actuator inputs and its locals: mentioning a sensor output would make the
    operation depend on sensing, which is what input events are for."""
    _check_kind(ctx, "operation")


@rule("PMap10", "a variable mapping reads the variable and writes actuator inputs")
def check_PMap10_variable_access(ctx: WFContext) -> None:
    """A variable mapping reads the variable, its locals and constants, and writes actuator
    inputs and its locals."""
    _check_kind(ctx, "variable")


# ---------------------------------------------------------------------------------------------
# PMap11, PMap12


@rule("PMap11", "actions in mappings do not call d-model operations")
def check_PMap11_no_operation_calls(ctx: WFContext) -> None:
    """Actions in mappings do not call operations of the d-model: a mapping says how the
    platform realises an operation, it cannot ask the software for one."""
    for site in sites(ctx):
        platform = site.platform
        ops: dict[str, str] = {}
        if platform is not None:
            ops.update({n: s.origin for n, s in platform.operations.items()})
            ops.update({n: s.origin for n, s in platform.others.items()
                        if s.kind == "operation"})
        for member in members_of(site.mapping):
            for action in member.actions:
                for statement in action.statements:
                    for e in ast.expressions_in(statement):
                        for node in e.walk():
                            if not isinstance(node, ex.Call):
                                continue
                            if isinstance(node.func, ex.PlatformRef):  # $op(…)
                                parts = node.func.name
                            elif isinstance(node.func, ex.Name):
                                parts = node.func.parts
                            else:
                                continue
                            origin = _called_operation(ctx, site, ops, parts)
                            if origin is None:
                                continue
                            name = parts[-1]
                            ctx.error("PMap11", node,
                                      f"an action of the mapping of {label_of(member)} calls "
                                      f"d-model operation {name} (of {origin})",
                                      "set the actuator inputs that realise it instead: a "
                                      "mapping cannot call the software's operations")


def _called_operation(ctx: WFContext, site: Site, ops: dict[str, str],
                      name: tuple[str, ...]) -> str | None:
    """Where the d-model operation that a call names is declared, or None: an operation of
    the platform (``stop``, or ``MovementI::stop`` through its interface) or a d-model
    operation definition the mapping's file can see."""
    origin = ops.get(name[-1])
    if origin is not None and (len(name) == 1 or name[-2] == origin.split()[-1]):
        return origin
    return _dmodel_operation(ctx, site.file, name)


def _dmodel_operation(ctx: WFContext, file: ast.SourceFile, name: tuple[str, ...]) -> str | None:
    """The d-model operation definition (``operation op(…) {…}``) ``name`` denotes, if any."""
    for d in ctx.scopes.lookup(file, name):
        if isinstance(d, ast.StateMachine) and d.kind == "operation":
            return f"operation definition {d.name}"
    return None


#: RoboTool's newer mappings leave the predicate out of an event that occurs in every cycle:
#: accepted, with a warning that says so (the semantics then uses ``true``, Rule 4).
_PMAP12_NO_PREDICATE = Code("PMap12", Severity.WARNING,
                            "an input event mapping without a predicate occurs every cycle")


@rule("PMap12", "an input event mapping has at most one predicate, over sensor outputs and "
      "locals (none: the event occurs every cycle, a warning)")
def check_PMap12_input_event_predicate(ctx: WFContext) -> None:
    """An input event mapping has a predicate (when the event occurs), at most one, and it is
    a boolean expression over sensor outputs, the mapping's locals and constants (its
    booleanness is checked with the other types, S3). Without one, the event occurs in every
    cycle: a warning, since the paper's mappings always give one."""
    for site in sites(ctx):
        for member in site.mapping.events:
            if member.direction != "input":
                continue
            preds = member.predicates
            label = label_of(member)
            if not preds:
                ctx.report.report(_PMAP12_NO_PREDICATE, f"the mapping of {label} has no "
                                  f"predicate: cyphy assumes that {member.name} occurs in "
                                  "every cycle (predicate true), as RoboTool's newer mappings "
                                  "mean", member.span, f"add 'predicate …' if {member.name} "
                                  "occurs only sometimes, over sensor outputs (e.g. "
                                  "'predicate S.voltage >= 3.0')")
                continue
            for extra in preds[1:]:
                ctx.error("PMap12", extra, f"the mapping of {label} has more than one predicate",
                          "conjoin them into one: 'predicate a /\\ b'")
            names = Names(ctx, site, member)
            for p in preds:
                for ref in names.refs(p.expr):
                    if ref.category in PREDICATE_READS:
                        continue
                    ctx.error("PMap12", ref.span,
                              f"the predicate of the mapping of {label} mentions {ref.what} "
                              f"({ref.text}); it may mention only sensor outputs, locals and "
                              "constants",
                              "define the parameter with equations, not in the predicate"
                              if ref.category == PARAM else _fix(member, ref, False))
