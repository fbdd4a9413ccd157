"""Name resolution and the scope conditions S1, S2, S4 and S5 of ``wellformedness.md``.

Walks every file the user asked about and reports names that do not resolve (S1, with "did you
mean" suggestions), names declared twice in one scope (S2), equations that reach outside their
block (S4) and imports that name no package or element, or parts that contain their own
p-model (S5). What each reference resolved to is recorded in a :class:`Resolution`, which later
stages read instead of resolving again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Iterator, Union

from cyphy import codes, progress
from cyphy import expr as ex
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.scopes import (
    Scopes, is_constant, is_definition, is_interface, is_machine, is_module, is_node, is_pmodel,
    is_template, is_type, is_value,
)
from cyphy.lang.typing import TypeChecker
from cyphy.lang.workspace import Declaration, Workspace

BUILTIN_NAMES = {"t"}  # time, used undeclared in equations and mappings
Container = Union[ast.PModel, ast.Block, ast.Part]


@dataclass
class Resolution:
    """What references resolved to, keyed by ``id`` of the referring node."""

    targets: dict[int, Declaration] = field(default_factory=dict)
    file_of: dict[int, ast.SourceFile] = field(default_factory=dict)
    uses: list[tuple[Span, ast.QName, object]] = field(default_factory=list)
    """Every resolved use of a name, for editors (go to definition, references, hover): the
    span of the referring node, the name, and what it denotes (a top-level declaration, or a
    local one: a variable, a block, an index)."""

    def get(self, node: object) -> Declaration | None:
        return self.targets.get(id(node))


@dataclass
class Scope:
    """Names declared by enclosing blocks: name → what declares it (a VarDecl, IndexDecl…)."""

    names: dict[str, object]
    parent: Scope | None = None

    def find(self, name: str) -> object | None:
        s: Scope | None = self
        while s is not None:
            if name in s.names:
                return s.names[name]
            s = s.parent
        return None

    def all_names(self) -> set[str]:
        out: set[str] = set()
        s: Scope | None = self
        while s is not None:
            out.update(s.names)
            s = s.parent
        return out

    def child(self, names: dict[str, object]) -> Scope:
        return Scope(names, self)


def check_scopes(ws: Workspace, report: Report) -> Resolution:
    """Run S1, S2, S4 and S5 on the user's files; return what references resolved to."""
    checker = _Checker(ws, report)
    checker.run()
    return checker.resolution


def steps_of(e: ex.Expr) -> list[tuple[str, Span, bool]] | None:
    """An element path as (name, span, indexed) steps: ``Core::Proximity[1].voltage`` →
    Core, Proximity (indexed), voltage. None when ``e`` is not a path."""
    if isinstance(e, ex.Name):
        return [(p, e.span, False) for p in e.parts]
    if isinstance(e, ex.Member):
        base = steps_of(e.base)
        return None if base is None else base + [(e.name, e.span, False)]
    if isinstance(e, ex.Index):
        base = steps_of(e.base)
        if not base:
            return None
        name, span, _ = base[-1]
        return base[:-1] + [(name, span, True)]
    return None


def block_children(node: Container) -> dict[str, list[ast.Block | ast.Part]]:
    out: dict[str, list[ast.Block | ast.Part]] = {}
    for m in node.members:
        if isinstance(m, (ast.Block, ast.Part)):
            out.setdefault(m.name, []).append(m)
    return out


