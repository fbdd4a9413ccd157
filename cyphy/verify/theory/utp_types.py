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
from cyphy.verify.theory.hm_types import (SYNONYMS, TCon, TVar, Type, TypeError_, constrain,
                                          fun, occurs, parse_type, prod_type, prune, show,
                                          uexpr, unify)
from cyphy.verify.theory.utp_signatures import H, INSTANCES, SIGNATURES, U

__all__ = ["H", "INSTANCES", "SIGNATURES", "SYNONYMS", "TCon", "TVar", "Type", "TypeError_",
           "U", "constrain", "fun", "occurs", "parse_type", "prod_type", "prune", "show",
           "uexpr", "unify"]



@lru_cache(maxsize=1)
def parser() -> Lark:
    """The grammar of the terms the utp printer writes (``utp_terms.lark``): the subset of
    Isabelle/UTP's inner syntax a generated theory uses."""
    return Lark.open(str(Path(__file__).with_name("utp_terms.lark")),
                     start=["action", "hol"], parser="lalr", strict=True)


#: Words an identifier of a theory must not be: the imported syntax's keywords.
KEYWORDS = frozenset(SYNTAX_WORDS) | frozenset(HOL_SYNTAX_WORDS) | OUTER_KEYWORDS


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


