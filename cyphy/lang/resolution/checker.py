"""The resolver's driver: the walk over the user's files, imports and package-level
duplicates, top-level declarations, expressions and names (S1, S2)."""

from __future__ import annotations

from typing import Any, Iterable

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.resolution.names import BUILTIN_NAMES, Resolution, Scope, name_hint, names_in
from cyphy.lang.scopes import Scopes, is_template, is_type, is_value
from cyphy.lang.typing import TypeChecker
from cyphy.lang.workspace import Declaration, Workspace


class CheckerBase:
    """The walk over the user's files and the checks of top-level items, expressions and names;
    the checks of p-models and d-models are mixins over it (:mod:`.pmodels`, :mod:`.dmodels`)."""

    def __init__(self, ws: Workspace, report: Report) -> None:
        self.ws = ws
        self.report = report
        self.scopes = Scopes(ws)
        self.resolution = Resolution()
        self.file: ast.SourceFile = ast.SourceFile("<none>", ())
        self._tables: dict[int, Any] = {}  # per-p-model name tables, built once

    # ------------------------------------------------------------------ driver
    def run(self) -> None:
        # Mappings last: the paths they name (`Rail::Carriage::Eye.voltage`) reach the
        # definitions of other files' blocks, resolved by then whatever the files' order.
        mappings: list[tuple[ast.SourceFile, ast.PlatformMapping]] = []
        for file in self.ws.user_files():
            self.file = file
            self._imports(file)
            for item in file.declarations():
                if isinstance(item, ast.PlatformMapping):
                    mappings.append((file, item))
                else:
                    self._item(item)
        for file, mapping in mappings:
            self.file = file
            self._item(mapping)
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
        unfound = [imp for imp in self.file.imports if not imp.wildcard
                   and imp.path[-1] == name[-1] and imp.path[:-1] not in self.ws.packages]
        if len(name) == 1 and unfound:  # its import names a package that is not there: S5
            package = "::".join(unfound[0].path[:-1])
            self.error(codes.S1, f"unknown {what} '{text}'", span,
                       f"it is imported from {package} (line {unfound[0].span.line}), which "
                       f"is not found: {_unknown_package_hint(unfound[0].path[:-1], [])}")
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
                               imp.span, _unknown_package_hint(imp.path, pkgs))
                continue
            pkg = self.ws.packages.get(imp.path[:-1])
            if pkg is None:
                pkgs = ["::".join(p) for p in self.ws.packages if p]
                self.error(codes.S5, f"import from unknown package '{'::'.join(imp.path[:-1])}'",
                           imp.span, _unknown_package_hint(imp.path[:-1], pkgs))
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
            self._mapping(item)
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
        for node in names_in(e):
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
            hint = name_hint(n, visible) or f"declare '{n}' or import the package defining it"
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


#: The packages of RoboTool's newer ``physmod`` library (spec notation.md §C.2: files in
#: robotool-meta-physmod's ``physmod-libs``). cyphy builds in the older library only
#: (spec library.md), so a model importing these needs the library's folder.
NEWER_PHYSMOD = ("SKO", "trivial", "Featherstone", "CGA")


def _unknown_package_hint(path: tuple[str, ...], known: list[str]) -> str:
    """The hint of S5 for an import of an unknown package: for the newer library, where it
    comes from (a spelling suggestion such as 'physmod::joints' for 'physmod::SKO::joints'
    would send the user to a library whose elements have other names and ports); otherwise a
    close package name, else the way to add a folder."""
    if len(path) > 1 and path[0] == "physmod" and path[1] in NEWER_PHYSMOD:
        return (f"physmod::{path[1]} is part of RoboTool's newer library, which cyphy does not "
                f"build in: give its folder, `--path <physmod-libs>/lib/physmod/{path[1]}`")
    return (did_you_mean("::".join(path), known)
            or "check the package name, or add its folder with --path")
