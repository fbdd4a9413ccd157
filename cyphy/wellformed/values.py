"""Value checks the paper leaves as future work: V1-V5 (on the elaborated model).

They need numbers, so they run on the elaborated top-level p-models (constants from the model
and ``--const``), and each looks only at values that could be computed: an element whose
value depends on a constant without a value is skipped, never guessed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from cyphy import progress
from cyphy.diagnostics import Code, Report, Severity
from cyphy.lang import ast
from cyphy.model.array import Array
from cyphy.model.choose import top_level_pmodels
from cyphy.model.device_names import RELATION
from cyphy.model.elaborate import INDEX, elaborate_pmodel
from cyphy.model.environment import EVAL
from cyphy.model.inertia import is_physical
from cyphy.model.mesh_paths import outside_model_folder
from cyphy.wellformed.registry import WFContext, rule
from cyphy.wellformed.value_spans import axis_span, inertia_span, mass_span

GEOMETRY_TOL = 1e-9
#: How far from 1 an AXIS's length may be: a direction written to three digits
#: ((|0.707, 0.707, 0|), length 0.99985) is the unit vector its writer meant, and scales the
#: joint's speed by less than 0.1%; (|0, 2, 0|) is a mistake.
UNIT_TOL = 1e-3


def _models(ctx: WFContext) -> list[Any]:
    """The elaborated top-level p-models, built once per check run (cached on the context).
    Of the elaboration's diagnostics, those about values that cannot be computed (``E-EVAL``:
    division by zero, overflow, a constant defined in terms of itself) and ranges that make
    too many copies (``E-INDEX``) are reported, so that
    ``cyphy check`` rejects what the generators reject; the others (a model that cannot be
    chosen, constants without values) concern generation only. Evaluation errors are reported
    when the model has no other errors, as ``gen`` reports them."""
    if "elaborated" not in ctx.cache:

        models = []
        for pm, f in top_level_pmodels(ctx.workspace):
            progress.stage(f"elaborating {pm.name}")
            scratch = Report()
            models.append(elaborate_pmodel(ctx.workspace, ctx.resolution, scratch, pm, f,
                                           ctx.consts, devices=False))
            # After other errors, these are often their consequence (a boolean given for a
            # real constant: P3, then E-EVAL; a real bound: IX1, then E-INDEX): `gen` reports
            # them only once the model has no other errors, and so does `check`.
            if not any(d.severity is Severity.ERROR for d in ctx.report.reported_since(0)):
                ctx.report.extend(d for d in scratch.reported_since(0)
                                  if d.code is EVAL or d.code is INDEX)
            # A relation that names every copy of a block (E-RELATION) is structural: no
            # other error causes it, and gen refuses it whatever else holds.
            ctx.report.extend(d for d in scratch.reported_since(0) if d.code is RELATION)
        ctx.cache["elaborated"] = models
    return ctx.cache["elaborated"]


def _number(v: object) -> float | None:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    return float(v)


@rule("V1", "masses are positive; inertia matrices are positive definite and satisfy the "
      "triangle inequalities")
def check_V1_physical_inertia(ctx: WFContext) -> None:
    """Every mass given (link or body) is positive, and every inertia matrix given is
    symmetric positive definite with ixx + iyy >= izz and its permutations: simulators
    invert the tensor and reject or explode on anything else."""

    for m in _models(ctx):
        for element, inertial, what in _given_inertials(m):
            if inertial.mass <= 0:
                ctx.error("V1", mass_span(ctx, element), f"the mass of {what} "
                          f"{element.name} is {inertial.mass:g}", "masses must be positive")
            elif any(inertial.inertia) and not is_physical(inertial.inertia):
                entries = " ".join(f"{v:g}" for v in inertial.inertia)
                ctx.error("V1", inertia_span(ctx, element), f"the inertia matrix of {what} "
                          f"{element.name} ({entries}) is not positive definite or breaks a "
                          "triangle inequality",
                          "check the entries: ixx + iyy >= izz, ixx + izz >= iyy, "
                          "iyy + izz >= ixx, all moments positive")


def _given_inertials(m: Any) -> Iterator[tuple[Any, Any, str]]:
    for link in m.links:
        if link.inertial is not None and link.inertial_source == "link":
            yield link, link.inertial, "link"
    for body in m.bodies:
        if body.inertial is not None:
            yield body, body.inertial, "body"


#: A zero size: degenerate but loadable (libsdformat and PyBullet accept a box of height 0,
#: and RoboTool writes the marXbot's track plates so); a negative one is an error.
_V2_ZERO = Code("V2", Severity.WARNING, "a geometry has a zero size")
#: A mesh outside the model's folder: not part of the model (see cyphy/model/mesh_paths.py).
_V2_OUTSIDE = Code("V2", Severity.WARNING, "a mesh lies outside the model's folder")


@rule("V2", "geometry sizes are positive (zero: a warning); meshes exist in the model's folder")
def check_V2_geometry(ctx: WFContext) -> None:
    """A negative size cannot be simulated; a zero size (a plate of height 0, as the
    marXbot's tracks) is degenerate but simulators load it: a warning. A mesh file must exist,
    relative to the model's folder; a mesh outside that folder (an absolute path, ``..``, a
    URL) is a warning, and whether it exists is not looked at, so that no diagnostic tells
    which files exist elsewhere on this machine."""

    for m in _models(ctx):
        for body in m.bodies:
            if isinstance(body.geometry, ast.Shape):
                for name, value in body.size.items():
                    v = _number(value)
                    if v is not None and v < 0:
                        arg = body.geometry.arg(name)
                        where = arg.span if arg is not None else body.span
                        ctx.error("V2", where, f"the {body.geometry.kind} of body {body.name} "
                                  f"has {name} = {v:g}", f"give the {body.geometry.kind} a "
                                  f"positive {name}")
                    elif v == 0:
                        ctx.report.report(_V2_ZERO, f"the {body.geometry.kind} of body "
                                          f"{body.name} has {name} = 0: it has no volume",
                                          body.span, "simulators load it, but it cannot "
                                          f"collide as a solid; give it a positive {name} "
                                          "unless a flat plate is meant")
            elif isinstance(body.geometry, ast.Mesh):
                uri = body.mesh_uri
                outside = outside_model_folder(uri) if uri else None
                if uri and outside:
                    ctx.report.report(_V2_OUTSIDE, f"the mesh of body {body.name} is "
                                      f"{outside} ('{_shown(uri)}'), outside the model's "
                                      "folder: the generated files refer to it as written",
                                      body.span, "copy the mesh into the model's folder and "
                                      "give its path relative to it, or a model:// URI")
                elif uri and not _mesh_exists(uri, body.span.file):
                    ctx.error("V2", body, f"the mesh '{uri}' of body {body.name} does not "
                              "exist", "give a path relative to the model's folder, or a "
                              "model:// URI")
                scale = _number(body.size.get("scaling"))
                if scale is not None and scale <= 0:
                    ctx.error("V2", body, f"the mesh of body {body.name} is scaled by "
                              f"{scale:g}", "give a positive scaling")


def _shown(text: str, limit: int = 80) -> str:
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _mesh_exists(uri: str, model_file: str) -> bool:
    """Whether a mesh inside the model's folder exists (``outside_model_folder`` is None)."""
    if "://" in uri:
        return True  # model:// and package:// URIs are resolved by the simulator
    return (Path(model_file).parent / uri).exists()


