"""The reserved words of each grammar check-theory knows, with where each is a keyword."""

from __future__ import annotations

from functools import lru_cache

from cyphy.backends.isabelle.library_words import HOL_SYNTAX_WORDS, SYNTAX_WORDS
from cyphy.backends.isabelle.names import OUTER_KEYWORDS
from cyphy.verify.theory.ax_signatures import AX_INNER_KEYWORDS


@lru_cache(maxsize=None)
def reserved_for(kind: str) -> dict[str, str]:
    """Word → where it is a keyword, for ``utp`` (HOL + utp-main c9122f14), ``axiomatic``
    (HOL + Ax_CyPhyCircus's public parents) or ``hol``: the outer keywords of theory headers
    and HOL's and Pure's mixfix words (derived from the sources: reserved_words.tsv)."""
    out = {w: "an outer keyword of Pure/HOL" for w in OUTER_KEYWORDS}
    out.update({w: f"HOL {src}" for w, src in HOL_SYNTAX_WORDS.items()})
    if kind == "utp":
        out.update({w: f"utp-main c9122f14 {src}" for w, src in SYNTAX_WORDS.items()})
    elif kind == "axiomatic":
        out.update({w: "Ax_CyPhyCircus's parents (ax_signatures.AX_INNER_KEYWORDS)"
                    for w in AX_INNER_KEYWORDS if w not in out})
    return out
