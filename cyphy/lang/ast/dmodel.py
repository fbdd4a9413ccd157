"""The syntax of d-models: interfaces, robotic platforms, modules and their connections,
controllers, state machines and operations."""

from __future__ import annotations

from dataclasses import field

from cyphy.diagnostics import Span
from cyphy.expr import Expr
from cyphy.lang.ast.core import Node, Param, QName, TypeRef, VarDecl, members_of
from cyphy.lang.ast.mappings import Statement
from cyphy.records import record


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
        return members_of(self.members, EventDecl)

    @property
    def operations(self) -> tuple[OperationSig, ...]:
        return members_of(self.members, OperationSig)

    @property
    def variables(self) -> tuple[VarDecl, ...]:
        return members_of(self.members, VarDecl)


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
        return tuple(m.interface for m in members_of(self.members, InterfaceUse) if m.relation == "uses")

    @property
    def provides(self) -> tuple[QName, ...]:
        return tuple(
            m.interface for m in members_of(self.members, InterfaceUse) if m.relation == "provides"
        )

    @property
    def interface_uses(self) -> tuple[InterfaceUse, ...]:
        return members_of(self.members, InterfaceUse)

    @property
    def events(self) -> tuple[EventDecl, ...]:
        return members_of(self.members, EventDecl)

    @property
    def operations(self) -> tuple[OperationSig, ...]:
        return members_of(self.members, OperationSig)

    @property
    def variables(self) -> tuple[VarDecl, ...]:
        return members_of(self.members, VarDecl)


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
        return members_of(self.members, State)

    @property
    def nodes(self) -> tuple[MachineNode, ...]:
        return members_of(self.members, MachineNode)

    @property
    def transitions(self) -> tuple[Transition, ...]:
        return members_of(self.members, Transition)


@record
class State(_Behaviour, Node):
    name: str
    members: tuple[object, ...]

    def actions(self, kind: str) -> tuple[Statement, ...]:
        """The statements of the ``entry``, ``during`` or ``exit`` actions, in order."""
        return tuple(s for a in members_of(self.members, StateAction) if a.kind == kind
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
        return members_of(self.members, VarDecl)

    @property
    def clocks(self) -> tuple[ClockDecl, ...]:
        return members_of(self.members, ClockDecl)

    @property
    def contexts(self) -> tuple[Context, ...]:
        return members_of(self.members, Context)

    @property
    def cycle_defs(self) -> tuple[CycleDef, ...]:
        return members_of(self.members, CycleDef)

    @property
    def interface_uses(self) -> tuple[InterfaceUse, ...]:
        """``uses``/``requires``/``provides``, written directly or in a context."""
        direct = members_of(self.members, InterfaceUse)
        return direct + tuple(u for c in self.contexts for u in c.members)


@record
class Controller(Node):
    name: str
    members: tuple[object, ...]

    @property
    def machine_refs(self) -> tuple[MachineRef, ...]:
        return members_of(self.members, MachineRef)

    @property
    def machines(self) -> tuple[StateMachine, ...]:
        return members_of(self.members, StateMachine)


@record
class Module(Node):
    name: str
    members: tuple[object, ...]

    @property
    def cycle_defs(self) -> tuple[CycleDef, ...]:
        return members_of(self.members, CycleDef)

    @property
    def platform(self) -> RoboticPlatform | None:
        platforms = members_of(self.members, RoboticPlatform)
        return platforms[0] if platforms else None