SURFACE_RANGES = {
    "restitution_coefficient": (0.0, 1.0),
    "threshold": (0.0, math.inf),
    "coefficient1": (0.0, math.inf),
    "coefficient2": (0.0, math.inf),
    "slip1": (0.0, math.inf),
    "slip2": (0.0, math.inf),
    "laser_retro": (0.0, math.inf),
    "transparency": (0.0, 1.0),
}


@rule("V3", "ratios lie in [0, 1]; friction and restitution coefficients are non-negative")
def check_V3_surface_ranges(ctx: WFContext) -> None:
    """Restitution coefficients and transparency are ratios in [0, 1]; friction
    coefficients, slips, thresholds and laser retro-reflection are non-negative."""
    for m in _models(ctx):
        for body in m.bodies:
            for name, value in body.surface.items():
                v, bounds = _number(value), SURFACE_RANGES.get(name)
                if v is None or bounds is None:
                    continue
                lo, hi = bounds
                if not lo <= v <= hi:
                    where = "[0, 1]" if hi == 1.0 else "non-negative"
                    ctx.error("V3", body, f"{name} of body {body.name} is {v:g}",
                              f"{name} must be {where}")


@rule("V4", "a joint's axis constant and its annotation's xyz agree", Severity.WARNING)
def check_V4_axis_agreement(ctx: WFContext) -> None:
    """The joint's ``AXIS`` constant (the equations' axis) and the ``xyz`` of its annotation
    (the simulator's axis) describe the same unit direction. Given twice, the two drift apart
    silently: the simulation then moves about another axis than the one the proofs assume.
    A zero axis is V6's error, not compared here."""
    for m in _models(ctx):
        for joint in m.joints:
            if joint.target_copy:
                continue
            axis = _vector(joint.axis)
            xyz = _vector(_annotation_xyz(joint.annotation))
            if axis is None or xyz is None:
                continue
            na, nx = math.hypot(*axis), math.hypot(*xyz)
            if na < GEOMETRY_TOL or nx < GEOMETRY_TOL:
                continue
            if not _allclose([a / na for a in axis], [x / nx for x in xyz]):
                ctx.error("V4", axis_span(ctx, joint, True), f"joint {joint.name}: AXIS "
                          f"{_fmt(axis)} and the "
                          f"annotation's xyz {_fmt(xyz)} are different directions",
                          "make instantiation AXIS and annotation axis xyz agree")


