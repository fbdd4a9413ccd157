"""Derive the reserved words of the Isabelle grammars cyphy prints for, from library sources.

A word that is a delimiter of a mixfix annotation (``(infixl "sums" 80)``, ``("(3INF _./ _)")``,
``(binder "LEAST " 10)``) is a keyword of Isabelle's inner lexer once the theory declaring it
is imported: an identifier spelt the same no longer parses. This script reads

- utp-main at c9122f14: the sessions UTP-Circus builds on (``optics``, ``toolkit``, ``utp``,
  ``theories/{kleene,designs,reactive,rea_designs,sf_rdes,circus}``), and
- Isabelle's HOL: every theory in the import closure of what those utp-main theories and
  cyphy's prelude (``HOL.Transcendental``) import, plus Pure's own inner keywords
  (src/Pure/pure_thy.ML),

and writes one line per word: ``word<TAB>library<TAB>file:line`` (the first declaration in
file order), sorted by library then word. Productions of the ``(output)`` mode (print only) are left out; every other mode
(``(ASCII)``, ``(input)``, ``(latex)``) parses, so its words count. Removals (``no_notation``,
``purge_notation``) are not subtracted: keeping such a word costs a rename at most.

Usage (git directories from ``fetch``; reads them with ``git show``, no checkout needed):

    python3 tools/derive_isabelle_words.py \\
        --utp-main /work/.mirror/isabelle-utp+utp-main/repo@c9122f14 \\
        --isabelle /work/.mirror/digama0+isabelle/repo@2d6638d \\
        > cyphy/backends/isabelle/reserved_words.tsv
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from cyphy.verify.theory.lexer import Command, LexError, Token, tokenize  # noqa: E402

UTP_DIRS = ("optics", "toolkit", "utp", "theories/kleene", "theories/designs",
            "theories/reactive", "theories/rea_designs", "theories/sf_rdes", "theories/circus")
PRELUDE_IMPORTS = ("HOL.Transcendental",)
#: HOL session directories by session name (Isabelle's src/HOL/ROOT).
HOL_SESSIONS = {"HOL": "src/HOL", "HOL-Library": "src/HOL/Library",
                "HOL-Eisbach": "src/HOL/Eisbach", "HOL-Analysis": "src/HOL/Analysis",
                "HOL-Computational_Algebra": "src/HOL/Computational_Algebra",
                "HOL-Algebra": "src/HOL/Algebra", "HOL-Cardinals": "src/HOL/Cardinals"}
#: Commands whose parenthesised strings are mixfix annotations.
_DECLARING = {"consts", "definition", "abbreviation", "fun", "function", "primrec", "primcorec",
              "axiomatization", "notation", "type_notation", "syntax", "datatype",
              "codatatype", "class", "locale", "inductive", "coinductive", "inductive_set",
              "coinductive_set", "lift_definition", "typedef", "record", "bundle",
              "open_bundle", "context", "nonterminal", "type_synonym", "typedecl", "alphabet",
              "chantype", "adhoc_overloading", "partial_function", "nominal_function"}
_MIXFIX_KEYS = {"infix", "infixl", "infixr", "binder", "open_binder", "structure"}
_WORD = re.compile(r"[A-Za-z][A-Za-z0-9_']*")


class Repo:
    def __init__(self, spec: str) -> None:
        self.path, _, self.commit = spec.partition("@")
        self.commit = self.commit or "HEAD"

    def files(self, folder: str) -> list[str]:
        out = subprocess.run(["git", "-C", self.path, "ls-tree", "--name-only", self.commit,
                              folder + "/"], capture_output=True, text=True, check=True).stdout
        return [p for p in out.split() if p.endswith(".thy")]

    def read(self, path: str) -> str | None:
        proc = subprocess.run(["git", "-C", self.path, "show", f"{self.commit}:{path}"],
                              capture_output=True)
        return proc.stdout.decode("utf-8", "replace") if proc.returncode == 0 else None


def delimiters(template: str) -> list[str]:
    """The literal delimiters of a mixfix template (``'`` escapes, ``_`` arguments, ``/``
    breaks, ``(N`` and ``)`` blocks, spaces separate)."""
    out, cur, i = [], "", 0
    while i < len(template):
        ch = template[i]
        if ch == "'" and i + 1 < len(template):
            cur += template[i + 1]
            i += 2
            continue
        if ch in " _/)\n\t" or ch == "(":
            if cur:
                out.append(cur)
            cur = ""
            if ch == "(":
                while i + 1 < len(template) and template[i + 1].isdigit():
                    i += 1
            i += 1
            continue
        if template.startswith("\\<^", i) or template.startswith("\\<", i):
            end = template.find(">", i)
            cur += template[i:end + 1]
            i = end + 1
            continue
        cur += ch
        i += 1
    if cur:
        out.append(cur)
    return out


def segments(text: str) -> list[Command]:
    """The theory cut at every identifier in column 1: the library sources write each
    theory-level command there, and indent everything else."""
    out: list[Command] = []
    for tok in tokenize(text):
        if tok.kind == "comment":
            continue
        if tok.kind == "ident" and tok.column == 1:
            out.append(Command(tok.text, [tok]))
        elif out:
            out[-1].tokens.append(tok)
    return out


def _word_of(delimiter: str) -> str | None:
    """The identifier a delimiter reserves: the whole delimiter when it is one, and (to be
    safe) a word glued to an opening bracket (``PAIRTYPE'(``: Isabelle's longest-match lexer
    may leave ``PAIRTYPE`` an identifier, but a rename costs nothing). A word with a subscript
    (``choose\\<^sub>R``) is another token and leaves the bare word free."""
    if _WORD.fullmatch(delimiter):
        return delimiter
    m = re.fullmatch(r"([A-Za-z][A-Za-z0-9_']*)[(\[{]", delimiter)
    return m.group(1) if m else None


def mixfix_words(text: str) -> list[tuple[str, int]]:
    """(word, line) of every identifier-like delimiter of the theory's additive mixfix."""
    try:
        cmds = segments(text)
    except LexError:
        return []
    found: list[tuple[str, int]] = []
    for cmd in cmds:
        if cmd.keyword not in _DECLARING:
            continue
        toks: list[Token] = cmd.tokens
        if len(toks) > 2 and toks[1].text == "(" and any(
                t.text == "output" for t in toks[2:4]):
            continue  # a print-only mode
        for i, tok in enumerate(toks[:-1]):
            if tok.text != "(":
                continue
            j = i + 1
            if toks[j].kind == "ident" and toks[j].text in _MIXFIX_KEYS:
                j += 1
            if j < len(toks) and toks[j].kind in ("string", "cartouche"):
                for d in delimiters(toks[j].content):
                    word = _word_of(d)
                    if word:
                        found.append((word, toks[j].line))
    return found


