"""Diagnostics as data: codes, spans, messages and hints, collected and rendered once.

Every stage reports problems through a :class:`Report`; nothing in the pipeline prints, raises
for bad input, or exits. The CLI renders the collected diagnostics and derives its exit status
from them (see ``../shared/spec/style.md``, sections 4 and 9).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Iterable, Iterator

from cyphy.pickling import FastPickle, restore
from cyphy.records import record, slot_setter


class Severity(str, Enum):
    ERROR = "ERROR"
    WARNING = "WARNING"


@dataclass(frozen=True, slots=True, order=True, init=False)
class Span(FastPickle):
    """A region of a source file; lines and columns count from 1, ``end_column`` is exclusive.
    (Its ``__init__``, below, sets the slots through their own setters: the parser makes a
    span per node, a third of a million for a 10,000-link model.)"""

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"

    @staticmethod
    def unknown(file: str = "<unknown>") -> Span:
        return Span(file, 0, 0, 0, 0)

    def __reduce__(self) -> tuple[object, ...]:
        """Pickled with its end line relative to its start: most spans end on the line they
        start on, and a small number is one shared object when unpickled where a line
        number past 256 is a new one (a tenth of a large model's cached tree was lines)."""
        return _span, (self.file, self.line, self.column, self.end_line - self.line,
                       self.end_column)

    def to_json(self) -> dict[str, object]:
        return {
            "file": self.file,
            "line": self.line,
            "column": self.column,
            "end_line": self.end_line,
            "end_column": self.end_column,
        }


_SET_FILE, _SET_LINE, _SET_COLUMN, _SET_END_LINE, _SET_END_COLUMN = (
    slot_setter(Span, name) for name in ("file", "line", "column", "end_line", "end_column"))


def _init_span(self: Span, file: str, line: int, column: int, end_line: int, end_column: int
               ) -> None:
    _SET_FILE(self, file)
    _SET_LINE(self, line)
    _SET_COLUMN(self, column)
    _SET_END_LINE(self, end_line)
    _SET_END_COLUMN(self, end_column)


Span.__init__ = _init_span  # type: ignore[method-assign]


def _span(file: str, line: int, column: int, lines: int, end_column: int) -> Span:
    """The inverse of :meth:`Span.__reduce__`."""
    return restore(Span, file, line, column, line + lines if lines else line,
                   end_column)


@record
class Code:
    """A diagnostic code: an id such as ``S1`` or ``E-SYNTAX``, its severity and a summary."""

    id: str
    severity: Severity
    summary: str


@record
class Diagnostic:
    code: Code
    message: str
    span: Span
    hint: str = ""
    notes: tuple[str, ...] = ()

    @property
    def severity(self) -> Severity:
        return self.code.severity

    def to_json(self) -> dict[str, object]:
        return {
            "code": self.code.id,
            "severity": self.severity.value,
            "message": self.message,
            "span": self.span.to_json(),
            "hint": self.hint,
            "notes": list(self.notes),
        }


def _sort_key(d: Diagnostic) -> tuple[object, ...]:
    return (d.span.file, d.span.line, d.span.column, d.code.id, d.message)


@record(frozen=False, slots=False)
class Report:
    """Collects diagnostics; de-duplicates and sorts them when read."""

    _items: list[Diagnostic] = field(default_factory=list)

    def add(self, diagnostic: Diagnostic) -> None:
        self._items.append(diagnostic)

    def extend(self, diagnostics: Iterable[Diagnostic]) -> None:
        self._items.extend(diagnostics)

    def report(
        self, code: Code, message: str, span: Span, hint: str = "", notes: Iterable[str] = ()
    ) -> None:
        self._items.append(Diagnostic(code, message, span, hint, tuple(notes)))

    def reported_since(self, start: int) -> list[Diagnostic]:
        """The diagnostics from the ``start``-th reported on, as reported (not sorted, not
        de-duplicated): for indexes kept up to date as a report grows."""
        return self._items[start:]

    @property
    def diagnostics(self) -> list[Diagnostic]:
        seen: set[tuple[object, ...]] = set()
        unique = []
        for d in sorted(self._items, key=_sort_key):
            key = (d.code.id, d.message, d.span)
            if key not in seen:
                seen.add(key)
                unique.append(d)
        return unique

    def __iter__(self) -> Iterator[Diagnostic]:
        return iter(self.diagnostics)

    def __len__(self) -> int:
        return len(self.diagnostics)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def has_errors(self) -> bool:
        return any(d.severity is Severity.ERROR for d in self._items)

    @property
    def exit_code(self) -> int:
        return 1 if self.has_errors else 0


#: The longest source excerpt and message printed: a model may hold a 5 MB line.
EXCERPT_WIDTH = 160
MESSAGE_WIDTH = 1000


def printable(text: str) -> str:
    """``text`` with control characters (terminal escape sequences, NUL, bidirectional
    overrides) written as escapes (``\\x1b``), so a model's bytes never act on the terminal."""
    if text.isprintable():  # the common case, checked in C (a long check prints thousands)
        return text
    return "".join(ch if ch.isprintable() or ch == " " else _escape(ch) for ch in text)


def _escape(ch: str) -> str:
    code = ord(ch)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 \
        else f"\\U{code:08x}"


def _shortened(text: str, limit: int = MESSAGE_WIDTH) -> str:
    text = printable(text)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _excerpt(line: str, column: int, width: int) -> tuple[str, int, int]:
    """The part of a source line to print, escaped, and where the caret goes in it (column
    from 0, width): a window of :data:`EXCERPT_WIDTH` characters around ``column``."""
    line = line.replace("\t", " ")
    start = max(0, min(column - 1 - EXCERPT_WIDTH // 3, len(line) - EXCERPT_WIDTH))
    end = min(len(line), start + EXCERPT_WIDTH)
    before = printable(line[start:column - 1])
    marked = printable(line[column - 1:column - 1 + width])
    text = ("…" if start > 0 else "") + printable(line[start:end]) + ("…" if end < len(line)
                                                                        else "")
    caret = len(before) + (1 if start > 0 else 0)
    return text, caret, max(1, min(len(marked), len(text) - caret))


@record(frozen=False, slots=False)
class Rendering:
    """How the command line shows diagnostics, set once by ``cyphy -q`` and
    ``--warnings-as-errors`` for whichever command runs: ``quiet`` leaves warnings out of
    :func:`render_text`; ``warnings_seen`` counts those it was given, so that the command's
    exit status can treat them as errors."""

    quiet: bool = False
    warnings_seen: int = 0
    #: errors whose code is a usage error (:data:`USAGE_CODES`): the command exits 2
    usage_errors: int = 0


#: Codes of errors in the command line's values rather than in the model: exit status 2.
USAGE_CODES = frozenset({"E-OPTION"})


RENDERING = Rendering()


def render_text(diagnostics: Iterable[Diagnostic], sources: dict[str, str] | None = None) -> str:
    """Render like rustc or mypy: location, severity and code, the source line with a caret.
    What comes from the model is escaped and cut (``printable``, :data:`EXCERPT_WIDTH`)."""
    sources = sources if sources is not None else {}
    split: dict[str, list[str]] = {}  # each file's lines, split once: a large model warns
    out: list[str] = []               # thousands of times about the same file
    for d in diagnostics:
        if d.severity is Severity.WARNING:
            RENDERING.warnings_seen += 1
            if RENDERING.quiet:
                continue
        elif d.code.id in USAGE_CODES:
            RENDERING.usage_errors += 1
        out.append(f"{_location(d.span)}{d.severity.value} {d.code.id}: "
                   f"{_shortened(d.message)}")
        text = sources.get(d.span.file)
        if text is None and d.span.line > 0:
            try:
                text = Path(d.span.file).read_text(encoding="utf-8", errors="replace")
                sources[d.span.file] = text
            except OSError:
                text = None
        if text is not None and d.span.line > 0:
            lines = split.get(d.span.file)
            if lines is None:
                lines = split[d.span.file] = text.splitlines()
            if d.span.line <= len(lines):
                width = 1
                if d.span.end_line == d.span.line and d.span.end_column > d.span.column:
                    width = d.span.end_column - d.span.column
                src, caret, width = _excerpt(lines[d.span.line - 1], d.span.column, width)
                gutter = f"{d.span.line:>5} | "
                out.append(gutter + src)
                out.append(" " * (len(gutter) + caret) + "^" * width)
        for note in d.notes:
            out.append(f"  note: {_shortened(note)}")
        if d.hint:
            out.append(f"  hint: {_shortened(d.hint)}")
    return "\n".join(out) + ("\n" if out else "")


def _location(span: Span) -> str:
    """``file:line:column: `` — the file alone when no line is known, nothing when neither
    is (never ``<unknown>:0:0``)."""
    if span.file in ("", "<unknown>"):
        return ""
    if span.line <= 0:
        return f"{printable(span.file)}: "
    return f"{printable(span.file)}:{span.line}:{span.column}: "


def render_json(diagnostics: Iterable[Diagnostic]) -> str:
    return json.dumps(diagnostics_json(diagnostics), indent=2) + "\n"


def diagnostics_json(diagnostics: Iterable[Diagnostic]) -> list[dict[str, object]]:
    """The diagnostics as JSON values (all of them: ``quiet`` concerns text only)."""
    out = [d.to_json() for d in diagnostics]
    RENDERING.warnings_seen += sum(1 for d in out if d["severity"] == "WARNING")
    RENDERING.usage_errors += sum(1 for d in out if d["code"] in USAGE_CODES)
    return out


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """A hint naming the closest candidates (``did you mean 'Revolute'?``), or ``""``."""
    import difflib  # lazy: only a misspelt name needs it, and every command imports this module

    close = difflib.get_close_matches(name, sorted(set(candidates)), n=3, cutoff=0.6)
    if not close:
        return ""
    return "did you mean " + " or ".join(f"'{c}'" for c in close) + "?"
