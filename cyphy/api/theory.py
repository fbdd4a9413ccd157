"""``check_theory``: cyphy check-theory's static check of an Isabelle session, for scripts."""

from __future__ import annotations

from pathlib import Path

from cyphy.verify.theory.check import Result, check_session
from cyphy.verify.theory.session import SessionError

__all__ = ["Result", "SessionError", "check_theory"]


def check_theory(folder: str | Path) -> Result:
    """Every finding on the session in ``folder`` (a static check, not Isabelle); raises
    :class:`SessionError` when the folder holds no session (no folder, no ROOT)."""
    return check_session(Path(folder))
