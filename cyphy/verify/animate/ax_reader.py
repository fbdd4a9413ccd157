"""The axiomatic dialect's session (Ax_CyPhyCircus) as ``animate`` runs it, read from its text.

The declarations come from :func:`cyphy.verify.theory.ax_types.read_theory` and every term is
parsed with the axiomatic checker's grammar, ``ax_terms.lark``. The trees are then rewritten
into the forms the executor runs (the utp reader's), so one executor serves both dialects:

- a name that is a field of the one alphabet is a state read (the dialect writes ``x`` where
  the utp dialect writes ``&x``); the composition's name sets give each process its fields;
- ``WaitT n`` (the theory's ``primrec``: ``n`` tocks) is the utp dialect's ``WaitC tock n``;
- ``cSpec frame (True)_e (True)_e`` (the world's rates, any values) is a ``choose``: the
  animator picks them (from ``--input``);
- ``[Λ x` = e, …]`` is an explicit ODE (``odes``), its frame the primed variables: every
  other variable stays as it is during the evolution."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.model import Definition, Process, TheoryModel, declared, line_of
from cyphy.verify.animate.terms import evaluate_hol

_WAIT = re.compile(r'^primrec (\w+) :: "nat \\<Rightarrow> [^"]*" where\n'
                   r'  "\w+ 0 = Skip" \|\n  "\w+ \(Suc n\) = \((\w+) \\<rightarrow> \w+ n\)"',
                   re.M)
_CHANNEL_SET = re.compile(r'^definition (\w+) :: "\w+ set" where\n  "\w+ = \\<lbrace>(.*)'
                          r'\\<rbrace>"', re.M)
_ALPHABET = re.compile(r"^alphabet (\w+) =(?: (\w+) \+)?\n((?:  \w+ :: .*\n)+)", re.M)


def _parse(text: str, start: str, path: Path, line: int) -> Any:
    from lark.exceptions import LarkError  # lazy: only a failed parse needs the class

    from cyphy.verify.theory.ax_types import parser  # lazy: lark loads with the theory
    try:
        return parser().parse(text, start=start)
    except LarkError as err:
        raise AnimateError("E-ANIMATE-READ", "a term animate cannot read: "
                           f"{str(err).splitlines()[0][:160]}", path=path, line=line,
                           status=2) from None


class _Rewrite:
    """The axiomatic trees in the executor's forms (see the module docstring)."""

    def __init__(self, fields: set[str], waits: dict[str, str]) -> None:
        self.fields = fields
        self.waits = waits  # primrec name → its event

    def expr(self, node: Any, bound: frozenset[str] = frozenset()) -> Any:
        from lark import Tree  # lazy: with the parser
        kind = getattr(node, "data", None)
        if kind is None:
            return node
        ch = node.children
        if kind == "name" and str(ch[0]) in self.fields and str(ch[0]) not in bound:
            return Tree("state", [ch[0]])
        if kind == "conj":
            parts = [self.expr(c, bound) for c in ch]
            out = parts[-1]
            for p in reversed(parts[:-1]):
                out = Tree("conj_u", [p, out])
            return out
        if kind == "apply":
            return Tree("apply", [ch[0], *(self.expr(c, bound) for c in ch[1:])])
        return Tree(kind, [self.expr(c, bound) for c in ch])

    def action(self, node: Any, bound: frozenset[str]) -> Any:
        from lark import Token, Tree  # lazy: with the parser
        kind = node.data
        ch = node.children
        if kind in ("skip", "stop", "call"):
            return node
        if kind == "call_args":
            name = str(ch[0])
            if name in self.waits and len(ch) == 2:
                return Tree("wait", [Token("IDENT", self.waits[name]), self.expr(ch[1], bound)])
            return Tree(kind, [ch[0], *(self.expr(c, bound) for c in ch[1:])])
        if kind == "prefix":
            event = ch[0]
            inner = bound
            if event.data == "event_in":
                inner = bound | {str(c) for c in event.children[1:]}
                new_event = event
            else:
                values = [self.expr(c, bound) for c in event.children[1:]]
                if len(values) > 1:  # c!(a, b): one value, a pair (c?(x, y) binds each)
                    values = [Tree("tuple", values)]
                new_event = Tree(event.data, [event.children[0], *values])
            return Tree("prefix", [new_event, self.action(ch[1], inner)])
        if kind in ("seq", "ext_choice", "interleave", "interrupt"):
            return Tree(kind, [self.action(c, bound) for c in ch])
        if kind == "cond":
            return Tree("cond", [self.action(ch[0], bound), self.expr(ch[1], bound),
                                 self.action(ch[2], bound)])
        if kind == "guard":
            return Tree("guard", [self.expr(ch[0], bound), self.action(ch[1], bound)])
        if kind == "mu":
            return Tree("mu", [ch[0], self.action(ch[1], bound)])
        if kind == "interrupt_cond":
            return Tree(kind, [self.action(ch[0], bound), self.expr(ch[1], bound)])
        if kind in ("assign_one", "assign"):
            return Tree(kind, [c if not hasattr(c, "data") else self.expr(c, bound)
                               for c in ch])
        if kind == "indexed_choice":
            # ``□ x ∈ UNIV. (p & A)`` in the utp dialect's form: p as an ``exists`` node of
            # its conjuncts (the executor solves them for x)
            var, typ, where, body = ch
            inner = bound | {str(var)}
            conjuncts = where.children if getattr(where, "data", "") == "conj" else [where]
            exists = Tree("exists", [self.expr(c, inner) for c in conjuncts])
            return Tree("indexed_choice", [var, typ, exists, self.action(body, inner)])
        if kind == "spec":
            return self._spec(node, bound)
        if kind == "evolution":
            odes = [Tree("ode", [c.children[0], self.expr(c.children[1], bound)])
                    for c in ch]
            return Tree("evolution", [Tree("odes", odes)])
        return node  # what the executor does not run: it reports it with its place

    def _spec(self, node: Any, bound: frozenset[str]) -> Any:
        from lark import Tree  # lazy: with the parser
        lens, pre, post = node.children
        frame = Tree("nameset", [c for c in lens.children if not hasattr(c, "data")])
        if getattr(post, "data", "") == "true":
            return Tree("choose", [frame])
        binders: list[Any] = []
        body = post
        if getattr(post, "data", "") == "exists":
            binders = [c for c in post.children if getattr(c, "data", "") == "binder"]
            rest = [c for c in post.children if getattr(c, "data", "") != "binder"]
            body = rest[0] if len(rest) == 1 else Tree("conj", rest)
        inner = bound | {str(b.children[0]) for b in binders}
        conjuncts = body.children if getattr(body, "data", "") == "conj" else [body]
        exists = Tree("exists", [*binders, *(self.expr(c, inner) for c in conjuncts)])
        return Tree("spec", [frame, self.expr(pre, bound), exists])


