"""The interpreter of a machine of the checked files, set up as the commands need it: the
operation definitions it calls, the values of the outside constants it reads, the values a
command gives (``--const``, a scenario's ``[consts]``), the output events no mapping maps.

Kept apart from :mod:`cyphy.semantics.machines.cycle` (the cycle rules) because it reads the
workspace (files, resolution, scopes), which the rules do not.
"""

from __future__ import annotations

from typing import Any, Mapping

from cyphy.lang import ast
from cyphy.model.machines import Machine, global_constants, open_constants, operation_definitions
from cyphy.semantics.machines.cycle import MachineInterpreter
from cyphy.semantics.machines.observable import observable_events


def machine_constants(consts: Mapping[str, object] | None) -> dict[str, object]:
    """The values given (``--const``, a scenario's ``[consts]``) that a machine may read:
    plain numbers and truth values under plain names (``wclose``, ``enabled = true``); a
    qualified name (``Motor::R``) is a p-model block's."""
    return {n: v for n, v in (consts or {}).items() if "::" not in n and
            isinstance(v, (bool, int, float))}


def interpreter_for(machine: Machine, files: list[ast.SourceFile], resolution: Any,
                    scopes: Any, consts: Mapping[str, object] | None = None,
                    pmodel: str | None = None, leave_open: bool = False
                    ) -> MachineInterpreter:
    """The interpreter of a machine of the checked files, with the operation definitions
    it calls, the values of the outside constants they name (``PI``) overridden by
    ``consts``, and, when the machine controls ``pmodel``, its observable output events
    (:func:`observable_events`); ``leave_open``: the constants without a value are left
    open (:attr:`MachineInterpreter.open`) instead of refused."""
    operations = operation_definitions(machine, files, resolution, scopes)
    known: dict[str, object] = {}
    left: dict[str, ast.VarDecl] = {}
    for m in [machine, *operations.values()]:
        known.update(global_constants(m, scopes))
        if leave_open:
            left.update(open_constants(m, scopes, set(consts or {})))
    interpreter = MachineInterpreter(machine, {**known, **(consts or {})},
                                     operations=operations, open_constants=left)
    interpreter.open_origins = _packages_own(left, scopes)
    if pmodel is not None:
        interpreter.observable = observable_events(
            [machine, *operations.values()], files, pmodel)
    return interpreter


def _packages_own(constants: Mapping[str, ast.VarDecl], scopes: Any) -> dict[str, str]:
    """The qualified name (``pkg::fast``) of each of ``constants`` that a package declares,
    by the name the machine reads it with: the names table gives RoboSim's full name."""
    out: dict[str, str] = {}
    for name, decl in constants.items():
        for qname, package in scopes.ws.packages.items():
            if any(d is decl for d in package.members.get(decl.name, ())):
                out[name] = "::".join((*qname, decl.name))
    return out
