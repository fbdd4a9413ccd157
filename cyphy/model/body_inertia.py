"""The inertia of a body that gives a mass and a shape but no matrix, and of a link that gives
only a mass: its mass spread over its bodies by volume. Shared by elaboration and by the SDF
translation, which spreads a mass-only link the same way."""

from __future__ import annotations

import math

from cyphy.lang import ast
from cyphy.model import inertia as inertia_math
from cyphy.model.elements import Body


def solid_inertia(body: Body, mass: float) -> inertia_math.InertiaEntries | None:
    """The solid inertia of a body's geometry, for a body that gives a mass and no matrix."""
    size = body.size
    shape = body.geometry.kind if isinstance(body.geometry, ast.Shape) else None
    try:
        if shape == "box":
            return inertia_math.solid_box(mass, float(size["length"]), float(size["width"]),
                                          float(size["height"]))
        if shape == "cylinder":
            return inertia_math.solid_cylinder(mass, float(size["radius"]),
                                               float(size["length"]))
        if shape == "sphere":
            return inertia_math.solid_sphere(mass, float(size["radius"]))
    except (KeyError, TypeError, ValueError):
        return None
    except OverflowError:  # a size near 1e155 squared: the caller reports it
        return (math.inf,) * 6
    return None


def volume(body: Body) -> float | None:
    size, shape = body.size, body.geometry.kind if isinstance(body.geometry, ast.Shape) else None
    try:
        if shape == "box":
            return float(size["length"]) * float(size["width"]) * float(size["height"])
        if shape == "cylinder":
            return 3.141592653589793 * float(size["radius"]) ** 2 * float(size["length"])
        if shape == "sphere":
            return 4 / 3 * 3.141592653589793 * float(size["radius"]) ** 3
    except (KeyError, TypeError, ValueError):
        return None
    return None


def distribute_mass(own: inertia_math.Inertial, bodies: list[Body]
                ) -> inertia_math.Inertial | None:
    """A link that gives only a mass: spread it over its bodies by volume and combine their
    solid inertias (the centre of mass follows the geometry)."""
    volumes = [(volume(b), b) for b in bodies]
    total = sum(v for v, _ in volumes if v)
    if own.mass <= 0 or total <= 0 or any(v is None or v <= 0 or b.pose is None
                                           for v, b in volumes):
        return None
    parts = []
    for v, b in volumes:
        mass = own.mass * (v or 0.0) / total
        solid = solid_inertia(b, mass)
        if solid is None or b.pose is None:
            return None
        parts.append(inertia_math.Inertial(mass, b.pose, solid))
    return inertia_math.combine(parts) if parts else None