def read_ax_model(path: Path, text: str) -> TheoryModel:
    """The composition an axiomatic theory states, its terms in the executor's forms."""
    from cyphy.verify.theory.ax_types import read_theory  # lazy: lark loads with the theory
    th = read_theory(text)
    if th.errors:
        raise AnimateError("E-ANIMATE-READ", f"cannot read the theory's declarations: "
                           f"{th.errors[0]}", path=path, status=2)
    values: dict[str, Any] = {}
    for name, _typ, value in th.values:
        line = line_of(text, rf"^definition {re.escape(name)} ::")
        try:
            values[name] = evaluate_hol(_parse(value, "expr", path, line), values.__getitem__)
        except KeyError as err:
            raise AnimateError("E-ANIMATE-READ", f"{name}'s value names {err}, which is not "
                               "defined before it", path=path, line=line, status=2) from None
    open_constants = {name: line_of(text, rf"^\s*{re.escape(name)} ::")
                      for name in th.constants if name not in values
                      and declared(text, name, "real|nat|int|bool")}
    truths = {name for name in open_constants if declared(text, name, "bool")}
    wholes = {name: kind for name in open_constants for kind in ("int", "nat")
              if declared(text, name, kind)}
    axioms = [(_parse(ax, "expr", path, line_of(text, re.escape(ax))),
               line_of(text, re.escape(ax))) for ax in th.axioms]
    fields = {name for name in th.lenses}
    rewrite = _Rewrite(fields, {m.group(1): m.group(2) for m in _WAIT.finditer(text)})
    definitions: dict[str, Definition] = {}
    composition = None
    for name, params, _typ, body in th.definitions:
        line = line_of(text, rf"^definition {re.escape(name)} ::")
        tree = _parse(body, "action", path, line + 1)
        if tree.data == "hide" and tree.children[0].data == "parallel_cs":
            composition = (name, tree, line)
            continue
        definitions[name] = Definition(name, params,
                                       rewrite.action(tree, frozenset(params)), path, line)
    if composition is None:
        raise AnimateError("E-ANIMATE-OPAQUE", "the theory does not state the composition "
                           "(D [| ns1 | cs | ns2 |] P) \\ cs", path=path, status=1)
    name, tree, line = composition
    d_call, d_names, cs, p_names, p_call = tree.children[0].children
    sets = {m.group(1): {c.strip() for c in m.group(2).split(",")}
            for m in _CHANNEL_SET.finditer(text)}
    if str(cs) not in sets:
        raise AnimateError("E-ANIMATE-READ", f"the channel set {cs} is not defined",
                           path=path, line=line, status=2)
    types = {f: t for m in _ALPHABET.finditer(text)
             for f, t in re.findall(r"  (\w+) :: \"?([^\"\n]*)\"?", m.group(3))}
    processes = []
    for call, names in ((d_call, d_names), (p_call, p_names)):
        main = str(call.children[0]) if call.data == "call" else ""
        if main not in definitions:
            raise AnimateError("E-ANIMATE-READ", f"the composition runs {main or call.data}, "
                               "which is not a defined action", path=path, line=line, status=2)
        own = [str(c) for c in names.children]
        processes.append(Process(main, main, {f: types.get(f, "") for f in own}))
    return TheoryModel(path, definitions, values, open_constants, sets[str(cs)], processes,
                       name, axioms, dialect="axiomatic", truths=truths, wholes=wholes)
