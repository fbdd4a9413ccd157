"""Lark's parse errors as diagnostics: what was expected in words, the span of the
offending token, hints for the usual slips (an unclosed block, a misspelt keyword)."""

from __future__ import annotations

import difflib
import re
from typing import Iterable

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from cyphy import codes
from cyphy.diagnostics import Diagnostic, Span
from cyphy.lang.grammar import grammar

_FRIENDLY = {
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "UNIT": "a unit",
    "$END": "end of file",
}


def _describe_terminal(name: str) -> str:
    if name in _FRIENDLY:
        return _FRIENDLY[name]
    try:
        term = grammar().get_terminal(name)
    except KeyError:
        return name
    if term.pattern.type == "str":
        return f"'{term.pattern.value}'"
    return name.lower()


def _expected_text(expected: Iterable[str]) -> str:
    names = sorted({_describe_terminal(e) for e in expected})
    if len(names) > 12:
        names = names[:12] + ["…"]
    return ", ".join(names)


def _keywords(expected: Iterable[str]) -> list[str]:
    out = []
    for e in expected:
        try:
            term = grammar().get_terminal(e)
        except KeyError:
            continue
        if term.pattern.type == "str" and term.pattern.value.isidentifier():
            out.append(term.pattern.value)
    return out


def _open_blocks(text: str, upto: int) -> list[int]:
    """Offsets of the braces still open at ``upto`` (ignoring comments and strings)."""
    stack: list[int] = []
    i = 0
    while i < upto:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = upto if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = upto if j < 0 else j + 2
            continue
        if c == '"':
            j = text.find('"', i + 1)
            i = upto if j < 0 else j + 1
            continue
        if c == "{":
            stack.append(i)
        elif c == "}" and stack:
            stack.pop()
        i += 1
    return stack


def _line_col(text: str, offset: int) -> tuple[int, int]:
    line = text.count("\n", 0, offset) + 1
    col = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return line, col


def syntax_diagnostic(err: UnexpectedInput, text: str, path: str) -> Diagnostic:
    line = getattr(err, "line", 1) or 1
    column = getattr(err, "column", 1) or 1
    if isinstance(err, UnexpectedCharacters):
        char = text[err.pos_in_stream] if err.pos_in_stream < len(text) else ""
        hint = "remove the character or check the spelling around it"
        message = f"unexpected character {char!r}"
        if text.startswith("/*", err.pos_in_stream):
            message = "unterminated block comment"
            hint = "close the comment with '*/'"
        elif char == '"':
            message = "unterminated string"
            hint = "close the string with '\"'"
        elif char == "^":
            hint = "'^' is a power operator or escapes a name ('^x'); nothing else"
        elif err.allowed:
            hint = f"expected {_expected_text(err.allowed)}"
        span = Span(path, line, column, line, column + 1)
        return Diagnostic(codes.LEX, message, span, hint)

    if isinstance(err, (UnexpectedToken, UnexpectedEOF)):
        token = getattr(err, "token", None)
        expected = getattr(err, "expected", set()) or set()
        at_end = token is None or token.type == "$END"
        if at_end:
            opened = _open_blocks(text, len(text))
            if opened:
                oline, ocol = _line_col(text, opened[-1])
                span = Span(path, oline, ocol, oline, ocol + 1)
                return Diagnostic(
                    codes.SYNTAX,
                    "unexpected end of file: this block is not closed",
                    span,
                    "add the missing '}'",
                    (f"expected {_expected_text(expected)}",),
                )
            eline, ecol = _line_col(text, len(text))
            span = Span(path, eline, ecol, eline, ecol + 1)
            return Diagnostic(
                codes.SYNTAX,
                "unexpected end of file",
                span,
                f"expected {_expected_text(expected)}",
            )
        value = str(token)
        rest = text[token.start_pos:] if token.start_pos is not None else ""
        if rest.startswith("/*") and "*/" not in rest:
            return Diagnostic(codes.LEX, "unterminated block comment",
                              Span(path, line, column, line, column + 2),
                              "close the comment with '*/'")
        if rest.startswith('"') and token.type != "STRING":
            return Diagnostic(codes.LEX, "unterminated string",
                              Span(path, line, column, line, column + 1),
                              "close the string with '\"'")
        end_col = (token.end_column or column + len(value)) if token.end_line == line else column + 1
        span = Span(path, line, column, line, max(end_col, column + 1))
        message = f"unexpected {_describe_token(token)}"
        hint = f"expected {_expected_text(expected)}"
        close = difflib.get_close_matches(value, _keywords(expected), n=1, cutoff=0.7)
        word = _connective(value, text[:token.start_pos or 0])
        if word:  # `a and b`: RoboSim's connectives are symbols
            symbol = "/\\" if word == "and" else "\\/"
            hint = f"RoboSim writes '{word}' as '{symbol}', for example a {symbol} b ({hint})"
        elif close and token.type == "NAME":
            hint = f"did you mean '{close[0]}'? ({hint})"
        elif token.type == "NAME" and value in _keywords(expected):
            pass
        return Diagnostic(codes.SYNTAX, message, span, hint)

    span = Span(path, line, column, line, column + 1)
    return Diagnostic(codes.SYNTAX, str(err).splitlines()[0], span, "")


def _connective(value: str, before: str) -> str | None:
    """``and`` or ``or`` when the unexpected token is that word or follows it: a newcomer's
    conjunction, which RoboSim writes ``/\\`` (and disjunction ``\\/``)."""
    if value in ("and", "or"):
        return value
    # `a and b`, or `(a) and (b)`, which parses as a call of `and` until the next line
    recent = "\n".join(before.splitlines()[-2:])
    found = re.findall(r"(?<![\w.:])(and|or)(?=\s*(?:\(|$))", recent)
    return found[-1] if found else None


def _describe_token(token: Token) -> str:
    if token.type == "NAME":
        return f"name '{token}'"
    if token.type == "NUMBER":
        return f"number {token}"
    return f"'{token}'"