class _Checker:
    def __init__(self, ws: Workspace, report: Report) -> None:
        self.ws = ws
        self.report = report
        self.scopes = Scopes(ws)
        self.resolution = Resolution()
        self.file: ast.SourceFile = ast.SourceFile("<none>", ())
        self._tables: dict[int, Any] = {}  # per-p-model name tables, built once

    # ------------------------------------------------------------------ driver
    def run(self) -> None:
        for file in self.ws.user_files():
            self.file = file
            self._imports(file)
            for item in file.declarations():
                self._item(item)
        self._package_duplicates()
        self._part_cycles()

    def error(self, code: codes.Code, message: str, span: Span, hint: str = "") -> None:
        self.report.report(code, message, span, hint)

    # ------------------------------------------------------------------ S3 typing
    def _types(self, scope: Scope) -> TypeChecker:
        def lookup(name: ex.Name) -> object | None:
            if len(name.parts) == 1:
                local = scope.find(name.parts[0])
                if local is not None:
                    return local
            found = self.scopes.lookup(self.file, name.parts, is_value)
            return found[0] if found else None

        return TypeChecker(lookup, self.report)

    def predicate(self, e: ex.Expr | None, scope: Scope, what: str) -> None:
        if e is not None:
            self._types(scope).expect_predicate(e, what)

    def number(self, e: ex.Expr | None, scope: Scope, what: str) -> None:
        if e is not None:
            self._types(scope).expect_number(e, what)

    def declared(self, d: ast.VarDecl, scope: Scope) -> None:
        if d.value is not None:
            self._types(scope).expect_declared(d.value, d.type, d.name)

    def resolve(self, node: object, name: ast.QName, accept, what: str, span: Span,
                candidates_accept=None) -> Declaration | None:
        found = self.scopes.lookup(self.file, name, accept)
        if found:
            self.resolution.targets[id(node)] = found[0]
            self.resolution.file_of[id(node)] = self.file
            self.resolution.uses.append((span, name, found[0]))
            return found[0]
        text = "::".join(name)
        if len(name) > 1 and not self.scopes.package_exists(name[:-1]):
            pkgs = ["::".join(p) for p in self.ws.packages if p]
            hint = did_you_mean("::".join(name[:-1]), pkgs) or "import or declare the package"
            self.error(codes.S1, f"unknown package '{'::'.join(name[:-1])}' in '{text}'", span,
                       hint)
            return None
        visible = self.scopes.visible_names(self.file, candidates_accept or accept)
        hint = did_you_mean(name[-1], visible) or self._importable(
            name[-1], candidates_accept or accept) or (
            f"declare {what} '{text}' or import its package")
        self.error(codes.S1, f"unknown {what} '{text}'", span, hint)
        return None

    def _importable(self, name: str, accept) -> str:
        """A hint naming a package that declares ``name`` (or a close name) but is not
        imported: ``import physmod::joints::Revolute``."""
        elsewhere: dict[str, ast.QName] = {}
        for package, member, decl in self.ws.all_declarations():
            if package.name and accept(decl):
                elsewhere.setdefault(member, package.name)
        if name in elsewhere:  # spelt right: only the import is missing
            package = "::".join(elsewhere[name])
            return (f"'{name}' is declared in {package}, which this file does not import: "
                    f"add `import {package}::*` (or `import {package}::{name}`)")
        close = did_you_mean(name, elsewhere)
        if not close:
            return ""
        best = close.split("'")[1]
        return f"{close} (import {'::'.join(elsewhere[best] + (best,))})"

    # ------------------------------------------------------------------ S5 imports
    def _imports(self, file: ast.SourceFile) -> None:
        for imp in file.imports:
            if imp.wildcard:
                if imp.path not in self.ws.packages:
                    pkgs = ["::".join(p) for p in self.ws.packages if p]
                    self.error(codes.S5, f"import of unknown package '{'::'.join(imp.path)}'",
                               imp.span, did_you_mean("::".join(imp.path), pkgs)
                               or "check the package name, or add its folder with --path")
                continue
            pkg = self.ws.packages.get(imp.path[:-1])
            if pkg is None:
                pkgs = ["::".join(p) for p in self.ws.packages if p]
                self.error(codes.S5, f"import from unknown package '{'::'.join(imp.path[:-1])}'",
                           imp.span, did_you_mean("::".join(imp.path[:-1]), pkgs)
                           or "check the package name, or add its folder with --path")
            elif imp.path[-1] not in pkg.members:
                self.error(codes.S5, f"package '{'::'.join(imp.path[:-1])}' declares no "
                           f"'{imp.path[-1]}'", imp.span,
                           did_you_mean(imp.path[-1], pkg.members) or
                           f"import '{'::'.join(imp.path[:-1])}::*' to see what it declares")
            else:  # every declaration of that name is imported (one per namespace)
                self.resolution.uses.append((imp.span, imp.path, pkg.members[imp.path[-1]][0]))

    # ------------------------------------------------------------------ S2 package level
    @staticmethod
    def _namespace(decl: Declaration) -> str:
        if isinstance(decl, ast.Definition):
            return "definition"
        if isinstance(decl, (ast.DataType, ast.TypeDecl, ast.Enumeration)):
            return "type"
        if isinstance(decl, (ast.Controller, ast.StateMachine)):
            return "behaviour"
        return type(decl).__name__

    def _package_duplicates(self) -> None:
        user_paths = set(self.ws.targets)
        for package in self.ws.packages.values():
            if package.builtin:
                continue
            for name, decls in package.members.items():
                by_ns: dict[str, list[Declaration]] = {}
                for d in decls:
                    by_ns.setdefault(self._namespace(d), []).append(d)
                for group in by_ns.values():
                    for d in group[1:]:
                        if d.span.file in user_paths:
                            first = group[0].span
                            pkg = "::".join(package.name) or "the global package"
                            self.error(codes.S2, f"'{name}' is declared twice in {pkg} "
                                       f"(first at {first})", d.span,
                                       "rename one of them or remove the duplicate")

    # ------------------------------------------------------------------ top-level items
    def _item(self, item: Declaration) -> None:
        globals_scope = Scope({})
        if isinstance(item, ast.VarDecl):
            self._type(item.type)
            if item.value is not None:
                self._expr(item.value, globals_scope)
                self.declared(item, globals_scope)
        elif isinstance(item, ast.FunctionDecl):
            self._function(item)
        elif isinstance(item, ast.DataType):
            self._unique(item.fields, "field", f"datatype {item.name}")
            for f in item.fields:
                self._type(f.type)
        elif isinstance(item, ast.AnnotationTemplate):
            self._template(item)
        elif isinstance(item, ast.Definition):
            self._definition_members(item.members, Scope({}), f"{item.kind.value} {item.name}",
                                     outer=None)
        elif isinstance(item, ast.PModel):
            self._pmodel(item)
        elif isinstance(item, ast.PlatformMapping):
            _MappingChecker(self, item).run()
        elif isinstance(item, ast.Interface):
            self._interface(item)
        elif isinstance(item, ast.RoboticPlatform):
            self._platform(item)
        elif isinstance(item, ast.Module):
            self._module(item)
        elif isinstance(item, ast.Solution):
            self._type(item.type)
        elif isinstance(item, ast.Controller):
            self._controller(item)
        elif isinstance(item, ast.StateMachine):
            self._machine(item)

    def _function(self, f: ast.FunctionDecl) -> None:
        self._unique(f.params, "parameter", f"function {f.name}")
        for p in f.params:
            self._type(p.type)
        if f.return_type is not None:
            self._type(f.return_type)
        scope = Scope({p.name: p for p in f.params})
        for e in f.preconditions:
            self._expr(e, scope)
            self.predicate(e, scope, "a precondition")
        post = scope.child({"result": ast.Param("result", f.return_type, span=f.span)}
                           if f.return_type is not None else {"result": f})
        for e in f.postconditions:
            self._expr(e, post)
            self.predicate(e, post, "a postcondition")

    def _template(self, t: ast.AnnotationTemplate) -> None:
        if t.extends is not None:
            self.resolve(t, t.extends, is_template, "annotation template", t.span)
        self._unique(t.params, "parameter", f"annotation template {t.name}")
        for p in t.params:
            if p.type is not None:
                self._type(p.type)
            if p.template is not None:
                self.resolve(p, p.template, is_template, "annotation template", p.span)
            if isinstance(p.default, ast.TemplateInstance):
                self._template_instance(p.default, Scope({}))
            elif p.default is not None:
                self._expr(p.default, Scope({}))

    # ------------------------------------------------------------------ types
    def _type(self, t: ast.TypeRef | None) -> None:
        if t is None:
            return
        if isinstance(t, ast.NamedType):
            self.resolve(t, t.name, is_type, "type", t.span)
        elif isinstance(t, (ast.VectorType, ast.SeqType, ast.SetType)):
            self._type(t.element)
            if isinstance(t, ast.VectorType) and t.size is not None:
                self._expr(t.size, Scope({}))
        elif isinstance(t, ast.MatrixType):
            self._type(t.element)
            self._expr(t.rows, Scope({}))
            self._expr(t.cols, Scope({}))

    # ------------------------------------------------------------------ S2 helpers
    def _unique(self, items: Iterable[object], what: str, where: str) -> None:
        seen: dict[str, Span] = {}
        for item in items:
            name = getattr(item, "name")
            span = getattr(item, "span")
            if name in seen:
                self.error(codes.S2, f"{what} '{name}' is declared twice in {where} "
                           f"(first at line {seen[name].line})", span,
                           f"rename or remove one '{name}'")
            else:
                seen[name] = span

    # ------------------------------------------------------------------ expressions
    def _expr(self, e: ex.Expr | None, scope: Scope, restricted: Scope | None = None,
              where: str = "") -> None:
        """Check the names of ``e``. With ``restricted`` (the block's own scope, for S4), a name
        found in ``scope`` but not in ``restricted`` or the package is an S4 violation."""
        if e is None:
            return
        for node in _names_in(e):
            self._name(node, scope, restricted, where)

    def _name(self, node: ex.Name, scope: Scope, restricted: Scope | None, where: str) -> None:
        name = node.parts
        if len(name) == 1:
            n = name[0]
            if n in BUILTIN_NAMES:
                return
            local = (restricted or scope).find(n)
            if local is not None:
                self.resolution.uses.append((node.span, name, local))
                return
            found = self.scopes.lookup(self.file, name, is_value)
            if found:
                self.resolution.uses.append((node.span, name, found[0]))
                return
            if restricted is not None and scope.find(n) is not None:
                self.error(codes.S4, f"the equation of {where} mentions '{n}', which is not "
                           f"declared in that block", node.span,
                           f"declare '{n}' in the block (input, output, InOut, local or const) "
                           "or relate it through a relation")
                return
            visible = scope.all_names() | self.scopes.visible_names(self.file, is_value)
            hint = _name_hint(n, visible) or f"declare '{n}' or import the package defining it"
            self.error(codes.S1, f"unknown name '{n}'", node.span, hint)
            return
        found = self.scopes.lookup(self.file, name, is_value)
        if found:
            self.resolution.uses.append((node.span, name, found[0]))
            return
        if scope.find(name[0]) is not None:
            return  # a path through a block, checked where paths are understood
        self.error(codes.S1, f"unknown name '{'::'.join(name)}'", node.span,
                   "qualified names denote package members (pkg::NAME) or element paths")

    # ------------------------------------------------------------------ p-models
    def _pmodel(self, pm: ast.PModel) -> None:
        names: dict[str, object] = {d.name: d for d in pm.declarations}
        self._unique(pm.declarations, "variable", f"p-model {pm.name}")
        self._unique([m for m in pm.members if isinstance(m, (ast.Block, ast.Part))], "block",
                     f"p-model {pm.name}")
        scope = Scope(names)
        blocks = self.all_blocks(pm)
        for d in pm.declarations:
            self._type(d.type)
            self._expr(d.value, scope)
            self.declared(d, scope)
        for i, m in enumerate(pm.members):
            progress.step(f"{pm.name}: {i + 1} of {len(pm.members)} elements")
            if isinstance(m, ast.Part):
                self._part(m, pm, scope)
            elif isinstance(m, ast.Block):
                self._block(m, pm, scope, blocks, ancestors=())
            elif isinstance(m, (ast.Equation, ast.Constraint, ast.Relation)):
                self._expr(m.expr, scope.child({n: bs[0] for n, bs in blocks.items()}))
                if not isinstance(m, ast.Relation):
                    self.predicate(m.expr, scope, f"an equation of p-model {pm.name}")
            elif isinstance(m, ast.Solution):
                self._type(m.type)
            elif isinstance(m, (ast.Pose, ast.IndexDecl)):
                self._members_exprs([m], scope)

    def _members_exprs(self, members: Iterable[object], scope: Scope) -> None:
        for m in members:
            if isinstance(m, ast.Pose):
                for f in m.fields:
                    self._expr(f.value, scope)
                    self.number(f.value, scope, f"pose field '{f.key}'")
            elif isinstance(m, ast.IndexDecl):
                for bound in (m.lower, m.upper):
                    self._expr(bound, scope)
                    self.number(bound, scope, "an index bound")

    def _part(self, part: ast.Part, pm: ast.PModel, scope: Scope) -> None:
        target = self.resolve(part, part.pmodel, is_pmodel, "p-model", part.span)
        inner = scope.child({part.index.var: part.index} if part.index else {})
        self._members_exprs(part.indices, scope)
        for m in part.members:
            if isinstance(m, ast.Pose):
                self._members_exprs([m], inner)
            elif isinstance(m, ast.Instantiation):
                self._expr(m.value, inner)
            elif isinstance(m, (ast.PartFixed, ast.PartFlexible)):
                self._part_connection(m, part, target, pm)

    def _part_connection(self, m: ast.PartFixed | ast.PartFlexible, part: ast.Part,
                         target: Declaration | None, pm: ast.PModel) -> None:
        if isinstance(target, ast.PModel):
            source = m.link if isinstance(m, ast.PartFixed) else m.joint
            kind = ast.BlockKind.LINK if isinstance(m, ast.PartFixed) else ast.BlockKind.JOINT
            found = any(b.kind is kind and b.name == source for b in self.all_blocks(
                target).get(source, []))
            if not found:
                names = [n for n, bs in self.all_blocks(target).items()
                         if any(b.kind is kind for b in bs)]
                self.error(codes.S1, f"p-model {target.name} has no {kind.value} '{source}'",
                           m.span, did_you_mean(source, names) or
                           f"name a {kind.value} of p-model {target.name}")
        self._connection_target(m.target, m.part, pm, m.span)

    def _table(self, key: Any, build: Any) -> Any:
        if key not in self._tables:
            self._tables[key] = build()
        return self._tables[key]

    def _links(self, pm: ast.PModel) -> set[str]:
        return self._table(("links", id(pm)), lambda: {
            b.name for b in pm.blocks if b.kind is ast.BlockKind.LINK})

    def all_blocks(self, pm: ast.PModel) -> dict[str, list[ast.Block]]:
        return self._table(("blocks", id(pm)), lambda: _all_blocks(pm))

    def _connection_target(self, link: str, part_name: str | None, pm: ast.PModel,
                           span: Span) -> None:
        if part_name is None:
            links = self._links(pm)
            if link not in links:
                self.error(codes.S1, f"p-model {pm.name} has no link '{link}'", span,
                           did_you_mean(link, links) or
                           "name a link of this p-model, or 'L in P' for link L of part P")
            else:
                self._link_use(pm, link, span)
            return
        parts = {p.name: p for p in pm.parts}
        part = parts.get(part_name)
        if part is None:
            self.error(codes.S1, f"p-model {pm.name} has no part '{part_name}'", span,
                       did_you_mean(part_name, parts) or "name a part of this p-model")
            return
        self.resolution.uses.append((span, (part_name,), part))
        target = self.resolution.get(part)
        if isinstance(target, ast.PModel):
            links = self._links(target)
            if link not in links:
                self.error(codes.S1, f"part {part_name} (p-model {target.name}) has no link "
                           f"'{link}'", span, did_you_mean(link, links) or
                           f"name a link of p-model {target.name}")
            else:
                self._link_use(target, link, span)

    def _link_use(self, pm: ast.PModel, link: str, span: Span) -> None:
        """Record that ``span`` names link ``link`` of ``pm`` (for editors)."""
        for b in self.all_blocks(pm).get(link, []):
            if b.kind is ast.BlockKind.LINK:
                self.resolution.uses.append((span, (link,), b))
                return

    def _block(self, block: ast.Block, pm: ast.PModel, scope: Scope,
               blocks: dict[str, list[ast.Block]], ancestors: tuple[ast.Block, ...]) -> None:
        what = f"{block.kind.value} {block.name}"
        definition: ast.Definition | None = None
        if block.ref is not None:
            found = self.resolve(block, block.ref, is_definition(), f"{block.kind.value} "
                                 "definition", block.span, candidates_accept=is_definition(
                                     block.kind))
            definition = found if isinstance(found, ast.Definition) else None
        index_names = {i.var: i for i in block.indices}
        self._members_exprs(block.indices, scope)
        def_members: list[object] = []
        if definition is not None:
            def_members.extend(definition.members)
        for d in block.definitions:
            def_members.extend(d.members)
        own_decls = [m for m in def_members if isinstance(m, ast.VarDecl)]
        own_decls += list(block.declarations)
        own = {d.name: d for d in own_decls}
        inner = scope.child({**index_names, **own})
        self._unique([m for m in block.members if isinstance(m, ast.Block)], "block", what)
        self._unique([d for d in block.declarations]
                     + [m for d in block.definitions for m in d.members
                        if isinstance(m, ast.VarDecl)], "variable", what)
        block_names = self._table(("names", id(pm)), lambda: {n: bs[0] for n, bs in
                                                               blocks.items()})
        # S4: a definition's equations see its own declarations, the index variables of
        # the enclosing blocks and package-level constants and functions, nothing else.
        visible_indices = {**_indices_of(ancestors), **index_names}
        for d in block.definitions:
            self._definition_members(d.members, Scope(visible_indices), what,
                                     outer=inner.child(block_names), pm=pm)
        for m in block.members:
            if isinstance(m, ast.Pose):
                self._members_exprs([m], scope.child(index_names).child(own))
            elif isinstance(m, ast.Block):
                self._block(m, pm, inner, blocks, ancestors + (block,))
            elif isinstance(m, ast.FixedConnection):
                self._connection_target(m.target, m.part, pm, m.span)
            elif isinstance(m, ast.FlexibleConnection):
                self._connection_target(m.target, m.part, pm, m.span)
            elif isinstance(m, ast.Relation):
                self._relation(m, inner, blocks)
            elif isinstance(m, ast.Annotation):
                self._template_instance(m.instance, inner, pm)
            elif isinstance(m, ast.Instantiation):
                self._expr(m.value, scope.child(index_names))
                if definition is not None and m.name not in {
                        d.name for d in definition.members if isinstance(d, ast.VarDecl)}:
                    consts = [d.name for d in definition.members if is_constant(d)]
                    self.error(codes.S1, f"{definition.kind.value} definition {definition.name}"
                               f" has no constant '{m.name}' to instantiate", m.span,
                               did_you_mean(m.name, consts) or
                               f"instantiate one of: {', '.join(consts) or '(no constants)'}")
            elif isinstance(m, (ast.Equation, ast.Constraint)):
                self._expr(m.expr, inner.child(block_names))
                self.predicate(m.expr, inner, f"an equation of {what}")
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)
                self._expr(m.value, inner)
                self.declared(m, inner)

    def _relation(self, rel: ast.Relation, scope: Scope, blocks: dict[str, list[ast.Block]]
                  ) -> None:
        """Relations label containment: their names are the block's own variables, or ports
        of blocks of the p-model written ``Block.port``."""
        for e in path_roots(rel.expr):
            steps = steps_of(e)
            if steps is None:
                continue
            first = steps[0][0]
            if scope.find(first) is not None or first in BUILTIN_NAMES:
                continue
            if self.scopes.lookup(self.file, (first,), is_value):
                continue
            if first in blocks:
                if len(steps) >= 2:
                    self._port(blocks[first][0], steps[1][0], steps[1][1])
                continue
            hint = _name_hint(first, scope.all_names() | set(blocks)) or \
                "name a variable of this block, or Block.port of a block of the p-model"
            self.error(codes.S1, f"unknown name '{first}' in relation", steps[0][1], hint)

    def ports_of(self, block: ast.Block) -> dict[str, ast.VarDecl] | None:
        """The variables a block declares (through its definition); None when unknown."""
        members: list[object] = list(block.declarations)
        for d in block.definitions:
            members.extend(d.members)
        if block.ref is not None:
            target = self.resolution.get(block)
            if target is None:
                target_list = self.scopes.lookup(self.file, block.ref, is_definition())
                target = target_list[0] if target_list else None
            if not isinstance(target, ast.Definition):
                return None
            members.extend(target.members)
        return {m.name: m for m in members if isinstance(m, ast.VarDecl)}

    def _port(self, block: ast.Block, port: str, span: Span) -> None:
        ports = self.ports_of(block)
        if ports is None or port in ports:
            return
        self.error(codes.S1, f"{block.kind.value} {block.name} has no variable '{port}'", span,
                   did_you_mean(port, ports) or
                   f"its variables are: {', '.join(sorted(ports)) or '(none)'}")

    def _definition_members(self, members: Iterable[object], scope: Scope, what: str,
                            outer: Scope | None, pm: ast.PModel | None = None) -> None:
        members = list(members)
        decls = [m for m in members if isinstance(m, ast.VarDecl)]
        restricted = scope.child({d.name: d for d in decls})
        # Geometry, inertia and annotation values may use the p-model's constants; only
        # equations are confined to the block (S4).
        own = outer.child(restricted.names) if outer is not None else restricted
        for d in decls:
            self._type(d.type)
            self._expr(d.value, own)
            self.declared(d, own)
        for m in members:
            if isinstance(m, (ast.Equation, ast.Constraint)):
                self._expr(m.expr, own, restricted=restricted, where=what)
                self.predicate(m.expr, own, f"an equation of {what}")
            elif isinstance(m, ast.Annotation):
                self._template_instance(m.instance, own, pm)
            elif not isinstance(m, ast.VarDecl):
                for e in ast.expressions_in(m):
                    self._expr(e, own)
                    if isinstance(m, (ast.Shape, ast.Inertial, ast.Bounce, ast.LaserRetro)):
                        self.number(e, own, f"a value of the {_MEMBER_WORD[type(m)]} of {what}")
        self._unique(decls, "variable", what)

    def _template_instance(self, inst: ast.TemplateInstance, scope: Scope,
                           pm: ast.PModel | None = None) -> None:
        self.resolve(inst, inst.template, is_template, "annotation template", inst.span)
        self._unique(inst.args, "parameter", f"annotation {'::'.join(inst.template)}")
        for arg in inst.args:
            if isinstance(arg.value, ast.TemplateInstance):
                self._template_instance(arg.value, scope, pm)
            else:
                self._annotation_value(arg.value, scope, pm)

    def _annotation_value(self, value: ex.Expr, scope: Scope, pm: ast.PModel | None) -> None:
        """Values are expressions over the block's constants, or element paths
        (``collision = Rod::my_body``)."""
        blocks = self.all_blocks(pm) if pm is not None else {}
        for node in _names_in(value):
            if pm is not None and all(p in blocks for p in node.parts):
                continue
            self._name(node, scope, None, "")

    # ------------------------------------------------------------------ d-models
    def _interface(self, i: ast.Interface) -> None:
        self._unique(list(i.events) + list(i.operations) + list(i.variables), "member",
                     f"interface {i.name}")
        for m in i.members:
            if isinstance(m, ast.EventDecl):
                self._type(m.type)
            elif isinstance(m, ast.OperationSig):
                self._unique(m.params, "parameter", f"operation {m.name}")
                for p in m.params:
                    self._type(p.type)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)

    def _platform(self, p: ast.RoboticPlatform) -> None:
        for use in p.interface_uses:
            self.resolve(use, use.interface, is_interface, "interface", use.span)
        for m in p.members:
            if isinstance(m, ast.EventDecl):
                self._type(m.type)
            elif isinstance(m, ast.OperationSig):
                for prm in m.params:
                    self._type(prm.type)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)

    def _controller(self, c: ast.Controller) -> None:
        for m in c.members:
            if isinstance(m, ast.InterfaceUse):
                self.resolve(m, m.interface, is_interface, "interface", m.span)
            elif isinstance(m, ast.MachineRef):
                self.resolve(m, m.target, is_machine, "state machine or operation", m.span)
            elif isinstance(m, ast.StateMachine):
                self._machine(m)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)

    def _machine(self, stm: ast.StateMachine) -> None:
        """The interfaces and types a machine names; its states, transitions and expressions
        are checked by the machine rules (``cyphy.wellformed.machines``)."""
        for p in stm.params:
            self._type(p.type)
        for use in stm.interface_uses:
            self.resolve(use, use.interface, is_interface, "interface", use.span)
        stack: list[object] = list(stm.members)
        while stack:
            m = stack.pop()
            if isinstance(m, ast.VarDecl):
                self._type(m.type)
            elif isinstance(m, ast.State):
                stack.extend(m.members)

    def _module(self, mod: ast.Module) -> None:
        nodes: dict[str, object] = {}
        for m in mod.members:
            if isinstance(m, ast.RoboticPlatform):
                self._platform(m)
                nodes[m.name] = m
            elif isinstance(m, ast.NodeRef):
                self.resolve(m, m.target, is_node, "controller or platform", m.span)
                nodes[m.name] = m
            elif isinstance(m, (ast.Controller, ast.StateMachine)):
                nodes[m.name] = m
            elif isinstance(m, ast.CycleDef):
                cycle = ast.Param("cycle", ast.PrimitiveType("nat"), span=m.span)
                self._expr(m.expr, Scope({"cycle": cycle}))
                self.predicate(m.expr, Scope({"cycle": cycle}), "cycleDef")
        for m in mod.members:
            if isinstance(m, ast.Connection):
                for node in (m.source, m.target):
                    if node not in nodes:
                        self.error(codes.S1, f"module {mod.name} has no node '{node}'", m.span,
                                   did_you_mean(node, nodes) or
                                   "connect the platform or a controller of this module")

    # ------------------------------------------------------------------ S5 part cycles
    def _part_cycles(self) -> None:
        """S5: a part must not (transitively) contain its own p-model. ``graphlib`` finds a
        cycle; its first edge is reported and removed until no cycle is left."""
        from graphlib import CycleError, TopologicalSorter

        edges: dict[tuple[int, int], ast.Part] = {}
        names: dict[int, str] = {}
        for file in self.ws.files.values():
            for item in file.items:
                if isinstance(item, ast.PModel):
                    names[id(item)] = item.name
                    for part in item.parts:
                        target = self.resolution.get(part)
                        if isinstance(target, ast.PModel):
                            edges.setdefault((id(item), id(target)), part)
        while edges:
            graph: dict[int, set[int]] = {}
            for source, target in edges:
                graph.setdefault(source, set()).add(target)
            try:
                TopologicalSorter(graph).prepare()
                return
            except CycleError as err:
                cycle = list(reversed(err.args[1]))  # graphlib lists it against the edges
                part = edges.pop((cycle[0], cycle[1]))
                chain = " → ".join(names[n] for n in cycle)
                self.error(codes.S5, f"part {part.name} makes a p-model contain itself "
                           f"({chain})", part.span,
                           "a part must not (transitively) contain its own p-model")