@rule("V6", "a joint's axis (its AXIS constant, its annotation's xyz) is not the zero vector; "
      "its AXIS is a unit vector")
def check_V6_nonzero_axis(ctx: WFContext) -> None:
    """A joint turns or slides along a direction: a zero axis has none. It is an error, not a
    warning: the joint's equations lose their motion subspace, and SDFormat rejects the
    ``<axis><xyz>0 0 0</xyz>`` that ``gen --sdf`` would write (libsdformat: "The norm of the
    xyz vector cannot be zero"). The AXIS constant is also a unit vector: the library's joint
    equations use it as written (``fV == pV + A * v``, ``A = ScrewAxis(AXIS, …)``), so
    ``(|0, 2, 0|)`` would turn the child twice as fast as the angle ``theta`` grows, while
    the equations of motion and SDFormat take the direction normalised. (The annotation's
    ``xyz`` is a direction for the simulator alone, which normalises it.)"""
    for m in _models(ctx):
        for joint in m.joints:
            if joint.target_copy:
                continue
            for what, value in (("the AXIS constant", joint.axis),
                                ("the annotation's xyz", _annotation_xyz(joint.annotation))):
                v = _vector(value)
                if v is not None and math.hypot(*v) < GEOMETRY_TOL:
                    ctx.error("V6", axis_span(ctx, joint, what == "the AXIS constant"),
                              f"{what} of joint {joint.name} is the zero vector",
                              "give the joint a non-zero axis, e.g. xyz = (|0, 0, 1|)")
                elif v is not None and what == "the AXIS constant" and \
                        abs(math.hypot(*v) - 1) > UNIT_TOL:
                    length = math.hypot(*v)
                    ctx.error("V6", axis_span(ctx, joint, True),
                              f"the AXIS constant of joint {joint.name} is {_fmt(v)}, of length "
                              f"{length:g}: the joint's equations would move it {length:g} "
                              "times as fast as its coordinate",
                              f"write the unit vector {_fmt([x / length for x in v])}")


