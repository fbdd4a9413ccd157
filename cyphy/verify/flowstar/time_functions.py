"""Functions of time in the ODEs (an environment such as ``-2 - sin(5*t)``) replaced by
auxiliary states whose own ODEs are linear, so a mode that would need ``nonpoly ode`` is
polynomial (often affine: ``lti ode``) again.

``sin(a*t + b)`` and ``cos(a*t + b)`` become the pair ``s' = a*c``, ``c' = -a*s`` with
``s(0) = sin(b)``, ``c(0) = cos(b)``; ``exp(a*t + b)`` becomes ``e' = a*e``, ``e(0) =
exp(b)``. These are the functions' own ODEs, so the trajectories are the same; Flow*'s
Taylor models of a polynomial flow are far tighter than its interval evaluation of ``sin``
over a step (a held input beside ``cos(3*t)`` computed no flowpipe at all at the default
step). The global clock ``t`` is never reset, so the functions stay exact across jumps.
An initial value that is not exactly a double (``sin(1)``) is the interval between its
neighbouring doubles, which contains it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import sympy


@dataclass(frozen=True)
class Auxiliary:
    """A state that holds a function of time: its ODE, initial interval, and what it is."""

    name: str
    rhs: Any
    initial: tuple[float, float]
    meaning: str


def replace_time_functions(rhs: dict[str, Any], clock: Any, taken: set[str]
                           ) -> tuple[dict[str, Any], list[Auxiliary]]:
    """``rhs`` with every ``sin``, ``cos`` and ``exp`` of an affine function of ``clock``
    replaced by auxiliary states (named ``cyphy_sinN``/``cyphy_cosN``/``cyphy_expN``, not
    among ``taken``); other functions are left as they are (``nonpoly ode``)."""
    atoms = sorted({a for f in rhs.values() for a in f.atoms(sympy.sin, sympy.cos, sympy.exp)
                    if _affine(a.args[0], clock) is not None}, key=sympy.default_sort_key)
    arguments = list(dict.fromkeys(a.args[0] for a in atoms))
    substitution: dict[Any, Any] = {}
    aux: list[Auxiliary] = []
    for k, arg in enumerate(arguments, start=1):
        slope, offset = _affine(arg, clock)
        used = {type(a) for a in atoms if a.args[0] == arg}
        if used & {sympy.sin, sympy.cos}:
            s, c = _name("cyphy_sin", k, taken), _name("cyphy_cos", k, taken)
            ss, cs = sympy.Symbol(s, real=True), sympy.Symbol(c, real=True)
            aux += [Auxiliary(s, slope * cs, _enclose(sympy.sin(offset)), f"sin({arg})"),
                    Auxiliary(c, -slope * ss, _enclose(sympy.cos(offset)), f"cos({arg})")]
            substitution[sympy.sin(arg)] = ss
            substitution[sympy.cos(arg)] = cs
        if sympy.exp in used:
            e = _name("cyphy_exp", k, taken)
            es = sympy.Symbol(e, real=True)
            aux.append(Auxiliary(e, slope * es, _enclose(sympy.exp(offset)), f"exp({arg})"))
            substitution[sympy.exp(arg)] = es
    if not substitution:
        return rhs, []
    return {x: sympy.expand(f.xreplace(substitution)) for x, f in rhs.items()}, aux


def _affine(arg: Any, clock: Any) -> tuple[Any, Any] | None:
    """(a, b) when ``arg`` is ``a*clock + b`` with numbers a ≠ 0 and b."""
    if arg.free_symbols != {clock}:
        return None
    poly = sympy.Poly(arg, clock) if arg.is_polynomial(clock) else None
    if poly is None or poly.degree() != 1 or not all(c.is_number for c in poly.all_coeffs()):
        return None
    slope, offset = poly.all_coeffs()
    return slope, offset


def _enclose(value: Any) -> tuple[float, float]:
    """A double interval that contains ``value`` (a point when the value is a double)."""
    v = float(value)
    if value.is_Rational and sympy.Rational(v) == value:
        return v, v
    return math.nextafter(v, -math.inf), math.nextafter(v, math.inf)


def _name(base: str, k: int, taken: set[str]) -> str:
    name = f"{base}{k}"
    while name in taken:
        name += "_"
    taken.add(name)
    return name
