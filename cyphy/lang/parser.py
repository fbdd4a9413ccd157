"""Text → syntax tree. Lark is touched here and in the modules this one composes.

The grammar (:mod:`cyphy.lang.grammar`) is loaded once. Parse errors become diagnostics with
spans and hints (:mod:`cyphy.lang.syntax_errors`); the builder (:mod:`cyphy.lang.builder`)
makes the frozen dataclasses of :mod:`cyphy.lang.ast` and :mod:`cyphy.expr` as the parser
reduces each rule (:mod:`cyphy.lang.reductions`: no Lark tree is built), so no Lark object
leaves the parser.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

from lark import Token, Tree
from lark.exceptions import UnexpectedInput

from cyphy.lang import reductions
from cyphy.lang.ast import ParseResult
from cyphy.lang.builder import Builder
from cyphy.lang.grammar import grammar
from cyphy.lang.syntax_errors import syntax_diagnostic

__all__ = ["ParseResult", "contains_lark_objects", "grammar", "parse_text"]


def parse_text(text: str, path: str = "<string>") -> ParseResult:
    """Parse one file's text. Never raises for bad input: problems come back as diagnostics."""
    if text.startswith("\ufeff"):
        text = text[1:]
    builder = Builder(text, path)
    # ``Lark.parse`` would call the tree builder's callbacks, made when the grammar was loaded;
    # an interactive parser has a state of its own, so this parse gets the builder's instead.
    parser = grammar().parse_interactive(text)
    parser.parser_state.parse_conf.callbacks = reductions.callbacks(_shapes(), builder)
    try:
        result, _ = parser.resume_parse()
    except UnexpectedInput as err:  # the builder's own diagnostics are of no use then
        return ParseResult(None, (syntax_diagnostic(err, text, path),))
    return ParseResult(result, tuple(builder.diagnostics))


@lru_cache(maxsize=None)
def _shapes() -> dict[Any, reductions.Shape]:
    """What each rule keeps, worked out once per process (the callbacks are per parse: they
    call one file's builder)."""
    return reductions.shapes(grammar())


def contains_lark_objects(node: object) -> bool:
    """True when a Lark ``Tree`` or ``Token`` is reachable from ``node`` (a test helper that
    guards the rule that no Lark object leaves this module)."""
    seen: set[int] = set()
    stack = [node]
    while stack:
        x = stack.pop()
        if id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, (Tree, Token)):
            return True
        if isinstance(x, (tuple, list)):
            stack.extend(x)
        elif hasattr(x, "__dataclass_fields__"):
            stack.extend(getattr(x, f) for f in x.__dataclass_fields__)
    return False
