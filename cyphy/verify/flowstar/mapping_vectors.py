"""An operation's mapping equations with its vector locals written per component.

A mapping may hold a vector in a local (``var g: vector(real, 2)``, ``equation g == (|w,
0|)``, ``equation Motor.das == g[1]``): the theory scalarises it with the rest of the
mapping, and the export and the simulator, which solve the operation's equations with SymPy
for its actuator inputs, need the same: one equation per component, ``g`` as the scalars
``g_1``, ``g_2`` (the names :mod:`cyphy.semantics.scalarise` gives). Without this SymPy was
handed a vector equation, and ``simulate`` stopped with an internal error.
"""

from __future__ import annotations

from typing import Any

from cyphy import expr as ex
from cyphy.semantics.scalarise.scalariser import Scalariser
from cyphy.semantics.scalarise.shapes import ScalariseError, components, type_shape


def per_component(eqs: list[ex.Expr], system: Any, op: str
                  ) -> tuple[list[ex.Expr], list[str]] | None:
    """The equations with each vector local of ``op``'s mapping split into its components,
    and the scalar locals to solve for (a vector local's components in its place); None when
    an equation does not fit the locals' shapes (the operation is then not determined)."""
    names = sorted({n.text for e in eqs for n in e.walk() if isinstance(n, ex.Name)
                    and n.text.startswith(f"{op}_") and system.kinds.get(n.text) == "local"})
    shapes = {n: s for n in names if (s := type_shape(system.variables.get(n))) is not None}
    scalars = [c for n in names for c in (components(n, shapes[n]) if n in shapes else [n])]
    if not shapes:
        return eqs, scalars
    split = Scalariser(shapes, frozenset(shapes))
    try:
        return [q for e in eqs for q in split.predicate(e)], scalars
    except ScalariseError:
        return None
