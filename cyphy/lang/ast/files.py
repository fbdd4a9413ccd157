"""A parsed file: its top-level items, and the result of parsing one file's text."""

from __future__ import annotations

from typing import Iterator, Union

from cyphy.diagnostics import Diagnostic
from cyphy.lang.ast.core import (
    AnnotationTemplate, DataType, EndPackage, Enumeration, FunctionDecl, Import, Node,
    PackageDecl, QName, TypeDecl, UnitDecl, VarDecl, members_of,
)
from cyphy.lang.ast.dmodel import Controller, Interface, Module, RoboticPlatform, StateMachine
from cyphy.lang.ast.mappings import PlatformMapping
from cyphy.lang.ast.physical import Definition, PModel, Solution
from cyphy.records import record


TopLevel = Union[
    PackageDecl, EndPackage, Import, VarDecl, TypeDecl, FunctionDecl, DataType, Enumeration,
    UnitDecl, AnnotationTemplate, Definition, PModel, PlatformMapping, Solution, Interface,
    Module, RoboticPlatform, Controller, StateMachine,
]


@record
class SourceFile(Node):
    path: str
    items: tuple[TopLevel, ...]

    @property
    def package(self) -> QName:
        """The file's package (``()`` for files without one: the global package)."""
        for item in self.items:
            if isinstance(item, PackageDecl):
                return item.name
        return ()

    @property
    def imports(self) -> tuple[Import, ...]:
        return members_of(self.items, Import)

    def declarations(self) -> Iterator[TopLevel]:
        for item in self.items:
            if not isinstance(item, (PackageDecl, EndPackage, Import)):
                yield item


@record
class ParseResult:
    """One file's text parsed: its syntax tree (None when it has syntax errors) and the
    diagnostics of parsing."""

    file: SourceFile | None
    diagnostics: tuple[Diagnostic, ...]
