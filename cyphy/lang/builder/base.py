"""What every rule's method of the syntax-tree builder shares: spans,
flattened children, the small records (qualified names, tagged children) that only a
parent rule interprets."""

from __future__ import annotations

from dataclasses import dataclass
from sys import intern
from typing import Any, Iterable

from lark import Token

from cyphy import codes
from cyphy.diagnostics import Diagnostic, Span
from cyphy.lang.reductions import Pos


@dataclass(frozen=True, slots=True)
class QN:
    parts: tuple[str, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class Tagged:
    """A child that only its parent interprets (index bracket, pre/postcondition…)."""

    tag: str
    value: Any
    span: Span


def text_of(tok: Token) -> str:
    """A token's text, interned: a large model repeats a few names and numbers (``x``,
    ``0.0``, ``Revolute``) hundreds of thousands of times, and each token's text is a string
    of its own (a 5,000-link tree held 345,000 strings, 17 MB; interned, 28,000). The parse
    cache then also writes each once."""
    return intern(str(tok))


def name_of(tok: Token) -> str:
    s = str(tok)
    return intern(s[1:] if s.startswith("^") else s)


def unescape(s: str) -> str:
    body = s[1:-1]
    return body.replace('\\"', '"').replace("\\\\", "\\")


class BuilderBase:
    """Builds the AST bottom-up. Methods are named after grammar rules and aliases and take
    ``(pos, children)``: the rule's text as ``(line, column, end_line, end_column)`` (None
    when it matched nothing) and its kept children, already built. They are called while the
    parser reduces (:mod:`cyphy.lang.reductions`), so no Lark tree is built or walked."""

    def __init__(self, text: str, path: str) -> None:
        self.text = text
        self.path = path
        self.diagnostics: list[Diagnostic] = []
        #: One int object per line number, shared by every span on that line: a line past
        #: 256 is otherwise a new int in each span that starts or ends on it (a 5,000-link
        #: tree held 600,000 of them, 16 MB; lark-cython's tokens make a new one per read).
        self._lines: dict[int, int] = {}

    # ----- helpers
    def _span(self, pos: Pos) -> Span:
        if pos is None:
            return Span(self.path, 1, 1, 1, 1)
        line, column, end_line, end_column = pos
        lines = self._lines
        return Span(self.path, lines.setdefault(line, line), column,
                    lines.setdefault(end_line, end_line), end_column)

    def _tok_span(self, tok: Token) -> Span:
        return self._span((tok.line or 0, tok.column or 0, tok.end_line or 0,
                           tok.end_column or 0))

    @staticmethod
    def _flat(children: Iterable[Any]) -> tuple[Any, ...]:
        out: list[Any] = []
        for c in children:
            if c is None:
                continue
            if isinstance(c, list):
                out.extend(c)
            else:
                out.append(c)
        return tuple(out)

    def _duplicate(self, what: str, where: str, span: Span) -> None:
        """A member given twice (a mesh's or an inertial's entry, a transition's part)."""
        self.diagnostics.append(
            Diagnostic(codes.DUPLICATE_MEMBER, f"'{what}' is given twice in {where}", span,
                       f"keep one '{what}'")
        )
