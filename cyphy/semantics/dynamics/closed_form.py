"""Closed expressions of reduced ODEs (:mod:`cyphy.semantics.dynamics.reduce`): the named
definitions written out (for targets that need one expression per state) and closed-form
solutions of linear systems with constant coefficients. Split from the reducer for issue 31.
"""

from __future__ import annotations

from typing import Any

import networkx as nx
import numpy as np
import sympy

from cyphy.translate.to_sympy import T
from cyphy.semantics.dynamics.equations import System
from cyphy.semantics.dynamics.obstacles import Obstacle
from cyphy.semantics.dynamics.reduce import Reduced
from cyphy.semantics.dynamics.solving import blocks_in_order


#: The largest expression (in nodes, every definition written out) that
#: ``inline_definitions`` writes out: the articulated-body definitions of a 2-joint arm
#: written out take about 1.3·10⁵ nodes and SymPy's expansion of them 7 s (measured).
INLINE_LIMIT = 20_000


def inline_definitions(reduced: Reduced, system: System) -> None:
    """Write the definitions into the rhs and outputs (and drop them), or, beyond
    ``INLINE_LIMIT`` nodes, leave the expressions as they are with an ``E-DYNAMICS``
    obstacle: closed expressions of a small tree's accelerations (one or two joints), to
    compare them with a formula."""
    sizes: dict[str, int] = {}
    for name, value in reduced.definitions:
        sizes[name] = value.size(sizes) if hasattr(value, "size") else \
            int(sympy.count_ops(value, visual=False)) + 1
    largest = max(sizes.values())
    if largest > INLINE_LIMIT:
        equations = tuple(eq for eq in system.equations if eq.origin.endswith(" motion"))
        joints = len(equations)
        reduced.obstacles.append(Obstacle(
            "too-large", f"the equations of motion of this {joints}-joint tree written out as "
            f"closed expressions take about {largest:.1e} terms (at most {INLINE_LIMIT:.0e} "
            "are written out): this target needs closed expressions", (),
            equations[:1]))
        return
    symbols: dict[str, Any] = {}
    for name, value in reduced.definitions:
        symbols[name] = value.to_sympy(symbols) if hasattr(value, "to_sympy") else value
    names = {sympy.Symbol(name, real=True): symbols[name] for name, _ in reduced.definitions}
    for s, v in list(reduced.rhs.items()):
        reduced.rhs[s] = sympy.expand(v.xreplace(names))
    for s, v in list(reduced.outputs.items()):
        reduced.outputs[s] = sympy.expand(v.xreplace(names))
    reduced.definitions = []


def closed_form(reduced: Reduced, inputs: dict[str, Any] | None = None) -> dict[str, Any] | None:
    """Each state as an expression of ``t`` and its initial value ``<state>_0``, for constant
    inputs; None when the system is not linear with constant coefficients.

    The states are split into blocks by their dependencies (strongly connected components);
    blocks are solved in order: a state that does not feed back on itself is integrated
    (``theta' = av``), a coupled block ``x' = A x + g`` with constant ``g`` is solved from the
    eigen-decomposition of ``A`` (``x = x* + V e^{Λt} V⁻¹ (x0 - x*)``, written with real
    exponentials, sines and cosines), anything else goes to ``dsolve``. Coefficients are
    floating point: exact roots of a cubic or quartic are of no use to anyone."""
    if not reduced.states:
        return None
    values = {sympy.Symbol(n, real=True): v for n, v in (inputs or {}).items()}
    sym = {s: reduced.symbols.get(s, sympy.Symbol(s, real=True)) for s in reduced.states}
    rhs = {s: sympy.N(reduced.rhs[s].xreplace(values)) for s in reduced.states}
    deps = nx.DiGraph()
    deps.add_nodes_from(reduced.states)
    for s, f in rhs.items():
        for other in reduced.states:
            if f.has(sym[other]):
                deps.add_edge(other, s)
    solution: dict[str, Any] = {}
    for block in blocks_in_order(deps):
        known = {sym[s]: solution[s] for s in solution}
        fs = {s: rhs[s].xreplace(known) for s in block}
        x0 = {s: sympy.Symbol(f"{s}_0", real=True) for s in block}
        if len(block) == 1 and not fs[block[0]].has(sym[block[0]]):
            s = block[0]
            tau = sympy.Symbol("tau", real=True)
            integral = sympy.integrate(fs[s].xreplace({T: tau}), (tau, 0, T))
            solution[s] = sympy.expand(x0[s] + integral)
            continue
        try:
            matrix, rest = sympy.linear_eq_to_matrix([fs[s] for s in block],
                                                     [sym[s] for s in block])
        except (sympy.polys.polyerrors.PolynomialError, ValueError):
            return None
        g = -rest
        if any(v.has(T) for v in g) or any(v.free_symbols - {*values} and
                                           not v.is_number for v in matrix):
            return None
        solved = _linear_block(matrix, g, [x0[s] for s in block])
        if solved is None:
            return None
        solution.update(dict(zip(block, solved)))
    return solution


def _linear_block(matrix: Any, g: Any, x0: list[Any]) -> list[Any] | None:
    """``x' = A x + g`` with constant ``A`` and ``g`` (``g`` may hold symbols, linearly)."""
    a = np.array(matrix.evalf(), dtype=float)
    if abs(np.linalg.det(a)) < 1e-12:
        return None
    eigenvalues, vectors = np.linalg.eig(a)
    if np.linalg.cond(vectors) > 1e10:
        return None  # defective: no basis of eigenvectors
    inverse = np.linalg.inv(vectors)
    a_inv = sympy.Matrix(np.linalg.inv(a).tolist())
    steady = -(a_inv * g)
    start = sympy.Matrix(x0) - steady
    out = []
    for i in range(len(x0)):
        total = steady[i]
        for k, lam in enumerate(eigenvalues):
            weight = sum(complex(vectors[i, k] * inverse[k, j]) * start[j]
                         for j in range(len(x0)))
            total += _exp_term(complex(lam), weight)
        total = sympy.expand(total)
        noise = {f: 0 for f in total.atoms(sympy.Float) if abs(f) < 1e-12}
        out.append(total.xreplace(noise))
    return out


def _exp_term(lam: complex, weight: Any) -> Any:
    """The real part of ``weight·e^{λt}`` (complex pairs add up to real cosines and sines)."""
    re, im = sympy.Float(lam.real), sympy.Float(lam.imag)
    weight = sympy.expand(weight)
    w_re = sympy.re(weight)
    w_im = sympy.im(weight)
    if abs(lam.imag) < 1e-14:
        return w_re * sympy.exp(re * T)
    return sympy.exp(re * T) * (w_re * sympy.cos(im * T) - w_im * sympy.sin(im * T))