def _annotation_xyz(annotation: Any) -> Any:
    if annotation is None:
        return None
    axis = annotation.get("axis")
    return axis.get("xyz") if hasattr(axis, "get") else None


def _vector(v: Any) -> tuple[float, float, float] | None:
    """``v`` as three floats, or None when it is not a 3-vector. Plain floats, not an array:
    the check does a few operations per joint, where NumPy's per-call cost dominates."""

    if isinstance(v, Array) and v.size == 3:
        x, y, z = v.flat
        return (x, y, z)
    return None


def _allclose(a: list[float], b: list[float], rtol: float = 1e-5, atol: float = 1e-9) -> bool:
    """``numpy.allclose(a, b, rtol, atol)`` for short vectors."""
    return all(abs(x - y) <= atol + rtol * abs(y) for x, y in zip(a, b))


def _fmt(v: Any) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


@rule("V5", "no two links, and no two bodies of a link, at the same place with the same shape",
      Severity.WARNING)
def check_V5_coincident(ctx: WFContext) -> None:
    """Two links (or two bodies of one link) with the same shape at the same place after all
    poses are composed are almost always a copy-and-paste slip (the paper's firefighter drone
    had two rotor arms at the same coordinates, found only by eye in Gazebo)."""
    for m in _models(ctx):
        for first, again in coincident(m):
            what, hint = ("links", "move one of them (check the poses of the links and of the "
                          "parts that contain them)") if hasattr(first, "bodies") else \
                ("bodies", "move one of them, or remove the duplicate")
            ctx.error("V5", again, f"{what} {first.name} and {again.name} have the same shape "
                      "at the same place", hint)


def coincident(model: Any) -> list[tuple[Any, Any]]:
    """V5's pairs in an elaborated model: (earlier, later) links, then bodies of one link,
    with the same shape at the same place (``cyphy view`` draws them highlighted)."""
    body_keys = {id(b): _body_key(b) for b in model.bodies}  # each body's key, once
    pairs = _coincident(model.links, lambda link: _link_key(link, body_keys))
    for link in model.links:
        if len(link.bodies) > 1:
            pairs += _coincident(link.bodies, lambda body: body_keys[id(body)])
    return pairs


def _coincident(elements: list[Any], key_of: Callable[[Any], Any]) -> list[tuple[Any, Any]]:
    """Each element whose (shape, place) key an earlier one already has, with that one."""
    seen: dict[Any, Any] = {}
    pairs = []
    for element in elements:
        key = key_of(element)
        if key is None:
            continue
        if key in seen:
            pairs.append((seen[key], element))
        else:
            seen[key] = element
    return pairs


def _rounded(values: Any) -> tuple[float, ...]:
    return tuple(round(float(v), 9) + 0.0 for v in values)


def _body_key(body: Any) -> Any:
    if body.pose is None or not body.size or any(_number(v) is None and v is not None
                                                 for v in body.size.values()):
        return None
    shape = body.geometry.kind if isinstance(body.geometry, ast.Shape) else body.mesh_uri
    size = tuple(sorted((k, _number(v)) for k, v in body.size.items()))
    return (shape, size, _rounded(body.pose.position),
            _rounded(x for row in body.pose.rotation for x in row))


def _link_key(link: Any, body_keys: dict[int, Any]) -> Any:
    if link.pose is None or not link.bodies:
        return None
    bodies = [body_keys[id(b)] for b in link.bodies]
    if any(b is None for b in bodies):
        return None
    return (_rounded(link.pose.position), _rounded(x for row in link.pose.rotation for x in row),
            tuple(sorted(bodies, key=repr)) if len(bodies) > 1 else tuple(bodies))