def imports_of(text: str) -> list[str]:
    """The imports of a theory's header (``theory N imports A "B.C" … begin``)."""
    try:
        tokens = [t for t in tokenize(text) if t.kind in ("ident", "string")]
    except LexError:
        return []
    words = [t.content if t.kind == "string" else t.text for t in tokens]
    start = next((i for i, t in enumerate(tokens) if t.text == "theory" and t.column == 1),
                 None)
    if start is None or "imports" not in words[start:start + 3]:
        return []
    out = []
    for w in words[words.index("imports", start) + 1:]:
        if w in ("keywords", "abbrevs", "begin"):
            break
        out.append(w)
    return out


def hol_path(name: str, importer_dir: str) -> str | None:
    """The file of a HOL theory import (None: not HOL's)."""
    if name.startswith("~~/"):
        return name[3:] + ".thy"
    if "." in name:
        session, _, theory = name.partition(".")
        folder = HOL_SESSIONS.get(session)
        return f"{folder}/{theory}.thy" if folder else None
    if importer_dir.startswith("src/HOL"):
        return f"{importer_dir}/{name}.thy"
    if name in ("Main", "Complex_Main"):
        return f"src/HOL/{name}.thy"
    return None


def hol_closure(isabelle: Repo, roots: list[str]) -> list[str]:
    seen: list[str] = []
    todo = [r for r in roots]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        text = isabelle.read(path)
        if text is None:
            if "/" in path.rsplit("/", 1)[0] and not path.startswith("src/HOL/"):
                continue
            alt = "src/HOL/" + path.rsplit("/", 1)[1]  # an unqualified import of session HOL
            if alt != path and alt not in seen:
                todo.append(alt)
            continue
        seen.append(path)
        folder = path.rsplit("/", 1)[0]
        for imp in imports_of(text):
            target = hol_path(imp, folder)
            if target is not None:
                todo.append(target)
    return sorted(seen)


def pure_words(isabelle: Repo) -> list[tuple[str, str]]:
    """Pure's inner keywords from its syntax table (src/Pure/pure_thy.ML)."""
    path = "src/Pure/pure_thy.ML"
    text = isabelle.read(path) or ""
    out = []
    for n, line in enumerate(text.splitlines(), 1):
        for m in re.finditer(r'Mixfix\.mixfix "([^"]*)"', line):
            for d in delimiters(m.group(1)):
                word = _word_of(d)
                if word:
                    out.append((word, f"{path}:{n}"))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--utp-main", required=True, metavar="GITDIR@COMMIT")
    parser.add_argument("--isabelle", required=True, metavar="GITDIR@COMMIT")
    args = parser.parse_args()
    utp, isabelle = Repo(args.utp_main), Repo(args.isabelle)
    table: dict[str, tuple[str, str]] = {}
    hol_roots: list[str] = [p for p in (hol_path(i, "") for i in PRELUDE_IMPORTS) if p]
    for folder in UTP_DIRS:
        for path in utp.files(folder):
            text = utp.read(path) or ""
            for word, line in mixfix_words(text):
                table.setdefault(word, ("utp-main", f"{path}:{line}"))
            for imp in imports_of(text):
                target = hol_path(imp, "")
                if target is not None:
                    hol_roots.append(target)
    hol: dict[str, str] = {}
    for word, where in pure_words(isabelle):
        hol.setdefault(word, where)
    for path in hol_closure(isabelle, hol_roots):
        for word, line in mixfix_words(isabelle.read(path) or ""):
            hol.setdefault(word, f"{path.removeprefix('src/')}:{line}")
    rows = [(w, "HOL", src) for w, src in hol.items()]
    rows += [(w, lib, src) for w, (lib, src) in table.items()]
    sys.stdout.write(f"# word\tlibrary\tfile:line  (tools/derive_isabelle_words.py; utp-main "
                     f"{utp.commit}, Isabelle {isabelle.commit})\n")
    for word, lib, src in sorted(rows, key=lambda r: (r[1], r[0])):
        sys.stdout.write(f"{word}\t{lib}\t{src}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
