"""Read the CyPhyCircus text form back into the AST (the grammar is ``text.lark``).

This is what makes the text a format rather than a picture: the tests print every program
the rules build and read it back into an equal AST, which catches brackets and precedence
the printer gets wrong. Spans are not kept (the AST's expressions compare without them).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, v_args

from cyphy import expr as ex
from cyphy.semantics.circus import ast as c

_OPS = {"⇔": "<=>", "⇒": "=>", "=": "==", "≠": "!=", "≤": "<=", "≥": ">=", "<": "<",
        ">": ">", "+": "+", "-": "-", "⁀": "cat", "*": "*", "/": "/", "mod": "%"}


@lru_cache(maxsize=1)
def _parser() -> Lark:
    grammar = (Path(__file__).parent / "text.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="earley", maybe_placeholders=True)


def read_program(text: str) -> c.Program:
    """The program a text printed by :func:`program_to_text` denotes."""
    return _Build().transform(_parser().parse(text))  # type: ignore[no-any-return]


def _flatten(e: ex.Expr, op: str) -> list[ex.Expr]:
    if isinstance(e, ex.BinOp) and e.op == op:
        return _flatten(e.left, op) + [e.right]
    return [e]


@v_args(inline=True)
class _Build(Transformer[Token, Any]):
    # ----- program
    def start(self, globals_: c.AxDef, *rest: Any) -> c.Program:
        channels = [r for r in rest if isinstance(r, tuple) and r and r[0] == "channel"]
        functions = tuple(r for r in rest if isinstance(r, c.FunctionDecl))
        opaque, process, system = rest[-3], rest[-2], rest[-1]
        decls: dict[str, list[c.ChannelVariant]] = {}
        for _, name, variant in channels:
            decls.setdefault(name, [])
            if variant is not None:
                decls[name].append(variant)
        chans = tuple(c.ChannelDecl(n, tuple(v)) for n, v in decls.items())
        tagged = {n for n, v in decls.items() if any(x.tag is not None for x in v)}
        process = _retag(process, tagged)
        if isinstance(opaque, c.BasicProcess):  # D written from the d-model's machine
            opaque = _retag(opaque, tagged)
        return c.Program(globals_, chans, opaque, process, system, functions)

    def globals(self, bindings: tuple[c.Binding, ...], conj: list[ex.Expr]) -> c.AxDef:
        return c.AxDef(bindings, tuple(conj))

    def bindings(self, *items: c.Binding) -> tuple[c.Binding, ...]:
        return items

    def binding(self, name: Token, t: c.Type) -> c.Binding:
        return c.Binding(str(name), t)

    def treal(self) -> c.Type:
        return c.REAL

    def tnat(self) -> c.Type:
        return c.NAT

    def tint(self) -> c.Type:
        return c.INT

    def tbool(self) -> c.Type:
        return c.BOOL

    def tname(self, name: Token) -> c.Type:
        return c.TBasic(str(name))

    def tseq(self, t: c.Type) -> c.Type:
        return c.TSeq(t)

    def tproduct(self, *items: c.Type) -> c.Type:
        return c.TProduct(items)

    def channel(self, name: Token, tag: Token | None, *types: c.Type | None
                ) -> tuple[Any, ...]:
        known = tuple(t for t in types if t is not None)
        if tag is None and not known:
            return ("channel", str(name), None)
        return ("channel", str(name), c.ChannelVariant(None if tag is None else str(tag),
                                                        known))

    def function(self, name: Token, arity: Token) -> c.FunctionDecl:
        return c.FunctionDecl(str(name), int(arity))

    def opaque(self, name: Token) -> c.OpaqueProcess:
        return c.OpaqueProcess(str(name))

    def process(self, name: Token, *rest: Any) -> c.BasicProcess:
        consts = tuple(r for r in rest if isinstance(r, c.Constant))
        schemas = [r for r in rest if isinstance(r, c.Schema)]
        actions = tuple(r for r in rest if isinstance(r, c.ActionDef))
        return c.BasicProcess(str(name), consts, schemas[0], schemas[1], actions, rest[-1])

    def const(self, name: Token, t: c.Type, value: ex.Expr | None) -> c.Constant:
        return c.Constant(str(name), t, value)

    def schema(self, name: Token, *fields: c.SchemaField | None) -> c.Schema:
        return c.Schema(str(name), tuple(f for f in fields if f is not None))

    def field(self, *items: Any) -> c.SchemaField:
        visible = len(items) == 3
        return c.SchemaField(str(items[-2]), items[-1], visible)

    def actiondef(self, name: Token, params: tuple[c.Binding, ...] | None, body: c.Action
                  ) -> c.ActionDef:
        return c.ActionDef(str(name), params or (), body)

    def system(self, name: Token, body: c.ProcessExpr) -> c.ProcessDef:
        return c.ProcessDef(str(name), body)

    def pref(self, name: Token) -> c.PRef:
        return c.PRef(str(name))

    def pparallel(self, left: c.ProcessExpr, cs: tuple[str, ...], right: c.ProcessExpr
                  ) -> c.PParallel:
        return c.PParallel(left, cs, right)

    def phide(self, p: c.ProcessExpr, cs: tuple[str, ...]) -> c.PHide:
        return c.PHide(p, cs)

    def chanset(self, *names: Token | None) -> tuple[str, ...]:
        return tuple(str(n) for n in names if n is not None)

    nameset = chanset

    # ----- actions
    def hide(self, a: c.Action, cs: tuple[str, ...]) -> c.Action:
        return c.Hide(a, cs)

    def interleave(self, *items: c.Action) -> c.Action:
        return c.Interleave(items)

    def parallel(self, left: c.Action, ns1: tuple[str, ...], cs: tuple[str, ...],
                 ns2: tuple[str, ...], right: c.Action) -> c.Action:
        return c.Parallel(left, ns1, cs, ns2, right)

    def extchoice(self, *items: c.Action) -> c.Action:
        return c.ExtChoice(items)

    def interrupt_(self, left: c.Action, right: c.Action) -> c.Action:
        return c.Interrupt(left, right)

    def interrupt_cond(self, a: c.Action, cond: c.Predicate) -> c.Action:
        return c.InterruptCond(a, cond)

    def seq(self, *items: c.Action) -> c.Action:
        return c.Seq(items)

    def prefix(self, comm: c.Comm, then: c.Action) -> c.Action:
        return c.Prefix(comm, then)

    def guard(self, cond: c.Predicate, a: c.Action) -> c.Action:
        return c.Guard(cond, a)

    def assign(self, names: tuple[str, ...], *values: ex.Expr) -> c.Action:
        return c.Assign(names, values)

    def cond(self, p: c.Predicate, then: c.Action, orelse: c.Action) -> c.Action:
        return c.Cond(p, then, orelse)

    def mu(self, name: Token, body: c.Action) -> c.Action:
        return c.Mu(str(name), body)

    def indexed_choice(self, var: Token, var2: Token, t: c.Type, where: c.Exists,
                       body: c.Action) -> c.Action:
        return c.IndexedExtChoice(c.Binding(str(var), t), where, body)

    def varblock(self, name: Token, t: c.Type, body: c.Action) -> c.Action:
        return c.VarBlock(c.Binding(str(name), t), body)

    def skip(self) -> c.Action:
        return c.Skip()

    def stop(self) -> c.Action:
        return c.Stop()

    def call(self, name: Token, *args: ex.Expr) -> c.Action:
        if str(name) == "Wait" and len(args) == 1:  # `Wait` is reserved in the text form
            return c.Wait(args[0])
        return c.Call(str(name), args)

    def spec(self, frame: tuple[str, ...] | None, pre: c.Predicate, post: c.Exists
             ) -> c.Action:
        frame = frame or ()
        names = set(frame)

        def unprime(node: ex.Expr) -> ex.Expr | None:
            if isinstance(node, ex.Derivative) and isinstance(node.operand, ex.Name) \
                    and node.operand.text in names:
                return node.operand
            return None

        post = c.Exists(post.bound, tuple(ex.transform(e, unprime) for e in post.body))
        return c.Spec(frame, pre, post)

    def evolution(self, state: Token, local: Token | None, conj: list[ex.Expr]) -> c.Action:
        return c.Evolution(str(state), None if local is None else str(local), tuple(conj))

    def names(self, *names: Token) -> tuple[str, ...]:
        return tuple(str(n) for n in names)

    def comm(self, channel: Token, *fields: c.Field) -> c.Comm:
        return c.Comm(str(channel), None, fields)

    def cin(self, name: Token) -> c.Field:
        return c.In(str(name))

    def cout(self, e: ex.Expr) -> c.Field:
        return c.Out(e)

    def cdot(self, e: ex.Expr) -> c.Field:
        return c.Dot(e)

    # ----- predicates
    def exists(self, bindings: tuple[c.Binding, ...], conj: list[ex.Expr]) -> c.Exists:
        return c.Exists(bindings, tuple(conj))

    def pred_ex(self, bindings: tuple[c.Binding, ...] | None, conj: list[ex.Expr]
                ) -> c.Exists:
        body = () if conj == [ex.Bool(True)] else tuple(conj)
        return c.Exists(bindings or (), body)

    def conj(self, *items: ex.Expr) -> list[ex.Expr]:
        return list(items)

    # ----- expressions
    def binop(self, left: ex.Expr, op: Token, right: ex.Expr) -> ex.Expr:
        return ex.BinOp(_OPS[str(op)], left, right)

    def or_(self, left: ex.Expr, right: ex.Expr) -> ex.Expr:
        return ex.BinOp("\\/", left, right)

    def and_(self, left: ex.Expr, right: ex.Expr) -> ex.Expr:
        return ex.BinOp("/\\", left, right)

    def not_(self, e: ex.Expr) -> ex.Expr:
        return ex.UnaryOp("not", e)

    def neg_(self, e: ex.Expr) -> ex.Expr:
        return ex.UnaryOp("-", e)

    def pow_(self, left: ex.Expr, right: ex.Expr) -> ex.Expr:
        return ex.BinOp("^", left, right)

    def derivative(self, e: ex.Expr) -> ex.Expr:
        return ex.Derivative(e)

    def apply(self, f: ex.Expr, *args: ex.Expr | None) -> ex.Expr:
        return ex.Call(f, tuple(a for a in args if a is not None))

    def index(self, base: ex.Expr, *args: ex.Expr) -> ex.Expr:
        return ex.Index(base, args)

    def member(self, base: ex.Expr, name: Token) -> ex.Expr:
        return ex.Member(base, str(name))

    def num(self, t: Token) -> ex.Expr:
        return ex.Num(str(t))

    def true(self) -> ex.Expr:
        return ex.Bool(True)

    def false(self) -> ex.Expr:
        return ex.Bool(False)

    def string(self, t: Token) -> ex.Expr:
        raw = str(t)[1:-1]
        return ex.Str(raw.replace('\\"', '"').replace("\\\\", "\\"))

    def name(self, t: Token) -> ex.Expr:
        return ex.Name((str(t),))

    def seqlit(self, *items: ex.Expr | None) -> ex.Expr:
        return ex.Seq(tuple(i for i in items if i is not None))

    def integral(self, operand: ex.Expr, *bounds: ex.Expr) -> ex.Expr:
        lower, upper = (bounds + (None, None))[:2]
        return ex.Integral(operand, lower, upper)

    def ifexpr(self, cond: ex.Expr, then: ex.Expr, orelse: ex.Expr) -> ex.Expr:
        return ex.IfExpr(cond, then, orelse)


def _retag(node: Any, tagged: set[str]) -> Any:
    """``registerRead.obstacle!true`` reads as a dot field; on a channel declared with
    tagged variants, the first dot field is the tag."""
    if isinstance(node, c.Comm):
        if node.channel in tagged and node.fields and isinstance(node.fields[0], c.Dot) \
                and isinstance(node.fields[0].value, ex.Name):
            return c.Comm(node.channel, node.fields[0].value.text, node.fields[1:])
        return node
    if isinstance(node, ex.Expr) or not hasattr(node, "__dataclass_fields__"):
        return node
    changes = {}
    for name in node.__dataclass_fields__:
        value = getattr(node, name)
        if isinstance(value, tuple):
            new = tuple(_retag(v, tagged) for v in value)
        else:
            new = _retag(value, tagged)
        if new != value:
            changes[name] = new
    return type(node)(**{**{n: getattr(node, n) for n in node.__dataclass_fields__},
                         **changes}) if changes else node
