"""A module and what it runs: one cycle (STM10), the platform's events carried to the
machines that read them (STM11), and the interfaces the controllers pass on (STM12).

A module runs its controllers' machines together. cyphy's semantics has one ``cycle`` per
module (semantics.md, Rule 1 and the main action: ``Wait(cycle)`` then ``Evolve`` until the
timer reaches ``cycle × tscale``), taken from the module's ``cycleDef``; the simulator runs
each machine with its own ``cycleDef``. A controller or machine whose cycle differs from its
module's would be run at one period by ``simulate`` and at another in the theory, and
machines of different cycles cannot be composed (``gen --isabelle`` refused them late, with
no place in the model): ``check`` refuses them at the ``cycleDef``.

RoboChart delivers an event only along a connection: a platform event that no connection of
the module carries to the controller (and no connection of the controller to the machine)
never reaches the machine: ``check`` warns at the machine's read, and every command takes
the event as absent (:mod:`cyphy.model.connections`, shared with the semantics).

A machine's ``requires I`` is met by its controller, which ``requires I`` of the platform
in turn: a controller that does not require it gives the machine nothing to call or write
(RoboChart's composition). ``check`` refuses the machine's first use of ``I``, with the
controller's missing line as the hint.
"""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Severity
from cyphy.lang import ast
from cyphy.model.connections import (controllers_of, machines_of_controller,
                                     missing_connection, module_machines)
from cyphy.model.machines import Machine, expressions, statements
from cyphy.wellformed.indexing import evaluate_in
from cyphy.wellformed.machines import callee_of, checked_machines, root
from cyphy.wellformed.registry import WFContext, rule

def _cycle(holder: object) -> ex.Expr | None:
    """``e`` of the holder's ``cycleDef cycle == e`` (None without one)."""
    for c in getattr(holder, "members", ()):
        if isinstance(c, ast.CycleDef) and isinstance(c.expr, ex.BinOp) and \
                c.expr.op == "==" and c.expr.left == ex.Name(("cycle",)):
            return c.expr.right
    return None


def _modules(ctx: WFContext) -> Iterator[tuple[ast.SourceFile, ast.Module]]:
    for f in ctx.files():
        for item in f.items:
            if isinstance(item, ast.Module):
                yield f, item


def _period(ctx: WFContext, holder: object, outer: object) -> float | None:
    """The holder's period, evaluated in its file (an inline machine's is its
    controller's, ``outer``); None without a cycleDef or without a computable value."""
    e = _cycle(holder)
    file = ctx.file_of(holder) or ctx.file_of(outer)
    if e is None or file is None:
        return None
    value, _ = evaluate_in(ctx, file, {}, e)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None  # a constant without a value: the commands given it judge
    return float(value)


@rule("STM10", "a module's controllers and machines run with the module's cycle")
def check_STM10_one_cycle(ctx: WFContext) -> None:
    """Each controller's and machine's ``cycleDef`` gives the module's period (or, when the
    module has none, the first one given): the semantics has one cycle per module."""
    for _, module in _modules(ctx):
        period = _period(ctx, module, module)
        owner = f"module {module.name}"
        for _, ctrl in controllers_of(module, ctx.resolution):
            holders: list[ast.Controller | ast.StateMachine] = [ctrl]
            holders += [stm for _, stm in machines_of_controller(ctrl, ctx.resolution)]
            for holder in holders:
                own = _period(ctx, holder, ctrl)
                if own is None or own == period:
                    continue
                if period is None:
                    period, owner = own, f"{machine_kind(holder)} {holder.name}"
                    continue
                ctx.error("STM10", _cycle(holder), f"the cycle of {machine_kind(holder)} "
                          f"{holder.name} is {own:g} time units, but {owner}'s is "
                          f"{period:g}: module {module.name} runs its controllers and "
                          "machines with one cycle", f"write 'cycleDef cycle == {period:g}', "
                          "and count longer periods with a clock or wait(n)")


def machine_kind(holder: object) -> str:
    return "controller" if isinstance(holder, ast.Controller) else "machine"


@rule("STM11", "the platform's events a machine reads reach it along connections",
      Severity.WARNING)
