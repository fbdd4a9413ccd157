"""The shared expression AST as SymPy expressions (symbolic evaluation, solving).

SymPy is imported by this module, so only the commands that need it import it. Decimal
literals become exact rationals (``0.025025`` stays 25025/1000000), so that solving does not
drift. With ``time_dependent`` names, variables become functions of the time symbol ``t``
and ``derivative(x)`` becomes ``Derivative(x(t), t)``: the form ``dsolve`` expects.
"""

from __future__ import annotations

from typing import Any, Callable

import sympy

from cyphy import expr as ex
from cyphy.model.evaluate import UNIT_FACTORS

T = sympy.Symbol("t", real=True)

_FUNCTIONS: dict[str, Callable[..., Any]] = {
    "sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "asin": sympy.asin,
    "acos": sympy.acos, "atan": sympy.atan, "atan2": sympy.atan2, "sqrt": sympy.sqrt,
    "exp": sympy.exp, "log": sympy.log, "abs": sympy.Abs, "sgn": sympy.sign,
    "transpose": lambda m: m.T, "inverse": lambda m: m.inv(), "det": lambda m: m.det(),
    "identity": lambda n: sympy.eye(int(n)),
    "skew": lambda v: _skew(v), "ad": lambda v: _ad(v),
}


def _skew(v: Any) -> Any:
    """``physmod::math::skew``: the matrix of ``v ×``."""
    return sympy.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _ad(v: Any) -> Any:
    """``physmod::math::ad``: ``[[skew(w), 0], [skew(v), skew(w)]]`` of the twist
    ``(w; v)`` (MR eq. 8.38), the velocity-product term's matrix."""
    w, u = _skew(v[:3]), _skew(v[3:])
    return sympy.Matrix(sympy.BlockMatrix([[w, sympy.zeros(3)], [u, w]]))
_COMPARISONS = {"==": sympy.Eq, "!=": sympy.Ne, "<": sympy.Lt, "<=": sympy.Le,
                ">": sympy.Gt, ">=": sympy.Ge}
_CONNECTIVES = {"/\\": sympy.And, "\\/": sympy.Or, "=>": sympy.Implies,
                "<=>": sympy.Equivalent}


class UnsupportedNode(Exception):
    """An expression SymPy has no counterpart for (sequences, records, field access)."""

    def __init__(self, node: ex.Expr) -> None:
        super().__init__(f"SymPy has no counterpart for {type(node).__name__}")
        self.node = node


