"""The syntax tree of RoboSim model files: frozen dataclasses with source spans.

This is what the parser returns and what name resolution and elaboration read. Member lists
keep source order (the notation's members are unordered and may repeat, and checks need to see
duplicates); properties give the members of one kind. Expressions are :mod:`cyphy.expr` nodes.
"""

from __future__ import annotations

from dataclasses import field
from enum import Enum
from typing import Any, Iterator, TypeVar, Union

from cyphy.diagnostics import Diagnostic, Span
from cyphy.expr import Expr, fields_of
from cyphy.pickling import FastPickle
from cyphy.records import record

_NO_SPAN = Span.unknown()
QName = tuple[str, ...]
T = TypeVar("T")


@record
class Node(FastPickle):
    span: Span = field(default=_NO_SPAN, compare=False, repr=False, kw_only=True)


_VIEWS: dict[tuple[int, type], tuple[tuple[object, ...], tuple[Any, ...]]] = {}


def _of(members: tuple[object, ...], cls: type[T]) -> tuple[T, ...]:
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


# --------------------------------------------------------------------------- block members


@record
class PoseField(Node):
    key: str  # x y z roll pitch yaw
    value: Expr


@record
class Pose(Node):
    fields: tuple[PoseField, ...]

    def get(self, key: str) -> Expr | None:
        for f in self.fields:
            if f.key == key:
                return f.value
        return None


@record
class IndexDecl(Node):
    """``index i : [a, b)`` (half-open) or ``[a, b]`` (closed)."""

    var: str
    lower: Expr
    upper: Expr
    closed: bool


@record
class FixedConnection(Node):
    """``fixed to L`` or ``fixed to L in P`` (link L of part P)."""

    target: str
    part: str | None


@record
class FlexibleConnection(Node):
    target: str
    part: str | None


@record
class Relation(Node):
    """A containment label: ``relation e``, ``relation_flexi e`` or a bare comparison."""

    expr: Expr
    flexi: bool = False
    bare: bool = False


@record
class Equation(Node):
    expr: Expr


@record
class Constraint(Node):
    expr: Expr


@record
class Instantiation(Node):
    name: str
    value: Expr


@record
class GeomArg(Node):
    name: str
    value: Expr


@record
class Shape(Node):
    """``box(length=…, width=…, height=…)``, ``cylinder(radius=…, length=…)``, ``sphere(…)``."""

    kind: str
    args: tuple[GeomArg, ...]

    def arg(self, name: str) -> Expr | None:
        for a in self.args:
            if a.name == name:
                return a.value
        return None


@record
class Mesh(Node):
    shape: str | None
    scaling: Expr | None


@record
class InertiaEntry(Node):
    name: str  # ixx ixy ixz iyy iyz izz
    value: Expr


@record
class Inertial(Node):
    """``inertial information { mass m inertia matrix {…} pose {…} }`` (in source order)."""

    mass: Expr | None
    inertia: tuple[InertiaEntry, ...] | None
    pose: Pose | None
    order: tuple[str, ...] = ()  # the member keywords in source order, for the order check


@record
class Bounce(Node):
    restitution: Expr | None
    threshold: Expr | None


@record
class FrictionEntry(Node):
    name: str
    value: Expr


@record
class Friction(Node):
    entries: tuple[FrictionEntry, ...]


@record
class LaserRetro(Node):
    value: Expr


DefMember = Union[
    Shape, Mesh, Inertial, Bounce, Friction, LaserRetro, VarDecl, Equation, Constraint,
    Annotation, Relation,
]


class BlockKind(str, Enum):
    LINK = "link"
    BODY = "body"
    JOINT = "joint"
    SENSOR = "sensor"
    ACTUATOR = "actuator"

    @property
    def ref_keyword(self) -> str:
        return self.value[0] + "ref" if self is not BlockKind.BODY else "bref"


REF_KINDS = {"lref": BlockKind.LINK, "bref": BlockKind.BODY, "jref": BlockKind.JOINT,
             "sref": BlockKind.SENSOR, "aref": BlockKind.ACTUATOR}


@record
class DefBlock(Node):
    """The ``def { … }`` of a local block: an anonymous definition."""

    members: tuple[DefMember, ...]


