"""Runs ``cyphy check-theory``'s check on a generated session held in memory (tests)."""

from __future__ import annotations

import tempfile
from pathlib import Path

from cyphy.verify.theory.check import check_session


def session_findings(files: dict[str, str]) -> list[str]:
    """The findings of check-theory on the session ``files`` (name → text), rendered."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, text in files.items():
            (folder / name).write_text(text)
        return [f.render(folder) for f in check_session(folder).findings]
