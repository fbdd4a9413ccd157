"""Which grammar is in force in each theory: UTP's, plain HOL's, or their ambiguous merge.

utp-main c9122f14 removes HOL's productions for the connectives and re-declares the symbols
for its own predicates: ``purge_notation conj (infixr "\\<and>" 35) and disj … and Not …``
(utp/utp_pred.thy:32-35) and the lattice symbols ``\\<sqinter> \\<squnion> \\<Sqinter>
\\<Squnion> \\<bottom> \\<top>`` (utp/utp_pred.thy:122-135). A theory's grammar is the union of
its parents' grammars, so importing any theory outside that line (``HOL.Transcendental``,
``Main``, Optics, a local theory over plain HOL) brings HOL's productions back and every term
using those symbols parses two ways; Isabelle type-checks every parse, exponentially many.
``recall_syntax`` (toolkit/Total_Recall.thy:15, 43-45) re-applies every recorded purge, and
utp-main's own theories that import plain HOL start with it (``begin recall_syntax``,
e.g. hybrid/utp_hyrel.thy:12, theories/circus/utp_circus_easy_parser.thy:5).
"""

from __future__ import annotations

from cyphy.verify.theory.findings import Finding
from cyphy.verify.theory.session import Session, Theory

#: Symbols whose HOL production utp_pred.thy purges (lines 32-35, 122-135 at c9122f14).
PURGED_SYMBOLS = ("\\<and>", "\\<or>", "\\<not>", "\\<sqinter>", "\\<squnion>", "\\<Sqinter>",
                  "\\<Squnion>", "\\<bottom>", "\\<top>")

#: utp-main sessions at or above UTP's utp_pred (ROOT at c9122f14); UTP-Toolkit is below it.
_NOT_UTP = ("UTP-Toolkit",)


def _session_of(import_name: str) -> str | None:
    return import_name.split(".", 1)[0] if "." in import_name else None


def is_utp_session(session: str) -> bool:
    return session.startswith("UTP") and session not in _NOT_UTP


def recalls(theory: Theory) -> bool:
    """Whether ``recall_syntax`` is the theory's first command after ``begin``."""
    return bool(theory.commands) and theory.commands[0].keyword == "recall_syntax"


def grammars(session: Session) -> tuple[dict[str, str], list[Finding]]:
    """Each theory's grammar (``utp``, ``hol`` or ``merged``) and the merges without recall."""
    kinds: dict[str, str] = {}
    findings: list[Finding] = []
    for th in session.theories:
        parents: list[tuple[str, str]] = []
        for imp in th.imports:
            local = session.local(imp) if "." not in imp else None
            if local is not None:
                parents.append((imp, kinds.get(imp, "hol")))
                continue
            owner = _session_of(imp) or session.parent
            parents.append((imp, "utp" if is_utp_session(owner) else "hol"))
        utp = [p for p, k in parents if k in ("utp", "merged")]
        hol = [p for p, k in parents if k in ("hol", "merged")]
        if not utp:
            kinds[th.name] = "hol"
        elif recalls(th):
            kinds[th.name] = "utp"
        elif [p for p, k in parents if k == "merged"] or hol:
            kinds[th.name] = "merged"
            plain = [p for p, k in parents if k == "hol"]
            if plain:
                findings.append(Finding(
                    th.path, th.begin_line, "T-RECALL",
                    f"{th.name} merges UTP ({', '.join(utp)}) with plain HOL "
                    f"({', '.join(plain)}) without 'recall_syntax' right after 'begin': HOL's "
                    "\\<and>, \\<or>, \\<not> come back and every UTP predicate using them "
                    "parses two ways"))
        else:
            kinds[th.name] = "utp"
    return kinds, findings


def ambiguous_terms(session: Session, kinds: dict[str, str]) -> list[Finding]:
    """Every term of a theory under the merged grammar that uses a purged symbol."""
    out: list[Finding] = []
    for th in session.theories:
        if kinds.get(th.name) != "merged":
            continue
        for cmd in th.commands:
            for tok in cmd.tokens:
                if tok.kind == "string":
                    used = [s for s in PURGED_SYMBOLS if s in tok.text]
                    if used:
                        out.append(Finding(
                            th.path, tok.line, "T-AMBIGUOUS",
                            f"this term parses two ways ({' '.join(used)} is both HOL's and "
                            "UTP's under the merged grammar)"))
    return out
