"""Why equations cannot be assembled: the errors that the tree, the algorithms over it and the
assembly of equations all raise, defined below them so each imports them one way."""

from __future__ import annotations

from cyphy import codes
from cyphy.diagnostics import Span

TREE = codes.code("E-DYNAMICS", codes.E,
                  "the kinematic tree has no well-defined equations of motion")


class AssemblyError(Exception):
    """Why the equations to solve cannot be assembled, at the element to blame (reported as
    ``E-SOLVE`` unless a subclass's ``code`` says otherwise)."""

    def __init__(self, message: str, span: Span, hint: str) -> None:
        super().__init__(message)
        self.message, self.span, self.hint = message, span, hint


class DynamicsError(AssemblyError):
    """Why the model's tree has no equations of motion, at the element to blame (an
    ``AssemblyError``, so every command that assembles equations reports it; ``code`` says
    which diagnostic)."""

    code = TREE
