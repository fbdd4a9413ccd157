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

from dataclasses import dataclass, field
from typing import Iterator, Union

from cyphy import expr as ex
from cyphy.diagnostics import Code, Severity, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import to_notation, type_to_notation
from cyphy.lang.resolve import block_children, path_roots, steps_of
from cyphy.lang.scopes import is_definition, is_interface, is_node, is_pmodel, is_value
from cyphy.wellformed.registry import WFContext, rule

MemberMapping = Union[ast.OperationMapping, ast.EventMapping, ast.VariableMapping]
Container = Union[ast.PModel, ast.Block, ast.Part]

# ---------------------------------------------------------------------------------------------
# What a mapping maps onto: the robotic platform of the d-model and the p-model


@dataclass(frozen=True)
class Service:
    """An operation, event or variable of a robotic platform and where it is declared."""

    kind: str  # "operation", "event", "variable" (or "constant", only for hints)
    decl: ast.OperationSig | ast.EventDecl | ast.VarDecl
    origin: str  # "interface MovementI" or "robotic platform marXbotServices"

    @property
    def name(self) -> str:
        return self.decl.name

    @property
    def label(self) -> str:
        if isinstance(self.decl, ast.OperationSig):
            params = ", ".join(f"{p.name}: {type_to_notation(p.type)}" for p in self.decl.params)
            return f"operation {self.name}({params})"
        if isinstance(self.decl, ast.EventDecl) and self.decl.type is not None:
            return f"event {self.name}: {type_to_notation(self.decl.type)}"
        return f"{self.kind} {self.name}"


@dataclass
class Platform:
    module: ast.Module
    platform: ast.RoboticPlatform
    operations: dict[str, Service] = field(default_factory=dict)
    events: dict[str, Service] = field(default_factory=dict)
    variables: dict[str, Service] = field(default_factory=dict)
    # Declared in the platform's interfaces but not mappable as such (an event of a provided
    # interface, an operation of a used one, a constant): only for hints.
    others: dict[str, Service] = field(default_factory=dict)

    def of_kind(self, kind: str) -> dict[str, Service]:
        return {"operation": self.operations, "event": self.events,
                "variable": self.variables}[kind]

    def find(self, name: str) -> Service | None:
        for table in (self.operations, self.events, self.variables, self.others):
            if name in table:
                return table[name]
        return None

    def direction(self, event: str) -> str | None:
        """``input`` when a module connection goes from the platform on ``event`` (the
        software receives it), ``output`` when one goes to it; None when unconnected."""
        for c in self.module.members:
            if isinstance(c, ast.Connection):
                if c.source == self.platform.name and c.source_event == event:
                    return "input"
                if c.target == self.platform.name and c.target_event == event:
                    return "output"
        return None


@dataclass
class _Site:
    """One platform mapping with what its header resolved to."""

    file: ast.SourceFile
    mapping: ast.PlatformMapping
    platform: Platform | None
    pmodel: ast.PModel | None
    pmodel_file: ast.SourceFile | None


def _sites(ctx: WFContext) -> Iterator[_Site]:
    for file, mapping in ctx.mappings():
        found = ctx.scopes.lookup(file, mapping.pmodel, is_pmodel)
        pm = found[0] if found else ctx.target(mapping.pmodel)
        if not isinstance(pm, ast.PModel):
            pm = None
        yield _Site(file, mapping, platform_of(ctx, mapping),
                    pm, ctx.file_of(pm) if pm is not None else None)


def platform_of(ctx: WFContext, mapping: ast.PlatformMapping) -> Platform | None:
    module = ctx.target(mapping)
    if not isinstance(module, ast.Module):
        return None  # S1 reported the d-model
    return module_platform(ctx, module)


