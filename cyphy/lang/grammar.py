"""The RoboSim grammar (``robosim.lark``) as Lark's LALR parser, built once per process: the
parser and the descriptions of parse errors both read it.

Two engines run the same LALR tables. Lark's own pure-Python lexer and parser loop take more
than half of a long file's parse; lark-cython (by Lark's author) runs the same LALR loop in C
and is used for every parse when it is installed (:func:`compiled`), fed by cyphy's one-pass
lexer (:mod:`cyphy.lang.lexer`), which cuts the tokens Lark's contextual lexer would. It has
no interactive parser of its own and its tokens are not ``str``, so a file with a syntax error
is parsed again by pure Lark, whose errors :mod:`cyphy.lang.syntax_errors` describes: both give
the same trees for correct files (``tests/test_parse_engines.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from lark import Lark, Token
from lark.grammar import Rule
from lark.parsers.lalr_parser import ParseConf, ParserState

from cyphy import progress
from cyphy.lang import lexer as one_pass

try:  # optional: without it every parse runs in Lark's pure-Python lexer and loop
    import lark_cython
except ImportError:  # pragma: no cover - exercised by a test in a child process
    lark_cython = None

GRAMMAR = "robosim.lark"

#: The classes of the tokens either engine makes (lark-cython's are not ``str``).
TOKEN_TYPES: tuple[type, ...] = (Token,) if lark_cython is None else (Token, lark_cython.Token)


@dataclass(frozen=True)
class Engine:
    """One way to run the grammar's LALR tables: the loaded ``Lark`` object and the classes
    of its parser's configuration and state (Lark's, or lark-cython's C versions), and the
    lexer that feeds it when it is not the ``Lark`` object's own."""

    lark: Lark
    parse_conf: type
    parser_state: type
    lexer: one_pass.Lexer | None = None

    def parse(self, text: str, callbacks: dict[Any, Any]) -> Any:
        """Run the parser over ``text`` with ``callbacks`` (one per rule) instead of the tree
        builder the ``Lark`` object was loaded with; raises Lark's ``UnexpectedInput``."""
        frontend = self.lark.parser
        lalr = frontend.parser
        conf = self.parse_conf(lalr._parse_table, callbacks, "start")
        if self.lexer is not None:
            return one_pass.parse(self.lexer, self.parser_state(conf, None), text)
        state = self.parser_state(conf, frontend._make_lexer_thread(text))
        return lalr.parser.parse_from_state(state)


@lru_cache(maxsize=None)
def grammar(strict: bool = False) -> Lark:
    """The LALR parser with the contextual lexer, built once per process."""
    return _load(strict, {})


@lru_cache(maxsize=None)
def pure() -> Engine:
    """Lark's own lexer and LALR loop: every parse when lark-cython is absent, and the
    re-parse of a file with a syntax error (its errors are what the diagnostics describe)."""
    return Engine(grammar(), ParseConf, ParserState)


@lru_cache(maxsize=None)
def compiled() -> Engine | None:
    """The same tables run by lark-cython's LALR loop, fed by :mod:`cyphy.lang.lexer` (by
    lark-cython's own contextual lexer if the grammar were one that lexer does not
    reproduce), or None when lark-cython is not installed."""
    if lark_cython is None:
        return None
    module = lark_cython.lark_cython
    lark = _load(False, lark_cython.plugins)
    for rule in lark.rules:  # this instance's own objects, also those of its parse table
        rule.__class__ = _IdentityRule
    return Engine(lark, module.ParseConf, module.ParserState, one_pass.build(lark, module.Token))


class _IdentityRule(Rule):
    """A rule compared and hashed by identity, in C. lark-cython's loop compares every rule
    it reduces with the end state (``assert arg != end_state``) and looks its callback up by
    the rule: Lark's ``Rule.__eq__`` and ``__hash__`` are Python methods, 2.3 million calls
    on a 10,000-link model. One loaded grammar has each rule once, so identity is equality."""

    __slots__ = ()
    __eq__ = object.__eq__
    __ne__ = object.__ne__
    __hash__ = object.__hash__


def _load(strict: bool, plugins: dict[str, Any]) -> Lark:
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
        # analysis takes 0.7 s, loading the cache a few milliseconds (either engine reads it).
        cache=not strict,
        lexer_callbacks={"LBRACE": _reached},  # progress through a long file, block by block
        _plugins=plugins,
    )


def _reached(token: Any) -> Any:
    progress.step(f"line {token.line}")
    return token
