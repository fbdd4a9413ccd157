"""The RoboSim grammar (``robosim.lark``) as Lark's LALR parser, built once per process: the
parser and the descriptions of parse errors both read it."""

from __future__ import annotations

from functools import lru_cache

from lark import Lark, Token

from cyphy import progress

GRAMMAR = "robosim.lark"


@lru_cache(maxsize=None)
def grammar(strict: bool = False) -> Lark:
    """The LALR parser with the contextual lexer, built once per process."""
    return Lark.open_from_package(
        "cyphy.lang",
        GRAMMAR,
        parser="lalr",
        lexer="contextual",
        # Positions are propagated by cyphy's own reduction callbacks (cyphy.lang.reductions),
        # which replace Lark's tree builder.
        propagate_positions=False,
        maybe_placeholders=True,
        strict=strict,
        # Lark stores the LALR tables in a temporary file keyed by the grammar's hash: the
        # analysis takes 0.7 s, loading the cache a few milliseconds.
        cache=not strict,
        lexer_callbacks={"LBRACE": _reached},  # progress through a long file, block by block
    )


def _reached(token: Token) -> Token:
    progress.step(f"line {token.line}")
    return token