def module_platform(ctx: WFContext, module: ast.Module) -> Platform | None:
    """The services of a module's robotic platform (None when it has none)."""
    module_file = ctx.file_of(module)
    platform, platform_file = module.platform, module_file
    if platform is None:  # `rref rp = Platform` to a platform declared on its own
        for m in module.members:
            if isinstance(m, ast.NodeRef) and m.kind == "rref":
                target = ctx.target(m)
                if target is None and module_file is not None:
                    found = ctx.scopes.lookup(module_file, m.target, is_node)
                    target = found[0] if found else None
                if isinstance(target, ast.RoboticPlatform):
                    platform, platform_file = target, ctx.file_of(target) or module_file
                    break
    if platform is None:
        return None
    out = Platform(module, platform)
    own = f"robotic platform {platform.name}"
    for op in platform.operations:
        out.operations.setdefault(op.name, Service("operation", op, own))
    for ev in platform.events:
        out.events.setdefault(ev.name, Service("event", ev, own))
    for v in platform.variables:
        _add_variable(out, v, own)
    for use in platform.interface_uses:
        interface = _interface(ctx, use, platform_file)
        if interface is None:
            continue  # S1 reported it
        where = f"interface {interface.name}"
        for v in interface.variables:
            _add_variable(out, v, where)
        if use.relation == "provides":
            for op in interface.operations:
                out.operations.setdefault(op.name, Service("operation", op, where))
            for ev in interface.events:
                out.others.setdefault(ev.name, Service("event", ev, f"provided {where}"))
        elif use.relation == "uses":
            for ev in interface.events:
                out.events.setdefault(ev.name, Service("event", ev, where))
            for op in interface.operations:
                out.others.setdefault(op.name, Service("operation", op, f"used {where}"))
    return out


def _add_variable(out: Platform, v: ast.VarDecl, where: str) -> None:
    if v.kind is ast.DeclKind.CONST:
        out.others.setdefault(v.name, Service("constant", v, where))
    else:
        out.variables.setdefault(v.name, Service("variable", v, where))


def _interface(ctx: WFContext, use: ast.InterfaceUse, file: ast.SourceFile | None
               ) -> ast.Interface | None:
    target = ctx.target(use)
    if isinstance(target, ast.Interface):
        return target
    if file is not None:
        found = ctx.scopes.lookup(file, use.interface, is_interface)
        if found and isinstance(found[0], ast.Interface):
            return found[0]
    for _, _, decl in ctx.workspace.all_declarations():
        if isinstance(decl, ast.Interface) and decl.name == use.interface[-1]:
            return decl
    return None


def _members(mapping: ast.PlatformMapping) -> Iterator[MemberMapping]:
    for m in mapping.members:
        if isinstance(m, (ast.OperationMapping, ast.EventMapping, ast.VariableMapping)):
            yield m


def _kind(member: MemberMapping) -> str:
    if isinstance(member, ast.OperationMapping):
        return "operation"
    if isinstance(member, ast.VariableMapping):
        return "variable"
    return "event"


def _label(member: MemberMapping) -> str:
    """``operation move``, ``input event obstacle``, ``variable level``."""
    if isinstance(member, ast.EventMapping):
        return f"{member.direction} event {member.name}"
    return f"{_kind(member)} {member.name}"


def _service(site: _Site, member: MemberMapping) -> Service | None:
    if site.platform is None:
        return None
    return site.platform.of_kind(_kind(member)).get(member.name)


def mapped_services(ctx: WFContext) -> Iterator[tuple[_Site, MemberMapping, ast.OperationSig |
                                                       ast.EventDecl | ast.VarDecl | None]]:
    """Every member of every platform mapping with the declaration of the service it maps
    (None when it maps none: PMap4): what the semantic checks of
    :mod:`cyphy.semantics.consistency` need to type the parameters."""
    for site in _sites(ctx):
        for member in _members(site.mapping):
            service = _service(site, member)
            yield site, member, service.decl if service is not None else None


def _in_user_file(ctx: WFContext, node: object) -> bool:
    span = getattr(node, "span", None)
    return span is not None and span.file in ctx.workspace.targets


# ---------------------------------------------------------------------------------------------
# What the names inside a mapping denote

LOCAL, CONST, PARAM, DVAR, TIME, OPERATION = "local", "const", "param", "dvar", "time", "op"
SENSOR_OUT, SENSOR_IN, ACT_IN, ACT_OUT, OTHER, UNKNOWN = (
    "sensor-out", "sensor-in", "actuator-in", "actuator-out", "other", "unknown")


@dataclass(frozen=True)
class _Ref:
    """One name or element path used in a mapping, with what it denotes."""

    category: str
    text: str  # as written: ``Base::J::M.das``
    what: str  # ``input das of actuator M``
    span: Span
    block: ast.Block | None = None
    ports: tuple[ast.VarDecl, ...] = ()  # all variables of ``block``, for hints


