"""The walk from Lark's tree to the syntax tree, and what every rule's method shares: spans,
flattened children, the small records (qualified names, tagged children) that only a
parent rule interprets."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable

from lark import Token, Tree

from cyphy import codes
from cyphy.diagnostics import Diagnostic, Span


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


def name_of(tok: Token) -> str:
    s = str(tok)
    return s[1:] if s.startswith("^") else s


def unescape(s: str) -> str:
    body = s[1:-1]
    return body.replace('\\"', '"').replace("\\\\", "\\")


class BuilderBase:
    """Builds the AST bottom-up. Methods are named after grammar rules and aliases and take
    ``(meta, children)``. The walk is a loop over Lark's bottom-up subtree order, so a long
    expression does not exhaust Python's stack, and it skips the per-call wrappers of Lark's
    ``Transformer`` (a fifth of the parse time)."""

    def __init__(self, text: str, path: str) -> None:
        self.text = text
        self.path = path
        self.diagnostics: list[Diagnostic] = []

    def transform(self, tree: Tree) -> Any:
        order: list[Tree] = []
        stack = [tree]
        while stack:  # parents before children; reversed, children before parents
            node = stack.pop()
            order.append(node)
            stack.extend(c for c in node.children if isinstance(c, Tree))
        results: dict[int, Any] = {}
        for sub in reversed(order):
            children = [results.pop(id(c)) if isinstance(c, Tree) else c for c in sub.children]
            results[id(sub)] = getattr(self, sub.data)(sub.meta, children)
        return results[id(tree)]

    # ----- helpers
    def _span(self, meta: Any) -> Span:
        if getattr(meta, "empty", True):
            return Span(self.path, 1, 1, 1, 1)
        return Span(self.path, meta.line, meta.column, meta.end_line, meta.end_column)

    def _tok_span(self, tok: Token) -> Span:
        return Span(self.path, tok.line or 0, tok.column or 0, tok.end_line or 0,
                    tok.end_column or 0)

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
