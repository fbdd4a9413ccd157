"""A Hindley–Milner type checker for the HOL/UTP terms cyphy's Isabelle printer emits.

Isabelle cannot run here, so this is the second route to "the theory type-checks": every
definition body of a generated theory (utp-main c9122f14 dialect) is parsed with the round-trip
grammar (``utp_terms.lark``) and its type inferred by unification, over

- :data:`SIGNATURES`: the type of every constant, operator and syntax translation the printer
  uses, each read from the library source it cites (utp-main at commit c9122f14; HOL's own
  constants from the Isabelle2020 HOL theories named; the prelude's from the prelude shipped
  in ``cyphy/backends/isabelle/templates``), and
- the theory's own declarations (``axiomatization``, ``definition``, ``consts``,
  ``datatype``, ``alphabet``, ``type_synonym``), read from the theory text.

Overloading is modelled with sorts (type classes): a type variable may carry classes, and a
type constructor belongs to a class only through :data:`INSTANCES` (``uexpr`` inherits
arithmetic from its value type, as utp_expr.thy instantiates it). So ``real list * real`` fails
to unify, and ``real list * real list`` fails for want of a ``times`` instance on lists.
Identifiers are also checked against the keywords of the imported syntax, and unknown names are
errors. What this does not model: Isabelle's parser itself (priorities; the printer
parenthesises every operator), coercion insertion (the printer writes ``real`` itself), proof.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from functools import lru_cache
from pathlib import Path

from lark import Lark, Token, Tree

from cyphy.backends.isabelle.library_words import HOL_SYNTAX_WORDS, SYNTAX_WORDS
from cyphy.backends.isabelle.names import OUTER_KEYWORDS



@lru_cache(maxsize=1)
def parser() -> Lark:
    """The grammar of the terms the utp printer writes (``utp_terms.lark``): the subset of
    Isabelle/UTP's inner syntax a generated theory uses."""
    return Lark.open(str(Path(__file__).with_name("utp_terms.lark")),
                     start=["action", "hol"], parser="lalr", strict=True)


