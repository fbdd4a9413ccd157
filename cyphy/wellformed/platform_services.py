"""What a platform mapping maps onto: the services of the d-model's robotic platform
(operations of the interfaces it provides, events of those it uses, its variables:
``notation.md`` B), the p-model its header names, and which service each member mapping is
for. Read by the PMap conditions, by the machines' checks and by the CyPhyCircus and
consistency translations."""

from __future__ import annotations

from dataclasses import field
from typing import Iterator, Union

from cyphy.lang import ast
from cyphy.lang.notation import type_to_notation
from cyphy.lang.scopes import is_interface, is_node, is_pmodel
from cyphy.records import record
from cyphy.wellformed.registry import WFContext

MemberMapping = Union[ast.OperationMapping, ast.EventMapping, ast.VariableMapping]
Container = Union[ast.PModel, ast.Block, ast.Part]


@record(slots=False)
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


@record(frozen=False, slots=False)
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


@record(frozen=False, slots=False)
class Site:
    """One platform mapping with what its header resolved to."""

    file: ast.SourceFile
    mapping: ast.PlatformMapping
    platform: Platform | None
    pmodel: ast.PModel | None
    pmodel_file: ast.SourceFile | None


def sites(ctx: WFContext) -> Iterator[Site]:
    for file, mapping in ctx.mappings():
        found = ctx.scopes.lookup(file, mapping.pmodel, is_pmodel)
        pm = found[0] if found else ctx.target(mapping.pmodel)
        if not isinstance(pm, ast.PModel):
            pm = None
        yield Site(file, mapping, platform_of(ctx, mapping),
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


def members_of(mapping: ast.PlatformMapping) -> Iterator[MemberMapping]:
    for m in mapping.members:
        if isinstance(m, (ast.OperationMapping, ast.EventMapping, ast.VariableMapping)):
            yield m


def kind_of(member: MemberMapping) -> str:
    if isinstance(member, ast.OperationMapping):
        return "operation"
    if isinstance(member, ast.VariableMapping):
        return "variable"
    return "event"


def label_of(member: MemberMapping) -> str:
    """``operation move``, ``input event obstacle``, ``variable level``."""
    if isinstance(member, ast.EventMapping):
        return f"{member.direction} event {member.name}"
    return f"{kind_of(member)} {member.name}"


def service_of(site: Site, member: MemberMapping) -> Service | None:
    if site.platform is None:
        return None
    return site.platform.of_kind(kind_of(member)).get(member.name)


def mapped_services(ctx: WFContext) -> Iterator[tuple[Site, MemberMapping, ast.OperationSig |
                                                       ast.EventDecl | ast.VarDecl | None]]:
    """Every member of every platform mapping with the declaration of the service it maps
    (None when it maps none: PMap4): what the semantic checks of
    :mod:`cyphy.semantics.consistency` need to type the parameters."""
    for site in sites(ctx):
        for member in members_of(site.mapping):
            service = service_of(site, member)
            yield site, member, service.decl if service is not None else None


def in_user_file(ctx: WFContext, node: object) -> bool:
    span = getattr(node, "span", None)
    return span is not None and span.file in ctx.workspace.targets
