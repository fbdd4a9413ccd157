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
from cyphy import expr as ex
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
        _machine_uses(index, ws, resolution)
    return index


def _machine_uses(index: Index, ws: Workspace, resolution: Resolution) -> None:
    """The names of state machines and operation definitions, as the machines' semantics
    resolves them (:mod:`cyphy.model.machines`): a transition's ends are nodes of its
    scope; a name in a trigger, guard or action is the machine's variable, constant or
    clock, or an event or operation of the interfaces it uses."""
    # lazy: the machines' model is built only when a request needs the index
    from cyphy.model.machines import expressions, machines_of

    try:
        machines = machines_of(list(ws.user_files()), resolution, operations=True)
    except Exception:  # a half-written machine: its names are simply not indexed
        return
    for m in machines:
        for t in m.transitions:
            for key, span in ((t.source, t.decl.source_span), (t.target, t.decl.target_span)):
                node = m.nodes.get(key) if key is not None else None
                if node is not None and span is not None:
                    _use(index, span, node.decl)
        tables = (m.variables, m.constants, m.clocks, m.platform.input_events,
                  m.platform.output_events, m.platform.operations)
        for e, _ in expressions(m):
            for name in e.walk():
                parts = name.parts if isinstance(name, ex.Name) else (
                    name.name if isinstance(name, ex.PlatformRef) else ())
                if len(parts) == 1:
                    target = next((t[parts[0]] for t in tables if parts[0] in t), None)
                    if target is not None:
                        text = index.texts.get(name.span.file, "")
                        _use(index, name_span(text, name.span, parts[0]), target)


def _use(index: Index, span: Span, target: object) -> None:
    if span.line > 0:
        index.uses.setdefault(span.file, []).append(Site(span, target))
        index.nodes[id(target)] = target


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