U = "utp-main c9122f14 "
H = "Isabelle 2d6638d src/HOL/"
#: name → (type, where it was read). Type variables may carry classes: ``'a::plus``.
SIGNATURES: dict[str, tuple[str, str]] = {
    # HOL: Isabelle's src/HOL at github:digama0/isabelle 2d6638d (a 2024 snapshot; these
    # declarations and their notation are as in Isabelle2020). Overloaded constants are
    # class operations: the class is the sort their type variable carries.
    "+": ("'a::plus \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:195 (class plus, line 194)"),
    "-": ("'a::minus \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:198 (class minus, line 197)"),
    "*": ("'a::times \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:204 (class times, line 203)"),
    "/": ("'a::inverse \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Fields.thy:26 (abbreviation inverse_divide (infixl \"'/\" 70) of class inverse, "
          "line 22; Rings.thy:683's divide is written div)"),
    "^": ("'a::power \\<Rightarrow> nat \\<Rightarrow> 'a",
          H + "Power.thy:17 (class power, line 14)"),
    "powr": ("real \\<Rightarrow> real \\<Rightarrow> real",
             H + "Transcendental.thy:1567 (class ln; real's instance, line 1575)"),
    "uminus": ("'a::uminus \\<Rightarrow> 'a", H + "Groups.thy:201 (class uminus, line 200)"),
    "=": ("'a \\<Rightarrow> 'a \\<Rightarrow> bool", H + "HOL.thy:87 (eq; notation line 91)"),
    "\\<noteq>": ("'a \\<Rightarrow> 'a \\<Rightarrow> bool", H + "HOL.thy:168 (not_equal)"),
    "<": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
          H + "Orderings.thy:177 (less of class ord)"),
    ">": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool", H + "Orderings.thy:191 (greater)"),
    "\\<le>": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
               H + "Orderings.thy:176 (less_eq of class ord)"),
    "\\<ge>": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
               H + "Orderings.thy:187 (greater_eq)"),
    "\\<longrightarrow>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool",
                           H + "HOL.thy:86 (implies)"),
    "\\<longleftrightarrow>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool",
                               H + "HOL.thy:179 (iff)"),
    "@": ("'a list \\<Rightarrow> 'a list \\<Rightarrow> 'a list", H + "List.thy:75 (append)"),
    "!": ("'a list \\<Rightarrow> nat \\<Rightarrow> 'a", H + "List.thy:125 (nth)"),
    "Cons": ("'a \\<Rightarrow> 'a list \\<Rightarrow> 'a list", H + "List.thy:13"),
    "Nil": ("'a list", H + "List.thy:12"),
    "real": ("nat \\<Rightarrow> real", H + "Real.thy:952 (abbreviation real, of_nat)"),
    "True": ("bool", H + "HOL.thy:100"), "False": ("bool", H + "HOL.thy:109"),
    "UNIV": ("'a set", H + "Set.thy:576"),
    "sin": ("real \\<Rightarrow> real", H + "Transcendental.thy:3271 (at real)"),
    "cos": ("real \\<Rightarrow> real", H + "Transcendental.thy:3274 (at real)"),
    "tan": ("real \\<Rightarrow> real", H + "Transcendental.thy:4645 (at real)"),
    "arctan": ("real \\<Rightarrow> real", H + "Transcendental.thy:5087"),
    "exp": ("real \\<Rightarrow> real", H + "Transcendental.thy:1152 (at real)"),
    "ln": ("real \\<Rightarrow> real",
           H + "Transcendental.thy:1564 (class ln; at real, line 1575)"),
    "sqrt": ("real \\<Rightarrow> real", H + "NthRoot.thy:397"),
    "abs": ("'a::abs \\<Rightarrow> 'a", H + "Groups.thy:1167 (class abs, line 1166)"),
    # utp-main c9122f14
    "lit": ("'t \\<Rightarrow> ('t, 'a) uexpr", U + "utp/utp_expr.thy:50"),
    "var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t, 'a) uexpr", U + "utp/utp_expr.thy:45"),
    "in_var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t \\<Longrightarrow> 'a \\<times> 'b)",
               U + "utp/utp_var.thy:53 ($x, utp_var.thy:250)"),
    "out_var": ("('t \\<Longrightarrow> 'b) \\<Rightarrow> ('t \\<Longrightarrow> 'a \\<times> 'b)",
                U + "utp/utp_var.thy:56 ($x\\<acute>, utp_var.thy:251)"),
    "pr_var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t \\<Longrightarrow> 'a)",
               U + "utp/utp_var.thy:69 (&x, utp_var.thy:249)"),
    "uop": ("('a \\<Rightarrow> 'b) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> ('b, 's) uexpr",
            U + "utp/utp_expr.thy:61"),
    "bop": ("('a \\<Rightarrow> 'b \\<Rightarrow> 'c) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
            "('b, 's) uexpr \\<Rightarrow> ('c, 's) uexpr", U + "utp/utp_expr.thy:66"),
    "trop": ("('a \\<Rightarrow> 'b \\<Rightarrow> 'c \\<Rightarrow> 'd) \\<Rightarrow> ('a, 's) uexpr "
             "\\<Rightarrow> ('b, 's) uexpr \\<Rightarrow> ('c, 's) uexpr \\<Rightarrow> "
             "('d, 's) uexpr", U + "utp/utp_expr.thy:70"),
    "=\\<^sub>u": ("('a, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> (bool, 's) uexpr",
                   U + "utp/utp_expr.thy:100"),
    "\\<noteq>\\<^sub>u": ("('a, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                           "(bool, 's) uexpr", U + "utp/utp_pred.thy:342"),
    "<\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                   "(bool, 's) uexpr", U + "utp/utp_expr.thy:262"),
    ">\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                   "(bool, 's) uexpr", U + "utp/utp_expr.thy:263"),
    "\\<le>\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                        "(bool, 's) uexpr", U + "utp/utp_expr.thy:264"),
    "\\<ge>\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                        "(bool, 's) uexpr", U + "utp/utp_expr.thy:265"),
    "\\<and>": ("'a::uconj \\<Rightarrow> 'a \\<Rightarrow> 'a",
                U + "utp/utp_pred.thy:38 (adhoc: conj, conj_upred, lines 47 and 334)"),
    "\\<or>": ("'a::uconj \\<Rightarrow> 'a \\<Rightarrow> 'a", U + "utp/utp_pred.thy:39"),
    "\\<Rightarrow>": ("'s upred \\<Rightarrow> 's upred \\<Rightarrow> 's upred",
                       U + "utp/utp_pred.thy:40 (adhoc: impl, line 336)"),
    "\\<Leftrightarrow>": ("'s upred \\<Rightarrow> 's upred \\<Rightarrow> 's upred",
                           U + "utp/utp_pred.thy:41 (adhoc: iff_upred, line 337)"),
    "\\<not>": ("'a::uconj \\<Rightarrow> 'a", U + "utp/utp_pred.thy:42 (adhoc: Not, not_upred)"),
    "true": ("'s upred", U + "utp/utp_pred.thy:234 (utrue, line 331)"),
    "false": ("'s upred", U + "utp/utp_pred.thy:235 (ufalse, line 332)"),
    "shEx": ("('b \\<Rightarrow> 's upred) \\<Rightarrow> 's upred",
             U + "utp/utp_pred.thy:54 (\\<^bold>\\<exists> x \\<bullet> P, line 76)"),
    "utuple": ("('a, 's) uexpr \\<Rightarrow> ('b, 's) uexpr \\<Rightarrow> ('a \\<times> 'b, 's) uexpr",
               U + "utp/utp_expr.thy:248"),
    "lens_plus": ("('a \\<Longrightarrow> 'c) \\<Rightarrow> ('b \\<Longrightarrow> 'c) \\<Rightarrow> "
                  "('a \\<times> 'b \\<Longrightarrow> 'c)",
                  U + "optics/Lens_Algebra.thy:38 ({x, y}\\<^sub>v: utp_var.thy:277, 332)"),
    "zero_lens": ("unit \\<Longrightarrow> 'a", U + "optics/Lens_Algebra.thy:72 (0\\<^sub>L)"),
    "salpha_none": ("unit \\<Longrightarrow> 'a",
                    U + "utp/utp_var.thy:265 (\\<emptyset>, translated to 0\\<^sub>L, line 328)"),
    "salphacomp": ("('a \\<Longrightarrow> 'c) \\<Rightarrow> ('b \\<Longrightarrow> 'c) \\<Rightarrow> "
                   "('a \\<times> 'b \\<Longrightarrow> 'c)",
                   U + "utp/utp_var.thy:262 ((x;y), translated to +\\<^sub>L, line 319)"),
    "Skip": ("('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_healths.thy:29"),
    "Stop": ("('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_healths.thy:26"),
    ";;": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
           U + "utp/utp_rel.thy:93 (useq at hrel)"),
    "\\<box>": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                U + "theories/sf_rdes/utp_sfrd_extchoice.thy:25"),
    "EXTCHOICE": ("'i set \\<Rightarrow> ('i \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> "
                  "('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_extchoice.thy:11 "
                  "(\\<box> x\\<in>A \\<bullet> P: syntax line 18, translation line 22)"),
    "|||": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
            U + "theories/circus/utp_circus_parallel.thy:846"),
    "inter_circus": ("('s, 'e) action \\<Rightarrow> ('a \\<Longrightarrow> 's) \\<Rightarrow> "
                     "('b \\<Longrightarrow> 's) \\<Rightarrow> ('s, 'e) action \\<Rightarrow> "
                     "('s, 'e) action", U + "theories/circus/utp_circus_parallel.thy:839"),
    "cond_srea": ("('s, 'e) action \\<Rightarrow> 's upred \\<Rightarrow> ('s, 'e) action "
                  "\\<Rightarrow> ('s, 'e) action",
                  U + "theories/reactive/utp_rea_prog.thy:298 (syntax line 306)"),
    "GuardCSP": ("'s upred \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                 U + "theories/sf_rdes/utp_sfrd_prog.thy:415 (&\\<^sub>C, line 422)"),
    "PrefixCSP": ("('e, 's) uexpr \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                  U + "theories/sf_rdes/utp_sfrd_prog.thy:708 (\\<^bold>\\<rightarrow>: "
                  "theories/circus/utp_circus_prefix.thy:8, output !(e): line 31)"),
    "InputCSP": ("('a \\<Rightarrow> 'e) \\<Rightarrow> ('a \\<Rightarrow> 's upred) \\<Rightarrow> "
                 "('a \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> ('s, 'e) action",
                 U + "theories/sf_rdes/utp_sfrd_prog.thy:864 (?(x): "
                 "theories/circus/utp_circus_prefix.thy:21)"),
    "assigns_csp": ("('a \\<Longrightarrow> 's) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                    "('s, 'e) action",
                    U + "theories/sf_rdes/utp_sfrd_prog.thy:290-291 (syntax; AssignsCSP, line 284, "
                    "by the translation of line 294)"),
    "SpecC": ("('a \\<Longrightarrow> 's) \\<Rightarrow> 's upred \\<Rightarrow> 's upred "
              "\\<Rightarrow> ('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_prog.thy:49"),
    # the prelude shipped with cyphy (cyphy/backends/isabelle/templates/CyPhyCircus_Prelude.thy)
    "EvolveC": ("('s \\<times> 's) upred \\<Rightarrow> ('s, 'e) action", "prelude: axiomatization"),
    "InterruptC": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                   "prelude: axiomatization"),
    "InterruptCondC": ("('s, 'e) action \\<Rightarrow> 's upred \\<Rightarrow> ('s, 'e) action",
                       "prelude: axiomatization"),
    "MuC": ("(('s, 'e) action \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> ('s, 'e) action",
            "prelude: definition MuC"),
    "WaitC": ("'e \\<Rightarrow> nat \\<Rightarrow> ('s, 'e) action", "prelude: primrec WaitC"),
    "fmod": ("real \\<Rightarrow> real \\<Rightarrow> real", "prelude: definition fmod"),
}

#: class → type constructors in it; ``uexpr`` is in a class when its value type is
#: (utp/utp_expr.thy:131-177, utp/utp_expr_insts.thy:10-76 at c9122f14).
INSTANCES: dict[str, set[str]] = {
    "plus": {"real", "nat", "int", "uexpr"}, "minus": {"real", "nat", "int", "uexpr"},
    "times": {"real", "nat", "int", "uexpr"},
    "uminus": {"real", "int", "uexpr"}, "power": {"real", "nat", "int", "uexpr"},
    "abs": {"real", "int", "uexpr"}, "ord": {"real", "nat", "int"},
    "numeral": {"real", "nat", "int", "uexpr"},
    # Fields.thy:22 (class inverse: what / needs); real is a field (Real.thy), nat and int
    # are not, so 1 / 2 :: nat is rejected, as Isabelle rejects it; uexpr: utp_expr_insts.thy:37
    "inverse": {"real", "uexpr"},
    "uconj": {"bool", "uexpr"},  # conj at bool, conj_upred at (bool, 's) uexpr
    # the axiomatic dialect's (ax_types.py): real and, component-wise, products
    # are real_normed_vectors (HOL/Real_Vector_Spaces.thy, HOL-Analysis Product_Vector.thy);
    # cyphyaction is a complete_lattice (Ax_CyPhyCircus.thy:18-21)
    "real_normed_vector": {"real", "prod"}, "complete_lattice": {"cyphyaction"},
}
#: classes a product is in when its components are.
_COMPONENTWISE = {"real_normed_vector"}
#: classes whose uexpr instance needs the value type in the class (bool for uconj).
_LIFTED = {"plus", "minus", "times", "inverse", "uminus", "power", "abs", "numeral"}

#: Words an identifier of a theory must not be: the imported syntax's keywords.
KEYWORDS = frozenset(SYNTAX_WORDS) | frozenset(HOL_SYNTAX_WORDS) | OUTER_KEYWORDS


class TypeError_(Exception):
    """A term that does not type-check (or names something undeclared)."""


# ----------------------------------------------------------------------------- types


@dataclass(eq=False)
class TVar:
    sort: set[str] = field(default_factory=set)
    ref: "Type | None" = None
    name: str = ""


@dataclass(frozen=True)
class TCon:
    name: str
    args: tuple["Type", ...] = ()


Type = TVar | TCon


def fun(*ts: Type) -> Type:
    out = ts[-1]
    for t in reversed(ts[:-1]):
        out = TCon("fun", (t, out))
    return out


def uexpr(value: Type, alpha: Type) -> Type:
    return TCon("uexpr", (value, alpha))


def prod_type(items: list[Type]) -> Type:
    """``a \\<times> b \\<times> …`` (right-nested, as HOL's ``\\<times>``); one item is itself."""
    out = items[-1]
    for t in reversed(items[:-1]):
        out = TCon("prod", (t, out))
    return out


def prune(t: Type) -> Type:
    while isinstance(t, TVar) and t.ref is not None:
        t = t.ref
    return t


def show(t: Type) -> str:
    t = prune(t)
    if isinstance(t, TVar):
        return "'?" + ("::" + ",".join(sorted(t.sort)) if t.sort else "")
    if not t.args:
        return t.name
    if t.name == "fun":
        return f"({show(t.args[0])} => {show(t.args[1])})"
    return "(" + ", ".join(show(a) for a in t.args) + f") {t.name}"


def occurs(v: TVar, t: Type) -> bool:
    t = prune(t)
    return t is v or (isinstance(t, TCon) and any(occurs(v, a) for a in t.args))


def constrain(t: Type, sort: set[str]) -> None:
    """Put ``t`` into every class of ``sort`` (instance resolution)."""
    t = prune(t)
    if isinstance(t, TVar):
        t.sort |= sort
        return
    for cls in sort:
        if t.name not in INSTANCES.get(cls, set()):
            raise TypeError_(f"no instance {t.name} :: {cls} (in {show(t)})")
        if t.name == "prod" and cls in _COMPONENTWISE:
            for arg in t.args:
                constrain(arg, {cls})
        if t.name == "uexpr":
            if cls in _LIFTED:
                constrain(t.args[0], {cls})
            elif cls == "uconj":
                unify(t.args[0], TCon("bool"))


def unify(a: Type, b: Type) -> None:
    a, b = prune(a), prune(b)
    if a is b:
        return
    if isinstance(a, TVar):
        if occurs(a, b):
            raise TypeError_(f"infinite type {show(a)} = {show(b)}")
        a.ref = b
        constrain(b, a.sort)
        return
    if isinstance(b, TVar):
        unify(b, a)
        return
    if a.name != b.name or len(a.args) != len(b.args):
        raise TypeError_(f"cannot unify {show(a)} with {show(b)}")
    for x, y in zip(a.args, b.args):
        unify(x, y)


# ----------------------------------------------------------------------------- type syntax

_TOKEN = re.compile(r"\s*(\\<Rightarrow>|\\<Longrightarrow>|\\<times>|'[A-Za-z][A-Za-z0-9_]*"
                    r"|::|[A-Za-z][A-Za-z0-9_]*|[(),{}])")
SYNONYMS: dict[str, tuple[int, str]] = {
    "upred": (1, "(bool, 'a1) uexpr"),  # utp/utp_pred.thy:20
    "hrel": (1, "(bool, 'a1 \\<times> 'a1) uexpr"),  # utp/utp_rel.thy:83
}


def parse_type(text: str, tvars: dict[str, TVar] | None = None,
               synonyms: dict[str, tuple[int, str]] | None = None) -> Type:
    """An Isabelle type as the printer and the signature table write it."""
    tokens = _TOKEN.findall(text)
    if "".join(tokens) != re.sub(r"\s+", "", text):
        raise TypeError_(f"cannot read the type {text!r}")
    tvars = {} if tvars is None else tvars
    synonyms = {**SYNONYMS, **(synonyms or {})}
    pos = 0

    def peek() -> str | None:
        return tokens[pos] if pos < len(tokens) else None

    def take() -> str:
        nonlocal pos
        pos += 1
        return tokens[pos - 1]

    def full() -> Type:
        left = product()
        if peek() == "\\<Rightarrow>":
            take()
            return fun(left, full())
        if peek() == "\\<Longrightarrow>":
            take()
            return TCon("lens", (left, full()))
        return left

    def product() -> Type:
        items = [applied()]
        while peek() == "\\<times>":
            take()
            items.append(applied())
        out = items[-1]
        for t in reversed(items[:-1]):
            out = TCon("prod", (t, out))
        return out

    def applied() -> Type:
        args = atom()
        while peek() is not None and re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", peek() or ""):
            args = [constructor(take(), args)]
        if len(args) != 1:
            raise TypeError_(f"a type tuple without constructor in {text!r}")
        return args[0]

    def constructor(name: str, args: list[Type]) -> Type:
        if name in synonyms:
            arity, body = synonyms[name]
            if arity != len(args):
                raise TypeError_(f"{name} takes {arity} type arguments")
            inner = {f"'a{i + 1}": a for i, a in enumerate(args)}
            return parse_type(body, inner, synonyms)  # type: ignore[arg-type]
        return TCon(name, tuple(args))

    def atom() -> list[Type]:
        tok = take()
        if tok.startswith("'"):
            var = tvars.get(tok)
            if var is None:
                var = tvars[tok] = TVar(name=tok)
            if peek() == "::":
                take()
                var.sort.add(take())
            return [var]
        if tok == "(":
            items = [full()]
            while peek() == ",":
                take()
                items.append(full())
            if take() != ")":
                raise TypeError_(f"unbalanced parentheses in {text!r}")
            return items
        return [constructor(tok, [])]

    out = full()
    if pos != len(tokens):
        raise TypeError_(f"trailing text in the type {text!r}")
    return out


def instance(sig: str) -> Type:
    """A fresh instance of a signature of the table."""
    return parse_type(SIGNATURES[sig][0])


# ----------------------------------------------------------------------------- the theory


@dataclass
class TheoryTypes:
    """The theory's own declarations: constants (with types), action definitions, the
    state type, and the identifiers it introduces (checked against :data:`KEYWORDS`)."""

    constants: dict[str, Type] = field(default_factory=dict)
    lenses: dict[str, Type] = field(default_factory=dict)  # alphabet fields
    synonyms: dict[str, tuple[int, str]] = field(default_factory=dict)
    definitions: list[tuple[str, list[str], str, str]] = field(default_factory=list)
    values: list[tuple[str, str, str]] = field(default_factory=list)  # (name, type, value)
    axioms: list[str] = field(default_factory=list)
    identifiers: list[str] = field(default_factory=list)
    channel_sets: list[tuple[str, ...]] = field(default_factory=list)  # (name, chan, value)
    compositions: list[tuple[str, ...]] = field(default_factory=list)  # see _COMPOSITION


_DEF_ACTION = re.compile(r'^definition (\w+) :: "([^"]*)" where\n  "(\w+)((?: \w+)*) = (.*?)"\n'
                         r'(?=lemma|\n|end)', re.S | re.M)
_DEF_CONST = re.compile(r'^definition (\w+) :: ("[^"]*"|\S+) where "(\w+) = (.*)"$', re.M)
_CONSTS_ONE = re.compile(r'^consts (\w+) :: ("[^"]*"|\S+)$', re.M)
_CONSTS_BLOCK = re.compile(r'^consts\n((?:  \w+ :: "[^"]*"\n)+)', re.M)
_AXIOMATIZATION = re.compile(r'^axiomatization\n((?:  \w+ :: \S+(?: and)?\n)+)where\n'
                             r'((?:  \w+: ".*"(?: and)?\n)+)', re.M)
_DATATYPE = re.compile(r'^datatype (\w+) =\n((?:  (?:  |\| )\w+(?: "[^"]*")?\n)+)', re.M)
_ALPHABET = re.compile(r'^alphabet (\w+) =(?: (\w+) \+)?\n((?:  \w+ :: ("[^"]*"|\S+)\n)+)',
                       re.M)
#: The composition's channel set: nullary constructors in braces, ``range c`` for those
#: with a payload (HOL/Set.thy insert/union, HOL/Fun.thy range), joined by union.
_CHANNEL_SET = re.compile(r'^definition (\w+) :: "(\w+) set" where "\1 = (.*)"$', re.M)
#: ``N = HideCSP ((state S1 \<bullet> A1) \<lbrakk>cs\<rbrakk>\<^sub>C (state S2 \<bullet> A2)) cs``:
#: state_srea (utp-main c9122f14 rea_designs/utp_rdes_prog.thy:424, syntax ``state _
#: \<bullet> _`` :429), ParCSP's ``_ \<lbrakk>_\<rbrakk>\<^sub>C _`` (circus/
#: utp_circus_parallel.thy:838), HideCSP (circus/utp_circus_hiding.thy:167).
_COMPOSITION = re.compile(
    r'^definition (\w+) :: "(\w+) process" where\n  "\1 = HideCSP \(\(state (\w+) \\<bullet> '
    r'(\w+)\) \\<lbrakk>(\w+)\\<rbrakk>\\<\^sub>C \(state (\w+) \\<bullet> (\w+)\)\) (\w+)"$', re.M)
_SYNONYM = re.compile(r'^type_synonym (\w+) = "([^"]*)"$', re.M)
_TYPEDECL = re.compile(r"^typedecl (\w+)$", re.M)


def _unquote(t: str) -> str:
    return t[1:-1] if t.startswith('"') else t


def read_theory(text: str) -> TheoryTypes:
    """The declarations of a generated theory (its layout is the template's)."""
    th = TheoryTypes()
    for m in _TYPEDECL.finditer(text):
        th.identifiers.append(m.group(1))
    for m in _AXIOMATIZATION.finditer(text):
        for line in m.group(1).splitlines():
            name, typ = re.match(r"  (\w+) :: (\S+)", line).groups()  # type: ignore[union-attr]
            th.constants[name] = parse_type(typ)
            th.identifiers.append(name)
        th.axioms += re.findall(r'  \w+: "(.*)"', m.group(2))
    for m in _DEF_CONST.finditer(text):
        name, typ, lhs, value = m.groups()
        if typ.endswith(' set"'):
            continue  # the composition's channel set, checked on its own
        if lhs != name:
            raise TypeError_(f"definition {name} defines {lhs}")
        th.constants[name] = parse_type(_unquote(typ))
        th.values.append((name, _unquote(typ), value))
        th.identifiers.append(name)
    for m in _CONSTS_ONE.finditer(text):
        th.constants[m.group(1)] = parse_type(_unquote(m.group(2)))
        th.identifiers.append(m.group(1))
    for m in _CONSTS_BLOCK.finditer(text):
        for name, typ in re.findall(r'  (\w+) :: "([^"]*)"', m.group(1)):
            th.constants[name] = parse_type(typ)
            th.identifiers.append(name)
    for m in _DATATYPE.finditer(text):
        dtype = TCon(m.group(1))
        th.identifiers.append(m.group(1))
        for ctor, payload in re.findall(r'(?:  |\| )(\w+)(?: "([^"]*)")?', m.group(2)):
            th.constants[ctor] = fun(parse_type(payload), dtype) if payload else dtype
            th.identifiers.append(ctor)
    alphabets = list(_ALPHABET.finditer(text))
    for m in _SYNONYM.finditer(text):
        th.synonyms[m.group(1)] = (0, m.group(2))
        th.identifiers.append(m.group(1))
    # a field is a lens into the alphabet that extends its own last (P's Visible + State);
    # each process has its own (P's and, when the theory states it, D's)
    extended_by = {m.group(2): m.group(1) for m in alphabets if m.group(2)}
    for m in alphabets:
        state_name = m.group(1)
        while state_name in extended_by:
            state_name = extended_by[state_name]
        th.identifiers.append(m.group(1))
        for name, typ in re.findall(r'  (\w+) :: ("[^"]*"|\S+)', m.group(3)):
            th.lenses[name] = TCon("lens", (parse_type(_unquote(typ)), TCon(state_name)))
            th.identifiers.append(name)
    for m in _CHANNEL_SET.finditer(text):
        th.channel_sets.append(m.groups())
        th.identifiers.append(m.group(1))
    for m in _COMPOSITION.finditer(text):
        th.compositions.append(m.groups())
        th.identifiers.append(m.group(1))
    for m in _DEF_ACTION.finditer(text):
        name, typ, lhs, params, body = m.groups()
        if typ.endswith(" process"):
            continue  # the composition, checked on its own
        if lhs != name:
            raise TypeError_(f"definition {name} defines {lhs}")
        th.definitions.append((name, params.split(), typ, body))
        th.constants[name] = parse_type(typ, synonyms=th.synonyms)
        th.identifiers.append(name)
    return th


class Checker:
    """Infers the type of a parsed term (a tree of ``utp_terms.lark``)."""

    def __init__(self, theory: TheoryTypes) -> None:
        self.theory = theory

    # names
    def constant(self, name: str, env: dict[str, Type]) -> Type:
        if name in KEYWORDS:
            raise TypeError_(f"'{name}' is a keyword of the imported syntax")
        if name in env:
            return env[name]
        if name in self.theory.constants:
            return self.theory.constants[name]
        if name in SIGNATURES:
            return instance(name)
        raise TypeError_(f"'{name}' is not declared")

    def lens(self, name: str) -> Type:
        if name in KEYWORDS:
            raise TypeError_(f"'{name}' is a keyword of the imported syntax")
        found = self.theory.lenses.get(name)
        if found is None:
            raise TypeError_(f"'{name}' is no variable of the state")
        return found

    def bind(self, env: dict[str, Type], name: str, t: Type) -> dict[str, Type]:
        if name in KEYWORDS:
            raise TypeError_(f"the bound name '{name}' is a keyword of the imported syntax")
        return {**env, name: t}

    def apply(self, ftype: Type, *args: Type) -> Type:
        result = TVar()
        unify(ftype, fun(*args, result))
        return result

    def sig(self, name: str, *args: Type) -> Type:
        return self.apply(instance(name), *args)

    # dispatch
    def infer(self, node: Tree | Token, env: dict[str, Type]) -> Type:
        if isinstance(node, Token):
            raise TypeError_(f"unexpected token {node!r}")
        method = getattr(self, "t_" + node.data, None)
        if method is None:
            raise TypeError_(f"no typing rule for {node.data}")
        return method(node.children, env)

    # ---- actions
    def t_skip(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("Skip")

    def t_stop(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("Stop")

    def t_call(self, ch, env):  # type: ignore[no-untyped-def]
        return self.constant(str(ch[0]), env)

    def t_call_args(self, ch, env):  # type: ignore[no-untyped-def]
        return self.apply(self.constant(str(ch[0]), env), *[self.infer(a, env) for a in ch[1:]])

    def _binary(self, sig: str, ch, env):  # type: ignore[no-untyped-def]
        return self.sig(sig, self.infer(ch[0], env), self.infer(ch[1], env))

    def t_seq(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary(";;", ch, env)

    def t_ext_choice(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("\\<box>", ch, env)

    def t_interleave(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("|||", ch, env)

    def t_interrupt(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("InterruptC", ch, env)

    def t_cond(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("cond_srea", *(self.infer(c, env) for c in ch))

    def t_guard(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("GuardCSP", ch, env)

    def t_interrupt_cond(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("InterruptCondC", ch, env)

    def t_mu(self, ch, env):  # type: ignore[no-untyped-def]
        var = TVar()
        body = self.infer(ch[1], self.bind(env, str(ch[0]), var))
        return self.sig("MuC", fun(var, body))

    def t_wait(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("WaitC", self.constant(str(ch[0]), env), self.infer(ch[1], env))

    def t_assign_one(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("assigns_csp", self.lens(str(ch[0])), self.infer(ch[1], env))

    def t_assign(self, ch, env):  # type: ignore[no-untyped-def]
        n = len(ch) // 2
        out = TVar()
        for target, value in zip(ch[:n], ch[n:]):
            unify(out, self.sig("assigns_csp", self.lens(str(target)), self.infer(value, env)))
        return out

    def t_spec(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("SpecC", *(self.infer(c, env) for c in ch))

    def t_evolution(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("EvolveC", self.infer(ch[0], env))

    def t_indexed_choice(self, ch, env):  # type: ignore[no-untyped-def]
        ident, typ, where, body = ch
        var = self.infer(typ, env)
        inner = self.bind(env, str(ident), var)
        branch = self.sig("GuardCSP", self.infer(where, inner), self.infer(body, inner))
        universe = instance("UNIV")
        unify(universe, TCon("set", (var,)))
        return self.sig("EXTCHOICE", universe, fun(var, branch))

    def t_parallel(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("inter_circus", *(self.infer(c, env) for c in ch))

    def t_prefix(self, ch, env):  # type: ignore[no-untyped-def]
        event, then = ch
        if event.data == "event_in":
            ctor, names = event.children[0], event.children[1:]
            types = [TVar() for _ in names]
            payload = prod_type(types)
            inner = env
            for n, t in zip(names, types):
                inner = self.bind(inner, str(n), t)
            action = self.infer(then, inner)
            state = TVar()
            unify(action, TCon("action", (state, TVar())))
            return self.sig("InputCSP", self.constant(str(ctor), env),
                            fun(payload, uexpr(TCon("bool"), state)), fun(payload, action))
        return self.sig("PrefixCSP", self.infer(event, env), self.infer(then, env))

    # ---- events: their type is the event as a UTP expression
    def t_event_plain(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("lit", self.constant(str(ch[0]), env))

    def _event_value(self, ch, env):  # type: ignore[no-untyped-def]
        payload = TVar()
        alpha = TVar()
        unify(self.infer(ch[1], env), uexpr(payload, alpha))
        ctor = self.constant(str(ch[0]), env)
        return uexpr(self.apply(ctor, payload), alpha)

    t_event_out = _event_value
    t_event_dot = _event_value

    # ---- name sets (lenses)
    def t_nameset_empty(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("zero_lens")

    def t_nameset(self, ch, env):  # type: ignore[no-untyped-def]
        out = self.lens(str(ch[-1]))
        for name in reversed(ch[:-1]):
            out = self.sig("lens_plus", self.lens(str(name)), out)
        return out

    # ---- predicates
    def t_exists(self, ch, env):  # type: ignore[no-untyped-def]
        inner = env
        pred = uexpr(TCon("bool"), TVar())
        for c in ch:
            if isinstance(c, Tree) and c.data == "binder":
                inner = self.bind(inner, str(c.children[0]), self.infer(c.children[1], env))
            else:
                unify(pred, self.infer(c, inner))
        return pred

    # ---- types (as written in binders)
    def t_type_basic(self, ch, env):  # type: ignore[no-untyped-def]
        return parse_type(str(ch[0]))

    def t_type_list(self, ch, env):  # type: ignore[no-untyped-def]
        return TCon("list", (self.infer(ch[0], env),))

    def t_type_product(self, ch, env):  # type: ignore[no-untyped-def]
        return prod_type([self.infer(c, env) for c in ch])

    # ---- UTP expressions
    def t_state(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("var", self.sig("pr_var", self.lens(str(ch[0]))))

    def t_state_in(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("var", self.sig("in_var", self.lens(str(ch[0]))))

    def t_state_derivative(self, ch, env):  # type: ignore[no-untyped-def]
        # $x\<acute> in EvolveC's relation: the rate of x, of x's type, over the same pair
        lens = self.lens(str(ch[0]))
        return self.sig("var", self.sig("out_var", lens))

    def t_lifted(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("lit", self.infer(ch[0], env))

    def t_utrue(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("true")

    def t_ufalse(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("false")

    def t_binop(self, ch, env):  # type: ignore[no-untyped-def]
        op = ch[1]
        text = str(op.children[0]) if isinstance(op, Tree) else str(op)
        if text not in SIGNATURES:
            raise TypeError_(f"operator {text} has no signature")
        return self.sig(text, self.infer(ch[0], env), self.infer(ch[2], env))

    def t_conj_u(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("\\<and>", self.infer(ch[0], env), self.infer(ch[1], env))

    def t_neg(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("uminus", self.infer(ch[0], env))

    def t_not_(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("\\<not>", self.infer(ch[0], env))

    def t_lifted_call(self, ch, env):  # type: ignore[no-untyped-def]
        lifter = str(ch[0].children[0])
        return self.sig(lifter, self.constant(str(ch[1]), env),
                        *(self.infer(a, env) for a in ch[2:]))

    def t_lifted_binop(self, ch, env):  # type: ignore[no-untyped-def]
        lifter, op = str(ch[0].children[0]), str(ch[1].children[0])
        return self.sig(lifter, instance(op), self.infer(ch[2], env), self.infer(ch[3], env))

    def t_cons(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("bop", instance("Cons"), self.infer(ch[0], env), self.infer(ch[1], env))

    def t_fmod(self, ch, env):  # type: ignore[no-untyped-def]
        left, right = self.infer(ch[0], env), self.infer(ch[1], env)
        if isinstance(prune(left), TCon) and prune(left).name == "uexpr" or \
                isinstance(prune(right), TCon) and prune(right).name == "uexpr":
            return self.sig("bop", instance("fmod"), left, right)
        return self.sig("fmod", left, right)

    def t_tuple(self, ch, env):  # type: ignore[no-untyped-def]
        items = [self.infer(c, env) for c in ch]
        if all(isinstance(prune(t), TCon) and prune(t).name == "uexpr" for t in items):
            out = items[-1]
            for t in reversed(items[:-1]):
                out = self.sig("utuple", t, out)
            return out
        return prod_type(items)

    # ---- HOL terms
    def t_name(self, ch, env):  # type: ignore[no-untyped-def]
        return self.constant(str(ch[0]), env)

    def t_number(self, ch, env):  # type: ignore[no-untyped-def]
        text = str(ch[0])
        # a decimal is numeral / 10^n (HOL/Rat.thy:1158-1173, float_tr): numeral and inverse
        return TVar({"numeral", "inverse"} if "." in text else {"numeral"})

    def t_true(self, ch, env):  # type: ignore[no-untyped-def]
        return TCon("bool")

    t_false = t_true

    def t_apply(self, ch, env):  # type: ignore[no-untyped-def]
        return self.apply(self.constant(str(ch[0]), env), *(self.infer(a, env) for a in ch[1:]))

    def t_index(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("!", self.infer(ch[0], env), TCon("nat"))

    def t_sequence(self, ch, env):  # type: ignore[no-untyped-def]
        item = TVar()
        for c in ch:
            if c is not None:
                unify(item, self.infer(c, env))
        return TCon("list", (item,))


def check_theory(text: str) -> list[str]:
    """Every type error of a generated theory (empty: it type-checks), one line each."""
    errors: list[str] = []
    try:
        theory = read_theory(text)
    except TypeError_ as err:
        return [f"declarations: {err}"]
    for ident in theory.identifiers:
        if ident in KEYWORDS:
            errors.append(f"'{ident}' is a keyword of the imported syntax")
    checker = Checker(theory)
    for axiom in theory.axioms:
        try:
            unify(checker.infer(parser().parse(axiom, start="hol"), {}), TCon("bool"))
        except (TypeError_, Exception) as err:  # lark errors too
            errors.append(f"axiom {axiom}: {err}")
    for name, typ, value in theory.values:
        try:
            unify(checker.infer(parser().parse(value, start="hol"), {}), parse_type(typ))
        except (TypeError_, Exception) as err:
            errors.append(f"definition {name}: {err}")
    for name, params, typ, body in theory.definitions:
        try:
            declared = parse_type(typ, synonyms=theory.synonyms)
            env: dict[str, Type] = {}
            result = declared
            for p in params:
                result = prune(result)
                if not (isinstance(result, TCon) and result.name == "fun"):
                    raise TypeError_(f"more parameters than the type {typ} has")
                env = checker.bind(env, p, result.args[0])
                result = result.args[1]
            tree = parser().parse(body, start="action")
            unify(checker.infer(tree, env), result)
            state = prune(prune(result).args[0]) if isinstance(prune(result), TCon) else None
            if isinstance(state, TVar):
                raise TypeError_("the action's state type is not determined")
        except (TypeError_, Exception) as err:
            errors.append(f"definition {name}: {err}")
    errors += _composition_errors(theory)
    return errors


def _composition_errors(theory: TheoryTypes) -> list[str]:
    """The channel set holds constructors of the channel type (``{c}`` nullary, ``range c``
    with a payload); the composition hides each process's state (``state S \\<bullet> A`` with
    ``A :: (S, chan) action``), synchronises and hides on that set, and is a ``chan process``
    (utp-main c9122f14 sf_rdes/utp_sfrd_core.thy:41, ``'e process`` over unit state)."""
    errors: list[str] = []
    sets = {name: chan for name, chan, _ in theory.channel_sets}
    for name, chan, value in theory.channel_sets:
        for token in re.findall(r"range (\w+)|\{([^}]*)\}", value):
            ranged, braced = token
            for ctor in ([ranged] if ranged else [b.strip() for b in braced.split(",")]):
                t = theory.constants.get(ctor)
                want_payload = bool(ranged)
                if t is None or (isinstance(prune(t), TCon) and prune(t).name == "fun") \
                        != want_payload or (_result(t) != TCon(chan)):
                    errors.append(f"definition {name}: {ctor} is no "
                                  f"{'constructor with a payload' if ranged else 'nullary constructor'}"
                                  f" of {chan}")
        rest = re.sub(r"range \w+|\{[^}]*\}|\\<union>|[()\s]", "", value)
        if rest:
            errors.append(f"definition {name}: unexpected {rest!r} in the channel set")
    for name, chan, s1, a1, cs1, s2, a2, cs2 in theory.compositions:
        if cs1 != cs2 or sets.get(cs1) != chan:
            errors.append(f"definition {name}: {cs1} is no channel set of {chan}")
        for state, action in ((s1, a1), (s2, a2)):
            t = theory.constants.get(action)
            if t is None:
                errors.append(f"definition {name}: '{action}' is not declared")
                continue
            try:
                unify(t, TCon("action", (TCon(state), TCon(chan))))
            except TypeError_ as err:
                errors.append(f"definition {name}: {err}")
    return errors


def _result(t: Type) -> Type:
    t = prune(t)
    while isinstance(t, TCon) and t.name == "fun":
        t = prune(t.args[1])
    return t


