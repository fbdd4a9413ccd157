"""The Hindley–Milner machinery of ``cyphy check-theory``'s checkers: types (variables with
sorts, constructors), unification with class constraints, and the reader of Isabelle type
text; the classes' instances are :data:`cyphy.verify.theory.utp_signatures.INSTANCES`."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from cyphy.verify.theory.utp_signatures import _COMPONENTWISE, _LIFTED, INSTANCES

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
