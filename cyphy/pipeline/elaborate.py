"""Checked files to one elaborated p-model: the stage every dynamic and geometric output
starts from."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from cyphy.deep import deep
from cyphy.diagnostics import Report
from cyphy.model.default_inertial import apply_default_inertial
from cyphy.model.elaborate import elaborate as run
from cyphy.model.elements import ElaboratedModel
from cyphy.pipeline.check import CheckOptions, CheckResult, check


@dataclass(frozen=True)
class ElaborateOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    despite_value_errors: bool = False  # `cyphy show`: elaborate a model with V1-V5/E-EVAL
    # Links without inertial information get these defaults ("sdf": SDFormat's), with a
    # warning each (cyphy.model.default_inertial); None: they stay without mass.
    default_inertial: str | None = None
    # a ``consts`` name that names no constant of the model is an error (E-CONST-NAME); a
    # scenario's [consts] also hold call arguments, which are no constants
    strict_consts: bool = True


@dataclass
class ElaborateResult:
    check: CheckResult
    model: ElaboratedModel | None

    @property
    def report(self) -> Report:
        return self.check.report


@deep
def elaborate(paths: Sequence[str | Path], options: ElaborateOptions = ElaborateOptions()
              ) -> ElaborateResult:
    """Check the files, then elaborate one p-model. The model is None when the files have
    errors (generation must not run on them) or no p-model can be chosen."""
    # With the constants given (--const, a scenario's [consts]): the checks that need a
    # constant's value (IX5's index ranges, STM9's cycle, the value checks) decide then.
    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts), find_in_folder="pmodel"))
    if checked.resolution is None or (checked.report.has_errors and not (
            options.despite_value_errors
            and all(_value_error(d) for d in checked.report.errors))):
        return ElaborateResult(checked, None)
    model = run(checked.workspace, checked.resolution, checked.report, options.model,
                options.consts, options.strict_consts)  # type: ignore[arg-type]
    if any(d.code.id in ("E-CONST-NAME", "E-OPTION") for d in checked.report.errors):
        return ElaborateResult(checked, None)  # a misspelt --const: nothing is shown
    if model is not None and options.default_inertial is not None:
        apply_default_inertial(model, checked.report, options.default_inertial)
    return ElaborateResult(checked, model)


def _value_error(d: Any) -> bool:
    """Whether an error concerns only values (``V1``-``V5``, ``E-EVAL``): the model can
    still be elaborated and shown, with the error reported; generators refuse it."""
    return d.code.id == "E-EVAL" or re.fullmatch(r"V\d+", d.code.id) is not None