@record
class Definition(Node):
    """A named package-level definition (``link Tip {}``, ``sensor IR {…}``)."""

    kind: BlockKind
    name: str
    members: tuple[DefMember, ...]


class _Members:
    """Typed views of a ``members`` tuple; shared by blocks, p-models and parts."""

    __slots__ = ()
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None

    def _view(self, cls: type[T]) -> tuple[T, ...]:
        """The members of one kind, remembered on the node: the checks ask every block of a
        model of thousands for its poses, blocks, declarations… several times over."""
        views = self._views
        if views is None:
            views = {}
            object.__setattr__(self, "_views", views)
        found = views.get(cls)
        if found is None:
            found = views[cls] = tuple(m for m in self.members if isinstance(m, cls))
        return found

    @property
    def blocks(self) -> tuple[Block, ...]:
        return self._view(Block)

    @property
    def poses(self) -> tuple[Pose, ...]:
        return self._view(Pose)

    @property
    def pose(self) -> Pose | None:
        poses = self.poses
        return poses[0] if poses else None

    @property
    def indices(self) -> tuple[IndexDecl, ...]:
        return self._view(IndexDecl)

    @property
    def index(self) -> IndexDecl | None:
        indices = self.indices
        return indices[0] if indices else None

    @property
    def declarations(self) -> tuple[VarDecl, ...]:
        return self._view(VarDecl)

    @property
    def equations(self) -> tuple[Equation, ...]:
        return self._view(Equation)

    @property
    def instantiations(self) -> tuple[Instantiation, ...]:
        return self._view(Instantiation)

    @property
    def annotations(self) -> tuple[Annotation, ...]:
        return self._view(Annotation)

    @property
    def relations(self) -> tuple[Relation, ...]:
        return self._view(Relation)


@record
class Block(_Members, Node):
    """A link, body, joint, sensor or actuator inside a p-model: local (``local link L {…}``)
    when ``ref`` is None, a reference (``jref LHinge = Revolute {…}``) otherwise."""

    kind: BlockKind
    name: str
    ref: QName | None
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def is_local(self) -> bool:
        return self.ref is None

    @property
    def definitions(self) -> tuple[DefBlock, ...]:
        return self._view(DefBlock)

    @property
    def definition(self) -> DefBlock | None:
        defs = self.definitions
        return defs[0] if defs else None

    @property
    def fixed(self) -> tuple[FixedConnection, ...]:
        return self._view(FixedConnection)

    @property
    def flexible(self) -> tuple[FlexibleConnection, ...]:
        return self._view(FlexibleConnection)


@record
class PartFixed(Node):
    """``link L fixed to T in P`` inside a part: link L of the part's p-model is fixed to T."""

    link: str
    target: str
    part: str | None


@record
class PartFlexible(Node):
    """``joint J flexibly connected to T in P`` inside a part."""

    joint: str
    target: str
    part: str | None


@record
class Part(_Members, Node):
    name: str
    pmodel: QName
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def fixed(self) -> tuple[PartFixed, ...]:
        return self._view(PartFixed)

    @property
    def flexible(self) -> tuple[PartFlexible, ...]:
        return self._view(PartFlexible)


@record
class SolutionInput(Node):
    name: str
    type: TypeRef


@record
class Solution(Node):
    """A generated p-model+ solution block (order of members fixed by the notation)."""

    expr_name: str
    type: TypeRef
    order: int
    group: int
    method: str
    inputs: tuple[SolutionInput, ...]
    constraints: tuple[Constraint, ...]


@record
class PModel(_Members, Node):
    """``pmodel N {…}`` or, with ``fragment`` set, ``fragment N {…}``."""

    name: str
    members: tuple[object, ...]
    fragment: bool = False
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def parts(self) -> tuple[Part, ...]:
        return self._view(Part)


# --------------------------------------------------------------------------- mappings


@record
class Predicate(Node):
    expr: Expr


@record
class Assign(Node):
    target: Expr
    value: Expr


@record
class CallStatement(Node):
    call: Expr


@record
class SkipStatement(Node):
    pass