class SympyPrinter:
    """``_print_<Node>`` per node class, found along the MRO (as SymPy's own printers)."""

    _default_settings: dict[str, Any] = {"time_dependent": frozenset(), "symbols": None}

    def __init__(self, **settings: Any) -> None:
        unknown = set(settings) - set(self._default_settings)
        if unknown:
            raise TypeError(f"unknown settings: {', '.join(sorted(unknown))}")
        self.settings = {**self._default_settings, **settings}
        self._symbols: dict[str, Any] = dict(self.settings["symbols"] or {})

    def doprint(self, e: ex.Expr) -> Any:
        return self._print(e)

    def _print(self, e: ex.Expr) -> Any:
        for cls in type(e).__mro__:
            method = getattr(self, "_print_" + cls.__name__, None)
            if method is not None:
                return method(e)
        raise UnsupportedNode(e)

    def symbol(self, name: str) -> Any:
        """The SymPy object for a variable: ``x`` or, if time-dependent, ``x(t)``."""
        if name not in self._symbols:
            if name in self.settings["time_dependent"]:
                self._symbols[name] = sympy.Function(name, real=True)(T)
            elif name == "t":
                self._symbols[name] = T
            else:
                self._symbols[name] = sympy.Symbol(name, real=True)
        return self._symbols[name]

    def _print_Num(self, e: ex.Num) -> Any:
        return sympy.Integer(e.text) if e.is_integer else sympy.Rational(e.text)

    def _print_Quantity(self, e: ex.Quantity) -> Any:
        factor = UNIT_FACTORS.get(e.unit)
        if factor is None:
            raise UnsupportedNode(e)
        exact = sympy.pi / 180 if e.unit.startswith("deg") else sympy.nsimplify(factor)
        return self._print(e.value) * exact

    def _print_Bool(self, e: ex.Bool) -> Any:
        return sympy.true if e.value else sympy.false

    def _print_Name(self, e: ex.Name) -> Any:
        return self.symbol("::".join(e.parts))

    def _print_UnaryOp(self, e: ex.UnaryOp) -> Any:
        operand = self._print(e.operand)
        return sympy.Not(operand) if e.op == "not" else -operand

    def _print_BinOp(self, e: ex.BinOp) -> Any:
        a, b = self._print(e.left), self._print(e.right)
        if e.op in _COMPARISONS:
            return _COMPARISONS[e.op](a, b, evaluate=False)
        if e.op in _CONNECTIVES:
            return _CONNECTIVES[e.op](a, b)
        if e.op == "+":
            return a + b
        if e.op == "-":
            return a - b
        if e.op == "*":
            return a * b
        if e.op == "/":
            return a / b
        if e.op == "%":
            return sympy.Mod(a, b)
        return a ** b  # ^ and `cat`, which RoboTool's models misuse as a power

    def _print_Call(self, e: ex.Call) -> Any:
        if not isinstance(e.func, ex.Name):
            raise UnsupportedNode(e)
        args = [self._print(a) for a in e.args]
        fn = _FUNCTIONS.get(e.func.text)
        if fn is not None:
            return fn(*args)
        return sympy.Function(e.func.text)(*args)  # uninterpreted (ScrewAxis, ind, …)

    def _print_Derivative(self, e: ex.Derivative) -> Any:
        return sympy.Derivative(self._print(e.operand), T)

    def _print_Integral(self, e: ex.Integral) -> Any:
        body = self._print(e.operand)
        if e.lower is not None and e.upper is not None:
            return sympy.Integral(body, (T, self._print(e.lower), self._print(e.upper)))
        tau = sympy.Symbol("tau", real=True)
        return sympy.Integral(body.subs(T, tau), (tau, 0, T))

    def _rows(self, rows: tuple[tuple[ex.Expr, ...], ...]) -> Any:
        values = [[self._print(x) for x in row] for row in rows]
        return sympy.Matrix(values[0]) if len(values) == 1 else sympy.Matrix(values)

    def _print_Vector(self, e: ex.Vector) -> Any:
        return self._rows(e.rows)

    def _print_Matrix(self, e: ex.Matrix) -> Any:
        return self._rows(e.rows)

    def _print_Index(self, e: ex.Index) -> Any:
        base = self._print(e.base)
        if isinstance(base, sympy.MatrixBase):
            indices = [int(self._print(a)) - 1 for a in e.args]  # RoboChart counts from 1
            return base[indices[0]] if len(indices) == 1 else base[indices[0], indices[1]]
        raise UnsupportedNode(e)

    def _print_IfExpr(self, e: ex.IfExpr) -> Any:
        return sympy.Piecewise((self._print(e.then), self._print(e.cond)),
                               (self._print(e.orelse), True))


def to_sympy(e: ex.Expr, **settings: Any) -> Any:
    return SympyPrinter(**settings).doprint(e)


#: SymPy functions back to the names of the expression AST's library functions.
_FUNCTION_NAMES = {sympy.sin: "sin", sympy.cos: "cos", sympy.tan: "tan", sympy.asin: "asin",
                   sympy.acos: "acos", sympy.atan: "atan", sympy.atan2: "atan2",
                   sympy.exp: "exp", sympy.log: "log", sympy.Abs: "abs", sympy.sign: "sgn"}


