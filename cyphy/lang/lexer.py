"""A faster lexer for lark-cython's LALR loop: one regular-expression pass over the text.

lark-cython's contextual lexer matches each token with the regular expression of the parser
state it is in, and builds it through several Python-level calls (the keyword lookup of every
name is Lark's ``UnlessCallback``, in Python). On a long model that is most of the parse: a
10,000-link model's 770,000 tokens took 1.4 s to lex and 0.8 s to parse. Here the text is cut
by ``finditer`` over the *root* lexer's expression (every terminal, in Lark's order, as the
contextual lexer's expressions are) and each token is passed to the LALR loop's
``feed_token``. The contextual lexer would cut the same token whenever the parser's state
accepts it:

* each state's lexer tries a subset of the root's terminals, in the same order, and the
  root's first match ``T`` was the first terminal there to match at this position;
* the only terminals a state's lexer has that the root lacks are keywords the root folds
  into ``NAME`` (``_create_unless``): a state that accepts ``T`` but not ``NAME`` keeps such a
  keyword apart, and it is shorter than or the same as a ``NAME`` match there. A longer
  keyword wins (Lark orders strings longest first), so the state cuts ``T`` too.

A token whose type the state does not accept (``link`` where only a name is allowed, ``kg``
where no unit is) is cut again by that state's own Lark lexer, and the pass resumes after it.
A character no terminal matches, or a token the state cannot take, ends the parse with Lark's
``UnexpectedInput``: the file is then parsed again by pure Lark, which describes the error
(:mod:`cyphy.lang.parser`). ``tests/test_parse_engines.py`` checks the trees are the same.
"""

from __future__ import annotations

import re
from copy import copy
from dataclasses import dataclass, field
from typing import Any, Callable

from lark import Lark
from lark.lexer import (BasicLexer, ContextualLexer, LexerState, LineCounter, PatternStr,
                        UnlessCallback)

try:  # Lark 1.3 lexes a slice of the text; Lark 1.1 and 1.2, the text itself
    from lark.lexer import TextSlice
except ImportError:  # pragma: no cover - tested by hand with Lark 1.2.2
    TextSlice = None


#: The name of the expression's last alternative, any one character: where no terminal
#: matches (a name no Lark terminal can have, and no parser state accepts).
UNMATCHED = "cyphy_unmatched"


@dataclass
class Lexer:
    """What the pass needs of one loaded grammar (``build``)."""

    #: the root lexer's terminals, one alternation in Lark's order, then UNMATCHED
    pattern: re.Pattern[str]
    #: a terminal -> its texts that are keywords -> the keyword's terminal (``NAME``'s
    #: ``link``; Lark's ``UnlessCallback``)
    keywords: dict[str, dict[str, str]]
    ignore: frozenset[str]
    newline: frozenset[str]  # terminals whose text may hold a line break
    accepts: dict[int, frozenset[str]]  # parser state -> the terminals it takes
    callbacks: dict[str, Callable[[Any], Any]]  # the grammar's lexer callbacks, by terminal
    lark: Lark
    token: type  # the class of the tokens the LALR loop takes (lark-cython's)
    _contextual: ContextualLexer | None = field(default=None, repr=False)

    def contextual(self) -> ContextualLexer:
        """Lark's own per-state lexers for these parse tables, built on first need (few files
        need them: a keyword used as a name)."""
        if self._contextual is None:
            conf = copy(self.lark.lexer_conf)
            conf.skip_validation = True  # validated when the grammar was loaded
            table = self.lark.parser.parser._parse_table
            self._contextual = ContextualLexer(conf, {s: list(row) for s, row in
                                                      table.states.items()})
        return self._contextual


