"""What the reduction to explicit ODEs cannot solve (:mod:`cyphy.semantics.dynamics.reduce`):
each obstacle with its equations and variables, and its diagnostic (code, place in the user's
files, hint). Split from the reducer for issue 31.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from cyphy.diagnostics import Report, Span
from cyphy.lang.notation import to_notation
from cyphy.lang.workspace import LIBRARY_ROOT
from cyphy.semantics.dynamics.equations import OBSTACLE, OVERDETERMINED, UNDERDETERMINED, Equation
from cyphy.semantics.dynamics.errors import TREE
from cyphy.semantics.dynamics.structure import Competition


@dataclass(frozen=True)
class Obstacle:
    kind: str  # overdetermined, underdetermined, algebraic-loop, unknown-function,
    #            unsupported, too-large
    message: str
    variables: tuple[str, ...]
    equations: tuple[Equation, ...]
    # where to report it (in the user's files) and what to say about each equation; set by
    # the reducer from the system's places (see ``Reducer.placed``)
    span: Span | None = None
    notes: tuple[str, ...] = ()


def in_library(span: Span) -> bool:
    return span.file.startswith(str(LIBRARY_ROOT))


def equation_text(eq: Equation) -> str:
    where = "relation" if eq.origin == "relation" else f"equation of {eq.origin}"
    return f"{where} `{to_notation(eq.expr)}`"


def note(eq: Equation, places: dict[str, Span]) -> str:
    text = f"{equation_text(eq)} at {eq.span}"
    if in_library(eq.span) and eq.origin in places:
        text += f" (the library's, for {eq.origin} declared at {places[eq.origin]})"
    return text


def competition(c: Competition[Equation]) -> Obstacle:
    """An over-determined equation and the equations that already determine its variables."""
    rivals = "; ".join(f"{v} by the {equation_text(eq)}" for v, eq in c.rivals)
    variables = tuple(v for v, _ in c.rivals)
    message = (f"the {equation_text(c.equation)} over-determines the equations: it adds an "
               f"equation but no unknown")
    if rivals:
        message += f", and each variable it names is already determined ({rivals})"
    equations = (c.equation, *dict.fromkeys(eq for _, eq in c.rivals))
    return Obstacle("overdetermined", message, variables, equations)


_OBSTACLE_HINTS = {
    "overdetermined": "remove it or one of the equations it competes with: a relation may "
                      "only set what nothing else determines, such as a joint's effort tau "
                      "or a motor's demand das; cyphy solves a joint's acceleration from its "
                      "effort, never an effort from a prescribed motion. A motor drives a "
                      "joint through its torque alone (relation M.T == J.tau): see "
                      "docs/equations.md",
    "underdetermined": "add an equation or relation that determines it, or restrict the "
                       "system with --element",
    "algebraic-loop": "rewrite the equations so the loop can be solved, or give the "
                      "constants values (--const)",
    "unknown-function": "the function is declared without a definition: SymPy cannot invert "
                        "it",
    "unsupported": "only equations lhs == rhs over numbers, vectors and matrices are solved",
    "too-large": "`cyphy solve` and `cyphy simulate` keep them as named definitions and "
                 "take trees of any size; for this target, restrict the model with "
                 "elements/--element to fewer joints",
}


def obstacle_code(o: Obstacle) -> Any:
    """``E-OVERDETERMINED``, ``E-UNDERDETERMINED``, ``E-DYNAMICS`` (too large) or
    ``E-REDUCE``."""
    return {"overdetermined": OVERDETERMINED, "underdetermined": UNDERDETERMINED,
            "too-large": TREE}.get(o.kind, OBSTACLE)


def obstacle_hint(o: Obstacle) -> str:
    return _OBSTACLE_HINTS[o.kind]


def obstacle_span(o: Obstacle) -> Span:
    return o.span or (o.equations[0].span if o.equations else Span.unknown())


def report_obstacles(reduced: Any, report: Report) -> None:
    """Each obstacle of ``reduced`` (:class:`cyphy.semantics.dynamics.reduce.Reduced`, which
    imports this module) as a diagnostic (:func:`obstacle_code`) in the user's files."""
    for o in reduced.obstacles:
        notes = list(o.notes) or [f"{eq.origin}: equation at {eq.span}" for eq in o.equations]
        report.report(obstacle_code(o), o.message, obstacle_span(o), obstacle_hint(o), notes)