@dataclass(frozen=True)
class _Access:
    """What one kind of mapping may read and write (PMap7-PMap10)."""

    rule: str
    reads: frozenset[str]
    writes: frozenset[str]
    summary: str


_ALWAYS = {CONST, TIME, OPERATION, UNKNOWN}  # OPERATION: PMap11's business; UNKNOWN: S1's
ACCESS = {
    "input": _Access("PMap7", frozenset({SENSOR_OUT, LOCAL, PARAM} | _ALWAYS),
                     frozenset({LOCAL, PARAM}),
                     "an input event mapping reads sensor outputs, its locals and constants, "
                     "and writes its locals and (if typed) its parameter"),
    "output": _Access("PMap8", frozenset({PARAM, LOCAL} | _ALWAYS), frozenset({ACT_IN, LOCAL}),
                      "an output event mapping reads its parameter, locals and constants, and "
                      "writes actuator inputs and its locals"),
    "operation": _Access("PMap9", frozenset({PARAM, LOCAL} | _ALWAYS),
                         frozenset({ACT_IN, LOCAL}),
                         "an operation mapping reads the operation's parameters, its locals "
                         "and constants, and writes actuator inputs and its locals"),
    "variable": _Access("PMap10", frozenset({DVAR, LOCAL} | _ALWAYS), frozenset({ACT_IN, LOCAL}),
                        "a variable mapping reads the variable, its locals and constants, and "
                        "writes actuator inputs and its locals"),
}
PREDICATE_READS = frozenset({SENSOR_OUT, LOCAL} | _ALWAYS)


def _access_of(member: MemberMapping) -> _Access:
    if isinstance(member, ast.EventMapping):
        return ACCESS[member.direction]
    return ACCESS[_kind(member)]


class _Names:
    """Classifies the names and element paths used inside one member mapping."""

    def __init__(self, ctx: WFContext, site: _Site, member: MemberMapping) -> None:
        self.ctx, self.site, self.member = ctx, site, member
        self.scope: dict[str, str] = {}
        for d in site.mapping.declarations:
            self.scope[d.name] = CONST if d.kind is ast.DeclKind.CONST else LOCAL
        service = _service(site, member)
        if isinstance(member, ast.OperationMapping) and service is not None:
            for p in service.decl.params:  # type: ignore[union-attr]
                self.scope[p.name] = PARAM
        elif isinstance(member, ast.EventMapping) and member.param:
            self.scope[member.param] = PARAM
        elif isinstance(member, ast.VariableMapping):
            self.scope[member.name] = DVAR
        for d in member.declarations:
            self.scope[d.name] = CONST if d.kind is ast.DeclKind.CONST else LOCAL

    def refs(self, e: ex.Expr) -> Iterator[_Ref]:
        """Every name and element path ``e`` uses (index arguments included)."""
        for root in path_roots(e):
            yield self.classify(root)

    def classify(self, e: ex.Expr) -> _Ref:
        steps = steps_of(e)
        text = to_notation(e)
        if not steps:
            return _Ref(UNKNOWN, text, text, e.span)
        first = steps[0][0]
        if first in self.scope:
            cat = self.scope[first]
            word = {LOCAL: "local", CONST: "constant", PARAM: "parameter",
                    DVAR: "d-model variable"}[cat]
            return _Ref(cat, text, f"{word} {first}", e.span)
        if first == "t" and len(steps) == 1:
            return _Ref(TIME, text, "time t", e.span)
        names = tuple(s[0] for s in steps)
        found = self.ctx.scopes.lookup(self.site.file, names, is_value) or (
            self.ctx.scopes.lookup(self.site.file, (first,), is_value))
        if found:
            return _Ref(CONST, text, f"constant {first}", e.span)
        platform = self.site.platform
        if len(steps) == 1 and platform is not None and (
                first in platform.operations or first in platform.others):
            return _Ref(OPERATION, text, f"operation {first}", e.span)
        return self._element(steps, text, e.span)

    def _element(self, steps: list[tuple[str, Span, bool]], text: str, span: Span) -> _Ref:
        pm, pm_file = self.site.pmodel, self.site.pmodel_file
        if pm is None or pm_file is None:
            return _Ref(UNKNOWN, text, text, span)
        names = [s[0] for s in steps]
        if names[0] == pm.name and len(names) > 1:
            names = names[1:]
        found = _navigate(self.ctx, pm, pm_file, names)
        if found is None:
            return _Ref(UNKNOWN, text, text, span)
        block, block_file, port = found
        ports = _ports(self.ctx, block, block_file)
        decl = ports.get(port) if ports is not None else None
        if decl is None:
            return _Ref(UNKNOWN, text, text, span)
        what = f"{decl.kind.value} {decl.name} of {block.kind.value} {block.name}"
        all_ports = tuple(ports.values()) if ports is not None else ()
        if decl.kind is ast.DeclKind.CONST:
            cat = CONST
        elif block.kind is ast.BlockKind.SENSOR and decl.kind in (ast.DeclKind.OUTPUT,
                                                                  ast.DeclKind.INOUT):
            cat = SENSOR_OUT
        elif block.kind is ast.BlockKind.SENSOR and decl.kind is ast.DeclKind.INPUT:
            cat = SENSOR_IN
        elif block.kind is ast.BlockKind.ACTUATOR and decl.kind in (ast.DeclKind.INPUT,
                                                                    ast.DeclKind.INOUT):
            cat = ACT_IN
        elif block.kind is ast.BlockKind.ACTUATOR and decl.kind is ast.DeclKind.OUTPUT:
            cat = ACT_OUT
        else:
            cat = OTHER
        return _Ref(cat, text, what, span, block, all_ports)


