"""Isabelle identifiers for CyPhyCircus names (``../shared/spec/isabelle.md`` section 4.1).

CyPhyCircus names arrive mangled (``LMotor_das``); Isabelle adds its own lexical rules on top:
identifiers restricted to ``[A-Za-z][A-Za-z0-9_]*`` without ``__`` or a trailing ``_``, and no
outer keyword, command name, inner-syntax word of the imported UTP/Circus syntax, nor a HOL or
UTP constant that a global name would shadow. A name that hits one gets ``_v`` appended (then a
number, until it is free), so the table stays a bijection; :class:`IsabelleNames` records it.
"""

from __future__ import annotations

import re

from cyphy.backends.isabelle.library_words import (HOL_SYNTAX_WORDS, LIBRARY_CONSTANTS,
                                                   SYNTAX_WORDS)
from cyphy.semantics.circus.names import identifier

_IDENT = re.compile(r"[A-Za-z](?:[A-Za-z0-9]|_(?=[A-Za-z0-9]))*")

#: Outer keywords of theory headers and specifications (Pure and HOL).
OUTER_KEYWORDS = frozenset("""
and begin imports keywords abbrevs theory end for if in is infix infixl infixr open output
overloaded pervasive premises structure unchecked when where assumes constrains defines fixes
includes notes rewrites obtains shows private qualified binder attach
""".split())

#: Isar command names that a user would read as commands (the full table is isar-tools').
COMMANDS = frozenset("""
ML apply axiomatization by chapter consts datatype declare definition done end fun lemma
lemmas notation oops proof qed record section sorry subsection text theorem theory
type_synonym typedecl value abbreviation alphabet chantype primrec function locale
interpretation context corollary proposition schematic_goal have show thus hence using
unfolding with from then also finally moreover ultimately next note fix assume obtain
presume case let back defer prefer subgoal supply instance instantiation class subclass
""".split())

#: Inner-syntax words of HOL and of the UTP/Circus syntax we import.
INNER_WORDS = frozenset("""
if then else let case of o O mod div dvd SOME THE ALL EX CONST TYPE true false Skip Stop
Chaos Miracle II while do od fi process state begin end var UNIV
""".split())

#: HOL and UTP constants that a global name would shadow, and the prelude's own names.
SHADOWED = frozenset("""
id set map fst snd real real_of_int int nat sin cos tan sqrt exp ln log abs sgn min max norm pi
inverse
length hd tl last dom ran card Inf Sup top bot tr tt st ok wait ref transpose rev nth take
drop zip filter concat sum prod list bool unit option Some None Nil Cons True False
uop bop trop qtop action hrel upred uexpr NCSP CSP Healthy
EvolveC InterruptC InterruptCondC MuC WaitC fmod
""".split())

#: CZT/Z keywords (one mangled name serves every printer).
Z_KEYWORDS = frozenset("""
if then else let pre true false function generic relation leftassoc rightassoc section
parents
""".split())

#: Every word a generated identifier avoids: the lists above (HOL, Isar, Z), and the mixfix
#: delimiters of HOL and utp-main and utp-main's constants, read from the library sources
#: (:mod:`cyphy.backends.isabelle.library_words`).
RESERVED = (OUTER_KEYWORDS | COMMANDS | INNER_WORDS | SHADOWED | Z_KEYWORDS
            | frozenset(SYNTAX_WORDS) | frozenset(HOL_SYNTAX_WORDS)
            | frozenset(LIBRARY_CONSTANTS))


def is_identifier(text: str) -> bool:
    """Whether ``text`` is an identifier of the restricted form we generate."""
    return _IDENT.fullmatch(text) is not None


class IsabelleNames:
    """A bijection between CyPhyCircus names and Isabelle identifiers, avoiding the reserved
    words and every name already handed out (``_v``, then ``_v2``, … appended)."""

    def __init__(self, taken: frozenset[str] = frozenset()) -> None:
        self._to: dict[str, str] = {}
        self._from: dict[str, str] = {}
        self._taken = set(taken)

    def add(self, name: str) -> str:
        """The identifier of ``name`` (the same one when asked again)."""
        found = self._to.get(name)
        if found is not None:
            return found
        base = identifier(name)
        candidate, n = base, 1
        while candidate in RESERVED or candidate in self._from or candidate in self._taken:
            candidate = f"{base}_v" if n == 1 else f"{base}_v{n}"
            n += 1
        self._to[name], self._from[candidate] = candidate, name
        return candidate

    def get(self, name: str) -> str | None:
        return self._to.get(name)

    def __getitem__(self, name: str) -> str:
        return self._to[name]

    def __contains__(self, name: str) -> bool:
        return name in self._to

    def identifiers(self) -> set[str]:
        return set(self._from)

    def inverse(self) -> dict[str, str]:
        """Isabelle identifier → CyPhyCircus name (the reader of the round trip uses it)."""
        return dict(self._from)

    def items(self) -> list[tuple[str, str]]:
        return list(self._to.items())
