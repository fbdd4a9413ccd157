"""The forces a joint's annotation puts on its coordinates besides the actuators: the SDF
``Axis``'s ``Dynamics`` (viscous damping, a spring about a reference position, Coulomb
friction) and ``Limit`` (the bounds of the coordinate), read as the SDF, URDF and MJCF
exports read them (the ``physmod::sdf::annotations`` defaults: no damping, no spring, no
friction, bounds ±1e16, which is none).

In the equations of motion (``solve``, ``simulate``, Flow*, the theories) a coordinate ``q``
of rate ``v`` receives the effort

    ``τ_passive = −damping·v − spring_stiffness·(q − spring_reference)``

besides its actuator's, as MuJoCo applies ``damping``, ``stiffness`` and ``springref``.
Limits are a contact model of ``solve`` and ``simulate`` only (:func:`stop`): a one-sided,
critically damped spring that acts while the coordinate is past a bound and pushes it back,
of time constant :data:`STOP_TIME` (MuJoCo's default ``solref`` for joint limits) scaled by
the joint's inertia at rest, so that the stop is as stiff for a light finger as for a heavy
arm. Coulomb friction is not in the equations (a discontinuous force that no ODE target
takes): the exports carry it (MJCF ``frictionloss``, URDF ``friction``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from cyphy import expr as ex
from cyphy.model.elements import AnnotationValue, Joint

#: The time constant of a joint-limit stop (seconds): MuJoCo's default ``solref`` (0.02, a
#: damping ratio of 1).
STOP_TIME = 0.02
#: SDF's "no limit" (the templates' default bounds are ±1e16): beyond this, a bound is none.
UNBOUNDED = 1e15


@dataclass(frozen=True)
class AxisForces:
    """What one coordinate's annotation axis gives (SI: N·m·s/rad or N·s/m, N·m/rad or
    N/m, rad or m)."""

    damping: float = 0.0
    friction: float = 0.0
    stiffness: float = 0.0
    reference: float = 0.0
    lower: float = -math.inf
    upper: float = math.inf

    @property
    def limited(self) -> bool:
        return math.isfinite(self.lower) or math.isfinite(self.upper)

    @property
    def passive(self) -> bool:
        return bool(self.damping or self.stiffness)


_AXES = {"revolute": ("axis",), "prismatic": ("axis",), "universal": ("axis", "axis2")}


def axis_forces(kind: str, element: object) -> tuple[AxisForces, ...]:
    """One :class:`AxisForces` per coordinate of a joint of ``kind`` (the tree's) whose
    element is ``element``: a revolute or prismatic joint's ``axis``, a universal joint's
    ``axis`` and ``axis2``; none for a ball joint (SDF's ``ball`` has no axis) or a floating
    base."""
    names = _AXES.get(kind)
    if names is None or not isinstance(element, Joint):
        return ()
    annotation = element.annotation
    return tuple(_read(annotation.get(n) if annotation is not None else None) for n in names)


def _read(axis: object) -> AxisForces:
    if not isinstance(axis, AnnotationValue):
        return AxisForces()
    dynamics, limit = axis.get("dynamics"), axis.get("limit")

    def number(block: object, name: str, default: float) -> float:
        value = block.get(name) if isinstance(block, AnnotationValue) else None
        return float(value) if isinstance(value, (int, float)) and \
            not isinstance(value, bool) else default

    lower = number(limit, "lower", -math.inf)
    upper = number(limit, "upper", math.inf)
    friction = number(dynamics, "_friction", number(dynamics, "friction", 0.0))
    return AxisForces(number(dynamics, "damping", 0.0), friction,
                      number(dynamics, "spring_stiffness", 0.0),
                      number(dynamics, "spring_reference", 0.0),
                      lower if lower > -UNBOUNDED else -math.inf,
                      upper if upper < UNBOUNDED else math.inf)


def passive_efforts(forces: Sequence[AxisForces], q: Sequence[Any], qd: Sequence[Any]
                    ) -> list[Any]:
    """``−damping·v − stiffness·(q − reference)`` per coordinate, in whatever arithmetic the
    coordinates have (floats, SymPy, the articulated-body polynomials); exact zeros where
    the axis has neither."""
    out: list[Any] = []
    for f, x, v in zip(forces, q, qd):
        effort: Any = 0.0
        if f.damping:
            effort = v * (-f.damping)
        if f.stiffness:
            effort = effort + (x - f.reference) * (-f.stiffness) if f.reference else \
                effort + x * (-f.stiffness)
        out.append(effort)
    return out


def stop(force: AxisForces, inertia: float, q: float, v: float) -> float:
    """The limit's contact effort at position ``q`` and rate ``v`` (numeric): zero between
    the bounds; past one, ``−inertia·(k·depth + b·v)`` with ``k = 1/STOP_TIME²`` and
    ``b = 2/STOP_TIME`` (critically damped), never pulling towards the bound it is past."""
    k, b = 1.0 / STOP_TIME ** 2, 2.0 / STOP_TIME
    if q > force.upper:
        return min(0.0, -inertia * (k * (q - force.upper) + b * v))
    if q < force.lower:
        return max(0.0, -inertia * (k * (q - force.lower) + b * v))
    return 0.0


def stop_expr(force: AxisForces, inertia: float, q: ex.Expr, v: ex.Expr) -> ex.Expr:
    """:func:`stop` as an expression of the shared AST (``if … then … else …``), for the
    equations ``solve`` reduces and ``simulate`` integrates."""
    k, b = 1.0 / STOP_TIME ** 2, 2.0 / STOP_TIME

    def num(x: float) -> ex.Expr:
        text = repr(abs(float(x)))
        return ex.UnaryOp("-", ex.Num(text)) if x < 0 else ex.Num(text)

    def push(bound: float) -> ex.Expr:  # −I·(k·(q − bound) + b·v)
        depth = ex.BinOp("-", q, num(bound))
        return ex.BinOp("*", num(-inertia), ex.BinOp("+", ex.BinOp("*", num(k), depth),
                                                     ex.BinOp("*", num(b), v)))

    out: ex.Expr = ex.Num("0")
    for bound, past, away in ((force.lower, "<", ">"), (force.upper, ">", "<")):
        if not math.isfinite(bound):
            continue
        effort = push(bound)
        condition = ex.BinOp("/\\", ex.BinOp(past, q, num(bound)),
                             ex.BinOp(away, effort, ex.Num("0")))
        out = ex.IfExpr(condition, effort, out)
    return out