class NotAnExpression(Exception):
    """A SymPy value the expression AST has no counterpart for (matrices, relations…)."""


def to_expr(value: Any, decimals: bool = False) -> ex.Expr:
    """A scalar SymPy expression as the shared expression AST, so that every printer can
    print what SymPy computed (the explicit ODEs of :mod:`cyphy.semantics.dynamics.reduce`). Sums and
    products in SymPy's canonical order (deterministic), negative terms as subtraction, a
    product's negative powers as one division, square roots as ``sqrt``. Rationals are
    ``p / q``, or with ``decimals`` one decimal number (a product's rational coefficient
    too): Flow*'s ``poly ode`` has no division. Whether a target has a function or a power
    is its printer's question."""
    v = sympy.sympify(value)
    if isinstance(v, sympy.Integer):
        n = ex.Num(str(abs(int(v))))
        return ex.UnaryOp("-", n) if v < 0 else n
    if isinstance(v, sympy.Rational) and not decimals:
        frac = ex.BinOp("/", ex.Num(str(abs(v.p))), ex.Num(str(v.q)))
        return ex.UnaryOp("-", frac) if v < 0 else frac
    if isinstance(v, (sympy.Rational, sympy.Float)):
        text = repr(float(abs(v)))
        return ex.UnaryOp("-", ex.Num(text)) if v < 0 else ex.Num(text)
    if isinstance(v, sympy.Symbol):
        return ex.Name((v.name,))
    if isinstance(v, sympy.Add):
        terms = v.as_ordered_terms()
        out = to_expr(terms[0], decimals)
        for term in terms[1:]:
            if term.as_coeff_Mul()[0].is_negative:
                out = ex.BinOp("-", out, to_expr(-term, decimals))
            else:
                out = ex.BinOp("+", out, to_expr(term, decimals))
        return out
    if isinstance(v, sympy.Mul):
        coeff, rest = v.as_coeff_Mul()
        if coeff.is_negative:
            return ex.UnaryOp("-", to_expr(-v, decimals))
        if decimals and coeff != 1:  # the coefficient as one number, never a division
            return ex.BinOp("*", to_expr(coeff, decimals), to_expr(rest, decimals))
        numerator, denominator = [], []
        for factor in v.as_ordered_factors():
            if isinstance(factor, sympy.Rational) and not isinstance(factor, sympy.Integer):
                if factor.p != 1:
                    numerator.append(sympy.Integer(factor.p))
                denominator.append(sympy.Integer(factor.q))
            elif isinstance(factor, sympy.Pow) and factor.exp.is_negative:
                denominator.append(factor.base ** -factor.exp)
            else:
                numerator.append(factor)
        top = _product(numerator, decimals) if numerator else ex.Num("1")
        return ex.BinOp("/", top, _product(denominator, decimals)) if denominator else top
    if isinstance(v, sympy.Pow):
        if v.exp == sympy.Rational(1, 2):
            return ex.Call(ex.Name(("sqrt",)), (to_expr(v.base, decimals),))
        if v.exp.is_negative:
            return ex.BinOp("/", ex.Num("1"), to_expr(v.base ** -v.exp, decimals))
        return ex.BinOp("^", to_expr(v.base, decimals), to_expr(v.exp, decimals))
    if isinstance(v, sympy.Function):
        name = _FUNCTION_NAMES.get(v.func, getattr(v.func, "__name__", None))
        if isinstance(v, sympy.core.function.AppliedUndef) or v.func in _FUNCTION_NAMES:
            return ex.Call(ex.Name((str(name),)),
                           tuple(to_expr(a, decimals) for a in v.args))
    raise NotAnExpression(f"{v} ({type(v).__name__}) has no counterpart in the expressions")


def _product(factors: list[Any], decimals: bool) -> ex.Expr:
    out = to_expr(factors[0], decimals)
    for f in factors[1:]:
        out = ex.BinOp("*", out, to_expr(f, decimals))
    return out

