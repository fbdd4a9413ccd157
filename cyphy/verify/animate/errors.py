"""The one error an animation can end with: a code, a place in the theory and an exit status."""

from __future__ import annotations

from pathlib import Path


class AnimateError(Exception):
    """Why the session cannot be animated.

    ``status`` is the command's exit status: 2 for input the command cannot use (not a
    session, a term the reader does not know, a bad option), 1 for a theory that reads but
    cannot be run (a state Init leaves open, a deadlock, equations that do not determine a
    rate)."""

    def __init__(self, code: str, message: str, *, hint: str = "", path: Path | None = None,
                 line: int = 0, status: int = 1) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.hint = hint
        self.path = path
        self.line = line
        self.status = status

    def where(self) -> str:
        if self.path is None:
            return "<command line>"
        return f"{self.path}:{self.line}" if self.line else str(self.path)