@record
class SendStatement(Node):
    """``$e!v`` (or ``$e!``-less ``$e`` as a call statement): an output event."""

    event: Expr
    value: Expr


@record
class ClockReset(Node):
    """``#C``: the clock ``C`` counts again from 0."""

    clock: str


@record
class ExecStatement(Node):
    """``exec`` inside an action: the cycle ends here; the rest runs in the next cycle."""


@record
class WaitStatement(Node):
    """``wait(n)``: the machine lets ``n`` cycles pass."""

    cycles: Expr


Statement = Union[Assign, CallStatement, SkipStatement, SendStatement, ClockReset,
                  ExecStatement, WaitStatement]


@record
class Action(Node):
    statements: tuple[Statement, ...]


MappingMember = Union[VarDecl, Equation, Predicate, Action]


class _MappingMembers:
    __slots__ = ()
    members: tuple[MappingMember, ...]

    @property
    def declarations(self) -> tuple[VarDecl, ...]:
        return _of(self.members, VarDecl)

    @property
    def equations(self) -> tuple[Equation, ...]:
        return _of(self.members, Equation)

    @property
    def predicates(self) -> tuple[Predicate, ...]:
        return _of(self.members, Predicate)

    @property
    def actions(self) -> tuple[Action, ...]:
        return _of(self.members, Action)


@record
class OperationMapping(_MappingMembers, Node):
    name: str
    members: tuple[MappingMember, ...]


@record
class EventMapping(_MappingMembers, Node):
    """``input event obstacle {…}`` or ``output event e ? p {…}``."""

    direction: str  # "input" or "output"
    name: str
    param: str | None
    members: tuple[MappingMember, ...]
    param_span: Span | None = field(default=None, compare=False, repr=False)


@record
class VariableMapping(_MappingMembers, Node):
    name: str
    members: tuple[MappingMember, ...]


@record
class PlatformMapping(Node):
    """``map M dmodel Module to pmodel PModel {…}``."""

    name: str
    dmodel: QName
    pmodel: QName
    members: tuple[object, ...]
    dmodel_span: Span = field(default=_NO_SPAN, compare=False, repr=False)
    pmodel_span: Span = field(default=_NO_SPAN, compare=False, repr=False)

    @property
    def declarations(self) -> tuple[VarDecl, ...]:
        return _of(self.members, VarDecl)

    @property
    def operations(self) -> tuple[OperationMapping, ...]:
        return _of(self.members, OperationMapping)

    @property
    def events(self) -> tuple[EventMapping, ...]:
        return _of(self.members, EventMapping)

    @property
    def variables(self) -> tuple[VariableMapping, ...]:
        return _of(self.members, VariableMapping)


# --------------------------------------------------------------------------- d-models


@record
class EventDecl(Node):
    name: str
    type: TypeRef | None


@record
class OperationSig(Node):
    name: str
    params: tuple[Param, ...]


@record
class ClockDecl(Node):
    name: str


@record
class Interface(Node):
    name: str
    members: tuple[object, ...]

    @property
    def events(self) -> tuple[EventDecl, ...]:
        return _of(self.members, EventDecl)

    @property
    def operations(self) -> tuple[OperationSig, ...]:
        return _of(self.members, OperationSig)

    @property
    def variables(self) -> tuple[VarDecl, ...]:
        return _of(self.members, VarDecl)


@record
class InterfaceUse(Node):
    """``uses I``, ``provides I`` or ``requires I`` in a robotic platform."""

    relation: str  # uses, provides, requires
    interface: QName


@record
class RoboticPlatform(Node):
    name: str
    members: tuple[object, ...]

    @property
    def uses(self) -> tuple[QName, ...]:
        return tuple(m.interface for m in _of(self.members, InterfaceUse) if m.relation == "uses")

    @property
    def provides(self) -> tuple[QName, ...]:
        return tuple(
            m.interface for m in _of(self.members, InterfaceUse) if m.relation == "provides"
        )

    @property
    def interface_uses(self) -> tuple[InterfaceUse, ...]:
        return _of(self.members, InterfaceUse)

    @property
    def events(self) -> tuple[EventDecl, ...]:
        return _of(self.members, EventDecl)

    @property
    def operations(self) -> tuple[OperationSig, ...]:
        return _of(self.members, OperationSig)

    @property
    def variables(self) -> tuple[VarDecl, ...]:
        return _of(self.members, VarDecl)


