"""Where every name of a checked workspace is declared and used, by source position.

Built from what the front end already decided: the declarations are the syntax tree's named
nodes, the uses are :attr:`cyphy.lang.resolve.Resolution.uses` (what each reference resolved
to). Nothing here searches the text for a name's meaning; the text is read only to narrow a
node's span (a whole ``jref … { … }`` block) to the name written in it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Iterator

from cyphy.diagnostics import Span
from cyphy.expr import Expr, fields_of
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.workspace import Workspace

#: Named nodes an editor lists, goes to and hovers (what ``name`` means for each).
NAMED = (ast.PModel, ast.Part, ast.Block, ast.Definition, ast.VarDecl, ast.Param,
         ast.IndexDecl, ast.TypeDecl, ast.FunctionDecl, ast.DataType, ast.Enumeration,
         ast.UnitDecl, ast.AnnotationTemplate, ast.Interface, ast.Module, ast.RoboticPlatform,
         ast.Controller, ast.StateMachine, ast.State, ast.EventDecl, ast.OperationSig,
         ast.ClockDecl, ast.Transition)


@dataclass(frozen=True)
class Site:
    """A name written in a file: where (the name's own span) and the node it declares or
    refers to."""

    span: Span
    target: object


@dataclass
class Index:
    """The declaration and use sites of a workspace's files (user files and library files
    alike, so that a definition in the library has its own site to hover)."""

    texts: dict[str, str]
    declarations: dict[str, list[Site]] = field(default_factory=dict)  # file → sites
    uses: dict[str, list[Site]] = field(default_factory=dict)  # file → sites
    declared_at: dict[int, Span] = field(default_factory=dict)  # id(node) → its name's span
    nodes: dict[int, object] = field(default_factory=dict)  # id → node (keeps ids valid)

    def site_at(self, path: str, line: int, column: int) -> Site | None:
        """The innermost use or declaration of a name at a 1-based position."""
        best: Site | None = None
        for site in (*self.uses.get(path, ()), *self.declarations.get(path, ())):
            if _contains(site.span, line, column) and (best is None or _size(site.span) <
                                                       _size(best.span)):
                best = site
        return best

    def definition_of(self, target: object) -> Span | None:
        return self.declared_at.get(id(target))

    def references_to(self, target: object) -> list[Span]:
        """Every use of ``target`` over the indexed files, in file and position order."""
        found = [s.span for sites in self.uses.values() for s in sites
                 if s.target is target]
        return sorted(found)


def build_index(ws: Workspace, resolution: Resolution | None) -> Index:
    index = Index(dict(ws.texts))
    for path, file in ws.files.items():
        text = ws.texts.get(path, "")
        sites = index.declarations.setdefault(path, [])
        for node in walk(file):
            if isinstance(node, NAMED) and isinstance(getattr(node, "name", None), str):
                span = name_span(text, node.span, node.name)
                sites.append(Site(span, node))
                index.declared_at[id(node)] = span
                index.nodes[id(node)] = node
    if resolution is not None:
        for span, name, target in resolution.uses:
            if not name or span.line <= 0:
                continue
            text = index.texts.get(span.file, "")
            index.uses.setdefault(span.file, []).append(
                Site(name_span(text, span, name[-1], use=True), target))
            index.nodes[id(target)] = target
    return index


def walk(node: object) -> Iterator[object]:
    """Every syntax-tree node under ``node`` (expressions excluded), parents first."""
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, tuple):
            stack.extend(reversed(n))
        elif isinstance(n, ast.Node) and not isinstance(n, Expr):
            yield n
            for f in fields_of(type(n)):
                if f.name != "span" and not f.name.startswith("_"):
                    value = getattr(n, f.name)
                    if isinstance(value, (tuple, ast.Node)):
                        stack.append(value)


_LINE_STARTS: dict[int, tuple[str, list[int]]] = {}


def offset(text: str, line: int, column: int) -> int:
    """The index in ``text`` of a 1-based line and column."""
    key = id(text)
    cached = _LINE_STARTS.get(key)
    if cached is None or cached[0] is not text:
        starts = [0] + [m.end() for m in re.finditer("\n", text)]
        if len(_LINE_STARTS) > 64:
            _LINE_STARTS.clear()
        _LINE_STARTS[key] = cached = (text, starts)
    starts = cached[1]
    if line < 1:
        return 0
    if line > len(starts):
        return len(text)
    return min(starts[line - 1] + column - 1, len(text))


def position(text: str, at: int) -> tuple[int, int]:
    """The 1-based line and column of index ``at`` of ``text``."""
    line = text.count("\n", 0, at) + 1
    return line, at - (text.rfind("\n", 0, at) + 1) + 1


def name_span(text: str, span: Span, name: str, use: bool = False) -> Span:
    """The span of ``name`` written as a word inside ``span``, else ``span`` itself. A use
    inside ``xref N = Def`` or ``part N = P`` is written after the ``=`` (the node's own name
    comes first, and may be the same word)."""
    if span.line <= 0 or not text:
        return span
    start, end = offset(text, span.line, span.column), offset(text, span.end_line,
                                                               span.end_column)
    if use:
        head = re.match(r"\s*(\w+ref|part|cref|rref|sref)\b[^=]*=", text[start:end])
        if head is not None:
            start += head.end()
    m = re.search(rf"(?<![\w]){re.escape(name)}(?![\w])", text[start:end])
    if m is None:
        return span
    line, column = position(text, start + m.start())
    return Span(span.file, line, column, line, column + len(name))


def _contains(span: Span, line: int, column: int) -> bool:
    return (span.line, span.column) <= (line, column) <= (span.end_line, span.end_column)


def _size(span: Span) -> tuple[int, int]:
    return span.end_line - span.line, span.end_column - span.column