class _MappingChecker:
    """Names inside a platform mapping: the d-model module and the p-model of the header,
    d-model operation parameters and event values, mapping variables and element paths."""

    def __init__(self, checker: _Checker, mapping: ast.PlatformMapping) -> None:
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
                self.c.predicate(m.expr, scope, f"{kind} of the mapping of "
                                 f"{getattr(member, 'name')}")
            elif isinstance(m, ast.Action):
                for s in m.statements:
                    if isinstance(s, ast.Assign):
                        self._expr(s.target, scope, known)
                        self._expr(s.value, scope, known)
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
                hint = _name_hint(first, scope.all_names()) or (
                    "declare it with 'var', or use a parameter of the d-model operation")
                self.c.error(codes.S1, f"unknown name '{first}' in mapping", steps[0][1], hint)
                continue
            if self.pmodel is not None:
                self._element_path(steps)

    def _element_path(self, steps: list[tuple[str, Span, bool]]) -> None:
        pm = self.pmodel
        assert pm is not None
        if steps[0][0] == pm.name:
            steps = steps[1:]
        current: ast.PModel | ast.Block | ast.Part = pm
        for i, (name, span, _) in enumerate(steps):
            found = _child(current, name, self.c)
            if found is None:
                if i == len(steps) - 1 and isinstance(current, ast.Block) and i > 0:
                    self.c._port(current, name, span)
                    return
                where = _describe(current)
                names = _child_names(current, self.c)
                self.c.error(codes.S1, f"{where} has no element '{name}'", span,
                             did_you_mean(name, names) or
                             f"its elements are: {', '.join(sorted(names)) or '(none)'}")
                return
            current = found
        if isinstance(current, ast.Block):
            self.c.error(codes.S1, f"the path names {current.kind.value} {current.name}, not "
                         "one of its variables", steps[-1][1],
                         f"write {steps[-1][0]}.<variable>")