def _pmodel_of_part(ctx: WFContext, part: ast.Part, file: ast.SourceFile
                    ) -> tuple[ast.PModel, ast.SourceFile] | None:
    target = ctx.target(part)
    if not isinstance(target, ast.PModel):
        found = ctx.scopes.lookup(file, part.pmodel, is_pmodel)
        target = found[0] if found else None
    if not isinstance(target, ast.PModel):
        return None
    return target, ctx.file_of(target) or file


def _navigate(ctx: WFContext, pm: ast.PModel, pm_file: ast.SourceFile, names: list[str]
              ) -> tuple[ast.Block, ast.SourceFile, str] | None:
    """Follow an element path from the p-model to (block, its file, port name)."""
    current: Container = pm
    file = pm_file
    for i, name in enumerate(names):
        if isinstance(current, ast.Part):
            inner = _pmodel_of_part(ctx, current, file)
            if inner is None:
                return None
            current, file = inner
        children = block_children(current)
        child = children[name][0] if name in children else None
        if child is None and isinstance(current, ast.Block):
            # A sensor or actuator of a joint is also reachable from the joint's link.
            for b in current.blocks:
                nested = block_children(b)
                if name in nested:
                    child = nested[name][0]
                    break
        if child is None:
            if isinstance(current, ast.Block) and i > 0:
                return current, file, name  # a port (further steps are record fields)
            return None
        current = child
    return None  # the path names a block, not a variable (S1 reports it)


def _ports(ctx: WFContext, block: ast.Block, file: ast.SourceFile
           ) -> dict[str, ast.VarDecl] | None:
    """The variables of a block: its own, its ``def``'s and its referenced definition's."""
    members: list[object] = list(block.declarations)
    for d in block.definitions:
        members.extend(d.members)
    if block.ref is not None:
        target = ctx.target(block)
        if not isinstance(target, ast.Definition):
            found = ctx.scopes.lookup(file, block.ref, is_definition(block.kind)) or \
                ctx.scopes.lookup(file, block.ref, is_definition())
            target = found[0] if found else None
        if not isinstance(target, ast.Definition):
            return None
        members.extend(target.members)
    out: dict[str, ast.VarDecl] = {}
    for m in members:
        if isinstance(m, ast.VarDecl):
            out.setdefault(m.name, m)
    return out


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
    for site in _sites(ctx):
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
                where: object = joint if _in_user_file(ctx, joint) else site.mapping.pmodel_span
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
    for site in _sites(ctx):
        pm, pm_file = site.pmodel, site.pmodel_file
        if pm is None or pm_file is None:
            continue
        for top in pm.parts:
            for path, inner, joint in _part_joints(ctx, top, pm_file, (), set(), set()):
                key = (id(top), f"{path}/{joint.name}")
                if key in seen:
                    continue
                seen.add(key)
                where: object = top if _in_user_file(ctx, top) else site.mapping.pmodel_span
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
    target = _pmodel_of_part(ctx, part, file)
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
    for site in _sites(ctx):
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
    for site in _sites(ctx):
        platform = site.platform
        if platform is None:
            continue
        pname = platform.platform.name
        for member in _members(site.mapping):
            kind = _kind(member)
            table = platform.of_kind(kind)
            if member.name in table:
                continue
            hint = _unknown_service_hint(platform, member.name, table, kind)
            ctx.error("PMap4", member,
                      f"robotic platform {pname} of d-model {platform.module.name} has no "
                      f"{kind} '{member.name}' for the mapping of {_label(member)}", hint)


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
    for site in _sites(ctx):
        for member in site.mapping.events:
            service = _service(site, member)
            if service is None or not isinstance(service.decl, ast.EventDecl):
                continue  # PMap4
            typed = service.decl.type is not None
            if typed and member.param is None:
                ctx.error("PMap5", member,
                          f"event {member.name} is typed ({type_to_notation(service.decl.type)}) but "
                          f"the mapping of {_label(member)} declares no parameter for its value",
                          f"write '{member.direction} event {member.name} ? {member.name[0]} "
                          "{ … }' and define the parameter with equations")
            elif not typed and member.param is not None:
                ctx.error("PMap5", member.param_span or member.span,
                          f"event {member.name} is untyped but the mapping of {_label(member)} "
                          f"declares parameter '{member.param}'",
                          f"remove '? {member.param}', or give event {member.name} a type in "
                          f"{service.origin}")


