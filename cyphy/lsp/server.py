"""The language server: LSP messages over stdio (``pygls``), answered by :mod:`cyphy.lsp.features`.

Each folder that holds an open document is one project, checked as ``cyphy check`` checks the
model files of that folder (their neighbours, the ``--path`` folders and the built-in library
resolve with them), with the open documents' unsaved texts in place of the files on disk. A
change re-checks its folder after a short pause (typing fast checks once); the parse cache
serves the files that did not change. Whatever a check raises is reported to the editor's log,
never to the protocol: the server keeps the last answers it had.
"""

from __future__ import annotations

import asyncio
import functools
import os
import traceback
from pathlib import Path
from typing import Any, Callable

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

import cyphy
from cyphy import collector
from cyphy.diagnostics import Diagnostic, Severity, Span
from cyphy.lang import parse_cache
from cyphy.lang.workspace import MODEL_SUFFIXES, model_files_in
from cyphy.lsp import features
from cyphy.lsp.features import Analysis, Symbol

#: Seconds without a change before a changed folder is checked again.
DEBOUNCE_S = 0.03


class CyphyServer(LanguageServer):
    """The server's state: the settings, each folder's last analysis and pending check."""

    def __init__(self, search_paths: tuple[str, ...] = ()) -> None:
        super().__init__("cyphy", cyphy.__version__,
                         text_document_sync_kind=lsp.TextDocumentSyncKind.Incremental)
        self.search_paths = search_paths
        self.consistency = False
        self.analyses: dict[str, Analysis] = {}  # folder → its last analysis
        self.published: dict[str, set[str]] = {}  # folder → files given diagnostics
        self.pending: dict[str, asyncio.Task[None]] = {}
        self.last_parsed: dict[str, Analysis] = {}  # file → last analysis where it parsed

    # ------------------------------------------------------------------ documents
    def open_texts(self) -> dict[str, str]:
        out = {}
        for uri, doc in self.workspace.text_documents.items():
            path = to_fs_path(uri)
            if path is not None and Path(path).suffix in MODEL_SUFFIXES:
                out[path] = doc.source
        return out

    def analyse_folder(self, folder: str) -> None:
        """Check the folder now and publish every open file's diagnostics in it."""
        texts = self.open_texts()
        opened = sorted(p for p in texts if str(Path(p).parent) == folder)
        if not opened:
            self.analyses.pop(folder, None)
            self._publish(folder, {})
            return
        on_disk = [str(p) for p in model_files_in(Path(folder), recursive=False)]
        targets = sorted(set(on_disk) | set(opened))
        try:
            analysis = features.analyse(targets, texts, self.search_paths, self.consistency)
        except (Exception, RecursionError) as err:  # a bug of ours: log it, keep serving
            self.window_log_message(lsp.LogMessageParams(
                type=lsp.MessageType.Error,
                message=f"cyphy: internal error while checking {folder}: "
                f"{type(err).__name__}: {err}\n{traceback.format_exc()}"))
            return
        self.analyses[folder] = analysis
        for path in targets:
            if path in analysis.result.workspace.files:
                self.last_parsed[path] = analysis
        # Every file of the folder gets its diagnostics (an editor lists those of closed
        # files too); one with no file (a folder's) goes to the first open one.
        by_file: dict[str, list[Diagnostic]] = {p: [] for p in targets}
        for d in analysis.result.report.diagnostics:
            by_file[d.span.file if d.span.file in by_file else opened[0]].append(d)
        sources = analysis.result.sources
        self._publish(folder, {p: [_diagnostic(texts.get(p, sources.get(p)), d) for d in ds]
                               for p, ds in by_file.items()})

    def _publish(self, folder: str, diagnostics: dict[str, list[lsp.Diagnostic]]) -> None:
        for path in sorted(self.published.get(folder, set()) - set(diagnostics)):
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
                uri=_uri(path), diagnostics=[]))
        for path, items in diagnostics.items():
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
                uri=_uri(path), diagnostics=items))
        self.published[folder] = set(diagnostics)

    def schedule(self, folder: str) -> None:
        """Check ``folder`` once no change has come for :data:`DEBOUNCE_S`."""
        task = self.pending.get(folder)
        if task is not None:
            task.cancel()

        async def later() -> None:
            await asyncio.sleep(DEBOUNCE_S)
            self.pending.pop(folder, None)
            self.analyse_folder(folder)

        self.pending[folder] = asyncio.ensure_future(later())

    def flush(self, folder: str) -> None:
        """Run a pending check of ``folder`` now: a request answers from the text it sees."""
        task = self.pending.pop(folder, None)
        if task is not None:
            task.cancel()
            self.analyse_folder(folder)

    def analysis_of(self, uri: str) -> tuple[str, Analysis | None]:
        path, folder = to_fs_path(uri) or uri, _folder(uri)
        self.flush(folder)
        if folder not in self.analyses and path in self.open_texts():
            self.analyse_folder(folder)
        analysis = self.analyses.get(folder)
        if analysis is not None and path not in analysis.result.workspace.files:
            # Half typed, it does not parse: answer from when it last did.
            analysis = self.last_parsed.get(path, analysis)
        return path, analysis