# ---------------------------------------------------------------------- helpers


def _names_in(e: ex.Expr) -> Iterator[ex.Name]:
    """Names an expression uses, skipping the field names of ``.member`` (they belong to the
    value on their left)."""
    for node in e.walk():
        if isinstance(node, ex.Name):
            yield node


def path_roots(e: ex.Expr) -> Iterator[ex.Expr]:
    """Maximal path-shaped subexpressions (``a::b.c``, ``a[1].v``, ``f``) of ``e``."""
    if isinstance(e, (ex.Name, ex.Member, ex.Index)) and steps_of(e) is not None:
        yield e
        for node in e.walk():
            if isinstance(node, ex.Index):
                for a in node.args:
                    yield from path_roots(a)
        return
    for child in e.children():
        yield from path_roots(child)


_MEMBER_WORD = {ast.Shape: "geometry", ast.Inertial: "inertial information",
                ast.Bounce: "bounce", ast.LaserRetro: "laser retro"}


def _indices_of(blocks: Iterable[ast.Block]) -> dict[str, object]:
    return {i.var: i for b in blocks for i in b.indices}


def _all_blocks(node: Container) -> dict[str, list[ast.Block]]:
    out: dict[str, list[ast.Block]] = {}
    stack: list[object] = list(node.members)
    while stack:
        m = stack.pop()
        if isinstance(m, ast.Block):
            out.setdefault(m.name, []).append(m)
            stack.extend(m.members)
    return out


