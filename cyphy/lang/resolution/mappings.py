"""Name resolution inside a platform mapping: the d-model module and the p-model of its
header, operation parameters and event values, mapping variables and element paths."""

from __future__ import annotations

from typing import Callable, Iterator

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.lang.resolution.checker import CheckerBase
from cyphy.lang.resolution.names import (
    BUILTIN_NAMES, Scope, block_children, describe, name_hint, path_roots, steps_of,
)
from cyphy.lang.scopes import is_interface, is_module, is_pmodel, is_value
from cyphy.lang.typing import ANY, Lookup, TypeChecker, Ty, type_of_declared


class MappingChecker:
    """Names inside a platform mapping: the d-model module and the p-model of the header,
    d-model operation parameters and event values, mapping variables and element paths."""

    def __init__(self, checker: CheckerBase, mapping: ast.PlatformMapping) -> None:
        self.c = checker
        self.m = mapping
        self.pmodel: ast.PModel | None = None
        self.platform: ast.RoboticPlatform | None = None

    def run(self) -> None:
        c, m = self.c, self.m
        module = c.resolve(m, m.dmodel, is_module, "d-model module", m.dmodel_span)
        pm = c.scopes.lookup(c.file, m.pmodel, is_pmodel)
        if pm:
            self.pmodel = pm[0]  # type: ignore[assignment]
            c.resolution.targets[id(m.pmodel)] = pm[0]
        else:
            c.resolve(("pmodel", m), m.pmodel, is_pmodel, "p-model", m.pmodel_span)
        if isinstance(module, ast.Module):
            self.platform = module.platform
        c._unique(m.declarations, "variable", f"mapping {m.name}")
        c._unique(m.operations, "operation mapping", f"mapping {m.name}")
        c._unique(m.events, "event mapping", f"mapping {m.name}")
        c._unique(m.variables, "variable mapping", f"mapping {m.name}")
        top = Scope({d.name: d for d in m.declarations})
        for d in m.declarations:
            c._type(d.type)
            c._expr(d.value, top)
            c.declared(d, top)
        for member in m.members:
            if isinstance(member, ast.OperationMapping):
                params = self._operation_params(member.name)
                self._members(member, top.child(params if params is not None else {}),
                              known=params is not None)
            elif isinstance(member, ast.EventMapping):
                names = {member.param: member} if member.param else {}
                self._members(member, top.child(names), known=True)
            elif isinstance(member, ast.VariableMapping):
                self._members(member, top.child({member.name: member}), known=True)

    def _interfaces(self, relation: str) -> Iterator[ast.Interface]:
        if self.platform is None:
            return
        module_file = self.c.resolution.file_of.get(id(self.m))
        for use in self.platform.interface_uses:
            if use.relation != relation:
                continue
            found = self.c.scopes.lookup(module_file or self.c.file, use.interface, is_interface)
            if not found:
                found = [d for _, _, d in self.c.ws.all_declarations()
                         if isinstance(d, ast.Interface) and d.name == use.interface[-1]]
            for i in found:
                if isinstance(i, ast.Interface):
                    yield i

    def _platform_operations(self) -> set[str]:
        if self.platform is None:
            return set()
        names = {o.name for o in self.platform.operations}
        for i in self._interfaces("provides"):
            names.update(o.name for o in i.operations)
        return names

    def _operation_params(self, name: str) -> dict[str, object] | None:
        if self.platform is None:
            return None
        sigs = list(self.platform.operations)
        for i in self._interfaces("provides"):
            sigs.extend(i.operations)
        for sig in sigs:
            if sig.name == name:
                return {p.name: p for p in sig.params}
        return None  # PMap4 reports a mapping of an unknown operation

    def _members(self, member: object, scope: Scope, known: bool) -> None:
        decls = [d for d in getattr(member, "members") if isinstance(d, ast.VarDecl)]
        self.c._unique(decls, "variable", f"mapping of {getattr(member, 'name')}")
        scope = scope.child({d.name: d for d in decls})
        for d in decls:
            self.c._type(d.type)
            self.c._expr(d.value, scope)
            self.c.declared(d, scope)
        for m in getattr(member, "members"):
            if isinstance(m, (ast.Equation, ast.Predicate)):
                self._expr(m.expr, scope, known)
                kind = "a predicate" if isinstance(m, ast.Predicate) else "an equation"
                self._types(scope).expect_predicate(m.expr, f"{kind} of the mapping of "
                                                    f"{getattr(member, 'name')}")
            elif isinstance(m, ast.Action):
                for s in m.statements:
                    if isinstance(s, ast.Assign):
                        self._expr(s.target, scope, known)
                        self._expr(s.value, scope, known)
                        self._types(scope).expect_assignable(
                            s.target, s.value, f"'{to_notation(s.target)}'")
                    elif isinstance(s, ast.CallStatement):
                        call = s.call
                        if isinstance(call, ex.Call) and isinstance(call.func, ex.Name) and \
                                call.func.parts[-1] in self._platform_operations():
                            # calling a d-model operation is PMap11's business, not S1's
                            for arg in call.args:
                                self._expr(arg, scope, known)
                        else:
                            self._expr(call, scope, known)

    def _expr(self, e: ex.Expr, scope: Scope, known: bool) -> None:
        for root in path_roots(e):
            steps = steps_of(root)
            if steps is None:
                continue
            first = steps[0][0]
            local = scope.find(first)
            if local is not None:
                self.c.resolution.uses.append((steps[0][1], (first,), local))
                continue
            if first in BUILTIN_NAMES:
                continue
            found = self.c.scopes.lookup(self.c.file, tuple(s[0] for s in steps), is_value)
            if found:
                self.c.resolution.uses.append((steps[-1][1], tuple(s[0] for s in steps),
                                               found[0]))
                continue
            if len(steps) == 1:
                if self.c.scopes.lookup(self.c.file, (first,), is_value) or not known:
                    continue  # with an unknown operation (PMap4) its parameters are unknown
                hint = name_hint(first, scope.all_names()) or (
                    "declare it with 'var', or use a parameter of the d-model operation")
                self.c.error(codes.S1, f"unknown name '{first}' in mapping", steps[0][1], hint)
                continue
            if self.pmodel is not None:
                self._element_path(steps)

    def _types(self, scope: Scope) -> TypeChecker:
        """S3's inference with the mapping's names: an event's parameter has the event's
        type, a mapped variable the platform variable's, and a path to a sensor or actuator
        variable (``Bench::Range.range``) the type its definition declares."""
        def lookup(name: ex.Name) -> object | None:
            if len(name.parts) == 1:
                local = scope.find(name.parts[0])
                if isinstance(local, (ast.EventMapping, ast.VariableMapping)):
                    decl = self._platform_decl(local)
                    if isinstance(decl, ast.EventDecl) and decl.type is not None:
                        return ast.Param(decl.name, decl.type, span=decl.span)
                    return decl
                if local is not None:
                    return local
            found = self.c.scopes.lookup(self.c.file, name.parts, is_value)
            return found[0] if found else None

        return _PathTypes(lookup, self.c.report, self._port_decl)

    def _platform_decl(self, member: ast.EventMapping | ast.VariableMapping
                       ) -> ast.EventDecl | ast.VarDecl | None:
        """The platform's declaration of the event or variable a member maps."""
        if self.platform is None:
            return None
        want = ast.EventDecl if isinstance(member, ast.EventMapping) else ast.VarDecl
        decls = list(self.platform.members)
        for relation in ("uses", "provides"):
            for i in self._interfaces(relation):
                decls.extend(i.members)
        return next((d for d in decls if isinstance(d, want) and d.name == member.name), None)

    def _port_decl(self, e: ex.Expr) -> ast.VarDecl | None:
        """The variable of a sensor or actuator that an element path names, or None."""
        steps = steps_of(e)
        if self.pmodel is None or not steps or len(steps) < 2:
            return None
        if steps[0][0] == self.pmodel.name:
            steps = steps[1:]
        current: ast.PModel | ast.Block | ast.Part | None = self.pmodel
        for name, _, _ in steps[:-1]:
            current = child_of(current, name, self.c) if current is not None else None
        if not isinstance(current, ast.Block):
            return None
        ports = self.c.ports_of(current)
        return ports.get(steps[-1][0]) if ports else None

    def _element_path(self, steps: list[tuple[str, Span, bool]]) -> None:
        pm = self.pmodel
        assert pm is not None
        if steps[0][0] == pm.name:
            steps = steps[1:]
        current: ast.PModel | ast.Block | ast.Part = pm
        for i, (name, span, _) in enumerate(steps):
            found = child_of(current, name, self.c)
            if found is None:
                if i == len(steps) - 1 and isinstance(current, ast.Block) and i > 0:
                    self.c._port(current, name, span)
                    return
                where = describe(current)
                names = child_names(current, self.c)
                self.c.error(codes.S1, f"{where} has no element '{name}'", span,
                             did_you_mean(name, names) or
                             f"its elements are: {', '.join(sorted(names)) or '(none)'}")
                return
            current = found
        if isinstance(current, ast.Block):
            self.c.error(codes.S1, f"the path names {current.kind.value} {current.name}, not "
                         "one of its variables", steps[-1][1],
                         f"write {steps[-1][0]}.<variable>")


