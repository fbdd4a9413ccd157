"""A session folder as Isabelle reads it: ``ROOT`` (session, parent, theories) and each theory's
header (name, imports) and commands, in the order Isabelle loads them."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from cyphy.verify.theory.findings import Finding
from cyphy.verify.theory.lexer import Command, LexError, Token, commands, tokenize


_MARKUP = {"section", "chapter", "subsection", "subsubsection", "paragraph", "text", "txt"}


class SessionError(Exception):
    """The folder cannot be read as a session at all (exit 2): no folder, no ROOT."""


@dataclass
class Theory:
    name: str
    path: Path
    text: str
    imports: list[str]
    commands: list[Command]  # after the header's ``begin``
    begin_line: int


@dataclass
class Session:
    name: str
    parent: str
    folder: Path
    theories: list[Theory] = field(default_factory=list)  # load order

    def local(self, name: str) -> Theory | None:
        for th in self.theories:
            if th.name == name:
                return th
        return None


def _read_text(path: Path, findings: list[Finding]) -> str | None:
    try:
        data = path.read_bytes()
    except OSError as err:
        findings.append(Finding(path, 0, "T-IO", f"cannot read the file ({err.strerror})"))
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data[:err.start].count(b"\n") + 1
        findings.append(Finding(path, line, "T-ENCODING",
                                f"byte 0x{data[err.start]:02x} is not UTF-8 (Isabelle reads "
                                "theories as UTF-8; write symbols as \\<name>)"))
        return None


def _words(tokens: list[Token]) -> list[str]:
    return [t.content if t.kind == "string" else t.text for t in tokens
            if t.kind in ("ident", "string")]


def _root(path: Path, text: str) -> tuple[str, str, list[str]]:
    """(session, parent, theories) of the first session of a ROOT file."""
    try:
        tokens = [t for t in tokenize(text) if t.kind != "comment"]
    except LexError as err:
        raise SessionError(f"{path}:{err.line}: {err}") from None
    words = [(t.text, t.content if t.kind == "string" else t.text) for t in tokens]
    kinds = [t.kind for t in tokens]
    try:
        at = next(i for i, (raw, _) in enumerate(words) if raw == "session")
        name = words[at + 1][1]
        eq = next(i for i in range(at, len(words)) if words[i][0] == "=")
    except (StopIteration, IndexError):
        raise SessionError(f"{path}: no 'session NAME = PARENT + …' entry") from None
    parent = words[eq + 1][1] if eq + 1 < len(words) and words[eq + 1][0] != "(" else ""
    theories: list[str] = []
    inside = False
    keywords = {"options", "sessions", "directories", "document_files", "export_files",
                "description", "session", "global_theories", "theories", "in"}
    for (raw, word), kind in zip(words[eq + 1:], kinds[eq + 1:]):
        if raw == "theories":
            inside = True
        elif raw in keywords:
            inside = False
        elif inside and kind in ("ident", "string"):
            theories.append(word)
    return name, parent, theories


def _theory(path: Path, text: str, findings: list[Finding]) -> Theory | None:
    try:
        tokens = tokenize(text)
    except LexError as err:
        findings.append(Finding(path, err.line, "T-LEX", str(err)))
        return None
    cmds = commands(tokens)
    while cmds and cmds[0].keyword in _MARKUP:  # Isabelle allows markup before the header
        cmds = cmds[1:]
    if not cmds or cmds[0].keyword != "theory":
        line = cmds[0].line if cmds else 1
        findings.append(Finding(path, line, "T-NOT-THEORY",
                                "this is not a theory: it must start with "
                                "'theory NAME imports … begin'"))
        return None
    header = cmds[0].tokens
    words = _words(header)
    if len(words) < 2 or "begin" not in words:
        findings.append(Finding(path, header[0].line, "T-NOT-THEORY",
                                "the theory header has no name or no 'begin'"))
        return None
    name = words[1]
    begin = next(t for t in header if t.text == "begin")
    imports: list[str] = []
    if "imports" in words:
        for w in words[words.index("imports") + 1:]:
            if w in ("keywords", "abbrevs", "begin"):
                break
            imports.append(w)
    after = [t for t in header if t.line >= begin.line and header.index(t) > header.index(begin)]
    body = cmds[1:]
    if after:  # e.g. 'begin' followed by non-command text on the same segment
        findings.append(Finding(path, after[0].line, "T-SYNTAX",
                                f"unexpected '{after[0].text}' after 'begin'"))
    if name != path.stem:
        findings.append(Finding(path, header[0].line, "T-NAME",
                                f"theory {name} is in the file {path.name}: Isabelle needs "
                                f"{name}.thy"))
    if not body or body[-1].keyword != "end":
        findings.append(Finding(path, (body[-1].line if body else begin.line), "T-SYNTAX",
                                "the theory does not end with 'end'"))
    return Theory(name, path, text, imports, body, begin.line)


def read_session(folder: Path) -> tuple[Session, list[Finding]]:
    """The session in ``folder`` and the problems met reading it (lexing, encoding, headers).

    Raises :class:`SessionError` when there is no session to read."""
    if not folder.is_dir():
        raise SessionError(f"{folder}: no such folder")
    root = folder / "ROOT"
    if not root.is_file():
        raise SessionError(f"{folder}: no ROOT file (a session folder has one)")
    findings: list[Finding] = []
    text = _read_text(root, findings)
    if text is None:
        raise SessionError(f"{root}: {findings[0].message}")
    name, parent, listed = _root(root, text)
    session = Session(name, parent, folder)
    seen: set[str] = set()

    def load(theory_name: str, line: int) -> None:
        if theory_name in seen:
            return
        seen.add(theory_name)
        path = folder / f"{theory_name}.thy"
        if not path.is_file():
            findings.append(Finding(root, line, "T-MISSING",
                                    f"theory {theory_name} is listed but {path.name} is "
                                    "not in the folder"))
            return
        body = _read_text(path, findings)
        theory = None if body is None else _theory(path, body, findings)
        if theory is None:
            return
        for imp in theory.imports:  # local imports load first (Isabelle's order)
            if "." not in imp and (folder / f"{imp}.thy").is_file():
                load(imp, 0)
        session.theories.append(theory)

    for theory_name in listed:
        load(theory_name, _line_of(text, theory_name))
    for path in sorted(folder.glob("*.thy")):  # theories in the folder that ROOT omits
        if path.stem not in seen:
            findings.append(Finding(path, 1, "T-UNLISTED",
                                    f"{path.name} is not among the ROOT's theories, so "
                                    "Isabelle does not load it (checked anyway)"))
            load(path.stem, 0)
    return session, findings


def _line_of(text: str, word: str) -> int:
    for n, line in enumerate(text.splitlines(), 1):
        if word in line.split():
            return n
    return 1
