"""Mass properties of links and bodies (sdf.md decision 7, the paper's Rule 4).

A link without its own inertial gets one computed from its bodies: each body's mass, centre of mass
and inertia (given, or the solid formula of its geometry) are combined into one rigid body.

Six inertia entries ``(ixx, ixy, ixz, iyy, iyz, izz)`` are components of the inertia tensor
``I = ∫ (|r|²E − r rᵀ) dm``, so the products of inertia carry the minus sign (``ixy = −∫xy dm``):
the convention of SDF's ``<inertia>`` and URDF, which lets them be printed as they are.
"""

from __future__ import annotations

import math
import sys
from typing import Any, Sequence

from cyphy.model.poses import Pose
from cyphy.records import record

InertiaEntries = tuple[float, float, float, float, float, float]

PHYSICAL_TOL = 1e-9
"""Relative tolerance of ``is_physical``: the largest entry scales it, so a flat plate, whose
moments meet the triangle inequality with equality, survives rounding."""


@record
class Inertial:
    """SDF's ``<inertial>``: ``mass`` in kg, ``com`` the pose of the centre-of-mass frame, and
    ``inertia`` about the centre of mass in the axes of ``com``'s rotation (kg·m²).

    No validation here: a model may state unphysical values, and the well-formedness checks report
    them as diagnostics (``is_physical``) instead of failing construction.
    """

    mass: float
    com: Pose
    inertia: InertiaEntries


def solid_box(mass: float, length: float, width: float, height: float) -> InertiaEntries:
    """A uniform box centred on its frame, ``length`` along x, ``width`` along y, ``height``
    along z (SDF's ``<size>`` order)."""
    return _diagonal(
        mass * (width**2 + height**2) / 12.0,
        mass * (length**2 + height**2) / 12.0,
        mass * (length**2 + width**2) / 12.0,
    )


def solid_cylinder(mass: float, radius: float, length: float) -> InertiaEntries:
    """A uniform cylinder centred on its frame with its axis along z, as SDF's ``<cylinder>``."""
    across = mass * (3.0 * radius**2 + length**2) / 12.0
    return _diagonal(across, across, mass * radius**2 / 2.0)


def solid_sphere(mass: float, radius: float) -> InertiaEntries:
    """A uniform ball centred on its frame."""
    moment = 2.0 * mass * radius**2 / 5.0
    return _diagonal(moment, moment, moment)


def combine(parts: Sequence[Inertial]) -> Inertial:
    """The rigid body made of ``parts``, all expressed in one frame.

    Mass adds up; the centre of mass is the mass-weighted mean of the parts' centres; each part's
    tensor is turned into the frame's axes (``R I Rᵀ``) and moved to the combined centre of mass
    by the parallel-axis theorem (``+ m(|d|²E − d dᵀ)``, ``d`` from the combined centre to the
    part's). The result's ``com`` has the identity rotation: its inertia is in the frame's axes.

    Raises ``ValueError`` when the total mass is not positive, since then there is no centre of
    mass; the caller turns that into a diagnostic about the link.

    NumPy computes the sums (its rounding is the one every output was written with), except
    for the commonest case, one body whose axes are the frame's: there ``R I Rᵀ`` is ``I``
    itself, as BLAS sums it (from +0.0, so a ``-0.0`` entry comes out ``0.0``), without
    loading NumPy (an infinite entry takes NumPy's way: ``0·∞`` makes it NaN).
    """
    if len(parts) == 1 and parts[0].com.rotation == _IDENTITY \
            and all(map(math.isfinite, parts[0].inertia)):
        (part,) = parts
        total = float(part.mass)
        if not total > 0.0:
            raise ValueError(
                f"cannot combine inertials with total mass {total}: it must be positive")
        return Inertial(total, Pose.at(part.com.position),
                        tuple(0.0 + v for v in part.inertia))  # type: ignore[arg-type]
    import numpy as np  # lazy: sums of products, with BLAS's rounding (see above)

    masses = np.array([part.mass for part in parts], dtype=float)
    total = float(masses.sum())
    if not total > 0.0:
        raise ValueError(f"cannot combine inertials with total mass {total}: it must be positive")
    if len(parts) == 1:  # most links have one body: no mean, no parallel axis to add
        (part,) = parts
        return Inertial(total, Pose.at(part.com.position), entries(_tensor_in_frame(part)))
    centres = np.array([part.com.position for part in parts], dtype=float)
    centre = masses @ centres / total
    combined = sum(
        _tensor_in_frame(part) + _parallel_axis(part.mass, offset)
        for part, offset in zip(parts, centres - centre)
    )
    return Inertial(total, Pose.at(centre), entries(combined))


_IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def tensor(inertia: Sequence[float]) -> Any:
    """The symmetric 3x3 NumPy tensor of six entries ``(ixx, ixy, ixz, iyy, iyz, izz)``."""
    import numpy as np  # lazy: for the dynamics and the non-diagonal checks only

    ixx, ixy, ixz, iyy, iyz, izz = inertia
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], dtype=float)


def entries(inertia: Any) -> InertiaEntries:
    """The six entries of a symmetric 3x3 tensor, read from its upper triangle."""
    return (
        float(inertia[0, 0]),
        float(inertia[0, 1]),
        float(inertia[0, 2]),
        float(inertia[1, 1]),
        float(inertia[1, 2]),
        float(inertia[2, 2]),
    )


def is_physical(inertia: Sequence[float] | Any, tol: float = PHYSICAL_TOL) -> bool:
    """Whether an inertia (six entries or a 3x3 tensor) can belong to a rigid body.

    Symmetric, positive definite (simulators invert the tensor, so a zero moment is rejected
    too), and the principal moments ``A, B, C`` obey ``A + B ≥ C`` (and permutations), up to
    ``tol`` times the largest entry. The principal inequality implies the one on the diagonal
    (``ixx + iyy ≥ izz``) in every axes, so the diagonal needs no separate check.
    """
    if isinstance(inertia, tuple) and len(inertia) == 6 and inertia[1] == inertia[2] \
            == inertia[4] == 0.0 and all(math.isfinite(v) for v in inertia):
        # Diagonal (the solid formulas, most models): the moments are the diagonal itself.
        # Worth the shortcut: the check runs once per link, and NumPy's cost is per call.
        a, b, c = sorted((float(inertia[0]), float(inertia[3]), float(inertia[5])))
        slack = tol * max(abs(a), abs(c), sys.float_info.min)
        return a > 0.0 and a + b >= c - slack
    import numpy as np  # lazy: eigenvalues of a tensor with products of inertia

    matrix = tensor(inertia) if np.shape(inertia) == (6,) else np.asarray(inertia, dtype=float)
    if not np.all(np.isfinite(matrix)):
        return False  # overflow or NaN: no rigid body (and LAPACK fails on it)
    slack = tol * max(float(np.abs(matrix).max()), np.finfo(float).tiny)
    if matrix.shape != (3, 3) or not np.allclose(matrix, matrix.T, rtol=0.0, atol=slack):
        return False
    moments = np.linalg.eigvalsh(matrix)
    return bool(moments[0] > 0.0 and moments[0] + moments[1] >= moments[2] - slack)


def _diagonal(ixx: float, iyy: float, izz: float) -> InertiaEntries:
    return (ixx, 0.0, 0.0, iyy, 0.0, izz)


def _tensor_in_frame(part: Inertial) -> Any:
    """The part's tensor turned from its ``com`` axes into the frame's axes: ``R I Rᵀ``."""
    import numpy as np  # lazy: called by ``combine`` once it has loaded NumPy

    rotation = np.array(part.com.rotation)
    return rotation @ tensor(part.inertia) @ rotation.T


def _parallel_axis(mass: float, offset: Any) -> Any:
    """What moving a body's tensor by ``offset`` away from the centre of mass adds to it."""
    import numpy as np  # lazy: called by ``combine`` once it has loaded NumPy

    return mass * (float(offset @ offset) * np.eye(3) - np.outer(offset, offset))
