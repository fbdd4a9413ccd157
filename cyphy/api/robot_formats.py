"""The geometric exports of one p-model: SDF (``--sdf``), URDF and MJCF (``--urdf``,
``--mjcf``), and the trees of links they share."""

from __future__ import annotations

import os
from dataclasses import field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from cyphy.deep import deep
from cyphy.pipeline.generated import Generated
from cyphy.pipeline.geometric import geometric_model
from cyphy.records import record

if TYPE_CHECKING:
    from cyphy.model.elements import ElaboratedModel


@record(slots=False)
class SdfGenOptions:
    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pose: tuple[float, float, float, float, float, float] = (0.0,) * 6
    short_names: bool = False
    target: str = "gazebo"  # or "coppeliasim", "pybullet", "drake"
    gazebo_model: bool = False  # files model.sdf and model.config instead of <Model>.sdf
    split_trees: bool = False  # a <world> with one <model> per tree of links


@deep
def generate_sdf(paths: Sequence[str | Path], options: SdfGenOptions = SdfGenOptions()
                 ) -> Generated:
    """SDF 1.6 for one p-model (``cyphy gen --sdf``): ``<Model>.sdf`` and the name table
    ``<Model>.names.json``, or, for a Gazebo model folder, ``model.sdf``, ``model.config``
    and the table. No files when the model has errors or constants without values."""
    # lazy: each export loads its own back end (the tree formats' import NumPy, SDF's not)
    from cyphy.backends.robot_formats.sdf_xml import model_config, names_json, to_xml
    from cyphy.semantics.sdf.rules import translate
    from cyphy.semantics.sdf.translation import SdfOptions

    checked, generated, model = geometric_model(paths, options.model, options.consts,
                                                 options.search_paths, "SDF generation")
    if model is None:
        return generated
    document = translate(model, checked.workspace, checked.report,
                         SdfOptions(options.pose, options.short_names, options.target,
                                    options.split_trees))
    text = to_xml(document.root)
    if options.gazebo_model:
        generated.files = {"model.sdf": text, "model.config": model_config(model.name),
                           f"{model.name}.names.json": names_json(document.names)}
    else:
        generated.files = {f"{model.name}.sdf": text,
                           f"{model.name}.names.json": names_json(document.names)}
    return generated


@record(slots=False)
class TreeGenOptions:
    """Options of the tree exports (``--urdf``, ``--mjcf``)."""

    model: str | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    output: str | None = None  # the output folder, to write mesh paths relative to it
    package: str | None = None  # mesh paths as package://PACKAGE/… (URDF)
    free_base: bool = False  # MJCF: each tree's root gets a free joint


@deep
def robot(paths: Sequence[str | Path], options: TreeGenOptions, target: str
          ) -> tuple[Generated, Any, Any]:
    """The checked model as trees of links for ``target`` (``urdf``, ``mjcf``):
    ``(generated, robot or None, elaborated model)``. A mesh outside the model's folder is
    V2's warning, reported by the check for every target."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.semantics.sdf.robot_tree import build_robot

    checked, generated, model = geometric_model(paths, options.model, options.consts,
                                                 options.search_paths,
                                                 f"{target.upper()} generation")
    if model is None:
        return generated, None, None
    built = build_robot(model, checked.workspace, checked.report, target)
    return generated, built, model


def _mesh_paths(options: TreeGenOptions, model: "ElaboratedModel") -> Any:
    """Mesh paths as the export names them: from the output folder to the model's."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.robot_formats.urdf import MeshPaths

    folder = Path(model.pmodel.span.file).resolve().parent
    out = Path(options.output).resolve() if options.output else folder
    return MeshPaths(Path(os.path.relpath(folder, out)).as_posix(), options.package)


@deep
def generate_urdf(paths: Sequence[str | Path], options: TreeGenOptions = TreeGenOptions()
                  ) -> Generated:
    """URDF 1.0 (``cyphy gen --urdf``): ``<Model>.urdf``, or one ``<Model>__<Root>.urdf`` per
    tree of links, and the name table. Loops are cut as for ``--target pybullet``."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.robot_formats.names import complete_names
    from cyphy.backends.robot_formats.sdf_xml import names_json, to_xml
    from cyphy.backends.robot_formats.urdf import robot_to_urdf

    generated, built, model = robot(paths, options, "urdf")
    if built is None:
        return generated
    report = generated.report
    files = robot_to_urdf(built, _mesh_paths(options, model), report, model.pmodel.span)
    if report.has_errors:
        return generated
    generated.files = {name: to_xml(node) for name, node in files.items()}
    generated.files[f"{built.name}.names.json"] = names_json(
        complete_names(_names(built), files.values()))
    return generated


@deep
def generate_mjcf(paths: Sequence[str | Path], options: TreeGenOptions = TreeGenOptions()
                  ) -> Generated:
    """MuJoCo's MJCF (``cyphy gen --mjcf``): ``<Model>.xml`` with every tree of links, a
    motor per driven joint, loops closed by equality constraints; and the name table."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.robot_formats.mjcf import robot_to_mjcf
    from cyphy.backends.robot_formats.names import complete_names
    from cyphy.backends.robot_formats.sdf_xml import names_json, to_xml

    generated, built, model = robot(paths, options, "mjcf")
    if built is None:
        return generated
    report = generated.report
    root = robot_to_mjcf(built, _mesh_paths(options, model), report, model.pmodel.span,
                         options.free_base)
    if report.has_errors:
        return generated
    generated.files = {f"{built.name}.xml": to_xml(root),
                       f"{built.name}.names.json":
                       names_json(complete_names(_names(built), [root]))}
    return generated


def _names(built: Any) -> dict[str, str]:
    """Exported link and joint names → qualified RoboSim names."""
    table = {link.name: link.qualified for link in built.links().values()}
    table.update((j.name, j.qualified) for j in built.joints())
    return table
