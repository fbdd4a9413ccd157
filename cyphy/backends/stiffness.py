"""Which integrator fits a model: an explicit Runge–Kutta method unless the model is stiff
(issue 31).

A mechanical tree is not stiff: its eigenvalues at rest are oscillations (±iω, small real
parts), and DOP853 integrates the benchmark's chains with fewer evaluations than any other
method (10 links: 599 against RK45's 608; 100 links: 776 against 836; LSODA 16,587 and 20.5
s). A motor whose electrical time constant ``L/R`` is far shorter than the run is stiff:
its current decays at ``−R/L``, and an explicit method must keep ``h·R/L`` within its
stability region (about 6 for DOP853 on the real axis) for the whole run, long after the
current has settled, which takes ``T·R/L/6`` steps whatever the tolerance.

So the test is on the eigenvalues of the state Jacobian at the start: the model is stiff
when its fastest decay rate ``max(−Re λ)`` times the simulated time exceeds
:data:`STIFF_SPAN`, i.e. when stability alone would cost an explicit method more than
about 2,000 steps (the chains of the benchmark need 50 to 80). Then BDF runs with the
analytic Jacobian when there is one. ``--method`` overrides the choice.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

#: ``max(−Re λ)·T`` above which a model is stiff (see the module's docstring).
STIFF_SPAN = 12_000.0
#: The methods chosen: explicit, and stiff.
EXPLICIT, STIFF_METHOD = "DOP853", "BDF"


@dataclass(frozen=True)
class Choice:
    method: str
    reason: str  # for the note on stderr


def choose(asked: str | None, jacobian_at_start: Callable[[], np.ndarray | None],
           span: float, analytic: bool) -> Choice:
    """The method asked for, else :data:`EXPLICIT` or, for a stiff model,
    :data:`STIFF_METHOD`; ``jacobian_at_start`` gives the state Jacobian at the initial
    state (None when the model has no state)."""
    if asked:
        return Choice(asked, "asked for")
    jac = jacobian_at_start()
    rate = fastest_decay(jac) if jac is not None and jac.size else 0.0
    if rate * span > STIFF_SPAN:
        how = "analytic Jacobian" if analytic else "finite-difference Jacobian"
        return Choice(STIFF_METHOD, f"stiff: the fastest decay rate at the start is "
                      f"{rate:.3g}/s over {span:g} s; {how}")
    return Choice(EXPLICIT, f"explicit: not stiff, the fastest decay rate at the start is "
                  f"{rate:.3g}/s over {span:g} s")


def fastest_decay(jacobian: np.ndarray) -> float:
    """``max(−Re λ)`` over the Jacobian's eigenvalues, 0 when none decays. The eigenvalues
    of a matrix that is block triangular under some ordering of the states are those of its
    diagonal blocks, the strongly connected components of its dependency graph (each motor
    apart from the tree it drives), so those are what is decomposed: 98 tree states and
    49 motors of 3 for a 50-link chain, not 245 states at once."""
    # lazy: SciPy is not needed by `cyphy check`
    from scipy.sparse.csgraph import connected_components

    if not np.all(np.isfinite(jacobian)):
        return 0.0
    count, labels = connected_components(jacobian != 0, directed=True, connection="strong")
    rate = 0.0
    for block in range(count):
        members = np.flatnonzero(labels == block)
        values = np.linalg.eigvals(jacobian[np.ix_(members, members)])
        rate = max(rate, float(np.max(-values.real)))
    return rate


def finite_difference(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """The Jacobian of ``f`` at ``x`` by central differences: only to *detect* stiffness
    once at the start where no analytic Jacobian exists, never inside the integrator."""
    out = np.zeros((len(x), len(x)))
    for k in range(len(x)):
        h = 1e-6 * max(1.0, abs(float(x[k])))
        up, down = x.copy(), x.copy()
        up[k] += h
        down[k] -= h
        out[:, k] = (np.asarray(f(up), dtype=float) - np.asarray(f(down), dtype=float)) / (2 * h)
    return out
