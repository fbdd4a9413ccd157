"""The d-model's state machine, ready to run under RoboSim's cycle semantics."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Sequence

from cyphy.deep import deep
from cyphy.diagnostics import Span
from cyphy.lang.scopes import Scopes
from cyphy.model.machines import select_machines
from cyphy.pipeline.check import CheckOptions, CheckResult, check

if TYPE_CHECKING:
    from cyphy.semantics.machines.cycle import MachineInterpreter
    from cyphy.semantics.machines.parallel import ModuleInterpreter


@deep
def machine_interpreter(paths: Sequence[str | Path], name: str | None = None,
                        consts: dict[str, object] | None = None,
                        search_paths: tuple[str, ...] = (), pmodel: str | None = None
                        ) -> tuple["MachineInterpreter | ModuleInterpreter | None", CheckResult]:
    """The d-model's state machine under RoboSim's cycle semantics, ready to run (the
    sampled controller of a simulation), with the operation definitions it calls: the
    machine ``name``, else the one the controller of the module mapped onto ``pmodel``
    runs (all of them together, a :class:`ModuleInterpreter`, when it runs several), else
    the only one. None (with diagnostics,
    code ``E-MACHINE`` for what is not a check) when the files have errors or there is no
    single machine to run."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.semantics.machines.cycle import MACHINE, MachineError
    from cyphy.semantics.machines.interpreters import interpreter_for
    from cyphy.semantics.machines.parallel import ModuleInterpreter

    checked = check(paths, CheckOptions(search_paths=search_paths))
    report = checked.report
    if report.has_errors or checked.resolution is None:
        return None, checked
    machines, (message, hint) = select_machines(list(checked.workspace.user_files()),
                                                checked.resolution, pmodel, name)
    if not machines:
        report.report(MACHINE, message, Span.unknown(str(next(iter(paths), "<input>"))), hint)
        return None, checked
    machine = machines[0]
    try:
        interpreters = []
        for machine in machines:
            interpreters.append(interpreter_for(machine, list(checked.workspace.user_files()),
                                                checked.resolution, Scopes(checked.workspace),
                                                consts, pmodel))
        if len(interpreters) == 1:
            return interpreters[0], checked
        return ModuleInterpreter(interpreters), checked
    except MachineError as err:
        report.report(MACHINE, f"state machine {machine.name}: {err.message}", err.span,
                      err.hint)
        return None, checked