def check_STM11_events_connected(ctx: WFContext) -> None:
    """A machine reads ``$e`` of its platform: the module connects the platform's ``e`` to
    the machine's controller, and the controller connects its ``e`` to the machine."""
    machines = {id(m.decl): m for m in checked_machines(ctx)}
    for module, ctrl_name, ctrl, stm_name, stm in module_machines(ctx.files(), ctx.resolution):
        m = machines.get(id(stm))
        if m is None:
            continue
        sent = {id(s.event) for s, _ in statements(m) if isinstance(s, ast.SendStatement)}
        warned: set[str] = set()
        for e, where in expressions(m):
            for node in e.walk():
                if not isinstance(node, ex.PlatformRef) or id(node) in sent:
                    continue
                name = node.name[-1]
                if name in warned or name not in m.platform.input_events:
                    continue
                missing = missing_connection(module, ctrl_name, ctrl, stm_name, name)
                if missing is None:
                    continue
                warned.add(name)
                ctx.error("STM11", node, f"{where}: machine {m.name} reads {name}, but "
                          f"{missing[0]} has no connection that carries it there: the event "
                          "never occurs for the machine (simulate, reach and the theory's D "
                          "take it as absent)", f"add 'connection {missing[1]}' to {missing[0]}")


def _requires(ctx: WFContext, holder: object) -> list[tuple[ast.InterfaceUse, ast.Interface]]:
    """The interfaces a controller or machine ``requires`` (a machine's, in its output
    context too), with the line that requires each."""
    uses = [u for u in getattr(holder, "members", ()) if isinstance(u, ast.InterfaceUse)]
    uses += [u for c in getattr(holder, "contexts", ()) for u in c.members
             if isinstance(u, ast.InterfaceUse)]
    return [(u, i) for u in uses if u.relation == "requires"
            and isinstance(i := ctx.target(u), ast.Interface)]


def _first_use(ctx: WFContext, m: Machine, interface: ast.Interface
               ) -> tuple[object, str, str] | None:
    """Where the machine first calls an operation of the interface or assigns or reads one
    of its variables: the node, where it is, and what it does there."""
    operations = {op.name for op in interface.operations}
    variables = {v.name for v in interface.variables if v.kind is ast.DeclKind.VAR}
    variables -= set(m.variables) | set(m.constants)
    for s, where in statements(m):
        if isinstance(s, ast.CallStatement) and isinstance(s.call, ex.Call):
            callee = callee_of(ctx, m, s.call)
            if callee is not None and callee[0] in operations:
                return s, where, f"calls {callee[0]}"
        elif isinstance(s, ast.Assign) and (name := _named(root(s.target))) in variables:
            return s.target, where, f"writes the variable {name}"
    for e, where in expressions(m):
        for node in e.walk():
            if (name := _named(node)) in variables:
                return node, where, f"reads the variable {name}"
    return None


def _named(node: ex.Expr) -> str | None:
    """The name ``x`` or ``$x`` stands for (None for another expression)."""
    return node.name[-1] if isinstance(node, ex.PlatformRef) else \
        node.text if isinstance(node, ex.Name) else None


@rule("STM12", "a controller requires the interfaces whose operations and variables its "
      "machines use")
def check_STM12_controller_requires(ctx: WFContext) -> None:
    """A machine's ``requires I`` reaches the platform through its controller: the
    controller that runs it ``requires I`` too (RoboChart's composition; the corpus's
    controllers all do). Reported at the machine's first call of an operation of ``I`` or
    use of a variable of ``I``, with the controller's missing line as the hint."""
    machines = {id(m.decl): m for m in checked_machines(ctx)}
    for _, _, ctrl, _, stm in module_machines(ctx.files(), ctx.resolution):
        m = machines.get(id(stm))
        if m is None:
            continue
        held = {id(i) for _, i in _requires(ctx, ctrl)}
        for use, interface in _requires(ctx, stm):
            if id(interface) in held:
                continue
            held.add(id(interface))  # once per interface
            found = _first_use(ctx, m, interface)
            if found is None:
                continue
            node, where, what = found
            ctx.error("STM12", node, f"{where}: machine {m.name} {what} of interface "
                      f"{interface.name}, which its controller {ctrl.name} does not require: "
                      "the controller passes the machine only what it requires itself",
                      f"add 'requires {'::'.join(use.interface)}' to controller {ctrl.name}, "
                      f"as machine {m.name} has it (line {use.span.line})")