def build(lark: Lark, token: type) -> Lexer | None:
    """The lexer for ``lark``'s grammar, making tokens of class ``token`` (the LALR loop's),
    or None when the grammar uses what this pass does
    not reproduce (then lark-cython's own lexer runs): more than one root expression,
    case-insensitive keywords, or a keyword test other than Lark's ``UnlessCallback``."""
    conf = lark.lexer_conf
    root = BasicLexer(copy(conf))
    scanner = root.scanner  # builds root.callback as well
    if len(scanner._mres) != 1 or conf.g_regex_flags or conf.use_bytes:
        return None
    keywords: dict[str, dict[str, str]] = {}
    for name, callback in root.callback.items():
        if conf.callbacks.get(name) is callback:
            continue  # the grammar's own, called as it is
        if not isinstance(callback, UnlessCallback):
            return None  # a keyword test and a callback of the grammar's, chained
        for term in callback.scanner.terminals:
            if not isinstance(term.pattern, PatternStr) or term.pattern.flags:
                return None
            keywords.setdefault(name, {})[term.pattern.value] = term.name
    states = lark.parser.parser._parse_table.states
    pattern = re.compile(f"{scanner._mres[0].pattern}|(?P<{UNMATCHED}>[\\s\\S])")
    return Lexer(pattern, keywords, frozenset(conf.ignore), frozenset(root.newline_types),
                 {s: frozenset(row) for s, row in states.items()}, dict(conf.callbacks), lark,
                 token)


def parse(lexer: Lexer, state: Any, text: str) -> Any:
    """Feed ``text``'s tokens to ``state`` (lark-cython's ``ParserState``), its ``$END`` last;
    returns what the start rule's callback made. Raises Lark's ``UnexpectedInput``."""
    feed = state.feed_token
    stack = state.state_stack
    keywords, ignore, newline = lexer.keywords, lexer.ignore, lexer.newline
    accepts, callbacks, token_class = lexer.accepts, lexer.callbacks, lexer.token
    line, line_start, pos = 1, 0, 0
    last = None
    while True:
        for match in lexer.pattern.finditer(text, pos):  # every character is in a match
            kind = match.lastgroup
            if kind in ignore:
                if kind in newline:
                    value = match.group()
                    if "\n" in value:
                        line += value.count("\n")
                        line_start = match.start() + value.rindex("\n") + 1
                continue
            value = match.group()
            start = match.start()
            if kind in keywords:
                kind = keywords[kind].get(value, kind)
            if kind not in accepts[stack[-1]]:  # UNMATCHED included
                pos = start
                break  # cut again by the state's own lexer
            first_line, column = line, start - line_start + 1
            if kind in newline and "\n" in value:
                line += value.count("\n")
                line_start = start + value.rindex("\n") + 1
            end = start + len(value)
            token = token_class(kind, value, start, first_line, column, line, end - line_start + 1,
                                end)
            if kind in callbacks:
                token = callbacks[kind](token)
            feed(token)
            last = token
        else:
            break  # the pass reached the end of the text
        last = _contextual_token(lexer, stack[-1], text, pos, line, line_start)
        pos, line = last.end_pos, last.end_line
        line_start = pos - last.end_column + 1
        feed(last)
    end = (token_class.new_borrow_pos("$END", "", last) if last is not None
           else token_class("$END", "", 0, 1, 1))
    return feed(end, True)


def _contextual_token(lexer: Lexer, state: int, text: str, pos: int, line: int, line_start: int
                      ) -> Any:
    """The token at ``pos`` as Lark's contextual lexer cuts it in parser state ``state``
    (raising its ``UnexpectedCharacters``, or ``UnexpectedToken`` for a token of another
    state, as it does)."""
    counter = LineCounter("\n")
    counter.char_pos, counter.line, counter.line_start_pos = pos, line, line_start
    counter.column = pos - line_start + 1
    whole = text if TextSlice is None else TextSlice(text, 0, len(text))
    cut = lexer.contextual().lex(LexerState(whole, counter), _InState(state))
    lexed = next(cut)  # there is a token at pos: pos is not in white space
    return lexer.token(lexed.type, str(lexed), lexed.start_pos, lexed.line, lexed.column,
                       lexed.end_line, lexed.end_column, lexed.end_pos)


@dataclass(frozen=True)
class _InState:
    """What the contextual lexer reads of the parser: its state."""

    position: int


__all__ = ["Lexer", "build", "parse"]
