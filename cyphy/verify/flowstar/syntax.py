"""Reading Flow* 2.1.0 model files with our grammar (``flowstar.lark``).

``cyphy reach`` re-reads the model it wrote before trusting a SAFE verdict (every mode is
listed under ``unsafe``, ``max jumps`` is large enough), and the tests parse every exported
model and interpret it. Expressions come back as the shared AST (:mod:`cyphy.expr`); an
interval constant ``[a, b]`` is the call ``interval(a, b)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedInput

from cyphy import expr as ex


class FlowstarSyntaxError(Exception):
    def __init__(self, message: str, line: int, column: int) -> None:
        super().__init__(f"line {line}, column {column}: {message}")
        self.line, self.column = line, column


@dataclass(frozen=True)
class Constraint:
    lhs: ex.Expr
    rel: str  # "<=", ">=", "=", "in"
    bounds: tuple[str, ...]  # one number or parameter name; two for "in"


@dataclass
class Mode:
    ode: str  # "poly ode 2", "nonpoly ode", …
    flow: dict[str, ex.Expr]
    invariant: list[Constraint]


@dataclass
class Jump:
    source: str
    target: str
    guard: list[Constraint]
    resets: dict[str, ex.Expr]


@dataclass
class FlowModel:
    kind: str  # "hybrid" or "continuous"
    variables: list[str]
    params: dict[str, str] = field(default_factory=dict)
    settings: dict[str, Any] = field(default_factory=dict)
    modes: dict[str, Mode] = field(default_factory=dict)
    jumps: list[Jump] = field(default_factory=list)
    initial_mode: str | None = None
    init: dict[str, tuple[str, str]] = field(default_factory=dict)
    unsafe: dict[str, list[Constraint]] | None = None  # mode → conjunction ("" continuous)


@lru_cache(maxsize=None)
def _parser() -> Lark:
    # The basic lexer (not the contextual one): like Flow*'s flex lexer, it reads a reserved
    # word as a keyword wherever it appears.
    return Lark.open_from_package("cyphy.verify.flowstar", "flowstar.lark", parser="lalr",
                                  lexer="basic")


def parse_model(text: str) -> FlowModel:
    """The model, or :class:`FlowstarSyntaxError` where Flow* would report a syntax error."""
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as err:
        line, column = getattr(err, "line", 0) or 0, getattr(err, "column", 0) or 0
        found = getattr(err, "token", None) or getattr(err, "char", None)
        raise FlowstarSyntaxError(f"syntax error at {found!r}" if found else "syntax error",
                                  line, column) from None
    return _ToModel().transform(tree)


def _text(tok: Token) -> str:
    return str(tok)


@v_args(inline=True)
class _ToModel(Transformer):
    # ---- expressions
    def num(self, tok: Token) -> ex.Expr:
        text = str(tok)
        return ex.UnaryOp("-", ex.Num(text[1:])) if text.startswith("-") else ex.Num(text)

    def var(self, tok: Token) -> ex.Expr:
        return ex.Name((str(tok),))

    def interval(self, lo: Token, hi: Token) -> ex.Expr:
        return ex.Call(ex.Name(("interval",)), (self.num(lo), self.num(hi)))

    def add(self, a: ex.Expr, b: ex.Expr) -> ex.Expr:
        return ex.BinOp("+", a, b)

    def sub(self, a: ex.Expr, b: ex.Expr) -> ex.Expr:
        return ex.BinOp("-", a, b)

    def mul(self, a: ex.Expr, b: ex.Expr) -> ex.Expr:
        return ex.BinOp("*", a, b)

    def div(self, a: ex.Expr, b: ex.Expr) -> ex.Expr:
        return ex.BinOp("/", a, b)

    def neg(self, a: ex.Expr) -> ex.Expr:
        return ex.UnaryOp("-", a)

    def pow(self, a: ex.Expr, tok: Token) -> ex.Expr:
        return ex.BinOp("^", a, self.num(tok))

    def call(self, name: Token, arg: ex.Expr) -> ex.Expr:
        return ex.Call(ex.Name((str(name),)), (arg,))

    # ---- constraints
    def _bound(self, b: Any) -> str:
        if isinstance(b, ex.Name):
            return b.text
        if isinstance(b, ex.UnaryOp):
            return "-" + b.operand.text  # type: ignore[attr-defined]
        return b.text

    def le(self, lhs: ex.Expr, b: Any) -> Constraint:
        return Constraint(lhs, "<=", (self._bound(b),))

    def ge(self, lhs: ex.Expr, b: Any) -> Constraint:
        return Constraint(lhs, ">=", (self._bound(b),))

    def eq(self, lhs: ex.Expr, b: Any) -> Constraint:
        return Constraint(lhs, "=", (self._bound(b),))

    def within(self, lhs: ex.Expr, lo: Token, hi: Token) -> Constraint:
        return Constraint(lhs, "in", (str(lo), str(hi)))

    def constraints(self, *items: Constraint) -> list[Constraint]:
        for c in items:
            if any(isinstance(n, ex.Call) for n in c.lhs.walk()):
                raise FlowstarSyntaxError("an interval constant in a constraint", 0, 0)
        return list(items)

    # ---- blocks
    def state_var(self, _kw: Token, *names: Token) -> list[str]:
        return [str(n) for n in names]

    def par_def(self, name: Token, value: Token) -> tuple[str, str]:
        return str(name), str(value)

    def par(self, *defs: tuple[str, str]) -> tuple[str, Any]:
        return "params", dict(defs)

    def fixed_steps(self, _kw: Token, h: Token) -> tuple[str, Any]:
        return "fixed steps", str(h)

    def adaptive_steps(self, _kw: Token, lo: Token, hi: Token) -> tuple[str, Any]:
        return "adaptive steps", (str(lo), str(hi))

    def time_(self, t: Token) -> tuple[str, Any]:
        return "time", str(t)

    def max_jumps(self, _kw: Token, n: Token) -> tuple[str, Any]:
        return "max jumps", int(str(n))

    def print_(self, tok: Token) -> tuple[str, Any]:
        return "print", str(tok)

    def settings(self, *items: Any) -> tuple[str, Any]:
        return "settings", {k: v for k, v in (i for i in items if isinstance(i, tuple))}

    def poly_eq(self, name: Token, rhs: ex.Expr) -> tuple[str, ex.Expr]:
        return str(name), rhs

    nonpoly_eq = poly_eq

    def ode(self, kind: Token, *eqs: tuple[str, ex.Expr]) -> tuple[str, Any]:
        return "ode", (" ".join(str(kind).split()), dict(eqs))

    def mode(self, name: Token, *rest: Any) -> tuple[str, Mode]:
        (_, ode), invariant = rest[-2], rest[-1]
        return str(name), Mode(ode[0], ode[1], invariant)

    def modes(self, *items: tuple[str, Mode]) -> tuple[str, Any]:
        return "modes", dict(items)

    def reset(self, name: Token, rhs: ex.Expr) -> tuple[str, ex.Expr]:
        return str(name), rhs

    def jump(self, src: Token, dst: Token, guard: list[Constraint], *rest: Any) -> Jump:
        resets = dict(r for r in rest if isinstance(r, tuple))
        return Jump(str(src), str(dst), guard, resets)

    def jumps(self, *items: Jump) -> tuple[str, Any]:
        return "jumps", list(items)

    def init_item(self, name: Token, interval: ex.Call) -> tuple[str, tuple[str, str]]:
        lo, hi = interval.args
        return str(name), (_number_text(lo), _number_text(hi))

    def init_hyb(self, mode: Token, *items: tuple[str, tuple[str, str]]) -> Any:
        return "init", (str(mode), dict(items))

    def init_cont(self, *items: tuple[str, tuple[str, str]]) -> Any:
        return "init", (None, dict(items))

    def unsafe_mode(self, name: Token, cons: list[Constraint]) -> tuple[str, list]:
        return str(name), cons

    def unsafe_hyb(self, *items: tuple[str, list]) -> tuple[str, Any]:
        out: dict[str, list[Constraint]] = {}
        for name, cons in items:
            out[name] = cons  # listed twice: the last entry wins (spec §4.9)
        return "unsafe", out

    def unsafe_cont(self, cons: list[Constraint]) -> tuple[str, Any]:
        return "unsafe", {"": cons}

    def _model(self, kind: str, items: tuple[Any, ...]) -> FlowModel:
        parts = dict(i for i in items[2:] if isinstance(i, tuple))
        m = FlowModel(kind, items[1], params=parts.get("params", {}))
        m.settings = dict(parts["settings"])
        if "max jumps" in parts:
            m.settings["max jumps"] = parts["max jumps"]
        if "ode" in parts:  # a continuous model: one anonymous mode
            m.modes = {"": Mode(parts["ode"][0], parts["ode"][1], [])}
        m.modes.update(parts.get("modes", {}))
        m.jumps = parts.get("jumps", [])
        m.initial_mode, m.init = parts["init"]
        m.unsafe = parts.get("unsafe")
        return m

    def hybrid(self, *items: Any) -> FlowModel:
        return self._model("hybrid", items)

    def continuous(self, *items: Any) -> FlowModel:
        return self._model("continuous", items)

    def start(self, model: FlowModel) -> FlowModel:
        return model


def _number_text(e: ex.Expr) -> str:
    if isinstance(e, ex.UnaryOp):
        return "-" + e.operand.text  # type: ignore[attr-defined]
    return e.text  # type: ignore[attr-defined]
