"""Which of the platform's events a module carries to each of its machines.

RoboChart delivers an event only along a connection: the module connects its robotic
platform's ``e`` to a controller, and the controller connects its ``e`` to the machine. An
event the machine's input context uses but no such pair of connections carries never occurs
for that machine. ``check`` warns about it (STM11, at the machine's read), and every command
that runs the machine (``simulate``, ``reach``, the theory's ``D`` and so ``animate``) takes
the event as absent, from the one function here: what the warning says is what they do.
"""

from __future__ import annotations

from typing import Any, Iterable, Iterator

from cyphy.lang import ast


def module_machines(files: Iterable[ast.SourceFile], resolution: Any
                    ) -> Iterator[tuple[ast.Module, str, ast.Controller, str,
                                        ast.StateMachine]]:
    """Every machine a module of the files runs: ``(module, controller's name in the
    module, controller, machine's name in the controller, machine)``."""
    for f in files:
        for module in f.items:
            if isinstance(module, ast.Module):
                for run in machines_run_by(module, resolution):
                    yield (module, *run)


def machines_run_by(module: ast.Module, resolution: Any
                    ) -> Iterator[tuple[str, ast.Controller, str, ast.StateMachine]]:
    """The machines the module runs, in the order it declares its controllers and they
    their machines: ``(controller's name in the module, controller, machine's name in the
    controller, machine)``, the names being those the connections use (a ``cref``'s or
    ``sref``'s own name, else the declaration's)."""
    for ctrl_name, ctrl in controllers_of(module, resolution):
        for stm_name, stm in machines_of_controller(ctrl, resolution):
            yield ctrl_name, ctrl, stm_name, stm


def controllers_of(module: ast.Module, resolution: Any) -> Iterator[tuple[str, ast.Controller]]:
    """The module's controllers, inline or by ``cref``, with their names in the module."""
    for m in module.members:
        if isinstance(m, ast.Controller):
            yield m.name, m
        elif isinstance(m, ast.NodeRef) and isinstance(resolution.get(m), ast.Controller):
            yield m.name, resolution.get(m)


def machines_of_controller(ctrl: ast.Controller, resolution: Any
                           ) -> Iterator[tuple[str, ast.StateMachine]]:
    """The controller's machines, inline then by ``sref``, with their names in it."""
    for stm in ctrl.machines:
        yield stm.name, stm
    for ref in ctrl.machine_refs:
        target = resolution.get(ref)
        if isinstance(target, ast.StateMachine):
            yield ref.name, target


def _connected(container: object, source: str, event: str, target: str) -> bool:
    return any(isinstance(c, ast.Connection) and c.source == source and
               c.source_event == event and c.target == target
               for c in getattr(container, "members", ()))


def missing_connection(module: ast.Module, ctrl_name: str, ctrl: ast.Controller,
                       stm_name: str, event: str) -> tuple[str, str] | None:
    """None when the module carries its platform's ``event`` to the controller and the
    controller carries it to the machine (or the module has no platform: nothing to carry);
    else where a connection is missing (``module M``, ``controller C``) and the connection
    to add there."""
    platform = module.platform
    if platform is None:
        return None
    if not _connected(module, platform.name, event, ctrl_name):
        return (f"module {module.name}",
                f"{platform.name} on {event} to {ctrl_name} on {event} (_async)")
    if not _connected(ctrl, ctrl.name, event, stm_name):
        return f"controller {ctrl.name}", f"{ctrl.name} on {event} to {stm_name} on {event}"
    return None


def unconnected_events(files: Iterable[ast.SourceFile], resolution: Any,
                       stm: ast.StateMachine, events: Iterable[str],
                       modules: set[int] | None = None) -> frozenset[str]:
    """Those of ``events`` (the input events of the machine ``stm``) that no connection
    carries to it, in the modules that run it (those whose ids are in ``modules``, when
    given: the module mapped onto the simulated p-model). A machine no module runs reads
    its events as they come: there is no module to connect them."""
    events = tuple(events)
    out: set[str] = set()
    for module, ctrl_name, ctrl, stm_name, target in module_machines(files, resolution):
        if target is not stm or modules is not None and id(module) not in modules:
            continue
        out.update(e for e in events
                   if missing_connection(module, ctrl_name, ctrl, stm_name, e) is not None)
    return frozenset(out)
