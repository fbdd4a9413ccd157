"""The reserved words of each grammar, with where each is a keyword."""

from __future__ import annotations

from functools import lru_cache


@lru_cache(maxsize=None)
def reserved_for(kind: str) -> dict[str, str]:
    """Word → source, for ``utp`` (Isabelle2020 HOL + utp-main), ``axiomatic`` or ``hol``."""
    from cyphy.backends.isabelle.library_words import SYNTAX_WORDS
    from cyphy.backends.isabelle.names import OUTER_KEYWORDS

    out = {w: "an outer keyword of Pure/HOL" for w in OUTER_KEYWORDS}
    hol = "if then else let case of o O mod div dvd SOME THE ALL EX CONST TYPE".split()
    out.update({w: "HOL's inner syntax" for w in hol})
    if kind == "utp":
        out.update({w: f"utp-main c9122f14 {src}" for w, src in SYNTAX_WORDS.items()})
    elif kind == "axiomatic":
        from cyphy.verify.theory.ax_types import AX_INNER_KEYWORDS

        out.update({w: "Ax_CyPhyCircus's parents" for w in AX_INNER_KEYWORDS if w not in out})
    return out
