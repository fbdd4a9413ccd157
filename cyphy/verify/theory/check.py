"""``cyphy check-theory``: every static check of :mod:`cyphy.verify.theory` on one session."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from cyphy.verify.theory.ax_types import check_ax_theory
from cyphy.verify.theory.findings import Finding
from cyphy.verify.theory.grammar import ambiguous_terms, grammars
from cyphy.verify.theory.reserved import reserved_for
from cyphy.verify.theory.scope import (build_scope, duplicates, proofs, reserved_bindings,
                                       uses_before_definition)
from cyphy.verify.theory.session import Session, Theory, read_session
from cyphy.verify.theory.utp_types import check_theory

#: The prelude cyphy ships: its own terms are not type-checked (the signature table types
#: what it declares), the rest of the checks apply.
PRELUDE = "CyPhyCircus_Prelude"
AX_IMPORT = "Axiomatic_CyPhyCircus.Ax_CyPhyCircus"


@dataclass
class Result:
    session: Session | None
    findings: list[Finding] = field(default_factory=list)
    theories: int = 0

    @property
    def exit_code(self) -> int:
        return 1 if self.findings else 0


def dialect(session: Session, theory: Theory) -> str | None:
    """``utp`` (utp-main 2020), ``axiomatic`` (Ax_CyPhyCircus) or None (plain HOL)."""
    if AX_IMPORT in theory.imports or session.parent.startswith("Axiomatic_CyPhyCircus"):
        return "axiomatic"
    return None


def reserved_words(kind: str) -> dict[str, str]:
    """Word → where it is a keyword, for the grammar of ``kind`` (utp or axiomatic)."""
    return reserved_for(kind)


def _line(theory: Theory, message: str) -> int:
    """The line a type checker's message is about (its messages name a definition or axiom)."""
    m = re.match(r"definition (\w+):", message)
    if m:
        for cmd in theory.commands:
            if cmd.keyword == "definition" and len(cmd.tokens) > 1 and \
                    cmd.tokens[1].text == m.group(1):
                return cmd.line
    m = re.match(r"axiom (.*?): ", message)
    if m:
        for cmd in theory.commands:
            for tok in cmd.tokens:
                if tok.kind == "string" and tok.content == m.group(1):
                    return tok.line
    m = re.match(r"'(\w+)'", message)
    if m:
        for n, text in enumerate(theory.text.splitlines(), 1):
            if re.search(rf"(?<![\w.]){re.escape(m.group(1))}(?![\w.])", text):
                return n
    return theory.begin_line


def type_findings(session: Session, kinds: dict[str, str]) -> list[Finding]:
    out = []
    for th in session.theories:
        if th.name == PRELUDE:
            continue
        if dialect(session, th) == "axiomatic":
            errors = check_ax_theory(th.text)
        elif kinds.get(th.name) in ("utp", "merged"):
            errors = check_theory(th.text)
        else:
            continue
        for message in errors:
            if re.match(r"'\w+' is a keyword", message):
                continue  # reported with its line by the reserved-word check
            out.append(Finding(th.path, _line(th, message), "T-TYPE", message))
    return out


def check_session(folder: Path) -> Result:
    """Every finding on the session in ``folder`` (raises ``SessionError`` if there is none)."""
    session, findings = read_session(folder)
    kinds, merged = grammars(session)
    findings += merged + ambiguous_terms(session, kinds)
    scope = build_scope(session)
    findings += duplicates(session, scope) + uses_before_definition(session, scope)
    for th in session.theories:
        kind = "axiomatic" if dialect(session, th) == "axiomatic" else (
            "utp" if kinds.get(th.name) in ("utp", "merged") else "hol")
        sub = Session(session.name, session.parent, session.folder, [th])
        findings += reserved_bindings(sub, reserved_words(kind))
    findings += proofs(session, scope) + type_findings(session, kinds)
    return Result(session, sorted(set(findings)), len(session.theories))