@record
class CycleDef(Node):
    expr: Expr


@record
class NodeRef(Node):
    """``cref cm = Movement`` or ``rref rp = Platform`` inside a module."""

    kind: str
    name: str
    target: QName


@record
class Connection(Node):
    source: str
    source_event: str
    target: str
    target_event: str
    flag: str | None


# --------------------------------------------------------------------------- behaviour


@record
class MachineRef(Node):
    """``sref sm = SMovement`` (or ``opref``) inside a controller."""

    kind: str
    name: str
    target: QName


@record
class Context(Node):
    """``input context { uses I }`` or ``output context { requires I }``."""

    direction: str  # input, output
    members: tuple[InterfaceUse, ...]


@record
class Terminates(Node):
    """``terminates`` in an operation definition."""


@record
class MachineNode(Node):
    """``initial i0``, ``junction j`` or ``final f``: a node without actions."""

    kind: str  # initial, junction, final
    name: str


@record
class StateAction(Node):
    kind: str  # entry, during, exit
    statements: tuple[Statement, ...]


@record
class Transition(Node):
    name: str
    source: str | None
    target: str | None
    exec: bool
    trigger: Expr | None
    condition: Expr | None
    action: tuple[Statement, ...] | None
    source_span: Span | None = field(default=None, compare=False, repr=False)
    target_span: Span | None = field(default=None, compare=False, repr=False)


class _Behaviour:
    """What machines, operation definitions and (composite) states share: nodes and
    transitions among their members."""

    __slots__ = ()
    members: tuple[object, ...]

    @property
    def states(self) -> tuple["State", ...]:
        return _of(self.members, State)

    @property
    def nodes(self) -> tuple[MachineNode, ...]:
        return _of(self.members, MachineNode)

    @property
    def transitions(self) -> tuple[Transition, ...]:
        return _of(self.members, Transition)


@record
class State(_Behaviour, Node):
    name: str
    members: tuple[object, ...]

    def actions(self, kind: str) -> tuple[Statement, ...]:
        """The statements of the ``entry``, ``during`` or ``exit`` actions, in order."""
        return tuple(s for a in _of(self.members, StateAction) if a.kind == kind
                     for s in a.statements)


@record
class StateMachine(_Behaviour, Node):
    """``stm NAME { … }``; also an operation definition (``kind`` operation, with
    parameters)."""

    name: str
    members: tuple[object, ...]
    kind: str = "stm"  # stm, operation
    params: tuple[Param, ...] = ()

    @property
    def variables(self) -> tuple[VarDecl, ...]:
        return _of(self.members, VarDecl)

    @property
    def clocks(self) -> tuple[ClockDecl, ...]:
        return _of(self.members, ClockDecl)

    @property
    def contexts(self) -> tuple[Context, ...]:
        return _of(self.members, Context)

    @property
    def cycle_defs(self) -> tuple[CycleDef, ...]:
        return _of(self.members, CycleDef)

    @property
    def interface_uses(self) -> tuple[InterfaceUse, ...]:
        """``uses``/``requires``/``provides``, written directly or in a context."""
        direct = _of(self.members, InterfaceUse)
        return direct + tuple(u for c in self.contexts for u in c.members)


@record
class Controller(Node):
    name: str
    members: tuple[object, ...]

    @property
    def machine_refs(self) -> tuple[MachineRef, ...]:
        return _of(self.members, MachineRef)

    @property
    def machines(self) -> tuple[StateMachine, ...]:
        return _of(self.members, StateMachine)


@record
class Module(Node):
    name: str
    members: tuple[object, ...]

    @property
    def cycle_defs(self) -> tuple[CycleDef, ...]:
        return _of(self.members, CycleDef)

    @property
    def platform(self) -> RoboticPlatform | None:
        platforms = _of(self.members, RoboticPlatform)
        return platforms[0] if platforms else None


# --------------------------------------------------------------------------- files


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
        return _of(self.items, Import)

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
