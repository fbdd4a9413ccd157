"""Reads the terms cyphy's Isabelle printer writes back into CyPhyCircus actions (tests only).

The grammar (``utp_terms.lark``) covers exactly the printed subset; the transformer
undoes the printer's choices: identifiers back to CyPhyCircus names (``_v`` / ``_b``
suffixes), lifted HOL subterms back to expressions, ``real`` coercions dropped, right-nested
binary chains flattened.
"""

from __future__ import annotations

import re

from lark import Transformer, v_args

from cyphy import expr as ex
from cyphy.backends.isabelle.terms import HOL_BINOPS, UTP_BINOPS, Symbols
from cyphy.backends.isabelle.names import RESERVED
from cyphy.semantics.circus import ast as c
from cyphy.verify.theory.utp_types import parser

_HOL_OPS = {v: k for k, v in HOL_BINOPS.items()} | {"powr": "^", "^": "^"}
_UTP_OPS = {v: k for k, v in UTP_BINOPS.items()} | {"^": "^"}
_BOUND_SUFFIX = re.compile(r"^(.+)_b\d*$")


class ReadError(Exception):
    pass


@v_args(inline=True)
class ToCircus(Transformer):
    """Parse tree → CyPhyCircus AST, given the symbols the printer used."""

    def __init__(self, symbols: Symbols, state_schema: str, local_schema: str | None) -> None:
        super().__init__()
        self.symbols = symbols
        self.globals = symbols.names.inverse()
        self.constructors = {v: k for k, v in symbols.constructors.items()}
        self.functions = {v: k for k, v in symbols.functions.items()}
        self.state_schema, self.local_schema = state_schema, local_schema

    # names
    def _name(self, ident: str) -> str:
        if ident in self.globals:
            return self.globals[ident]
        m = _BOUND_SUFFIX.match(ident)
        if m and (m.group(1) in RESERVED or m.group(1) in self.globals.values()
                  or m.group(1) in self.globals):
            return m.group(1)
        return ident

    # actions
    def skip(self) -> c.Action:
        return c.Skip()

    def stop(self) -> c.Action:
        return c.Stop()

    def call(self, ident) -> c.Action:
        return c.Call(self._name(str(ident)))

    def call_args(self, ident, *args) -> c.Action:
        return c.Call(self._name(str(ident)), tuple(args))

    def prefix(self, comm, then) -> c.Action:
        return c.Prefix(comm, then)

    def _comm(self, ident, fields) -> c.Comm:
        channel, tag = self.constructors[str(ident)]
        return c.Comm(channel, tag, tuple(fields))

    def event_plain(self, ident) -> c.Comm:
        return self._comm(ident, ())

    def event_in(self, ident, *names) -> c.Comm:
        return self._comm(ident, [c.In(self._name(str(n))) for n in names])

    def _values(self, value) -> list[ex.Expr]:
        return list(value) if isinstance(value, tuple) else [value]

    def event_out(self, ident, value) -> c.Comm:
        return self._comm(ident, [c.Out(v) for v in self._values(value)])

    def event_dot(self, ident, value) -> c.Comm:
        return self._comm(ident, [c.Dot(v) for v in self._values(value)])

    def _flatten(self, cls, left, right):
        items = right.items if isinstance(right, cls) else (right,)
        return cls((left, *items))

    def seq(self, left, right) -> c.Action:
        return self._flatten(c.Seq, left, right)

    def ext_choice(self, left, right) -> c.Action:
        return self._flatten(c.ExtChoice, left, right)

    def interleave(self, left, right) -> c.Action:
        return self._flatten(c.Interleave, left, right)

    def cond(self, then, pred, orelse) -> c.Action:
        return c.Cond(pred, then, orelse)

    def guard(self, pred, action) -> c.Action:
        return c.Guard(pred, action)

    def mu(self, ident, body) -> c.Action:
        return c.Mu(self._name(str(ident)), body)

    def interrupt(self, left, right) -> c.Action:
        return c.Interrupt(left, right)

    def interrupt_cond(self, action, pred) -> c.Action:
        return c.InterruptCond(action, pred)

    def wait(self, tock, count) -> c.Action:
        return c.Wait(count)

    def assign_one(self, ident, value) -> c.Action:
        return c.Assign((self._name(str(ident)),), (value,))

    def assign(self, *items) -> c.Action:
        n = len(items) // 2
        return c.Assign(tuple(self._name(str(i)) for i in items[:n]), tuple(items[n:]))

    def spec(self, frame, pre, post) -> c.Action:
        return c.Spec(frame, pre, post)

    def evolution(self, pred: c.Exists) -> c.Action:
        return c.Evolution(self.state_schema, self.local_schema, pred.body)

    def indexed_choice(self, ident, typ, where, body) -> c.Action:
        return c.IndexedExtChoice(c.Binding(self._name(str(ident)), typ), where, body)

    def parallel(self, left, ns1, ns2, right) -> c.Action:
        return c.Parallel(left, ns1, (), ns2, right)

    def nameset_empty(self) -> tuple[str, ...]:
        return ()

    def nameset(self, *idents) -> tuple[str, ...]:
        return tuple(self._name(str(i)) for i in idents)

    def exists(self, *items) -> c.Exists:
        bound = tuple(i for i in items if isinstance(i, c.Binding))
        body = tuple(i for i in items if not isinstance(i, c.Binding))
        if body == (ex.Bool(True),):  # the printer's text for the empty conjunction
            body = ()
        return c.Exists(bound, body)

    def binder(self, ident, typ) -> c.Binding:
        return c.Binding(self._name(str(ident)), typ)

    # types
    def type_basic(self, ident) -> c.Type:
        name = str(ident)
        return c.TBasic(name if name in ("real", "nat", "int", "bool") else self._name(name))

    def type_list(self, of) -> c.Type:
        return c.TSeq(of)

    def type_product(self, *items) -> c.Type:
        return c.TProduct(tuple(items))

    # expressions (both modes)
    def state(self, ident) -> ex.Expr:
        return ex.Name((self._name(str(ident)),))

    state_in = state

    def state_derivative(self, ident) -> ex.Expr:
        return ex.Derivative(ex.Name((self._name(str(ident)),)))

    def lifted(self, hol) -> ex.Expr:
        return hol

    def number(self, token) -> ex.Expr:
        return ex.Num(str(token))

    def true(self) -> ex.Expr:
        return ex.Bool(True)

    def false(self) -> ex.Expr:
        return ex.Bool(False)

    utrue, ufalse = true, false

    def binop(self, left, op, right) -> ex.Expr:
        text = str(op.children[0]) if hasattr(op, "children") else str(op)
        table = _HOL_OPS if text in _HOL_OPS else _UTP_OPS
        return ex.BinOp(table[text], left, right)

    def conj_u(self, left, right) -> ex.Expr:
        return ex.BinOp("/\\", left, right)

    def holop(self, token):
        return str(token)

    def neg(self, operand) -> ex.Expr:
        return ex.UnaryOp("-", operand)

    def not_(self, operand) -> ex.Expr:
        return ex.UnaryOp("not", operand)

    def lifter(self, token) -> str:
        return str(token)

    def lifted_call(self, lifter, ident, *args) -> ex.Expr:
        return self.apply(ident, *args)

    def lifted_binop(self, lifter, op, left, right) -> ex.Expr:
        return ex.BinOp(_HOL_OPS[op], left, right)

    def cons(self, head, tail) -> ex.Expr:
        rest = tail.items if isinstance(tail, ex.Seq) else ()
        return ex.Seq((head, *rest))

    def index(self, base, k) -> ex.Expr:
        if isinstance(base, ex.Index):  # ((M ! i) ! j) is M[i, j]
            return ex.Index(base.base, (*base.args, ex.Num(str(k))))
        return ex.Index(base, (ex.Num(str(k)),))

    def fmod(self, left, right) -> ex.Expr:
        return ex.BinOp("%", left, right)

    def sequence(self, *items) -> ex.Expr:
        return ex.Seq(tuple(i for i in items if i is not None))

    def tuple(self, *items):
        return tuple(items)

    def name(self, ident) -> ex.Expr:
        return ex.Name((self._name(str(ident)),))

    def apply(self, ident, *args) -> ex.Expr:
        func = str(ident)
        if func == "real" and len(args) == 1:
            return args[0]
        return ex.Call(ex.Name((self.functions.get(func, func),)), tuple(args))


_DEFINITION = re.compile(
    r'^definition (\w+) :: "[^"]*" where\n  "(\w+(?: \w+)*) = (.*?)"\nlemma (\w+) \[closure\]: '
    r'"([^"]*) is NCSP"\n  by \(simp add: (\w+)_def closure[^)]*\)$', re.S | re.M)


def read_definitions(theory: str) -> list[tuple[str, list[str], str, str, str]]:
    """(name, parameters, body text, lemma name, lemma statement) per action definition."""
    out = []
    for m in _DEFINITION.finditer(theory):
        name, lhs, body, lemma, stated, cited = m.groups()
        lhs_parts = lhs.split()
        if lhs_parts[0] != name or cited != name:
            raise ReadError(f"definition {name} is malformed")
        out.append((name, lhs_parts[1:], body, lemma, stated))
    return out


def read_action(body: str, params: list[str], symbols: Symbols, state_schema: str,
                local_schema: str | None) -> c.Action:
    tree = parser().parse(body, start="action")
    return ToCircus(symbols, state_schema, local_schema).transform(tree)
