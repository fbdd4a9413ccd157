"""CyPhyCircus actions and expressions as Isabelle/UTP terms (utp-main c9122f, ``UTP-Circus``).

One ``_print_<Node>`` method per action node and per expression node, found along the MRO as
in SymPy's printers; children are printed through :meth:`IsabellePrinter._print` only. The
output is ASCII: every symbol is written ``\\<name>``.

Every binary operator is printed inside its own parentheses, so no Isabelle precedence can
regroup what we print (and the round-trip reader of the tests needs no precedence either).
n-ary sequences, choices and interleavings print as right-nested binary operators.

Expressions print in one of three modes (``../shared/spec/isabelle.md`` section 1.1):

- ``hol``: a plain HOL term (constants, parameters and bound variables by name);
- ``uexpr``: a UTP expression over the state: ``&x`` for a state variable; every maximal
  subterm that mentions no state variable is lifted whole as ``\\<guillemotleft>…\\<guillemotright>``
  (integer literals stay bare, Booleans are the UTP ``true``/``false``);
- ``rel``: a relation between a state and its rate of change (the argument of ``EvolveC``):
  ``$x`` is the value, ``$x\\<acute>`` the time derivative.

A derivative is printed only as ``$x\\<acute>`` of a state variable inside an evolution, and
integrals become integrator states before printing; any other is refused (UnsupportedNode).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import field
from decimal import Decimal
from typing import Any, Iterator

from cyphy import expr as ex
from cyphy.backends.isabelle.names import RESERVED, IsabelleNames
from cyphy.records import record
from cyphy.semantics.circus.names import identifier
from cyphy.semantics.circus import ast as c

LIFT_OPEN, LIFT_CLOSE = "\\<guillemotleft>", "\\<guillemotright>"

#: HOL operators of the expression AST's binary operators.
HOL_BINOPS = {
    "+": "+", "-": "-", "*": "*", "/": "/", "%": "fmod", "cat": "@",
    "==": "=", "!=": "\\<noteq>", "<": "<", ">": ">", "<=": "\\<le>", ">=": "\\<ge>",
    "/\\": "\\<and>", "\\/": "\\<or>", "=>": "\\<longrightarrow>",
    "<=>": "\\<longleftrightarrow>",
}
#: UTP operators (state-dependent operands); the others go through ``bop``.
UTP_BINOPS = {
    "+": "+", "-": "-", "*": "*", "/": "/",
    "==": "=\\<^sub>u", "!=": "\\<noteq>\\<^sub>u", "<": "<\\<^sub>u", ">": ">\\<^sub>u",
    "<=": "\\<le>\\<^sub>u", ">=": "\\<ge>\\<^sub>u",
    "/\\": "\\<and>", "\\/": "\\<or>", "=>": "\\<Rightarrow>", "<=>": "\\<Leftrightarrow>",
}
#: Library functions that HOL has under a name of its own; the rest are declared ``consts``.
HOL_FUNCTIONS = {"sin": "sin", "cos": "cos", "tan": "tan", "sqrt": "sqrt", "exp": "exp",
                 "log": "ln", "abs": "abs", "arctan": "arctan", "atan": "arctan"}
#: Expression classes whose names action classes share: their printers are ``_print_<alias>``.
_ALIASES: dict[type, str] = {ex.Seq: "SeqExpr", ex.Call: "CallExpr"}
_LIFTERS = {1: "uop", 2: "bop", 3: "trop"}
_BASIC_TYPES = {"real": "real", "nat": "nat", "int": "int", "bool": "bool"}


def bound_identifier(name: str, globals_: set[str]) -> str:
    """The identifier of a bound name: free of reserved words and of every global name
    (``_b``, then ``_b2``, … appended), so no binder shadows a constant or a state field."""
    base = identifier(name)
    ident, n = base, 1
    while ident in RESERVED or ident in globals_:
        ident = f"{base}_b" if n == 1 else f"{base}_b{n}"
        n += 1
    return ident


class UnsupportedNode(Exception):
    """A node the Isabelle printer has no counterpart for; the message says which."""

    def __init__(self, node: object, why: str = "") -> None:
        super().__init__(f"Isabelle/UTP has no counterpart for {type(node).__name__}"
                         + (f": {why}" if why else ""))
        self.node = node


@record(frozen=False, slots=False)
class Symbols:
    """What a name means where the printer meets it: state variables, constants (``nat``
    and ``int`` ones need ``real`` and ``real_of_int`` in real arithmetic), actions,
    functions, the channel constructors, and the globals' Isabelle identifiers."""

    names: IsabelleNames
    state: frozenset[str] = frozenset()
    constants: frozenset[str] = frozenset()
    nat: frozenset[str] = frozenset()
    ints: frozenset[str] = frozenset()
    actions: frozenset[str] = frozenset()
    functions: dict[str, str] = field(default_factory=dict)
    constructors: dict[tuple[str, str | None], str] = field(default_factory=dict)
    given_sets: tuple[str, ...] = ()
    locals: tuple[c.Binding, ...] = ()  # the local schema: Evolve quantifies the used ones