@rule("PMap6", "a mapping is given by actions or by equations, at least one, not both")
def check_PMap6_actions_or_equations(ctx: WFContext) -> None:
    """A mapping is given by actions or by equations: at least one, not both. An untyped
    input event mapping is given by its predicate alone (PMap12); a typed one also needs
    equations or actions for its parameter. Predicates belong to input event mappings only."""
    for site in _sites(ctx):
        for member in _members(site.mapping):
            label = _label(member)
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


def _typed(site: _Site, member: ast.EventMapping) -> bool:
    """Whether the mapped event is typed (when the event is unknown, whether the mapping
    says so by declaring a parameter)."""
    service = _service(site, member)
    if service is not None and isinstance(service.decl, ast.EventDecl):
        return service.decl.type is not None
    return member.param is not None


# ---------------------------------------------------------------------------------------------
# PMap7-PMap10: what each kind of mapping reads and writes


def _fix(member: MemberMapping, ref: _Ref, writing: bool) -> str:
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


def _check_access(ctx: WFContext, site: _Site, member: MemberMapping) -> None:
    access = _access_of(member)
    names = _Names(ctx, site, member)
    label = _label(member)

    def report(ref: _Ref, verb: str, writing: bool) -> None:
        ctx.error(access.rule, ref.span,
                  f"the mapping of {label} {verb} {ref.what} ({ref.text}); {access.summary}",
                  _fix(member, ref, writing))

    both = access.reads | access.writes
    for eq in member.equations:
        for ref in names.refs(eq.expr):
            if ref.category not in both:
                report(ref, "mentions", False)
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


def _check_kind(ctx: WFContext, kind: str) -> None:
    for site in _sites(ctx):
        for member in _members(site.mapping):
            direction = member.direction if isinstance(member, ast.EventMapping) else None
            if (direction or _kind(member)) == kind:
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
    for site in _sites(ctx):
        platform = site.platform
        ops: dict[str, str] = {}
        if platform is not None:
            ops.update({n: s.origin for n, s in platform.operations.items()})
            ops.update({n: s.origin for n, s in platform.others.items()
                        if s.kind == "operation"})
        for member in _members(site.mapping):
            for action in member.actions:
                for statement in action.statements:
                    for e in ast.expressions_in(statement):
                        for node in e.walk():
                            if not isinstance(node, ex.Call) or not isinstance(node.func, ex.Name):
                                continue
                            origin = _called_operation(ctx, site, ops, node.func.parts)
                            if origin is None:
                                continue
                            name = node.func.parts[-1]
                            ctx.error("PMap11", node,
                                      f"an action of the mapping of {_label(member)} calls "
                                      f"d-model operation {name} (of {origin})",
                                      "set the actuator inputs that realise it instead: a "
                                      "mapping cannot call the software's operations")


def _called_operation(ctx: WFContext, site: _Site, ops: dict[str, str],
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
    for site in _sites(ctx):
        for member in site.mapping.events:
            if member.direction != "input":
                continue
            preds = member.predicates
            label = _label(member)
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
            names = _Names(ctx, site, member)
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
