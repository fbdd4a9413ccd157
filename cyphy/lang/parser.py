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

from lark import Tree
from lark.exceptions import UnexpectedInput

from cyphy.lang import reductions
from cyphy.lang.ast import ParseResult
from cyphy.lang.builder import Builder
from cyphy.lang.grammar import TOKEN_TYPES, Engine, compiled, grammar, pure
from cyphy.lang.syntax_errors import syntax_diagnostic

__all__ = ["ParseResult", "contains_lark_objects", "grammar", "parse_text"]


def parse_text(text: str, path: str = "<string>") -> ParseResult:
    """Parse one file's text. Never raises for bad input: problems come back as diagnostics.

    lark-cython parses when it is installed; a file it finds a syntax error in is parsed again
    by pure Lark, which describes the error (:mod:`cyphy.lang.grammar`)."""
    if text.startswith("\ufeff"):
        text = text[1:]
    fast = compiled()
    if fast is not None:
        try:
            return parse_with(fast, text, path)
        except UnexpectedInput:
            pass  # described below, by the engine whose errors the diagnostics read
    try:
        return parse_with(pure(), text, path)
    except UnexpectedInput as err:  # the builder's own diagnostics are of no use then
        return ParseResult(None, (syntax_diagnostic(err, text, path),))


def parse_with(engine: Engine, text: str, path: str) -> ParseResult:
    """One parse by ``engine``, the syntax tree built as it reduces; raises Lark's
    ``UnexpectedInput`` on a syntax error. (``parse_text`` chooses the engine; the tests
    compare the two.)"""
    builder = Builder(text, path)
    result, _ = engine.parse(text, reductions.callbacks(_shapes(engine.lark), builder))
    return ParseResult(result, tuple(builder.diagnostics))


@lru_cache(maxsize=None)
def _shapes(lark: Any) -> dict[Any, reductions.Shape]:
    """What each rule keeps, worked out once per engine (the callbacks are per parse: they
    call one file's builder). Keyed by the engine's own rule objects, which its parser looks
    up by identity first."""
    return reductions.shapes(lark)


def contains_lark_objects(node: object) -> bool:
    """True when a Lark ``Tree`` or a token (of either engine) is reachable from ``node`` (a
    test helper that guards the rule that no Lark object leaves this module)."""
    seen: set[int] = set()
    stack = [node]
    while stack:
        x = stack.pop()
        if id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, (Tree, *TOKEN_TYPES)):
            return True
        if isinstance(x, (tuple, list)):
            stack.extend(x)
        elif hasattr(x, "__dataclass_fields__"):
            stack.extend(getattr(x, f) for f in x.__dataclass_fields__)
    return False
