"""``view``: one p-model drawn headless as a PNG."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from cyphy.deep import deep
from cyphy.diagnostics import Report
from cyphy.pipeline.generated import Generated
from cyphy.pipeline.geometric import geometric_model

if TYPE_CHECKING:
    from cyphy.model.elements import ElaboratedModel


@dataclass(frozen=True)
class ViewRequest:
    """``cyphy view``: which model, its joints' positions (joint → radians or metres; the
    exported name, the qualified name with or without the p-model, or a simple name that
    only one joint has) and the camera."""

    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    positions: dict[str, float] = field(default_factory=dict)
    view: str = "iso"
    elevation: float | None = None
    azimuth: float | None = None


@deep
def view(paths: Sequence[str | Path], request: ViewRequest = ViewRequest()
         ) -> tuple[Generated, Any]:
    """The picture of one p-model (``cyphy view``): ``(generated with <Model>.png, the
    Picture with the bodies' image positions)``; nothing when the model has errors."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.show.view import ViewOptions, render
    from cyphy.semantics.sdf.robot_tree import build_robot
    from cyphy.wellformed.values import coincident

    checked, generated, model = geometric_model(paths, request.model, request.consts,
                                                 request.search_paths, "the picture")
    if model is None:
        return generated, None
    # Cuts and other tree warnings concern the exports, not the picture: not reported.
    built = build_robot(model, checked.workspace, Report(), "urdf")
    positions = _joint_positions(built, request.positions, generated.report, model)
    if generated.report.has_errors:
        return generated, None
    highlighted = {e.name for pair in coincident(model) for e in pair}
    picture = render(built, positions, highlighted, ViewOptions(
        request.view, request.elevation, request.azimuth))
    generated.files = {f"{built.name}.png": picture.png}
    return generated, picture


def _joint_positions(built: Any, given: dict[str, float], report: Report,
                     model: "ElaboratedModel") -> dict[str, float]:
    """``--set`` names to the exported joint names; an unknown or ambiguous name is an
    error (E-VIEW-JOINT) that lists the joints."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.show.view import UNKNOWN_JOINT

    joints = [j for j in built.joints() if j.kind != "fixed"]
    out: dict[str, float] = {}
    for name, value in given.items():
        found = [j for j in joints if name in (j.name, j.qualified)
                 or j.qualified.endswith("::" + name)]
        if len(found) != 1:
            why = "no joint" if not found else f"{len(found)} joints"
            report.report(UNKNOWN_JOINT, f"--set {name}: {why} of {model.name} has that name",
                          model.pmodel.span, "name one of: "
                          + ", ".join(j.qualified for j in joints) or "(it has no joints)")
            continue
        out[found[0].name] = value
    return out
