"""Typed input events for ``cyphy simulate``: a machine that reads one (``$echo?seen``) runs on
its interpreter, and the event, when its predicate holds, carries the value its mapping's
equations give the parameter (spec semantics.md, Rule 5: ``registerRead.echo!true!p`` for
``p`` in ``{ p | ∃ locals • equations }``). Here: which events the machines read, the
mapping of one in the model's names, and its equations solved once for the parameter, so the
simulator evaluates one expression of the states and inputs per cycle. A set of values that is
not one number (two roots, a local left open, no solution, a vector) is refused: the machine
reads one value, and the theory's choice over it is not something a simulation can make.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping

import sympy

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.lang.notation import to_notation, type_to_notation
from cyphy.model.machines import expressions
from cyphy.semantics.dynamics.equations import member_equations
from cyphy.translate.to_sympy import UnsupportedNode, to_sympy
from cyphy.verify.flowstar.problem import symbol

#: The event types whose values are one number.
NUMBERS = ("real", "int", "nat")


class ValueRefused(Exception):
    """The event's value cannot be computed as one number: why, and what to do."""

    def __init__(self, message: str, hint: str = "") -> None:
        super().__init__(message)
        self.message, self.hint = message, hint


@dataclass(frozen=True)
class TypedEvent:
    """A typed input event's mapping in the model's names: its parameter (``? r``, renamed
    ``cyphy_event_<event>`` so that it names nothing of the model), its locals
    (``<event>_<local>``), the equations that give the parameter its value (actions'
    assignments as equations) and the predicate, which may read both."""

    name: str
    mapping: str
    param: str
    written: str  # the parameter as the mapping names it, for messages
    locals: tuple[str, ...]
    equations: tuple[ex.Expr, ...]
    predicate: ex.Expr | None
    span: Span  # the mapping of the event


def machine_events(machine: Any) -> list[tuple[str, Span, Any]]:
    """The input events the machines of ``machine`` (an interpreter, or a module's: its
    ``parts``) and the operation definitions they call read, each with where it is first
    read and its declared type, in the order read."""
    out: dict[str, tuple[str, Span, Any]] = {}
    for part in machine.parts:
        for m in [part.machine, *part.operations.values()]:
            for e, _where in expressions(m):
                for node in e.walk():
                    decl = m.platform.input_events.get(node.name[-1]) \
                        if isinstance(node, ex.PlatformRef) else None
                    if decl is not None:
                        out.setdefault(node.name[-1], (node.name[-1], node.span, decl.type))
    return list(out.values())


def not_one_number(name: str, type_: Any) -> ValueRefused | None:
    """Why a typed event of this type cannot be simulated (None: it can)."""
    if isinstance(type_, ast.PrimitiveType) and type_.name in NUMBERS:
        return None
    return ValueRefused(f"the input event {name} carries a {type_to_notation(type_)}: "
                        "simulate computes an event's value as one number",
                        "give the event a real, int or nat type (one event per number)")


def typed_event(model: Any, mapping: Any, event: Any) -> TypedEvent:
    """The event's mapping (:class:`cyphy.lang.ast.EventMapping`) in the model's names."""
    param = f"cyphy_event_{event.name}"
    members = member_equations(model, mapping, event, {event.param: ex.Name((param,))})
    preds = [p.expr for p in members.predicates]
    return TypedEvent(event.name, mapping.name, param, event.param, tuple(members.locals),
                      tuple(e.expr for e in members.equations),
                      ex.conjunction(preds) if preds else None, event.span)


def solve_value(t: TypedEvent, names: Mapping[str, Any], variables: set[Any],
                in_states: Callable[[Any], Any], consts: Mapping[str, float]
                ) -> tuple[Any, dict[Any, Any]]:
    """The event's value as a function of ``variables`` (the states, inputs and clocks; the
    SymPy symbols of ``names``): its equations solved for the parameter, with the sensor
    outputs they read replaced by ``in_states`` and the plain ``consts`` by their values;
    also the substitution of the parameter and the locals solved, for the predicate. Raises
    :class:`ValueRefused` unless the equations give the parameter exactly one value."""
    what = f"the value of the input event {t.name}"
    hint = (f"give the parameter of {t.name} one value with an equation over sensor "
            "outputs, locals and constants (equation r == Link::Joint::Sensor.output)")

    def written(e: ex.Expr) -> str:  # the equation with the parameter as the mapping names it
        return to_notation(ex.transform(e, lambda n: ex.Name((t.written,)) if isinstance(
            n, ex.Name) and n.text == t.param else None))

    values = {symbol(n): sympy.Rational(repr(float(v))) for n, v in consts.items()}
    relations = []
    for e in t.equations:
        try:
            rel = to_sympy(e, symbols=names)
            if rel is sympy.true:
                continue
            if not isinstance(rel, sympy.Equality):
                raise ValueRefused(f"{what}: the equation {written(e)} cannot hold", hint)
            difference = sympy.expand(rel.lhs - rel.rhs)
        except UnsupportedNode as err:
            raise ValueRefused(f"{what}: {err}", hint) from None
        except TypeError:  # SymPy's: a vector or record where a number is meant
            difference = None
        if not isinstance(difference, sympy.Expr):
            raise ValueRefused(f"{what}: the equation {written(e)} is not between numbers",
                               hint)
        relations.append(in_states(difference.xreplace(values)))
    param = symbol(t.param)
    unknowns = [param, *(symbol(n) for n in t.locals)]
    try:
        solutions = sympy.solve(relations, unknowns, dict=True) if relations else []
    except NotImplementedError:
        solutions = []
    determined = [s for s in solutions if param in s and not s[param].free_symbols - variables]
    if len(solutions) != 1 or not determined:
        found = "no equation gives it" if not relations else \
            "its equations have no solution" if not solutions else \
            f"its equations allow {len(solutions)} values" if len(solutions) > 1 else \
            "its equations leave it open"
        raise ValueRefused(f"{what} is not determined by mapping {t.mapping}: {found}, and "
                           "the machine reads one", hint)
    value = determined[0][param]
    if value.has(sympy.zoo, sympy.oo, -sympy.oo, sympy.nan):
        raise ValueRefused(f"{what} is undefined (a division by zero, or an infinite value)",
                           hint)
    return value, {k: v for k, v in determined[0].items() if not v.free_symbols - variables}
