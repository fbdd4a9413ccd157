"""Names across a session: what each command declares, duplicates, uses before the definition
(theory order, then file order), reserved words bound as identifiers, and proofs citing facts
that nothing defines.

Read from the outer syntax (:mod:`lexer`), not from the layout cyphy writes, so a hand-edited
session is read the same way. Isabelle rejects a second declaration of a name in one theory
("Duplicate constant declaration"), a ``definition`` whose body names a constant declared only
later (it is a free variable there: "Extra variables on rhs"), a keyword where a name is
expected, and a proof citing an undefined fact ("Undefined fact").
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from cyphy.verify.theory.findings import Finding
from cyphy.verify.theory.lexer import Command, Token
from cyphy.verify.theory.session import Session, Theory

#: Library facts the generated proofs cite (name → where it is declared).
LIBRARY_FACTS: dict[str, str] = {
    "closure": "utp-main c9122f14 utp/utp_healthy.thy:11 (named_theorems closure)",
    "Healthy_Idempotent": "utp-main c9122f14 utp/utp_healthy.thy:115",
    "NCSP_Idempotent": "utp-main c9122f14 theories/sf_rdes/utp_sfrd_healths.thy:517",
    "prod.case_eq_if": "Isabelle 2d6638d src/HOL/Product_Type.thy:229 (free_constructors "
                       "case_prod)",
}

_CONSTANT_COMMANDS = {"definition", "abbreviation", "fun", "function", "primrec", "consts",
                      "axiomatization", "lift_definition", "recursive"}
_TYPE_COMMANDS = {"typedecl", "type_synonym", "datatype", "codatatype", "record", "alphabet",
                  "chantype"}
_LEMMA_COMMANDS = {"lemma", "theorem", "corollary", "proposition", "lemmas"}
#: Proof words after which fact names follow (``simp add: a b``, ``unfolding a``, ``rule a``).
_FACT_INTRO = {"add", "only", "del", "unfolding", "using", "rule", "OF", "intro", "elim",
               "dest", "subst", "THEN", "from", "with"}
_PROOF_COMMANDS = {"by", "apply", "apply_end", "done", "proof", "qed", "oops", "sorry", "next",
                   "including", "supply"}
_BINDERS = ("\\<lambda>", "\\<exists>", "\\<forall>", "\\<mu>", "\\<box>", "\\<Lambda>", "?(", "?",
            "\\<Sqinter>", "\\<Squnion>", "\\<^bold>\\<exists>", "\\<^bold>\\<forall>", "EX", "ALL",
            "SOME", "THE", "\\<nexists>")
_WORD = re.compile(r"(?<![\w'.])([A-Za-z][A-Za-z0-9_']*)(?![\w.])")


@dataclass
class Declaration:
    name: str
    kind: str  # constant, type, fact
    command: str
    line: int
    theory: str
    position: tuple[int, int]  # (theory index, command index): the load order


@dataclass
class Scope:
    declarations: list[Declaration] = field(default_factory=list)

    def first(self, kind: str) -> dict[str, Declaration]:
        out: dict[str, Declaration] = {}
        for d in self.declarations:
            if d.kind == kind:
                out.setdefault(d.name, d)
        return out


def term_words(term: str) -> list[str]:
    """The identifiers of an inner-syntax term (symbols, subscripts and strings removed)."""
    text = re.sub(r"''.*?''", " ", term)
    text = re.sub(r"\\<\^(?:sub|sup|bold|bsub|esub)>\w*", " ", text)
    text = re.sub(r"\\<[^>]*>", " ", text)
    text = re.sub(r"'[a-z]\w*", " ", text)  # type variables
    return _WORD.findall(text)


def bound_words(term: str) -> set[str]:
    """Names a term binds: after a binder, and the tuple of an input prefix ``c?(x)?(y)``."""
    out: set[str] = set()
    for binder in _BINDERS:
        for m in re.finditer(re.escape(binder) + r"\s*\(?\s*([A-Za-z][A-Za-z0-9_']*)", term):
            out.add(m.group(1))
    out |= set(re.findall(r"([A-Za-z][A-Za-z0-9_']*)\s*(?:\\<in>|::)", term))
    for m in re.finditer(r"\\<lambda>\s*([A-Za-z][\w' ]*)[.\\]", term):  # \<lambda> x y. …
        out |= set(m.group(1).split())
    return out


def _idents_before(tokens: list[Token], stop: str) -> list[Token]:
    out = []
    for t in tokens:
        if t.kind == "ident" and t.text == stop:
            break
        out.append(t)
    return out


def _typed_names(tokens: list[Token]) -> list[Token]:
    """``name :: type`` entries: every identifier followed by ``::``."""
    out = []
    for i, t in enumerate(tokens[:-2]):
        if t.kind == "ident" and tokens[i + 1].text == ":" and tokens[i + 2].text == ":":
            out.append(t)
    return out


def _labels(tokens: list[Token]) -> list[Token]:
    """``label:`` and ``label [attrs]:`` (fact names of axioms and lemmas)."""
    out = []
    for i, t in enumerate(tokens):
        if t.kind != "ident" or i + 1 >= len(tokens):
            continue
        j = i + 1
        if tokens[j].text == "[":
            while j < len(tokens) and tokens[j].text != "]":
                j += 1
            j += 1
        if j < len(tokens) and tokens[j].text == ":" and (
                j + 1 >= len(tokens) or tokens[j + 1].text != ":"):
            out.append(t)
    return out


def declarations(cmd: Command) -> list[tuple[str, Token]]:
    """(kind, name token) of what one command declares."""
    toks = cmd.tokens[1:]
    if cmd.keyword in ("definition", "abbreviation", "lift_definition"):
        head = _idents_before(toks, "where")
        names = [t for t in head if t.kind == "ident" and t.text not in ("in",)]
        if names and not (len(toks) > 1 and toks[0].text == "(" and names[0] is toks[1]):
            name = names[0]
        else:
            strings = [t for t in toks if t.kind == "string"]
            words = term_words(strings[-1].content) if strings else []
            if not words:
                return []
            name = Token("ident", words[0], strings[-1].line)
        out = [("constant", name)]
        if cmd.keyword != "abbreviation":
            out.append(("fact", Token("ident", f"{name.text}_def", name.line)))
        return out
    if cmd.keyword in ("fun", "function", "primrec", "recursive"):
        head = _idents_before(toks, "where")
        names = [t for t in head if t.kind == "ident" and t.text != "and"]
        names = _typed_names(head) or names[:1]
        return [k for n in names for k in (("constant", n),
                                            ("fact", Token("ident", f"{n.text}.simps", n.line)))]
    if cmd.keyword == "consts":
        return [("constant", t) for t in _typed_names(toks)]
    if cmd.keyword == "axiomatization":
        head = _idents_before(toks, "where")
        tail = toks[len(head) + 1:]
        return [("constant", t) for t in _typed_names(head)] + [("fact", t)
                                                                   for t in _labels(tail)]
    if cmd.keyword in _TYPE_COMMANDS:
        names = [t for t in toks if t.kind == "ident"]
        if not names:
            return []
        out = [("type", names[0])]
        eq = next((i for i, t in enumerate(toks) if t.text == "="), None)
        if eq is None:
            return out
        body = toks[eq + 1:]
        if cmd.keyword in ("alphabet", "chantype", "record"):
            out += [("constant", t) for t in _typed_names(body)]
        elif cmd.keyword in ("datatype", "codatatype"):
            starts = [body[0]] + [body[i + 1] for i, t in enumerate(body[:-1]) if t.text == "|"]
            out += [("constant", t) for t in starts if t.kind == "ident"]
        return out
    if cmd.keyword in _LEMMA_COMMANDS:
        head = []
        for t in toks:
            if t.kind == "string":
                break
            head.append(t)
        labels = _labels(head) if cmd.keyword != "lemmas" else toks[:1]
        return [("fact", t) for t in labels if t.kind == "ident"]
    return []


def _statement_and_proof(cmd: Command) -> tuple[list[Token], list[Token]]:
    for i, t in enumerate(cmd.tokens):
        if t.kind == "ident" and t.text in ("by", "apply", "proof", "unfolding", "using",
                                            "including", "supply"):
            return cmd.tokens[:i], cmd.tokens[i:]
    return cmd.tokens, []


def cited_facts(proof: list[Token]) -> list[Token]:
    """The fact names a proof cites (after ``add:``, ``unfolding``, ``rule``, ``OF`` …)."""
    out: list[Token] = []
    active, depth = False, 0
    for i, t in enumerate(proof):
        nxt = proof[i + 1].text if i + 1 < len(proof) else ""
        if t.text == "[":
            depth += 1
        elif t.text == "]":
            depth -= 1
        if t.kind == "ident" and t.text in _PROOF_COMMANDS:
            active = False
            continue
        if t.kind == "ident" and t.text in _FACT_INTRO:
            active = True
            continue
        if t.kind == "ident" and nxt == ":":
            active = False
            continue
        if t.text in (")", "(", ",") and depth == 0:
            active = active and t.text == ","
            continue
        if active and t.kind == "ident" and (depth == 0 or proof[i - 1].text == "OF"):
            out.append(t)
        elif active and depth == 0 and t.text not in ("[", "]", ":"):
            active = t.kind == "ident"
    return out


def build_scope(session: Session) -> Scope:
    scope = Scope()
    for ti, th in enumerate(session.theories):
        for ci, cmd in enumerate(th.commands):
            for kind, tok in declarations(cmd):
                scope.declarations.append(Declaration(tok.text, kind, cmd.keyword, tok.line,
                                                      th.name, (ti, ci)))
    return scope


def duplicates(session: Session, scope: Scope) -> list[Finding]:
    out = []
    seen: dict[tuple[str, str, str], Declaration] = {}
    paths = {th.name: th.path for th in session.theories}
    for d in scope.declarations:
        key = (d.theory, d.kind, d.name)
        if key in seen:
            first = seen[key]
            out.append(Finding(paths[d.theory], d.line, "T-DUPLICATE",
                               f"{d.kind} {d.name} is declared twice in {d.theory} (first at "
                               f"line {first.line}): Isabelle rejects the second"))
        else:
            seen[key] = d
    return out


def _term_tokens(cmd: Command) -> list[Token]:
    statement, _ = _statement_and_proof(cmd)
    return [t for t in statement if t.kind == "string"]


def uses_before_definition(session: Session, scope: Scope) -> list[Finding]:
    """Names a term uses that are declared only later (or, in a definition, by itself)."""
    out = []
    defined = {**scope.first("type"), **scope.first("constant")}
    for ti, th in enumerate(session.theories):
        for ci, cmd in enumerate(th.commands):
            if cmd.keyword in ("text", "section", "subsection", "chapter", "ML", "theory"):
                continue
            own = {tok.text for kind, tok in declarations(cmd) if kind != "fact"}
            recursive = cmd.keyword in ("fun", "function", "primrec", "recursive",
                                        "axiomatization", "consts", "datatype", "codatatype",
                                        "alphabet", "chantype", "record")
            for string in _term_tokens(cmd):
                words = term_words(string.content)
                bound = bound_words(string.content)
                if cmd.keyword == "definition" and words:
                    lhs = string.content.split("=", 1)[0]
                    bound |= set(term_words(lhs)[1:])  # the parameters
                    words = words[1:] if words[0] in own else words
                for word in dict.fromkeys(words):
                    if word in bound:
                        continue
                    decl = defined.get(word)
                    if decl is None:
                        continue
                    if word in own and not recursive:
                        out.append(Finding(th.path, string.line, "T-ORDER",
                                           f"{word} is used in its own {cmd.keyword}, which is "
                                           "not recursive"))
                    elif decl.position > (ti, ci) and word not in own:
                        out.append(Finding(th.path, string.line, "T-ORDER",
                                           f"{word} is used before its {decl.command} "
                                           f"({decl.theory}, line {decl.line})"))
    return out


def reserved_bindings(session: Session, reserved: dict[str, str]) -> list[Finding]:
    """Declared names and bound names (parameters, binders) that are reserved words."""
    out = []
    for th in session.theories:
        for cmd in th.commands:
            names = [(tok.text, tok.line) for kind, tok in declarations(cmd) if kind != "fact"]
            for string in _term_tokens(cmd):
                bound = set(bound_words(string.content))
                if cmd.keyword in ("definition", "fun", "primrec"):
                    lhs = string.content.split("=", 1)[0]
                    bound |= set(term_words(lhs)[1:])
                names += [(b, string.line) for b in sorted(bound)]
            for name, line in dict.fromkeys(names):
                if name in reserved:
                    out.append(Finding(th.path, line, "T-RESERVED",
                                       f"'{name}' is a keyword of the grammar in force "
                                       f"({reserved[name]}): it cannot name a constant or a "
                                       "variable"))
    return out


def proofs(session: Session, scope: Scope) -> list[Finding]:
    """Facts a proof cites that nothing defines, and closure lemmas not citing their
    definition."""
    out = []
    facts = scope.first("fact")
    constants = scope.first("constant")
    for ti, th in enumerate(session.theories):
        for ci, cmd in enumerate(th.commands):
            if cmd.keyword not in _LEMMA_COMMANDS:
                continue
            statement, proof = _statement_and_proof(cmd)
            cited = cited_facts(proof)
            for tok in cited:
                known = facts.get(tok.text)
                if tok.text in LIBRARY_FACTS or (known and known.position < (ti, ci)):
                    continue
                why = ("no definition of " + tok.text[:-4] if tok.text.endswith("_def")
                       else "nothing in the session or in the library facts cyphy knows "
                       "defines it")
                out.append(Finding(th.path, tok.line, "T-FACT",
                                   f"the proof cites {tok.text}: {why}"))
            attrs = [t.text for t in statement if t.kind == "ident"]
            if "closure" in attrs:
                strings = [t for t in statement if t.kind == "string"]
                words = term_words(strings[0].content) if strings else []
                subject = words[0] if words else ""
                decl = constants.get(subject)
                if decl is not None and decl.command == "definition" and \
                        f"{subject}_def" not in {t.text for t in cited}:
                    out.append(Finding(th.path, cmd.line, "T-CLOSURE",
                                       f"the closure lemma about {subject} does not cite "
                                       f"{subject}_def, so simp cannot unfold it"))
    return out
