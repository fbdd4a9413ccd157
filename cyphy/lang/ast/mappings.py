"""The syntax of platform mappings: how a d-model's operations, events and variables are
realised on a p-model (predicates, actions and their statements)."""

from __future__ import annotations

from dataclasses import field
from typing import Union

from cyphy.diagnostics import Span
from cyphy.expr import Expr
from cyphy.lang.ast.core import NO_SPAN, Node, QName, VarDecl, members_of
from cyphy.lang.ast.physical import Equation
from cyphy.records import record


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
        return members_of(self.members, VarDecl)

    @property
    def equations(self) -> tuple[Equation, ...]:
        return members_of(self.members, Equation)

    @property
    def predicates(self) -> tuple[Predicate, ...]:
        return members_of(self.members, Predicate)

    @property
    def actions(self) -> tuple[Action, ...]:
        return members_of(self.members, Action)


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
    dmodel_span: Span = field(default=NO_SPAN, compare=False, repr=False)
    pmodel_span: Span = field(default=NO_SPAN, compare=False, repr=False)

    @property
    def declarations(self) -> tuple[VarDecl, ...]:
        return members_of(self.members, VarDecl)

    @property
    def operations(self) -> tuple[OperationMapping, ...]:
        return members_of(self.members, OperationMapping)

    @property
    def events(self) -> tuple[EventMapping, ...]:
        return members_of(self.members, EventMapping)

    @property
    def variables(self) -> tuple[VariableMapping, ...]:
        return members_of(self.members, VariableMapping)
