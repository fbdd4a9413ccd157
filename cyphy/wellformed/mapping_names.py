"""What the names inside a member mapping denote (a sensor's output, an actuator's input, a
local, a parameter, the d-model's variable…), and what each kind of mapping may read and
write (PMap7-PMap10): the classification the access conditions judge."""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.lang.resolve import block_children, path_roots, steps_of
from cyphy.lang.scopes import is_definition, is_pmodel, is_value
from cyphy.records import record
from cyphy.wellformed.platform_services import Container, MemberMapping, Site, kind_of, service_of
from cyphy.wellformed.registry import WFContext

LOCAL, CONST, PARAM, DVAR, TIME, OPERATION = "local", "const", "param", "dvar", "time", "op"
SENSOR_OUT, SENSOR_IN, ACT_IN, ACT_OUT, OTHER, UNKNOWN = (
    "sensor-out", "sensor-in", "actuator-in", "actuator-out", "other", "unknown")


@record(slots=False)
class Ref:
    """One name or element path used in a mapping, with what it denotes."""

    category: str
    text: str  # as written: ``Base::J::M.das``
    what: str  # ``input das of actuator M``
    span: Span
    block: ast.Block | None = None
    ports: tuple[ast.VarDecl, ...] = ()  # all variables of ``block``, for hints


@record(slots=False)
class Access:
    """What one kind of mapping may read and write (PMap7-PMap10)."""

    rule: str
    reads: frozenset[str]
    writes: frozenset[str]
    summary: str


_ALWAYS = {CONST, TIME, OPERATION, UNKNOWN}  # OPERATION: PMap11's business; UNKNOWN: S1's
ACCESS = {
    "input": Access("PMap7", frozenset({SENSOR_OUT, LOCAL, PARAM} | _ALWAYS),
                     frozenset({LOCAL, PARAM}),
                     "an input event mapping reads sensor outputs, its locals and constants, "
                     "and writes its locals and (if typed) its parameter"),
    "output": Access("PMap8", frozenset({PARAM, LOCAL} | _ALWAYS), frozenset({ACT_IN, LOCAL}),
                      "an output event mapping reads its parameter, locals and constants, and "
                      "writes actuator inputs and its locals"),
    "operation": Access("PMap9", frozenset({PARAM, LOCAL} | _ALWAYS),
                         frozenset({ACT_IN, LOCAL}),
                         "an operation mapping reads the operation's parameters, its locals "
                         "and constants, and writes actuator inputs and its locals"),
    "variable": Access("PMap10", frozenset({DVAR, LOCAL} | _ALWAYS), frozenset({ACT_IN, LOCAL}),
                        "a variable mapping reads the variable, its locals and constants, and "
                        "writes actuator inputs and its locals"),
}
PREDICATE_READS = frozenset({SENSOR_OUT, LOCAL} | _ALWAYS)


def access_of(member: MemberMapping) -> Access:
    if isinstance(member, ast.EventMapping):
        return ACCESS[member.direction]
    return ACCESS[kind_of(member)]


class Names:
    """Classifies the names and element paths used inside one member mapping."""

    def __init__(self, ctx: WFContext, site: Site, member: MemberMapping) -> None:
        self.ctx, self.site, self.member = ctx, site, member
        self.scope: dict[str, str] = {}
        for d in site.mapping.declarations:
            self.scope[d.name] = CONST if d.kind is ast.DeclKind.CONST else LOCAL
        service = service_of(site, member)
        if isinstance(member, ast.OperationMapping) and service is not None:
            for p in service.decl.params:  # type: ignore[union-attr]
                self.scope[p.name] = PARAM
        elif isinstance(member, ast.EventMapping) and member.param:
            self.scope[member.param] = PARAM
        elif isinstance(member, ast.VariableMapping):
            self.scope[member.name] = DVAR
        for d in member.declarations:
            self.scope[d.name] = CONST if d.kind is ast.DeclKind.CONST else LOCAL

    def refs(self, e: ex.Expr) -> Iterator[Ref]:
        """Every name and element path ``e`` uses (index arguments included)."""
        for root in path_roots(e):
            yield self.classify(root)

    def classify(self, e: ex.Expr) -> Ref:
        steps = steps_of(e)
        text = to_notation(e)
        if not steps:
            return Ref(UNKNOWN, text, text, e.span)
        first = steps[0][0]
        if first in self.scope:
            cat = self.scope[first]
            word = {LOCAL: "local", CONST: "constant", PARAM: "parameter",
                    DVAR: "d-model variable"}[cat]
            return Ref(cat, text, f"{word} {first}", e.span)
        if first == "t" and len(steps) == 1:
            return Ref(TIME, text, "time t", e.span)
        names = tuple(s[0] for s in steps)
        found = self.ctx.scopes.lookup(self.site.file, names, is_value) or (
            self.ctx.scopes.lookup(self.site.file, (first,), is_value))
        if found:
            return Ref(CONST, text, f"constant {first}", e.span)
        platform = self.site.platform
        if len(steps) == 1 and platform is not None and (
                first in platform.operations or first in platform.others):
            return Ref(OPERATION, text, f"operation {first}", e.span)
        return self._element(steps, text, e.span)

    def _element(self, steps: list[tuple[str, Span, bool]], text: str, span: Span) -> Ref:
        pm, pm_file = self.site.pmodel, self.site.pmodel_file
        if pm is None or pm_file is None:
            return Ref(UNKNOWN, text, text, span)
        names = [s[0] for s in steps]
        if names[0] == pm.name and len(names) > 1:
            names = names[1:]
        found = _navigate(self.ctx, pm, pm_file, names)
        if found is None:
            return Ref(UNKNOWN, text, text, span)
        block, block_file, port = found
        ports = _ports(self.ctx, block, block_file)
        decl = ports.get(port) if ports is not None else None
        if decl is None:
            return Ref(UNKNOWN, text, text, span)
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
        return Ref(cat, text, what, span, block, all_ports)


def pmodel_of_part(ctx: WFContext, part: ast.Part, file: ast.SourceFile
                    ) -> tuple[ast.PModel, ast.SourceFile] | None:
    target = ctx.target(part)
    if not isinstance(target, ast.PModel):
        found = ctx.scopes.lookup(file, part.pmodel, is_pmodel)
        target = found[0] if found else None
    if not isinstance(target, ast.PModel):
        return None
    return target, ctx.file_of(target) or file


def walk_path(ctx: WFContext, pm: ast.PModel, pm_file: ast.SourceFile, names: list[str]
              ) -> Iterator[tuple[ast.Block | ast.Part, ast.SourceFile]]:
    """The elements an element path names one after another from the p-model (with the
    file of each), entering a part's p-model; it stops at the first name that is no element
    (a port, or a mistake)."""
    current: Container = pm
    file = pm_file
    for name in names:
        if isinstance(current, ast.Part):
            inner = pmodel_of_part(ctx, current, file)
            if inner is None:
                return
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
            return
        yield child, file
        current = child


def _navigate(ctx: WFContext, pm: ast.PModel, pm_file: ast.SourceFile, names: list[str]
              ) -> tuple[ast.Block, ast.SourceFile, str] | None:
    """Follow an element path from the p-model to (block, its file, port name)."""
    walked = list(walk_path(ctx, pm, pm_file, names))
    if not walked or len(walked) == len(names):
        return None  # nothing, or the path names a block, not a variable (S1 reports it)
    block, file = walked[-1]
    if not isinstance(block, ast.Block):
        return None
    return block, file, names[len(walked)]  # a port (further steps are record fields)


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