def child_of(node: ast.PModel | ast.Block | ast.Part, name: str, c: CheckerBase
           ) -> ast.PModel | ast.Block | ast.Part | None:
    if isinstance(node, ast.Part):
        target = c.resolution.get(node)
        if not isinstance(target, ast.PModel):
            target_list = c.scopes.lookup(c.file, node.pmodel, is_pmodel)
            target = target_list[0] if target_list else None
        if not isinstance(target, ast.PModel):
            return None
        node = target
    children = block_children(node)
    if name in children:
        return children[name][0]
    # A sensor or actuator of a joint is also reachable from the joint's link
    # (`BaseLink::ShoulderEncoder` and `BaseLink::ShoulderJoint::ShoulderEncoder`).
    if isinstance(node, ast.Block):
        for b in node.blocks:
            nested = block_children(b)
            if name in nested:
                return nested[name][0]
    return None


def child_names(node: ast.PModel | ast.Block | ast.Part, c: CheckerBase) -> set[str]:
    if isinstance(node, ast.Part):
        target = c.resolution.get(node)
        if not isinstance(target, ast.PModel):
            return set()
        node = target
    return set(block_children(node))


class _PathTypes(TypeChecker):
    """S3's inference where a ``.`` names a port of the p-model (``Motor.das``): its type is
    the one its definition declares, not unknown."""

    def __init__(self, lookup: Lookup, report: Report,
                 port: Callable[[ex.Expr], ast.VarDecl | None]) -> None:
        super().__init__(lookup, report)
        self.port = port

    def _infer_Member(self, e: ex.Member) -> Ty:
        for node in e.walk():
            if isinstance(node, ex.Index):
                for a in node.args:
                    self.infer(a)
        decl = self.port(e)
        return type_of_declared(decl.type) if decl is not None else ANY
