"""RoboSim state machines: STM8, the types of a machine's behaviour; STM9, a positive cycle.

S3 (expressions are well-typed) for what a machine does: a transition's condition is a
boolean, an assignment gives a variable a value of its declared type, a call passes each
operation parameter a value of its type, ``$e!v`` sends a value of the event's type and
``$e?x`` binds a variable of it. Name resolution (STM5) and arities (STM3) are
checked by their own rules; here a name that does not resolve, a field, or a call with the
wrong number of arguments has an unknown type and is passed over, so nothing is reported
twice and nothing is guessed.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.diagnostics import Report
from cyphy.lang import ast
from cyphy.lang.notation import type_to_notation
from cyphy.lang.scopes import is_value
from cyphy.lang.typing import BOOL, ANY, Kind, TypeChecker, Ty, same_shape, type_of_declared
from cyphy.model.machines import Machine, called_operation, expressions, statements
from cyphy.wellformed.indexing import evaluate_in
from cyphy.wellformed.machines import checked_machines
from cyphy.wellformed.registry import RULES, WFContext, rule


class _MachineTypes(TypeChecker):
    """S3's inference with the names of one machine: its variables, constants and
    parameters, the constants in scope, and ``$e`` (an event occurred: a boolean; a platform
    variable: its type)."""

    def __init__(self, ctx: WFContext, m: Machine, report: Report) -> None:
        own: dict[str, object] = {**m.platform.written, **m.constants, **m.variables,
                                  **{p.name: p for p in m.decl.params}}

        def lookup(name: ex.Name) -> object | None:
            if len(name.parts) == 1 and name.parts[0] in own:
                return own[name.parts[0]]
            found = ctx.scopes.lookup(m.file, name.parts, is_value)
            return found[0] if found else None

        super().__init__(lookup, report)
        self.machine = m

    def error(self, node: ex.Expr, message: str, hint: str) -> None:
        self.report.report(RULES["STM8"].code, message, getattr(node, "span"), hint)

    def _infer_PlatformRef(self, e: ex.PlatformRef) -> Ty:
        p = self.machine.platform
        name = e.name[-1]
        if name in p.variables:
            return type_of_declared(p.variables[name].type)
        if name in p.input_events or name in p.output_events:
            return BOOL
        return ANY


def _parameters(ctx: WFContext, m: Machine, call: ex.Call) -> tuple[str, tuple[ast.Param, ...]]:
    """The operation a call names and its parameters (none when it names no operation)."""
    defined = called_operation(m, call, ctx.scopes)
    if defined is not None:
        return defined.name, defined.params
    func = call.func
    name = func.name[-1] if isinstance(func, ex.PlatformRef) else (
        func.parts[-1] if isinstance(func, ex.Name) else "")
    op = m.platform.operations.get(name)
    return name, op.params if op is not None else ()


@rule("STM8", "a machine's conditions are booleans; assignments, operation arguments and "
      "events' values have the declared types")
def check_STM8_machine_types(ctx: WFContext) -> None:
    """A transition's condition is a boolean (``condition speed`` is a number: the machine
    would never, or always, take it); an assignment ``x = e`` gives ``x`` a value of its
    declared type; ``$op(a, b)`` passes each parameter a value of its type. Any other
    expression of the behaviour is typed as S3 types equations (``not`` of a number, ``+``
    of a boolean). ``$e!v`` gives a typed output event a value of its type, ``$e?x`` binds
    the value of a typed input event to a variable of its type (whether a value travels at
    all is STM4's)."""
    for m in checked_machines(ctx):
        types = _MachineTypes(ctx, m, ctx.report)
        for t in m.transitions:
            if t.decl.condition is not None:
                types.expect_predicate(t.decl.condition, f"the condition of transition {t.name}")
        for s, where in statements(m):
            if isinstance(s, ast.Assign):
                types.expect_assignable(s.target, s.value, f"{where}: {_text(s.target)}")
            elif isinstance(s, ast.CallStatement) and isinstance(s.call, ex.Call):
                name, params = _parameters(ctx, m, s.call)
                if len(params) != len(s.call.args):
                    for a in s.call.args:
                        types.infer(a)
                    continue  # STM3 reports the arity
                for arg, param in zip(s.call.args, params):
                    types.expect_type(arg, type_of_declared(param.type),
                                      f"{where}: parameter '{param.name}' of {name}")
            elif isinstance(s, ast.SendStatement):
                _check_sent(types, m, s, where)
        for e, where in expressions(m):
            for node in e.walk():
                if isinstance(node, ex.PlatformRef) and node.binding is not None:
                    _check_bound(types, m, node, where)


def _event_type(events: dict[str, ast.EventDecl], ref: ex.Expr) -> Ty | None:
    """The type of the typed event ``ref`` names (None: not such an event, STM4's)."""
    if not isinstance(ref, ex.PlatformRef):
        return None
    event = events.get(ref.name[-1])
    return type_of_declared(event.type) if event is not None and event.type is not None \
        else None


def _check_sent(types: _MachineTypes, m: Machine, s: ast.SendStatement, where: str) -> None:
    """``$e!v``: ``v`` has the type of ``e`` (a number where a boolean is declared is what
    the platform's mapping cannot read; an int where a real is declared is fine)."""
    want = _event_type(m.platform.output_events, s.event)
    if want is None:
        types.infer(s.value)
    else:
        types.expect_type(s.value, want, f"{where}: the value of event "
                          f"{_text(s.event)}")


def _check_bound(types: _MachineTypes, m: Machine, ref: ex.PlatformRef, where: str) -> None:
    """``$e?x``: the variable ``x`` holds values of the type of ``e``, as an assignment
    ``x = value`` would need."""
    want = _event_type(m.platform.input_events, ref)
    var = m.variables.get(ref.binding or "")
    if want is None or var is None:
        return  # STM4 reports an untyped event or a binding that is no variable
    held = type_of_declared(var.type)
    if Kind.ANY in (want.kind, held.kind):
        return
    if want.kind is not held.kind or not same_shape(want.shape, held.shape) or \
            _narrower(var.type, _event_decl(m, ref).type):
        sent, kept = (type_to_notation(d.type) for d in (_event_decl(m, ref), var))
        types.error(ref, f"{where}: '${_text(ref)}?{ref.binding}' binds the value of event "
                    f"{_text(ref)} ({sent}) to '{ref.binding}', a variable of type {kept}",
                    f"bind a variable of type {sent} (a nat is an int, an int a real)")


#: RoboChart's numeric types, each a subtype of the next: a nat is an int, an int a real.
_NUMERIC_RANK = {"nat": 0, "int": 1, "real": 2}


def _narrower(held: ast.TypeRef | None, sent: ast.TypeRef | None) -> bool:
    """A variable of ``held`` cannot take every value of ``sent`` (a real bound to an int,
    an int to a nat). Both types are declared, so this is exact, unlike an expression's
    kind, which STM8 infers without telling the numbers apart."""
    if not (isinstance(held, ast.PrimitiveType) and isinstance(sent, ast.PrimitiveType)):
        return False
    h, s = _NUMERIC_RANK.get(held.name), _NUMERIC_RANK.get(sent.name)
    return h is not None and s is not None and h < s


def _event_decl(m: Machine, ref: ex.PlatformRef) -> ast.EventDecl:
    return m.platform.input_events[ref.name[-1]]


def _text(e: ex.Expr) -> str:
    return e.text if isinstance(e, (ex.Name, ex.PlatformRef)) else "the target"


@rule("STM9", "a cycleDef gives the cycle a positive period")
def check_STM9_positive_cycle(ctx: WFContext) -> None:
    """``cycleDef cycle == 0`` (or a negative period) in a module, controller or machine: a
    cycle that takes no time runs the machine infinitely often per time unit, and the
    semantics' and the simulator's clocks divide by it. The period is evaluated with the
    constants in scope (``cycleDef cycle == P``); one that needs a constant without a value
    is left to the commands that are given it."""
    for file, item in ((f, i) for f in ctx.files() for i in f.items):
        holders = [item, *getattr(item, "members", ())] if isinstance(item, ast.Controller) \
            else [item]
        for holder in holders:
            if not isinstance(holder, (ast.Module, ast.Controller, ast.StateMachine)):
                continue
            for c in (m for m in holder.members if isinstance(m, ast.CycleDef)):
                e = c.expr
                if not (isinstance(e, ex.BinOp) and e.op == "==" and
                        e.left == ex.Name(("cycle",))):
                    continue
                value, _ = evaluate_in(ctx, file, {}, e.right)
                if isinstance(value, (int, float)) and not isinstance(value, bool) and \
                        value <= 0:
                    ctx.error("STM9", e.right, f"the cycle of {holder.name} is {value:g}: a "
                              "cycle takes a positive time", "write 'cycleDef cycle == 1' "
                              "(one time unit), or the period in time units")