class IsabellePrinter:
    """The 2020 Circus syntax of utp-main (``UTP-Circus``) plus our prelude's operators."""

    _default_settings: dict[str, Any] = {}
    #: Operator symbols that differ between dialects (a subclass sets its own).
    INTERLEAVE = "|||"
    GUARD = "&\\<^sub>C"
    CHOICE_DOT = " \\<bullet>"
    COND = ("\\<triangleleft>", "\\<triangleright>\\<^sub>R")
    INTERRUPT = "\\<triangle>\\<^sub>C"
    EXISTS = "\\<^bold>\\<exists>"
    TRUE = "true"
    ARROW = "\\<^bold>\\<rightarrow>"
    ASSIGN = ":=\\<^sub>C"

    def __init__(self, symbols: Symbols, **settings: Any) -> None:
        unknown = set(settings) - set(self._default_settings)
        if unknown:
            raise TypeError(f"unknown settings: {', '.join(sorted(unknown))}")
        self.settings = {**self._default_settings, **settings}
        self.symbols = symbols
        self._mode = "hol"
        self._coerce_nat = False
        self._bound: list[dict[str, str]] = [{}]
        #: Parameters of type int or nat (name -> type) of the definition being printed.
        self._whole_params: dict[str, str] = {}
        self._free_memo: dict[tuple[int, int], bool] = {}
        self._memo_keep: list[object] = []

    # ------------------------------------------------------------------ dispatch

    def doprint(self, node: object, mode: str = "hol") -> str:
        with self._in_mode(mode):
            return self._print(node)

    def _print(self, node: object) -> str:
        if isinstance(node, ex.Expr) and self._mode != "hol" and self._state_free(node):
            return self._lifted(node)
        for cls in type(node).__mro__:
            method = getattr(self, "_print_" + _ALIASES.get(cls, cls.__name__), None)
            if method is not None:
                return method(node)
        return self.emptyPrinter(node)

    def emptyPrinter(self, node: object) -> str:
        raise UnsupportedNode(node)

    @contextmanager
    def _in_mode(self, mode: str, coerce_nat: bool | None = None) -> Iterator[None]:
        saved = self._mode, self._coerce_nat
        self._mode = mode
        if coerce_nat is not None:
            self._coerce_nat = coerce_nat
        try:
            yield
        finally:
            self._mode, self._coerce_nat = saved

    # ------------------------------------------------------------------ names and scopes

    @contextmanager
    def whole_params(self, params: dict[str, str]) -> Iterator[None]:
        """Print with these parameters (name -> ``int`` or ``nat``) embedded in the reals
        where an action uses them (a call's effect on the p-model's real state)."""
        saved, self._whole_params = self._whole_params, dict(params)
        try:
            yield
        finally:
            self._whole_params = saved

    @contextmanager
    def binding(self, names: tuple[str, ...] | list[str]) -> Iterator[list[str]]:
        """Bind names (parameters, inputs, quantified and recursion variables) for the
        printing of a subterm; each gets an identifier free of every global one."""
        scope = dict(self._bound[-1])
        self._memo_keep.append(scope)  # its id keys the memo of _state_free
        idents = []
        globals_ = self._globals()
        for name in names:
            ident = bound_identifier(name, globals_)
            scope[name] = ident
            idents.append(ident)
        self._bound.append(scope)
        try:
            yield idents
        finally:
            self._bound.pop()

    def _globals(self) -> set[str]:
        """The identifiers a bound name must not take (it would shadow them)."""
        return self.symbols.names.identifiers()

    def _bound_ident(self, name: str) -> str | None:
        return self._bound[-1].get(name)

    def _is_state(self, name: str) -> bool:
        return name in self.symbols.state and self._bound_ident(name) is None

    def _state_free(self, e: ex.Expr) -> bool:
        """Whether ``e`` mentions no state variable (memoised per node and scope: the
        printer asks it of every subterm, and evolutions are large)."""
        key = (id(e), id(self._bound[-1]))
        found = self._free_memo.get(key)
        if found is None:
            if isinstance(e, ex.Name):
                found = not self._is_state(e.text)
            else:
                found = all(self._state_free(ch) for ch in e.children())
            self._free_memo[key] = found
            self._memo_keep.append(e)  # keeps the id valid while the memo lives
        return found

    def name(self, text: str) -> str:
        """The identifier of a bound or global name; unknown names are refused (a free
        variable in a definition is an Isabelle error)."""
        bound = self._bound_ident(text)
        if bound is not None:
            return bound
        ident = self.symbols.names.get(text)
        if ident is None:
            raise UnsupportedNode(ex.Name((text,)), f"'{text}' is not declared")
        return ident

    # ------------------------------------------------------------------ expressions

    def _lifted(self, e: ex.Expr) -> str:
        if isinstance(e, ex.Num) and e.is_integer:
            return e.text
        if isinstance(e, ex.Bool):
            return "true" if e.value else "false"
        with self._in_mode("hol"):
            return LIFT_OPEN + self._print(e) + LIFT_CLOSE

    def _print_Num(self, e: ex.Num) -> str:
        text = e.text
        if "e" in text.lower():  # HOL has no exponent notation
            text = format(Decimal(text), "f")
        return text

    def _print_Bool(self, e: ex.Bool) -> str:
        return "True" if e.value else "False"

    def _print_Name(self, e: ex.Name) -> str:
        text = e.text
        if self._mode != "hol" and self._is_state(text):
            return ("$" if self._mode == "rel" else "&") + self.symbols.names[text]
        ident = self.name(text)
        if self._coerce_nat and self._bound_ident(text) is None:
            # HOL has no implicit coercion into the reals (Real.thy: real = of_nat,
            # real_of_int = of_int)
            if text in self.symbols.nat:
                return f"(real {ident})"
            if text in self.symbols.ints:
                return f"(real_of_int {ident})"
        whole = self._whole_params.get(text)
        if self._coerce_nat and whole is not None and self._bound_ident(text) is not None:
            # an int or nat parameter of a call in the p-model's real arithmetic: HOL has no
            # implicit coercion (Real.thy: real = of_nat, real_of_int = of_int)
            return f"({'real_of_int' if whole == 'int' else 'real'} {ident})"
        return ident

    def _print_BinOp(self, e: ex.BinOp) -> str:
        left, right = self._print(e.left), self._print(e.right)
        if e.op == "^":
            # HOL's ^ takes a nat exponent (Power.thy); any other is powr (Transcendental.thy)
            if isinstance(e.right, ex.Num) and e.right.is_integer:
                return f"({left} ^ {right})"
            if self._mode == "hol":
                return f"({left} powr {right})"
            return f"(bop (powr) {left} {right})"
        if e.op == "%":  # HOL has no mod on real: the prelude's fmod
            if self._mode == "hol":
                return f"(fmod {left} {right})"
            return f"(bop fmod {left} {right})"
        table = HOL_BINOPS if self._mode == "hol" else UTP_BINOPS
        op = table.get(e.op)
        if op is None:
            hol = HOL_BINOPS.get(e.op)
            if hol is None:
                raise UnsupportedNode(e, f"operator {e.op}")
            return f"(bop ({hol}) {left} {right})"
        return f"({left} {op} {right})"

    def _print_UnaryOp(self, e: ex.UnaryOp) -> str:
        operand = self._print(e.operand)
        if e.op == "-":
            return f"(- {operand})"
        if e.op == "not":
            return f"(\\<not> {operand})"
        raise UnsupportedNode(e, f"operator {e.op}")

    def _print_CallExpr(self, e: ex.Call) -> str:
        if not isinstance(e.func, ex.Name) or e.func.text not in self.symbols.functions:
            raise UnsupportedNode(e, "only declared functions can be applied")
        func = self.symbols.functions[e.func.text]
        args = [self._print(a) for a in e.args]
        if self._mode == "hol":
            return f"({func} {' '.join(args)})"
        lifter = _LIFTERS.get(len(args))
        if lifter is None:
            raise UnsupportedNode(e, "a function of more than 3 arguments over the state")
        return f"({lifter} {func} {' '.join(args)})"

    def _print_Index(self, e: ex.Index) -> str:
        """A component of a vector or matrix constant (the scalarisation's ``A[k]``): HOL's
        ``nth``, ``(A ! k)``, counted from 0."""
        if self._mode != "hol" or not all(isinstance(a, ex.Num) and a.is_integer
                                           for a in e.args):
            raise UnsupportedNode(e, "an index into a vector of the state")
        out = self._print(e.base)
        for a in e.args:
            out = f"({out} ! {a.text})"
        return out

    def _print_Derivative(self, e: ex.Derivative) -> str:
        operand = e.operand
        if isinstance(operand, ex.Name) and self._mode == "rel" and self._is_state(operand.text):
            return f"${self.symbols.names[operand.text]}\\<acute>"
        raise UnsupportedNode(e, "a derivative outside an evolution's equations")

    def _print_Integral(self, e: ex.Integral) -> str:
        # the scalar process turns each integral of an evolution into an integrator state
        # (cyphy.semantics.scalarise); one left here has no Isabelle meaning
        raise UnsupportedNode(e, "an integral outside an evolution's equations")

    def _print_SeqExpr(self, e: ex.Seq) -> str:
        """A HOL list; over the state, consed with ``bop Cons`` (utp-main's explicit syntax
        has no list display for UTP expressions: only the easy parser's)."""
        items = [self._print(i) for i in e.items]
        if self._mode == "hol":
            return f"[{', '.join(items)}]"
        out = LIFT_OPEN + "[]" + LIFT_CLOSE
        for item in reversed(items):
            out = f"(bop Cons {item} {out})"
        return out

    # ------------------------------------------------------------------ predicates

    def _print_Exists(self, p: c.Exists) -> str:
        """``(\\<^bold>\\<exists> x::T \\<bullet> … P1 \\<and> … \\<and> Pn)``: the whole
        predicate in one pair of parentheses, the conjuncts flat inside."""
        with self.binding([b.name for b in p.bound]) as idents:
            sep = "\n      " if len(p.bound) > 2 else ""
            binders = "".join(f"{self.EXISTS} {i}::{self.type(b.type)}{self.CHOICE_DOT} {sep}"
                              for i, b in zip(idents, p.bound))
            joiner = " \\<and>\n      " if len(p.body) > 2 else " \\<and> "
            body = joiner.join(self._print(x) for x in p.body) or self.TRUE
        return f"({binders}{body})"

    # ------------------------------------------------------------------ types

    def type(self, t: c.Type) -> str:
        if isinstance(t, c.TBasic):
            basic = _BASIC_TYPES.get(t.name)
            return basic if basic is not None else self.symbols.names[t.name]
        if isinstance(t, c.TSeq):
            inner = self.type(t.of)
            return f"({inner} list)" if " " in inner else f"{inner} list"
        if isinstance(t, c.TProduct):
            return "(" + " \\<times> ".join(self.type(i) for i in t.items) + ")"
        raise UnsupportedNode(t)

    # ------------------------------------------------------------------ actions

    def action(self, a: c.Action) -> str:
        with self._in_mode("uexpr", coerce_nat=True):
            return self._print(a)

    def _print_Skip(self, a: c.Skip) -> str:
        return "Skip"

    def _print_Stop(self, a: c.Stop) -> str:
        return "Stop"

    def _constructor(self, comm: c.Comm) -> str:
        found = self.symbols.constructors.get((comm.channel, comm.tag))
        if found is None:
            raise UnsupportedNode(comm, f"channel {comm.channel}.{comm.tag} is not declared")
        return found

    def _print_Prefix(self, a: c.Prefix) -> str:
        comm = a.comm
        ctor = self._constructor(comm)
        inputs = [f.name for f in comm.fields if isinstance(f, c.In)]
        values = [f.value for f in comm.fields if not isinstance(f, c.In)]
        if inputs and values:
            raise UnsupportedNode(comm, "inputs and outputs in one communication")
        if inputs:
            with self.binding(inputs) as idents:
                event = self._input_event(ctor, idents)
                return f"({event} {self.ARROW} {self._print(a.then)})"
        if values:
            kinds = {type(f) for f in comm.fields}
            if len(kinds) != 1:
                raise UnsupportedNode(comm, "dots and outputs in one communication")
            event = self._output_event(ctor, kinds == {c.Out}, values)
        else:
            event = ctor
        return f"({event} {self.ARROW} {self._print(a.then)})"

    def _input_event(self, ctor: str, idents: list[str]) -> str:
        """``c?(x)?(y)``: one input per field."""
        return ctor + "".join(f"?({i})" for i in idents)

    def _output_event(self, ctor: str, output: bool, values: list[ex.Expr]) -> str:
        """``c!(e)`` (``c.(e)`` for dots); several values as one lifted tuple."""
        mark = "!" if output else "."
        printed = [self._print(v) for v in values]
        if len(printed) == 1:
            return f"{ctor}{mark}({printed[0]})"
        if all(self._state_free(v) for v in values):
            with self._in_mode("hol"):
                inner = ", ".join(self._print(v) for v in values)
            return f"{ctor}{mark}({LIFT_OPEN}({inner}){LIFT_CLOSE})"
        return f"{ctor}{mark}(({', '.join(printed)})\\<^sub>u)"

    def _chain(self, items: tuple[c.Action, ...], op: str) -> str:
        printed = [self._print(i) for i in items]
        out = printed[-1]
        for item in reversed(printed[:-1]):
            out = f"({item} {op} {out})"
        return out

    def _print_Seq(self, a: c.Seq) -> str:
        return self._chain(a.items, ";;")

    def _print_ExtChoice(self, a: c.ExtChoice) -> str:
        return self._chain(a.items, "\\<box>")

    def _print_Interleave(self, a: c.Interleave) -> str:
        return self._chain(a.items, self.INTERLEAVE)

    def _print_IndexedExtChoice(self, a: c.IndexedExtChoice) -> str:
        with self.binding([a.var.name]) as (ident,):
            where = self._print(a.where)
            body = self._print(a.body)
        universe = f"(UNIV :: {self.type(a.var.type)} set)"
        return f"(\\<box> {ident}\\<in>{universe}{self.CHOICE_DOT} ({where} {self.GUARD} {body}))"

    def _print_Parallel(self, a: c.Parallel) -> str:
        if a.channels:
            raise UnsupportedNode(a, "synchronisation on channels inside an action")
        left, right = self._print(a.left), self._print(a.right)
        return f"({left} \\<lbrakk>{self._namesets(a.left_names, a.right_names)}\\<rbrakk> {right})"

    def _namesets(self, left: tuple[str, ...], right: tuple[str, ...]) -> str:
        """The name sets of a parallel composition, between its brackets: there utp-main
        reads the ``salpha`` category (utp/utp_var.thy, lines 259-268 at c9122f14), whose
        forms are a variable ``x``, a composition ``(x;y)`` and the empty set ``\\<emptyset>``,
        not the ``{x}\\<^sub>v`` or ``0\\<^sub>L`` terms."""
        return f"{self._salpha(left)}\\<parallel>{self._salpha(right)}"

    def _salpha(self, names: tuple[str, ...]) -> str:
        if not names:
            return "\\<emptyset>"
        idents = [self.symbols.names[n] for n in names]
        return idents[0] if len(idents) == 1 else "(" + ";".join(idents) + ")"

    def _nameset(self, names: tuple[str, ...]) -> str:
        if not names:
            return "0\\<^sub>L"
        return "{" + ", ".join(self.symbols.names[n] for n in names) + "}\\<^sub>v"

    def _print_Cond(self, a: c.Cond) -> str:
        before, after = self.COND
        return (f"({self._print(a.then)} {before} {self._print(a.cond)} {after} "
                f"{self._print(a.orelse)})")

    def _print_Guard(self, a: c.Guard) -> str:
        return f"({self._print(a.cond)} {self.GUARD} {self._print(a.action)})"

    def _print_Mu(self, a: c.Mu) -> str:
        with self.binding([a.var]) as (ident,):
            return f"(MuC (\\<lambda> {ident}. {self._print(a.body)}))"

    def _print_Call(self, a: c.Call) -> str:
        bound = self._bound_ident(a.name)
        if bound is None and a.name not in self.symbols.actions:
            raise UnsupportedNode(a, f"action {a.name} is not defined")
        head = bound or self.symbols.names[a.name]
        if not a.args:
            return head
        args = []
        for arg in a.args:
            if not self._state_free(arg):
                raise UnsupportedNode(a, "an action argument that depends on the state")
            with self._in_mode("hol"):
                args.append(self._print(arg))
        return f"({head} {' '.join(args)})"

    def _print_Interrupt(self, a: c.Interrupt) -> str:
        return f"({self._print(a.left)} {self.INTERRUPT} {self._print(a.right)})"

    def _print_InterruptCond(self, a: c.InterruptCond) -> str:
        return f"(InterruptCondC {self._print(a.action)} {self._print(a.cond)})"

    def _print_Wait(self, a: c.Wait) -> str:
        with self._in_mode("hol", coerce_nat=False):
            count = self._print(a.count)
        tock = self.symbols.constructors.get(("tock", None), "tock")
        return f"(WaitC {tock} {count})"

    def _print_Assign(self, a: c.Assign) -> str:
        targets = [self.symbols.names[t] for t in a.targets]
        values = [self._print(v) for v in a.values]
        if len(targets) == 1:
            return f"({targets[0]} {self.ASSIGN} {values[0]})"
        return f"(({', '.join(targets)}) {self.ASSIGN} ({', '.join(values)}))"

    def _print_Spec(self, a: c.Spec) -> str:
        frame = self._nameset(a.frame)
        return f"({frame}:[{self._print(a.pre)}, {self._print(a.post)}]\\<^sub>C)"

    def _print_Evolution(self, a: c.Evolution) -> str:
        with self._in_mode("rel"):
            used = set()
            for e in a.equations:
                used |= {n.text for n in e.walk() if isinstance(n, ex.Name)}
            local = [b for b in self.symbols.locals if b.name in used]
            return f"(EvolveC {self._print(c.Exists(tuple(local), a.equations))})"
