"""The base of the syntax tree (:class:`Node`, spans, members of one kind) and its
declarations: types, constants and variables, packages and imports, functions, data
types, units, annotations and their templates."""

from __future__ import annotations

from dataclasses import field
from enum import Enum
from typing import Any, Iterator, TypeVar, Union

from cyphy.diagnostics import Span
from cyphy.expr import Expr, fields_of
from cyphy.pickling import FastPickle
from cyphy.records import record

NO_SPAN = Span.unknown()
QName = tuple[str, ...]
T = TypeVar("T")


@record
class Node(FastPickle):
    span: Span = field(default=NO_SPAN, compare=False, repr=False, kw_only=True)


_VIEWS: dict[tuple[int, type], tuple[tuple[object, ...], tuple[Any, ...]]] = {}


def members_of(members: tuple[object, ...], cls: type[T]) -> tuple[T, ...]:
    """The members of one kind. Remembered for long member lists (a p-model with thousands
    of links is asked for its blocks once per block by the checks); the identity check makes
    a reused ``id`` harmless."""
    if len(members) < 32:
        return tuple(m for m in members if isinstance(m, cls))
    key = (id(members), cls)
    hit = _VIEWS.get(key)
    if hit is not None and hit[0] is members:
        return hit[1]  # type: ignore[return-value]
    result = tuple(m for m in members if isinstance(m, cls))
    if len(_VIEWS) > 4096:
        _VIEWS.clear()
    _VIEWS[key] = (members, result)
    return result


def expressions_in(node: object) -> Iterator[Expr]:
    """The outermost expressions held by a syntax-tree node (a shape's arguments, an
    inertial's mass, entries and pose values…), in field order."""
    if isinstance(node, Expr):
        yield node
    elif isinstance(node, tuple):
        for item in node:
            yield from expressions_in(item)
    elif isinstance(node, Node):
        for f in fields_of(type(node)):
            if f.name != "span":
                yield from expressions_in(getattr(node, f.name))


# --------------------------------------------------------------------------- types


@record
class PrimitiveType(Node):
    name: str  # real, int, nat, boolean, string


@record
class VectorType(Node):
    element: TypeRef
    size: Expr | None


@record
class MatrixType(Node):
    element: TypeRef
    rows: Expr
    cols: Expr


@record
class SeqType(Node):
    element: TypeRef


@record
class SetType(Node):
    element: TypeRef


@record
class NamedType(Node):
    name: QName


TypeRef = Union[PrimitiveType, VectorType, MatrixType, SeqType, SetType, NamedType]


# --------------------------------------------------------------------------- declarations


class DeclKind(str, Enum):
    CONST = "const"
    VAR = "var"
    INPUT = "input"
    OUTPUT = "output"
    INOUT = "InOut"
    LOCAL = "local"


@record
class VarDecl(Node):
    """One declared name; comma lists (``const a: real, b: real``) become several."""

    kind: DeclKind
    name: str
    type: TypeRef
    value: Expr | None


@record
class Param(Node):
    name: str
    type: TypeRef


@record
class PackageDecl(Node):
    name: QName


@record
class EndPackage(Node):
    pass


@record
class Import(Node):
    path: QName
    wildcard: bool

    @property
    def text(self) -> str:
        return "::".join(self.path) + ("::*" if self.wildcard else "")


@record
class TypeDecl(Node):
    name: str


@record
class FunctionDecl(Node):
    name: str
    params: tuple[Param, ...]
    return_type: TypeRef | None
    preconditions: tuple[Expr, ...] = ()
    postconditions: tuple[Expr, ...] = ()


@record
class DataType(Node):
    name: str
    fields: tuple[Param, ...]
    is_record: bool = False


@record
class Enumeration(Node):
    name: str
    literals: tuple[str, ...]


@record
class UnitDecl(Node):
    """``primitive unit metre`` (no base) or ``derived unit newton { base … factor … }``."""

    name: str
    base: Expr | None = None
    factor: Expr | None = None


# --------------------------------------------------------------------------- annotations


@record
class TemplateInstance(Node):
    """``Axis { xyz = (|0,1,0|) }``: a template applied to named arguments."""

    template: QName
    args: tuple[AnnotationArg, ...]

    def arg(self, name: str) -> AnnotationArg | None:
        for a in self.args:
            if a.name == name:
                return a
        return None


@record
class AnnotationArg(Node):
    name: str
    value: Expr | TemplateInstance


@record
class Annotation(Node):
    """``annotation Revolute { … }`` on a joint, sensor or actuator."""

    instance: TemplateInstance


@record
class TemplateParam(Node):
    """A parameter of an annotation template: a value (``xyz: vector(real,3)``) or a nested
    template (``limit: template Limit``), with an optional default."""

    name: str
    type: TypeRef | None
    template: QName | None
    default: Expr | TemplateInstance | None


@record
class AnnotationTemplate(Node):
    name: str
    extends: QName | None
    params: tuple[TemplateParam, ...]
