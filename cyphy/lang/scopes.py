"""Package-level name lookup: what a name written in a file refers to.

A single name is looked up, in order, among the declarations of the file's own package, the
names it imports one by one (``import a::b::X``), the packages it imports whole
(``import a::b::*``), the global package (files without ``package``) and, last, the functions
of ``physmod::math`` and the annotation templates of ``physmod::sdf::annotations`` (RoboTool's
own models use both without importing them). A qualified name
``a::b::X`` is element ``X`` of package ``a::b``. Lookups take a predicate so that names in
different namespaces (the joint definition ``Revolute`` and the annotation template
``Revolute``) do not hide each other.
"""

from __future__ import annotations

from typing import Callable

from cyphy.lang import ast
from cyphy.lang.workspace import Declaration, Workspace

Accept = Callable[[Declaration], bool]

MATH_PACKAGE: ast.QName = ("physmod", "math")
ANNOTATIONS_PACKAGE: ast.QName = ("physmod", "sdf", "annotations")


def is_definition(kind: ast.BlockKind | None = None) -> Accept:
    def accept(d: Declaration) -> bool:
        return isinstance(d, ast.Definition) and (kind is None or d.kind is kind)

    return accept


def is_pmodel(d: Declaration) -> bool:
    return isinstance(d, ast.PModel)


def is_template(d: Declaration) -> bool:
    return isinstance(d, ast.AnnotationTemplate)


def is_constant(d: Declaration) -> bool:
    return isinstance(d, ast.VarDecl) and d.kind is ast.DeclKind.CONST


def is_function(d: Declaration) -> bool:
    return isinstance(d, ast.FunctionDecl)


def is_value(d: Declaration) -> bool:
    """Names usable in expressions: constants, functions, enumeration literals' types."""
    return isinstance(d, (ast.VarDecl, ast.FunctionDecl))


def is_type(d: Declaration) -> bool:
    return isinstance(d, (ast.DataType, ast.TypeDecl, ast.Enumeration))


def is_module(d: Declaration) -> bool:
    return isinstance(d, ast.Module)


def is_interface(d: Declaration) -> bool:
    return isinstance(d, ast.Interface)


def is_node(d: Declaration) -> bool:
    """Targets of ``cref``/``rref`` in a module: controllers and robotic platforms."""
    return isinstance(d, (ast.Controller, ast.RoboticPlatform))


def is_machine(d: Declaration) -> bool:
    """Targets of ``sref``/``opref`` in a controller: state machines and operations."""
    return isinstance(d, ast.StateMachine)


def is_anything(d: Declaration) -> bool:
    return True


class Scopes:
    """Per-file visibility tables over a workspace, computed once per file."""

    def __init__(self, ws: Workspace) -> None:
        self.ws = ws
        self._levels: dict[str, list[dict[str, list[Declaration]]]] = {}

    def levels(self, file: ast.SourceFile) -> list[dict[str, list[Declaration]]]:
        cached = self._levels.get(file.path)
        if cached is not None:
            return cached
        own = self.ws.package_of(file).members if file.path in self.ws.file_package else {}
        explicit: dict[str, list[Declaration]] = {}
        wildcard: dict[str, list[Declaration]] = {}
        for imp in file.imports:
            if imp.wildcard:
                pkg = self.ws.packages.get(imp.path)
                if pkg is not None:
                    for name, decls in pkg.members.items():
                        wildcard.setdefault(name, []).extend(decls)
            else:
                pkg = self.ws.packages.get(imp.path[:-1])
                if pkg is not None and imp.path[-1] in pkg.members:
                    explicit.setdefault(imp.path[-1], []).extend(pkg.members[imp.path[-1]])
        global_pkg = self.ws.packages.get(())
        glob = global_pkg.members if global_pkg is not None else {}
        builtins: dict[str, list[Declaration]] = {}
        math = self.ws.packages.get(MATH_PACKAGE)
        for name, decls in (math.members.items() if math is not None else ()):
            builtins.setdefault(name, []).extend(
                d for d in decls if isinstance(d, ast.FunctionDecl))
        templates = self.ws.packages.get(ANNOTATIONS_PACKAGE)
        for name, decls in (templates.members.items() if templates is not None else ()):
            builtins.setdefault(name, []).extend(
                d for d in decls if isinstance(d, ast.AnnotationTemplate))
        levels = [own, explicit, wildcard, glob, builtins]
        self._levels[file.path] = levels
        return levels

    def lookup(self, file: ast.SourceFile, name: ast.QName, accept: Accept = is_anything
               ) -> list[Declaration]:
        """Declarations that ``name`` denotes from ``file`` (empty when it does not resolve)."""
        if not name:
            return []
        if len(name) > 1:
            pkg = self.ws.packages.get(name[:-1])
            if pkg is None:
                return []
            return [d for d in pkg.members.get(name[-1], ()) if accept(d)]
        for level in self.levels(file):
            found = [d for d in level.get(name[0], ()) if accept(d)]
            if found:
                return found
        return []

    def visible_names(self, file: ast.SourceFile, accept: Accept = is_anything) -> set[str]:
        names: set[str] = set()
        for level in self.levels(file):
            names.update(n for n, decls in level.items() if any(accept(d) for d in decls))
        return names

    def package_exists(self, name: ast.QName) -> bool:
        return name in self.ws.packages
