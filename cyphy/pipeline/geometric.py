"""The p-model the geometric exports (SDF, URDF, MJCF, pictures) start from: elaborated, with
every constant the geometry needs valued (the equations' constants may stay without one)."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from cyphy.model.choose import choose_pmodel, require_constants
from cyphy.model.elaborate import elaborate_pmodel
from cyphy.model.elements import ElaboratedModel
from cyphy.pipeline.check import CheckOptions, CheckResult, check
from cyphy.pipeline.generated import Generated
from cyphy.semantics.sdf.rules import unvalued


def geometric_model(paths: Sequence[str | Path], name: str | None,
                     consts: dict[str, object], search_paths: tuple[str, ...], purpose: str
                     ) -> tuple[CheckResult, Generated, ElaboratedModel | None]:
    """Check the files and elaborate one p-model for a geometric export (SDF, URDF, MJCF,
    pictures): the model is None when the files have errors or a constant that geometry
    needs has no value (constants only the equations use may stay without one)."""
    checked = check(paths, CheckOptions(search_paths=search_paths, consts=dict(consts),
                                        find_in_folder="pmodel"))
    generated = Generated(checked.report, checked.sources)
    if checked.report.has_errors or checked.resolution is None:
        return checked, generated, None
    chosen = choose_pmodel(checked.workspace, name, checked.report)
    if chosen is None:
        return checked, generated, None
    model = elaborate_pmodel(checked.workspace, checked.resolution, checked.report, *chosen,
                             consts)  # type: ignore[arg-type]
    if unvalued(model):  # only constants that SDF needs must have values
        needed = {n: spans for n, spans in model.missing.items()
                  if not _device_constant(model, n)} or model.missing
        model.missing = needed
        require_constants(model, checked.report, purpose)
    if checked.report.has_errors:
        return checked, generated, None
    return checked, generated, model


def _device_constant(model: ElaboratedModel, name: str) -> bool:
    """Whether a missing constant (``IR::a``) is a constant of a device's definition: the
    equations need it, SDF only if an annotation uses it."""
    definition, _, const = name.rpartition("::")
    return any(e.definition == definition and e.device is not None
               and e.device.port(const) is not None
               for e in [*model.joints, *model.sensors, *model.actuators])