def _folder(uri: str) -> str:
    """The folder of a document: the project it is checked with."""
    return str(Path(to_fs_path(uri) or uri).parent)


def _uri(path: str) -> str:
    return from_fs_path(path) or path


# --------------------------------------------------------------------------- positions
# cyphy counts lines and columns from 1 in code points; LSP from 0 in UTF-16 code units.


def _line_text(text: str, line: int) -> str:
    lines = text.split("\n")
    return lines[line - 1] if 0 < line <= len(lines) else ""


def to_lsp(text: str | None, line: int, column: int) -> lsp.Position:
    if line <= 0:
        return lsp.Position(line=0, character=0)
    prefix = _line_text(text, line)[:column - 1] if text is not None else "x" * (column - 1)
    return lsp.Position(line=line - 1, character=len(prefix.encode("utf-16-le")) // 2)


def from_lsp(text: str, pos: lsp.Position) -> tuple[int, int]:
    source = _line_text(text, pos.line + 1)
    units, column = 0, 0
    while column < len(source) and units < pos.character:
        units += 2 if ord(source[column]) > 0xFFFF else 1
        column += 1
    return pos.line + 1, column + 1


def _range(text: str | None, span: Span) -> lsp.Range:
    return lsp.Range(start=to_lsp(text, span.line, span.column),
                     end=to_lsp(text, span.end_line, span.end_column))


def _diagnostic(text: str | None, d: Diagnostic) -> lsp.Diagnostic:
    severity = (lsp.DiagnosticSeverity.Error if d.severity is Severity.ERROR
                else lsp.DiagnosticSeverity.Warning)
    message = d.message + "".join(f"\nnote: {n}" for n in d.notes) + (
        f"\nhint: {d.hint}" if d.hint else "")
    return lsp.Diagnostic(range=_range(text, d.span), message=message, severity=severity,
                          code=d.code.id, source="cyphy")


def _location(server: CyphyServer, analysis: Analysis, span: Span) -> lsp.Location:
    text = server.open_texts().get(span.file) or analysis.index.texts.get(span.file)
    return lsp.Location(uri=_uri(span.file), range=_range(text, span))


# --------------------------------------------------------------------------- the protocol


def _guarded(default: Any) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """A request that raises answers ``default`` (and the error goes to the editor's log):
    a bug met on a half-typed file must not turn into an error box at every keystroke."""
    def wrap(handler: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(handler)
        def guarded(ls: CyphyServer, params: Any) -> Any:
            try:
                return handler(ls, params)
            except (Exception, RecursionError) as err:
                ls.window_log_message(lsp.LogMessageParams(
                    type=lsp.MessageType.Error, message=f"cyphy: internal error in "
                    f"{handler.__name__}: {type(err).__name__}: {err}\n"
                    f"{traceback.format_exc()}"))
                return default() if callable(default) else default
        return guarded
    return wrap


def build(search_paths: tuple[str, ...] = ()) -> CyphyServer:
    parse_cache.keep_recent()  # unchanged files are checked again at every edit
    # A server runs for hours, checking at every edit: the cycles among what one check built
    # must be collected before the next (the ``cyphy`` command keeps its results frozen).
    collector.keep_frozen(False)
    server = CyphyServer(search_paths)

    @server.feature(lsp.INITIALIZE)
    def initialize(ls: CyphyServer, params: lsp.InitializeParams) -> None:
        options: Any = params.initialization_options or {}
        if isinstance(options, dict):
            ls.consistency = bool(options.get("consistency", False))
            extra = options.get("path", [])
            if isinstance(extra, list):
                ls.search_paths = ls.search_paths + tuple(str(p) for p in extra)

    # Opening or closing a file changes what its folder's check covers: check it now. An
    # edit or a save: once typing pauses.
    @server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: CyphyServer, params: lsp.DidOpenTextDocumentParams) -> None:
        ls.analyse_folder(_folder(params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: CyphyServer, params: lsp.DidCloseTextDocumentParams) -> None:
        ls.analyse_folder(_folder(params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: CyphyServer, params: lsp.DidChangeTextDocumentParams) -> None:
        ls.schedule(_folder(params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: CyphyServer, params: lsp.DidSaveTextDocumentParams) -> None:
        ls.schedule(_folder(params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
    @_guarded(None)
    def definition(ls: CyphyServer, params: lsp.DefinitionParams) -> lsp.Location | None:
        path, analysis = ls.analysis_of(params.text_document.uri)
        site = _site(ls, analysis, path, params.position)
        if analysis is None or site is None:
            return None
        span = analysis.index.definition_of(site.target)
        return _location(ls, analysis, span) if span is not None else None

    @server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
    @_guarded(list)
    def references(ls: CyphyServer, params: lsp.ReferenceParams) -> list[lsp.Location]:
        path, analysis = ls.analysis_of(params.text_document.uri)
        site = _site(ls, analysis, path, params.position)
        if analysis is None or site is None:
            return []
        spans = analysis.index.references_to(site.target)
        declared = analysis.index.definition_of(site.target)
        if params.context.include_declaration and declared is not None:
            spans = [declared, *spans]
        return [_location(ls, analysis, s) for s in spans]

    @server.feature(lsp.TEXT_DOCUMENT_HOVER)
    @_guarded(None)
    def hover(ls: CyphyServer, params: lsp.HoverParams) -> lsp.Hover | None:
        path, analysis = ls.analysis_of(params.text_document.uri)
        text = ls.open_texts().get(path)
        if analysis is None or text is None:
            return None
        line, column = from_lsp(text, params.position)
        found = features.hover(analysis, path, line, column)
        if found is None:
            return None
        markdown, span = found
        return lsp.Hover(contents=lsp.MarkupContent(kind=lsp.MarkupKind.Markdown, value=markdown),
                         range=_range(text, span))

    @server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                    lsp.CompletionOptions(trigger_characters=[":", "{"]))
    @_guarded(_no_completions)
    def completion(ls: CyphyServer, params: lsp.CompletionParams) -> lsp.CompletionList:
        path, analysis = ls.analysis_of(params.text_document.uri)
        text = ls.open_texts().get(path, "")
        line, column = from_lsp(text, params.position)
        items = [lsp.CompletionItem(label=c.label, kind=_COMPLETION_KIND.get(
            c.kind, lsp.CompletionItemKind.Text), detail=c.detail or None)
            for c in features.completions(analysis, path, text, line, column)]
        return lsp.CompletionList(is_incomplete=False, items=items)

    @server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    @_guarded(list)
    def document_symbol(ls: CyphyServer, params: lsp.DocumentSymbolParams
                        ) -> list[lsp.DocumentSymbol]:
        path, analysis = ls.analysis_of(params.text_document.uri)
        if analysis is None:
            return []
        file = analysis.result.workspace.files.get(path)
        if file is None:  # it never parsed
            return []
        text = ls.open_texts().get(path)
        return [_symbol(text, s) for s in features.document_symbols(analysis.index, file)]

    return server


def _no_completions() -> lsp.CompletionList:
    return lsp.CompletionList(is_incomplete=False, items=[])


def _site(ls: CyphyServer, analysis: Analysis | None, path: str,
          pos: lsp.Position) -> Any:
    text = ls.open_texts().get(path)
    if analysis is None or text is None:
        return None
    line, column = from_lsp(text, pos)
    return analysis.index.site_at(path, line, column)


_COMPLETION_KIND = {
    "keyword": lsp.CompletionItemKind.Keyword, "module": lsp.CompletionItemKind.Module,
    "class": lsp.CompletionItemKind.Class, "constant": lsp.CompletionItemKind.Constant,
    "variable": lsp.CompletionItemKind.Variable, "field": lsp.CompletionItemKind.Field,
    "function": lsp.CompletionItemKind.Function, "reference": lsp.CompletionItemKind.Reference,
}


def _symbol(text: str | None, s: Symbol) -> lsp.DocumentSymbol:
    kind = getattr(lsp.SymbolKind, "".join(w.capitalize() for w in s.kind.split("_")),
                   lsp.SymbolKind.Object)
    return lsp.DocumentSymbol(name=s.name, detail=s.detail, kind=kind,
                              range=_range(text, s.span),
                              selection_range=_range(text, s.selection),
                              children=[_symbol(text, c) for c in s.children])


def serve(search_paths: tuple[str, ...] = ()) -> None:
    """Serve over stdin and stdout until the client exits. The server reads and writes
    copies of the two descriptors, which it closes when the client leaves; the process's own
    streams stay open for the command line's orderly exit."""
    with os.fdopen(os.dup(0), "rb") as stdin, os.fdopen(os.dup(1), "wb") as stdout:
        build(search_paths).start_io(stdin, stdout)