def _child(node: ast.PModel | ast.Block | ast.Part, name: str, c: _Checker
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


def _child_names(node: ast.PModel | ast.Block | ast.Part, c: _Checker) -> set[str]:
    if isinstance(node, ast.Part):
        target = c.resolution.get(node)
        if not isinstance(target, ast.PModel):
            return set()
        node = target
    return set(block_children(node))


def _describe(node: ast.PModel | ast.Block | ast.Part) -> str:
    if isinstance(node, ast.PModel):
        return f"p-model {node.name}"
    if isinstance(node, ast.Part):
        return f"part {node.name}"
    return f"{node.kind.value} {node.name}"


#: Names a newcomer writes for values RoboSim does not have (Python's, C's, IEEE 754's).
NON_FINITE = frozenset({"nan", "NaN", "NAN", "inf", "Inf", "INF", "infinity", "Infinity"})


def _name_hint(name: str, candidates: Iterable[str]) -> str:
    """The hint for an unknown value name: RoboSim has no ``nan`` or ``inf`` (rather than
    "did you mean 'tan'?"), else the close names."""
    if name in NON_FINITE:
        return (f"RoboSim has no '{name}': every value is a finite number (a quantity "
                "without a known value is a const without one, given by --const)")
    return did_you_mean(name, candidates)
