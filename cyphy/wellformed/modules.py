"""A module and what it runs: one cycle (STM10), and the platform's events carried to the
machines that read them (STM11).

A module runs its controllers' machines together. cyphy's semantics has one ``cycle`` per
module (semantics.md, Rule 1 and the main action: ``Wait(cycle)`` then ``Evolve`` until the
timer reaches ``cycle × tscale``), taken from the module's ``cycleDef``; the simulator runs
each machine with its own ``cycleDef``. A controller or machine whose cycle differs from its
module's would be run at one period by ``simulate`` and at another in the theory, and
machines of different cycles cannot be composed (``gen --isabelle`` refused them late, with
no place in the model): ``check`` refuses them at the ``cycleDef``.

RoboChart delivers an event only along a connection: a platform event that no connection of
the module carries to the controller (and no connection of the controller to the machine)
never reaches the machine, which then waits for it forever; ``simulate`` and the theory
would deliver it all the same. ``check`` warns at the machine's read.
"""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Severity
from cyphy.lang import ast
from cyphy.model.connections import (controllers_of, machines_of_controller,
                                     missing_connection, module_machines)
from cyphy.model.machines import expressions, statements
from cyphy.wellformed.indexing import evaluate_in
from cyphy.wellformed.machines import _machines
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
                    period, owner = own, f"{_kind(holder)} {holder.name}"
                    continue
                ctx.error("STM10", _cycle(holder), f"the cycle of {_kind(holder)} "
                          f"{holder.name} is {own:g} time units, but {owner}'s is "
                          f"{period:g}: module {module.name} runs its controllers and "
                          "machines with one cycle", f"write 'cycleDef cycle == {period:g}', "
                          "and count longer periods with a clock or wait(n)")


def _kind(holder: object) -> str:
    return "controller" if isinstance(holder, ast.Controller) else "machine"


@rule("STM11", "the platform's events a machine reads reach it along connections",
      Severity.WARNING)
def check_STM11_events_connected(ctx: WFContext) -> None:
    """A machine reads ``$e`` of its platform: the module connects the platform's ``e`` to
    the machine's controller, and the controller connects its ``e`` to the machine."""
    machines = {id(m.decl): m for m in _machines(ctx)}
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
