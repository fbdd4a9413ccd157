"""Isabelle's outer syntax, as far as a static check needs it: tokens with their lines, and
the theory cut into commands.

Isabelle/Isar reference manual (Isabelle2020), section 3.2 "Lexical matters": nested comments
``(* … *)``, nested cartouches ``\\<open> … \\<close>``, strings ``"…"`` and alternative
strings with backslash escapes, verbatim ``{* … *}``, symbols ``\\<name>``. An unterminated
one is an error at the line where it starts (Isabelle reports it there too).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

#: Theory-level commands: a command segment starts at one of them. Proof commands (``by``,
#: ``apply``, ``unfolding``, …) stay inside the segment of the statement they prove.
THEORY_COMMANDS = frozenset("""
theory end text section subsection subsubsection chapter paragraph txt ML ML_file
definition abbreviation axiomatization consts lemma theorem corollary proposition lemmas
datatype codatatype record type_synonym typedecl fun function primrec primcorec
alphabet chantype notation no_notation syntax no_syntax translations declare
purge_notation purge_syntax recall_syntax adhoc_overloading no_adhoc_overloading
locale context instantiation instance class subclass interpretation global_interpretation
named_theorems setup method_setup bundle unbundle hide_const hide_fact hide_type value
typ term thm print_theorems find_theorems export_code code_printing specification
lift_definition setup_lifting recursive dataspace
""".split())


class LexError(Exception):
    """Unterminated comment, cartouche, string or verbatim text (``line`` where it starts)."""

    def __init__(self, line: int, message: str) -> None:
        super().__init__(message)
        self.line = line


@dataclass(frozen=True)
class Token:
    kind: str  # ident, string, cartouche, comment, verbatim, symbol, other
    text: str
    line: int
    column: int = 1  # of the first character

    @property
    def content(self) -> str:
        """A string's or cartouche's text without its delimiters (escapes kept)."""
        if self.kind == "string":
            return self.text[1:-1]
        if self.kind == "cartouche":
            return self.text[len("\\<open>"):-len("\\<close>")]
        return self.text


@dataclass
class Command:
    """One theory-level command: its keyword, its tokens (comments dropped), first line."""

    keyword: str
    tokens: list[Token] = field(default_factory=list)

    @property
    def line(self) -> int:
        return self.tokens[0].line


_IDENT = re.compile(r"(?:[A-Za-z]|\\<[A-Za-z]{1,2}>)"
                    r"(?:[A-Za-z0-9_'.]|\\<\^sub>|\\<[A-Za-z]{1,2}>)*")
_SYMBOL = re.compile(r"\\<\^?[A-Za-z0-9_]*>")
_NESTED = {"(*": ("comment", "(*", "*)"), "\\<open>": ("cartouche", "\\<open>", "\\<close>")}


def _nested(text: str, pos: int, line: int, kind: str, start: str, stop: str) -> int:
    """End (exclusive) of a nested comment or cartouche starting at ``pos``."""
    depth, i = 0, pos
    while i < len(text):
        if text.startswith(start, i):
            depth, i = depth + 1, i + len(start)
        elif text.startswith(stop, i):
            depth, i = depth - 1, i + len(stop)
            if depth == 0:
                return i
        else:
            i += 1
    raise LexError(line, f"unterminated {kind} (it starts here)")


def _quoted(text: str, pos: int, line: int, quote: str) -> int:
    i = pos + 1
    while i < len(text):
        if text[i] == "\\":
            i += 2
        elif text[i] == quote:
            return i + 1
        else:
            i += 1
    raise LexError(line, "unterminated string (it starts here)")


def tokenize(text: str) -> list[Token]:
    """Every token of ``text`` except white space, with its first line."""
    out: list[Token] = []
    pos, line, line_start = 0, 1, 0
    while pos < len(text):
        ch = text[pos]
        if ch.isspace():
            end = pos + 1
            kind = ""
        elif text.startswith("(*", pos) or text.startswith("\\<open>", pos):
            kind, start, stop = _NESTED["(*" if ch == "(" else "\\<open>"]
            end = _nested(text, pos, line, kind, start, stop)
        elif ch in "\"`":
            kind, end = "string", _quoted(text, pos, line, ch)
        elif text.startswith("{*", pos):
            stop = text.find("*}", pos + 2)
            if stop < 0:
                raise LexError(line, "unterminated verbatim text {* (it starts here)")
            kind, end = "verbatim", stop + 2
        elif (m := _IDENT.match(text, pos)) is not None:
            kind, end = "ident", m.end()
        elif (m := _SYMBOL.match(text, pos)) is not None:
            kind, end = "symbol", m.end()
        else:
            kind, end = "other", pos + 1
        if kind:
            out.append(Token(kind, text[pos:end], line, pos - line_start + 1))
        newlines = text.count("\n", pos, end)
        if newlines:
            line += newlines
            line_start = text.rindex("\n", pos, end) + 1
        pos = end
    return out


def commands(tokens: list[Token]) -> list[Command]:
    """The theory cut at its theory-level commands (comments dropped; what precedes the first
    command is a segment with the empty keyword)."""
    out: list[Command] = []
    for tok in tokens:
        if tok.kind == "comment":
            continue
        if tok.kind == "ident" and tok.text in THEORY_COMMANDS:
            out.append(Command(tok.text, [tok]))
        elif out:
            out[-1].tokens.append(tok)
        else:
            out.append(Command("", [tok]))
    return out
