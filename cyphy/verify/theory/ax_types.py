"""A Hindley–Milner type checker for the axiomatic dialect's theories (``cyphy check-theory``).

The sibling of :mod:`cyphy.verify.theory.utp_types` for the theories of
``cyphy gen --isabelle --isabelle-dialect axiomatic``:
the same unifier with sorts, over :data:`AX_SIGNATURES`, the type of every constant, operator
and syntax translation the axiomatic printer emits, each read from the public source it cites:

- ``Ax`` = isabelle-utp/Ax_CyPhyCircus at 8bfbe4a (Ax_CyPhyCircus.thy: the axiomatised
  ``c…`` operators, lines 34-61, and their ``adhoc_overloading``, lines 64-84);
- ``CT`` = isabelle-utp/Circus_Toolkit at 97811b8 (IsaCircus_Syntax.thy: the generic Circus
  constants and mixfix, Channels_Events.thy: channel instantiation);
- ``APS`` = isabelle-utp/Abstract_Prog_Syntax at b97410d (``;;``, ``\\<lhd> \\<rhd>``, ``:=``);
- ``SE`` = isabelle-utp/Shallow-Expressions at 4ed4348 (``(e)\\<^sub>e``, svids, substitutions);
- ``OP`` = isabelle-utp/Optics at f48265c (lenses, prisms, ``chantype``, ``alphabet``);
- HOL's own constants from :data:`cyphy.verify.theory.utp_types.SIGNATURES`.

Ax_CyPhyCircus's parent session, ``CyPhyCircus_Toolkit``, is in no public repository (its ROOT
names it; no repository holds a session of that name). What only it defines is typed from a
public *use site* and marked ``use site``: the evolution ``[\\<Lambda> x` = e, …]``, the
conditional interrupt ``P \\<triangle>\\<^sub>p b`` and ``\\<mu> X. P`` (all written in
Ax_CyPhyCircus's examples/Ranger_CyPhyCircus.thy), with the constants they denote typed by the
``c…`` operators Ax_CyPhyCircus overloads them with. :data:`UNCHECKED` lists what the checker
assumes without any public source (the README repeats it).

Expressions inside an action are lifted over the state as Shallow-Expressions' ``(e)\\<^sub>e``
does under ``literal_variables`` (Ax_CyPhyCircus.thy:97): a state variable (a lens constant
``x :: 'a \\<Longrightarrow> 's``) stands for its value ``'a``; a parameter or bound variable is
a literal. Outside a lifted position (action arguments, channel instantiations ``c\\<^bold>.v``,
constant values) a state variable is the lens itself, so using it as a value is a type error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from lark import Lark, Token, Tree

from cyphy.verify.theory.ax_signatures import (AX_CONSTANTS, AX_INNER_KEYWORDS, AX_KEYWORDS,
                                               AX_SIGNATURES)
from cyphy.verify.theory.utp_types import (TCon, TVar, Type, TypeError_, constrain, fun,
                                           parse_type, prod_type, prune, unify)


@lru_cache(maxsize=1)
def parser() -> Lark:
    return Lark.open(str(Path(__file__).with_name("ax_terms.lark")),
                     start=["action", "expr"], parser="lalr")


def instance(name: str) -> Type:
    return parse_type(AX_SIGNATURES[name][0])


def _constrain(t: Type, cls: str) -> None:
    """``t`` in class ``cls`` (the classes of
    :data:`cyphy.verify.theory.utp_types.INSTANCES`), and known."""
    if isinstance(prune(t), TVar):
        raise TypeError_(f"the type is not determined where {cls} is needed")
    constrain(t, {cls})


# ----------------------------------------------------------------------------- the theory


@dataclass
class AxTheory:
    """The declarations of an axiomatic theory (its layout is ax_theory.thy.j2's)."""

    constants: dict[str, Type] = field(default_factory=dict)
    lenses: dict[str, Type] = field(default_factory=dict)
    state: Type | None = None
    channels: dict[str, Type] = field(default_factory=dict)
    values: list[tuple[str, Type, str]] = field(default_factory=list)
    axioms: list[str] = field(default_factory=list)
    definitions: list[tuple[str, list[str], Type, str]] = field(default_factory=list)
    identifiers: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    schemes: dict[str, str] = field(default_factory=dict)  # polymorphic: a fresh type per use


def _unquoted(text: str) -> str:
    return text[1:-1] if text.startswith('"') else text


def _t(text: str) -> Type:
    text = text[1:-1] if text.startswith('"') else text
    return parse_type(text.replace("\\<Longrightarrow>\\<^sub>\\<triangle>", "prism"))


_TYPE = r'("[^"]*"|\S+)'
_CONSTS = re.compile(r"^consts\n((?:  \w+ :: " + _TYPE + r"\n)+)", re.M)
_CONST_ONE = re.compile(r"^consts (\w+) :: " + _TYPE + "$", re.M)
_AXIOMS = re.compile(r'^axiomatization where\n((?:  \w+: ".*"(?: and)?\n)+)', re.M)
_DEF_VALUE = re.compile(r'^definition (\w+) :: ' + _TYPE + r' where "(\w+) = (.*)"$', re.M)
_DEF_FUN = re.compile(r'^definition (\w+) :: "([^"]*)" where\n  "(\w+)((?: \w+)*) = (.*?)"\n'
                      r'(?=\n|end)', re.S | re.M)
_CHANTYPE = re.compile(r"^chantype (\w+) =\n((?:  \w+ :: " + _TYPE + r"\n)+)", re.M)
_ALPHABET = re.compile(r"^alphabet (\w+) =(?: (\w+) \+)?\n((?:  \w+ :: " + _TYPE + r"\n)*)",
                       re.M)
_TYPEDECL = re.compile(r"^typedecl (\w+)$", re.M)
_PRIMREC = re.compile(r'^primrec (\w+) :: "nat \\<Rightarrow> ([^"]*)" where\n'
                      r'  "(\w+) 0 = Skip" \|\n'
                      r'  "(\w+) \(Suc n\) = \((\w+) \\<rightarrow> (\w+) n\)"',
                      re.M)
_FMOD = 'definition fmod :: "real \\<Rightarrow> real \\<Rightarrow> real" where'
_FMOD_BODY = "x - y * of_int \\<lfloor>x / y\\<rfloor>"


def read_theory(text: str) -> AxTheory:
    """The declarations of a generated axiomatic theory."""
    th = AxTheory()

    def declare(name: str) -> None:
        th.identifiers.append(name)

    for m in _TYPEDECL.finditer(text):
        declare(m.group(1))
    for m in _CONSTS.finditer(text):
        for name, typ in re.findall(r"  (\w+) :: " + _TYPE, m.group(1)):
            th.constants[name] = _t(typ)
            declare(name)
    for m in _CONST_ONE.finditer(text):
        th.constants[m.group(1)] = _t(m.group(2))
        declare(m.group(1))
    for m in _AXIOMS.finditer(text):
        th.axioms += re.findall(r'  \w+: "(.*)"', m.group(1))
    for m in _DEF_VALUE.finditer(text):
        name, typ, lhs, value = m.groups()
        if lhs != name:
            th.errors.append(f"definition {name} defines {lhs}")
        th.constants[name] = _t(typ)
        th.values.append((name, _t(typ), value))
        declare(name)
    if _FMOD in text:
        th.constants["fmod"] = parse_type("real \\<Rightarrow> real \\<Rightarrow> real")
        declare("fmod")
    for m in _CHANTYPE.finditer(text):
        chan = TCon(m.group(1))
        declare(m.group(1))
        for name, typ in re.findall(r"  (\w+) :: " + _TYPE, m.group(2)):
            # Optics Channel_Type.ML:130: each constructor is a prism into the channel type
            th.channels[name] = TCon("prism", (_t(typ), chan))
            declare(name)
    alphabets = list(_ALPHABET.finditer(text))
    if alphabets:
        # an alphabet's fields and its parents' are lenses into it (Optics
        # Lens_Instances.thy:5, alphabet; the parents' by their record scheme): a field is a
        # lens into the alphabet that extends its own last. The p-model's state is the first
        # alphabet's; the d-model process's, when stated, another (its actions' type says)
        extended_by = {m.group(2): m.group(1) for m in alphabets if m.group(2)}

        def final(name: str) -> str:
            while name in extended_by:
                name = extended_by[name]
            return name

        th.state = TCon(final(alphabets[0].group(1)))
        for m in alphabets:
            declare(m.group(1))
            for name, typ in re.findall(r"  (\w+) :: " + _TYPE, m.group(3)):
                th.lenses[name] = TCon("lens", (_t(typ), TCon(final(m.group(1)))))
                declare(name)
    for m in _PRIMREC.finditer(text):
        name, action, lhs0, lhs1, tock, rec = m.groups()
        if not lhs0 == lhs1 == rec == name:
            th.errors.append(f"primrec {name} defines {lhs0}, {lhs1} and recurs on {rec}")
        result = _t(action)
        th.schemes[name] = f"nat \\<Rightarrow> {_unquoted(action)}"  # 's: fresh per use
        declare(name)
        try:
            unify(th.channels.get(tock) or _undeclared(tock),
                  TCon("prism", (TCon("unit"), TVar())))
            unify(result, TCon("cyphyaction", (TVar(), TVar())))
        except TypeError_ as err:
            th.errors.append(f"primrec {name}: {err}")
    for m in _DEF_FUN.finditer(text):
        name, typ, lhs, params, body = m.groups()
        if name == "fmod":  # HOL's floor and of_int (Archimedean_Field.thy, Int.thy)
            if (lhs, params, body) != ("fmod", " x y", _FMOD_BODY):
                th.errors.append(f"fmod is not defined as {_FMOD_BODY}")
            continue
        if lhs != name:
            th.errors.append(f"definition {name} defines {lhs}")
        if body.startswith(_LBRACE) and body.endswith(_RBRACE) and not params:
            _channel_set(th, name, _t(typ), body[len(_LBRACE):-len(_RBRACE)])
            declare(name)
            continue
        th.definitions.append((name, params.split(), _t(typ), body))
        th.constants[name] = _t(typ)
        declare(name)
    return th


_LBRACE, _RBRACE = "\\<lbrace>", "\\<rbrace>"


def _channel_set(th: AxTheory, name: str, declared: Type, body: str) -> None:
    """``X = \\<lbrace>c1, …, cn\\<rbrace>``: ``csinsert c1 (… (csbasic cn))``, every
    event of each channel (Circus_Toolkit Channels_Events.thy:74-105), of the declared set
    type."""
    try:
        chans = [c.strip() for c in body.split(",")]
        result = instance("csbasic")
        unify(prune(result).args[0], th.channels.get(chans[-1]) or _undeclared(chans[-1]))
        result = prune(result).args[1]
        for chan in reversed(chans[:-1]):
            step = instance("csinsert")
            unify(step, fun(th.channels.get(chan) or _undeclared(chan), fun(result, TVar())))
            result = prune(step).args[1].args[1]
        unify(result, declared)
        th.constants[name] = declared
    except TypeError_ as err:
        th.errors.append(f"definition {name}: {err}")


def _undeclared(name: str) -> Type:
    raise TypeError_(f"'{name}' is not declared")


# ----------------------------------------------------------------------------- the checker


class AxChecker:
    """Infers types of parsed terms; ``state`` is the action's state type."""

    def __init__(self, theory: AxTheory, state: Type) -> None:
        self.theory = theory
        self.state = state

    def sig(self, name: str, *args: Type) -> Type:
        return self.apply(instance(name), *args)

    @staticmethod
    def apply(ftype: Type, *args: Type) -> Type:
        result = TVar()
        unify(ftype, fun(*args, result))
        return result

    # names
    def _check_word(self, name: str) -> None:
        if name in AX_INNER_KEYWORDS:
            raise TypeError_(f"'{name}' is a keyword of the imported syntax")

    def lens(self, name: str) -> Type:
        self._check_word(name)
        found = self.theory.lenses.get(name)
        if found is None:
            raise TypeError_(f"'{name}' is no variable of the state")
        return found

    def channel(self, name: str) -> Type:
        self._check_word(name)
        found = self.theory.channels.get(name)
        if found is None:
            raise TypeError_(f"'{name}' is no channel")
        return found

    def bind(self, env: dict[str, Type], name: str, t: Type) -> dict[str, Type]:
        if name in AX_INNER_KEYWORDS:
            raise TypeError_(f"the bound name '{name}' is a keyword of the imported syntax")
        return {**env, name: t}

    def name(self, name: str, env: dict[str, Type], lifted: bool) -> Type:
        self._check_word(name)
        if name in env:
            return env[name]
        if name in self.theory.lenses:
            lens = self.theory.lenses[name]
            if not lifted:
                return lens
            value = TVar()
            unify(lens, TCon("lens", (value, self.state)))
            return value
        if name in self.theory.channels:
            return self.theory.channels[name]
        if name in self.theory.constants:
            return self.theory.constants[name]
        if name in self.theory.schemes:
            return _t(self.theory.schemes[name])
        if name in AX_SIGNATURES and name.isidentifier():
            return instance(name)
        raise TypeError_(f"'{name}' is not declared")

    def quoted(self, node: Tree, env: dict[str, Type], value: Type | None = None) -> Type:
        """``(e)\\<^sub>e``: ``e`` lifted over the state, an ``'s ⇒ 'a``."""
        inner = self.expr(node, env, lifted=True)
        if value is not None:
            unify(inner, value)
        return self.sig("SEXP", fun(self.state, inner))

    # ---- actions
    def action(self, node: Tree | Token, env: dict[str, Type]) -> Type:
        if isinstance(node, Token):
            raise TypeError_(f"unexpected token {node!r}")
        method = getattr(self, "a_" + node.data, None)
        if method is None:
            raise TypeError_(f"no typing rule for the action {node.data}")
        return method(node.children, env)

    def a_skip(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("Skip")

    def a_stop(self, ch, env):  # type: ignore[no-untyped-def]
        return instance("Stop")

    def a_call(self, ch, env):  # type: ignore[no-untyped-def]
        return self.name(str(ch[0]), env, lifted=False)

    def a_call_args(self, ch, env):  # type: ignore[no-untyped-def]
        return self.apply(self.name(str(ch[0]), env, lifted=False),
                          *(self.expr(a, env, lifted=False) for a in ch[1:]))

    def _binary(self, sig: str, ch, env):  # type: ignore[no-untyped-def]
        return self.sig(sig, self.action(ch[0], env), self.action(ch[1], env))

    def a_seq(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary(";;", ch, env)

    def a_ext_choice(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("\\<box>", ch, env)

    def a_interleave(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("cParallel", instance("{}"), self.action(ch[0], env),
                        self.action(ch[1], env))

    def a_interrupt(self, ch, env):  # type: ignore[no-untyped-def]
        return self._binary("cInterrupt", ch, env)

    def a_cond(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("cCond", self.action(ch[0], env),
                        self.quoted(ch[1], env, TCon("bool")), self.action(ch[2], env))

    def a_guard(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("cGuard", self.quoted(ch[0], env, TCon("bool")),
                        self.action(ch[1], env))

    def a_interrupt_cond(self, ch, env):  # type: ignore[no-untyped-def]
        return self.sig("cInterruptCond", self.action(ch[0], env),
                        self.quoted(ch[1], env, TCon("bool")))

    def a_mu(self, ch, env):  # type: ignore[no-untyped-def]
        var = TVar()
        body = self.action(ch[1], self.bind(env, str(ch[0]), var))
        result = self.sig("\\<mu>", fun(var, body))
        _constrain(result, "complete_lattice")
        return result

    def _assign(self, lens: Type, value: Tree, env):  # type: ignore[no-untyped-def]
        update = self.sig("subst_upd", instance("subst_id"), lens, self.quoted(value, env))
        return self.sig("cAssigns", update)

    def a_assign_one(self, ch, env):  # type: ignore[no-untyped-def]
        return self._assign(self.lens(str(ch[0])), ch[1], env)

    def a_assign(self, ch, env):  # type: ignore[no-untyped-def]
        n = len(ch) // 2
        lens = self._pair([self.lens(str(t)) for t in ch[:n]])
        return self._assign(lens, Tree("tuple", list(ch[n:])), env)

    def _pair(self, lenses: list[Type]) -> Type:
        out = lenses[-1]
        for lens in reversed(lenses[:-1]):
            out = self.sig("var_pair", lens, out)
        return out

    def a_spec(self, ch, env):  # type: ignore[no-untyped-def]
        frame, pre, post = ch
        return self.sig("cSpec", self.lens_term(frame), self.quoted(pre, env, TCon("bool")),
                        self.quoted(post, env, TCon("bool")))

    def lens_term(self, node: Tree) -> Type:
        if node.data == "lens_zero":
            return instance("zero_lens")
        lenses = [self.lens(str(n)) for n in node.children]
        return self._pair(lenses)

    def a_evolution(self, ch, env):  # type: ignore[no-untyped-def]
        """``[\\<Lambda> x1` = e1, …]``: Evolve of the lenses x1, … with the substitution
        x_i ↦ e_i (each e_i of x_i's type, over the state) and the guard True; each x_i of
        a real_normed_vector type (cEvolve's sort, Ax_CyPhyCircus.thy:57)."""
        seen: set[str] = set()
        lenses = []
        for ode in ch:
            var, rhs = ode.children
            if str(var) in seen:
                raise TypeError_(f"{var} has two derivatives in one evolution")
            seen.add(str(var))
            lens = self.lens(str(var))
            value = TVar()
            unify(lens, TCon("lens", (value, self.state)))
            _constrain(value, "real_normed_vector")
            unify(self.expr(rhs, env, lifted=True), value)
            lenses.append(lens)
        subst = fun(self.state, self.state)
        return self.sig("cEvolve", self._pair(lenses), subst, fun(self.state, TCon("bool")))

    def a_indexed_choice(self, ch, env):  # type: ignore[no-untyped-def]
        ident, typ, where, body = ch
        var = self.type_of(typ)
        inner = self.bind(env, str(ident), var)
        branch = self.sig("cGuard", self.quoted(where, inner, TCon("bool")),
                          self.action(body, inner))
        universe = instance("UNIV")
        unify(universe, TCon("set", (var,)))
        return self.sig("cExtChoiceIdx", universe, fun(var, branch))

    def a_parallel(self, ch, env):  # type: ignore[no-untyped-def]
        left, ns1, ns2, right = ch
        return self.sig("cParallelAct", self.lens_term(ns1), self.lens_term(ns2),
                        instance("{}"), self.action(left, env), self.action(right, env))

    def a_parallel_cs(self, ch, env):  # type: ignore[no-untyped-def]
        left, ns1, cs, ns2, right = ch
        return self.sig("cParallelAct", self.lens_term(ns1), self.lens_term(ns2),
                        self.name(str(cs), env, lifted=False), self.action(left, env),
                        self.action(right, env))

    def a_hide(self, ch, env):  # type: ignore[no-untyped-def]
        body, cs = ch
        return self.sig("cHide", self.action(body, env), self.name(str(cs), env, lifted=False))

    def a_parallel_act(self, ch, env):  # type: ignore[no-untyped-def]
        ns1, ns2, left, right = ch
        return self.sig("cParallelAct", self.lens_term(ns1), self.lens_term(ns2),
                        instance("{}"), self.action(left, env), self.action(right, env))

    def a_prefix(self, ch, env):  # type: ignore[no-untyped-def]
        event, then = ch
        kind = event.data
        parts = event.children
        if kind == "event_plain":
            return self.sig("cSyncPrefix", self.channel(str(parts[0])), self.action(then, env))
        if kind == "event_dot":
            value = self._values(parts[1:], env, lifted=False)
            chan = self.sig("chinst1", self.channel(str(parts[0])), value)
            return self.sig("cSyncPrefix", chan, self.action(then, env))
        if kind == "event_out":
            value = self._values(parts[1:], env, lifted=True)
            return self.sig("cOutputPrefix", self.channel(str(parts[0])),
                            self.sig("SEXP", fun(self.state, value)), self.action(then, env))
        # input: \<lambda> pattern. ((True)\<^sub>e, P) over UNIV (IsaCircus_Syntax.thy:90)
        names = [str(n) for n in parts[1:]]
        types = [TVar() for _ in names]
        inner = env
        for n, t in zip(names, types):
            inner = self.bind(inner, n, t)
        payload = prod_type(types)
        guard = self.sig("SEXP", fun(self.state, TCon("bool")))
        body = TCon("prod", (guard, self.action(then, inner)))
        universe = instance("UNIV")
        return self.sig("cInputPrefix", self.channel(str(parts[0])), universe,
                        fun(payload, body))

    def _values(self, nodes, env, lifted: bool) -> Type:  # type: ignore[no-untyped-def]
        if len(nodes) == 1:
            return self.expr(nodes[0], env, lifted)
        return self.expr(Tree("tuple", list(nodes)), env, lifted)

    # ---- types
    def type_of(self, node: Tree | Token) -> Type:
        if isinstance(node, Token):
            return parse_type(str(node))
        if node.data == "type_basic":
            return parse_type(str(node.children[0]))
        if node.data == "type_list":
            return TCon("list", (self.type_of(node.children[0]),))
        items = [self.type_of(c) for c in node.children]
        return prod_type(items)

    # ---- HOL terms
    def expr(self, node: Tree | Token, env: dict[str, Type], lifted: bool) -> Type:
        if isinstance(node, Token):
            raise TypeError_(f"unexpected token {node!r}")
        method = getattr(self, "e_" + node.data, None)
        if method is None:
            raise TypeError_(f"no typing rule for the term {node.data}")
        return method(node.children, env, lifted)

    def e_name(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return self.name(str(ch[0]), env, lifted)

    def e_number(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        # a decimal is numeral / 10^n (HOL/Rat.thy:1158-1173): numeral and inverse
        return TVar({"numeral", "inverse"} if "." in str(ch[0]) else {"numeral"})

    def e_true(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return TCon("bool")

    e_false = e_true

    def e_binop(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        op = str(ch[1])
        return self.sig(op, self.expr(ch[0], env, lifted), self.expr(ch[2], env, lifted))

    def e_conj(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        for c in ch:
            unify(self.expr(c, env, lifted), TCon("bool"))
        return TCon("bool")

    def e_exists(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        inner = env
        for c in ch:
            if isinstance(c, Tree) and c.data == "binder":
                inner = self.bind(inner, str(c.children[0]), self.type_of(c.children[1]))
                self.sig("Ex", fun(inner[str(c.children[0])], TCon("bool")))
            else:
                unify(self.expr(c, inner, lifted), TCon("bool"))
        return TCon("bool")

    def e_neg(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return self.sig("uminus", self.expr(ch[0], env, lifted))

    def e_not_(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return self.sig("\\<not>", self.expr(ch[0], env, lifted))

    def e_apply(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return self.apply(self.name(str(ch[0]), env, lifted=False),
                          *(self.expr(a, env, lifted) for a in ch[1:]))

    def e_index(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        return self.sig("!", self.expr(ch[0], env, lifted), TCon("nat"))

    def e_sequence(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        item = TVar()
        for c in ch:
            if c is not None:
                unify(item, self.expr(c, env, lifted))
        return TCon("list", (item,))

    def e_tuple(self, ch, env, lifted):  # type: ignore[no-untyped-def]
        items = [self.expr(c, env, lifted) for c in ch]
        return prod_type(items)


def check_ax_theory(text: str) -> list[str]:
    """Every type error of a generated axiomatic theory (empty: it type-checks)."""
    try:
        theory = read_theory(text)
    except TypeError_ as err:
        return [f"declarations: {err}"]
    errors = list(theory.errors)
    for ident in theory.identifiers:
        if ident in AX_KEYWORDS:
            errors.append(f"'{ident}' is a keyword of the imported syntax")
        elif ident in AX_CONSTANTS:
            errors.append(f"'{ident}' shadows a constant of the imported sessions")
    if theory.state is None:
        return errors + ["the theory declares no state (alphabet)"]
    checker = AxChecker(theory, theory.state)
    for axiom in theory.axioms:
        try:
            tree = parser().parse(axiom, start="expr")
            unify(checker.expr(tree, {}, lifted=False), TCon("bool"))
        except Exception as err:  # TypeError_ and lark's errors
            errors.append(f"axiom {axiom}: {err}")
    for name, typ, value in theory.values:
        try:
            tree = parser().parse(value, start="expr")
            unify(checker.expr(tree, {}, lifted=False), typ)
        except Exception as err:
            errors.append(f"definition {name}: {err}")
    for name, params, declared, body in theory.definitions:
        try:
            env: dict[str, Type] = {}
            result = declared
            for p in params:
                result = prune(result)
                if not (isinstance(result, TCon) and result.name == "fun"):
                    raise TypeError_("more parameters than the type has")
                env = checker.bind(env, p, result.args[0])
                result = result.args[1]
            state = prune(result).args[1] if isinstance(prune(result), TCon) \
                and prune(result).name == "cyphyaction" else theory.state
            unify(result, TCon("cyphyaction", (TVar(), state)))
            tree = parser().parse(body, start="action")
            unify(AxChecker(theory, state).action(tree, env), result)
        except Exception as err:
            errors.append(f"definition {name}: {err}")
    return errors
