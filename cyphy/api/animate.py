"""``animate``: run a generated Isabelle/UTP session from its text alone, for scripts."""

from __future__ import annotations

from pathlib import Path

from cyphy.verify.animate.animation import Animation, animate as _animate
from cyphy.verify.animate.errors import AnimateError

__all__ = ["Animation", "AnimateError", "animate"]


def animate(folder: str | Path, t_end: float = 1.0, inputs: dict[str, str] | None = None,
            consts: dict[str, float] | None = None, samples: int = 201) -> Animation:
    """The composition the session in ``folder`` states, run for ``t_end`` seconds:
    ``inputs`` gives world inputs as expressions of t and the state, ``consts`` the open
    constants' values; raises :class:`AnimateError` (its ``status`` the exit status)."""
    return _animate(folder, t_end, inputs, consts, samples)
