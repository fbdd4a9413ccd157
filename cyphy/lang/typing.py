"""Expression typing: condition S3 of ``wellformedness.md``.

A small, sound-where-it-speaks inference: every expression gets a kind (boolean, number,
string, vector/matrix with a shape when it is known, or unknown) and an operator applied to a
kind it cannot take is an S3 error. Unknown kinds (record fields, sequence elements, ports of
other blocks reached through ``.``) never produce errors, so the check does not guess.
"""

from __future__ import annotations

from enum import Enum
from typing import Callable

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report
from cyphy.lang import ast
from cyphy.records import record


class Kind(str, Enum):
    BOOL = "boolean"
    NUM = "number"
    STR = "string"
    ARRAY = "vector or matrix"
    ANY = "unknown"


@record
class Ty:
    kind: Kind
    shape: tuple[int, ...] | None = None  # (n,) for vectors, (rows, cols) for matrices

    def describe(self) -> str:
        if self.kind is Kind.ARRAY and self.shape is not None:
            if len(self.shape) == 1:
                return f"a {self.shape[0]}-vector"
            return f"a {self.shape[0]}x{self.shape[1]} matrix"
        return {Kind.BOOL: "a boolean", Kind.NUM: "a number", Kind.STR: "a string",
                Kind.ARRAY: "a vector or matrix", Kind.ANY: "a value"}[self.kind]


BOOL, NUM, STR, ANY = Ty(Kind.BOOL), Ty(Kind.NUM), Ty(Kind.STR), Ty(Kind.ANY)
ARITHMETIC = {"+", "-", "*", "/", "%", "^", "cat"}
ORDERING = {"<", "<=", ">", ">="}
EQUALITY = {"==", "!="}
CONNECTIVES = {"/\\", "\\/", "=>", "<=>"}

Lookup = Callable[[ex.Name], object | None]
"""What a name denotes (a VarDecl, Param, IndexDecl, FunctionDecl…), or None if unknown."""


def _literal_int(e: ex.Expr | None) -> int | None:
    return int(e.text) if isinstance(e, ex.Num) and e.is_integer else None


def type_of_declared(t: ast.TypeRef | None) -> Ty:
    if isinstance(t, ast.PrimitiveType):
        return {"boolean": BOOL, "string": STR}.get(t.name, NUM)
    if isinstance(t, ast.VectorType):
        n = _literal_int(t.size)
        return Ty(Kind.ARRAY, (n,) if n is not None else None)
    if isinstance(t, ast.MatrixType):
        r, c = _literal_int(t.rows), _literal_int(t.cols)
        # matrix(real, 0, 0) is the notation's "any size" in generated signatures
        known = r is not None and c is not None and r > 0 and c > 0
        return Ty(Kind.ARRAY, (r, c) if known else None)  # type: ignore[arg-type]
    return ANY


def same_shape(a: tuple[int, ...] | None, b: tuple[int, ...] | None) -> bool:
    """Unknown shapes agree with anything; an n-vector is an n×1 column."""
    if a is None or b is None:
        return True
    column = {(a[0],), (a[0], 1)} if len(a) == 1 or a[1:] == (1,) else {a}
    return b in column if len(column) > 1 else a == b


def _rows_shape(rows: tuple[tuple[ex.Expr, ...], ...]) -> tuple[int, ...] | None:
    if len(rows) == 1:
        return (len(rows[0]),)
    widths = {len(r) for r in rows}
    return (len(rows), widths.pop()) if len(widths) == 1 else None


class TypeChecker:
    """Infers kinds bottom-up and reports S3 where an operator meets a kind it cannot take."""

    def __init__(self, lookup: Lookup, report: Report) -> None:
        self.lookup = lookup
        self.report = report

    def error(self, node: ex.Expr, message: str, hint: str) -> None:
        self.report.report(codes.S3, message, getattr(node, "span"), hint)

    # ------------------------------------------------------------------ contexts
    def expect_predicate(self, e: ex.Expr, what: str) -> None:
        t = self.infer(e)
        if t.kind in (Kind.NUM, Kind.STR, Kind.ARRAY):
            self.error(e, f"{what} is {t.describe()}, not a predicate",
                       "write a comparison such as 'lhs == rhs'")

    def expect_number(self, e: ex.Expr, what: str) -> None:
        t = self.infer(e)
        if t.kind in (Kind.BOOL, Kind.STR, Kind.ARRAY):
            self.error(e, f"{what} must be a number, not {t.describe()}",
                       "give a numeric expression")

    def expect_declared(self, e: ex.Expr, declared: ast.TypeRef, name: str) -> None:
        want, got = type_of_declared(declared), self.infer(e)
        if Kind.ANY in (want.kind, got.kind):
            return
        if want.kind is not got.kind:
            self.error(e, f"'{name}' is declared {want.describe()} but its value is "
                       f"{got.describe()}", "make the value match the declared type")
        elif not same_shape(want.shape, got.shape):
            self.error(e, f"'{name}' is declared {want.describe()} but its value is "
                       f"{got.describe()}", "give as many entries as the declared size")

    def expect_assignable(self, target: ex.Expr, value: ex.Expr, what: str) -> None:
        """``target = value`` (or an argument passed for a parameter): a boolean where a
        number is held, or the reverse, is an error; unknown kinds pass."""
        self.expect_type(value, self.infer(target), what)

    def expect_type(self, e: ex.Expr, want: Ty, what: str) -> None:
        """``e`` where a value of type ``want`` is needed (an operation's argument)."""
        got = self.infer(e)
        if Kind.ANY in (want.kind, got.kind):
            return
        if want.kind is not got.kind or not same_shape(want.shape, got.shape):
            self.error(e, f"{what} is {want.describe()}, but it is given {got.describe()}",
                       "give a value of the declared type")

    # ------------------------------------------------------------------ inference
    def infer(self, e: ex.Expr) -> Ty:
        method = getattr(self, "_infer_" + type(e).__name__, None)
        return method(e) if method is not None else ANY

    def _infer_Num(self, e: ex.Num) -> Ty:
        return NUM

    def _infer_Quantity(self, e: ex.Quantity) -> Ty:
        self.expect_number(e.value, "a value with a unit")
        return NUM

    def _infer_Bool(self, e: ex.Bool) -> Ty:
        return BOOL

    def _infer_Str(self, e: ex.Str) -> Ty:
        return STR

    def _infer_Vector(self, e: ex.Vector) -> Ty:
        for row in e.rows:
            for item in row:
                self.infer(item)
        return Ty(Kind.ARRAY, _rows_shape(e.rows))

    _infer_Matrix = _infer_Vector  # type: ignore[assignment]

    def _infer_Name(self, e: ex.Name) -> Ty:
        decl = self.lookup(e)
        if isinstance(decl, (ast.VarDecl, ast.Param)):
            return type_of_declared(decl.type)
        if isinstance(decl, ast.IndexDecl):
            return NUM
        return ANY

    def _infer_IfExpr(self, e: ex.IfExpr) -> Ty:
        cond = self.infer(e.cond)
        if cond.kind in (Kind.NUM, Kind.STR, Kind.ARRAY):
            self.error(e.cond, f"the condition of 'if' is {cond.describe()}",
                       "write a boolean condition")
        a, b = self.infer(e.then), self.infer(e.orelse)
        return a if a == b else ANY

    def _infer_UnaryOp(self, e: ex.UnaryOp) -> Ty:
        t = self.infer(e.operand)
        if e.op == "not":
            if t.kind in (Kind.NUM, Kind.STR, Kind.ARRAY):
                self.error(e, f"'not' applied to {t.describe()}", "negate a boolean")
            return BOOL
        if t.kind in (Kind.BOOL, Kind.STR):
            self.error(e, f"'-' applied to {t.describe()}", "negate a number")
            return NUM
        return t

    def _infer_BinOp(self, e: ex.BinOp) -> Ty:
        left, right = self.infer(e.left), self.infer(e.right)
        if e.op in CONNECTIVES:
            for side, t in ((e.left, left), (e.right, right)):
                if t.kind in (Kind.NUM, Kind.STR, Kind.ARRAY):
                    self.error(side, f"'{e.op}' needs booleans, but this is {t.describe()}",
                               "compare it first (for example 'x > 0')")
            return BOOL
        if e.op in EQUALITY:
            if {left.kind, right.kind} in ({Kind.BOOL, Kind.NUM}, {Kind.BOOL, Kind.ARRAY},
                                           {Kind.STR, Kind.NUM}):
                self.error(e, f"'{e.op}' compares {left.describe()} with {right.describe()}",
                           "compare values of the same type")
            elif not same_shape(left.shape, right.shape):
                transposed = (left.shape is not None and right.shape is not None
                              and len(left.shape) == len(right.shape) == 2
                              and left.shape == right.shape[::-1])
                self.error(e, f"'{e.op}' compares {left.describe()} with {right.describe()}",
                           "one side is the other's transpose (RoboTool's newer generated "
                           "files write such equations): declare the matrix with the other "
                           "size, or transpose one side" if transposed
                           else "the two sides must have the same size")
            return BOOL
        if e.op in ORDERING:
            for side, t in ((e.left, left), (e.right, right)):
                if t.kind in (Kind.BOOL, Kind.STR, Kind.ARRAY):
                    self.error(side, f"'{e.op}' orders numbers, but this is {t.describe()}",
                               "compare numbers")
            return BOOL
        for side, t in ((e.left, left), (e.right, right)):
            if t.kind in (Kind.BOOL, Kind.STR):
                self.error(side, f"arithmetic ('{e.op}') on {t.describe()}",
                           "use numbers, vectors or matrices")
                return ANY
        return self._arithmetic(e, left, right)

    def _arithmetic(self, e: ex.BinOp, left: Ty, right: Ty) -> Ty:
        if Kind.ANY in (left.kind, right.kind):
            return ANY
        if left.kind is Kind.NUM and right.kind is Kind.NUM:
            return NUM
        if e.op in ("+", "-"):
            if left.kind is not right.kind:
                self.error(e, f"'{e.op}' between {left.describe()} and {right.describe()}",
                           "add values of the same shape")
                return ANY
            if not same_shape(left.shape, right.shape):
                self.error(e, f"'{e.op}' between {left.describe()} and {right.describe()}",
                           "the two sides must have the same size")
                return ANY
            return Ty(Kind.ARRAY, left.shape or right.shape)
        if e.op == "*":
            if left.kind is Kind.NUM:
                return right
            if right.kind is Kind.NUM:
                return left
            a, b = left.shape, right.shape
            if a and b and len(a) == 2:
                if a[1] != b[0]:
                    self.error(e, f"matrix product of {left.describe()} and "
                               f"{right.describe()}: the inner sizes differ",
                               "the left operand's columns must equal the right's rows")
                    return ANY
                return Ty(Kind.ARRAY, (a[0],) if len(b) == 1 else (a[0], b[1]))
            return ANY
        return ANY if left.kind is Kind.ARRAY else left

    def _infer_Call(self, e: ex.Call) -> Ty:
        args = [self.infer(a) for a in e.args]
        if isinstance(e.func, ex.Call):  # curried: submatrix(M)(0, 0, 3, 3)
            self.infer(e.func.func)
            for a in e.func.args:
                self.infer(a)
            return ANY
        if not isinstance(e.func, ex.Name):
            return ANY
        decl = self.lookup(e.func)
        if not isinstance(decl, ast.FunctionDecl):
            return ANY  # a call on a variable (`theta(0)`) is element access
        if len(e.args) != len(decl.params):
            self.error(e, f"{decl.name} takes {len(decl.params)} argument"
                       f"{'s' if len(decl.params) != 1 else ''}, not {len(e.args)}",
                       f"call it as {decl.name}({', '.join(p.name for p in decl.params)})")
            return ANY
        for arg, got, param in zip(e.args, args, decl.params):
            want = type_of_declared(param.type)
            if want.kind is Kind.ARRAY and got.kind is Kind.ARRAY \
                    and not same_shape(want.shape, got.shape):
                self.error(arg, f"'{param.name}' of {decl.name} is {want.describe()}, but "
                           f"this is {got.describe()}", "pass an argument of the declared size")
        return self._call_shape(decl, e.args, args)

    def _call_shape(self, decl: ast.FunctionDecl, exprs: tuple[ex.Expr, ...],
                    args: list[Ty]) -> Ty:
        """The result of a call: the declared type, or for the size-generic matrix
        functions of physmod::math (declared ``matrix(real, 0, 0)``) the size they give."""
        declared = type_of_declared(decl.return_type) if decl.return_type is not None else ANY
        if declared.kind is not Kind.ARRAY or declared.shape is not None:
            return declared
        first = args[0].shape if args and args[0].kind is Kind.ARRAY else None
        if decl.name == "transpose" and first is not None:
            return Ty(Kind.ARRAY, (1, first[0]) if len(first) == 1 else (first[1], first[0]))
        if decl.name in ("inverse", "adj") and first is not None:
            return Ty(Kind.ARRAY, first)
        sizes = [_literal_int(x) for x in exprs]
        if decl.name == "identity" and len(sizes) == 1 and sizes[0]:
            return Ty(Kind.ARRAY, (sizes[0], sizes[0]))
        if decl.name == "zeroes" and len(sizes) == 2 and sizes[0] and sizes[1]:
            return Ty(Kind.ARRAY, (sizes[0], sizes[1]))
        return declared

    def _infer_Derivative(self, e: ex.Derivative) -> Ty:
        t = self.infer(e.operand)
        if t.kind in (Kind.BOOL, Kind.STR):
            self.error(e, f"derivative of {t.describe()}", "differentiate a number or vector")
            return ANY
        return t

    def _infer_Integral(self, e: ex.Integral) -> Ty:
        return self._infer_Derivative(ex.Derivative(e.operand, span=e.span))

    def _infer_Index(self, e: ex.Index) -> Ty:
        base = self.infer(e.base)
        for a in e.args:
            self.infer(a)
        if base.kind is Kind.ARRAY:
            return NUM if base.shape is None or len(base.shape) == len(e.args) else ANY
        return base if len(e.args) == 1 and _is_time_condition(e.args[0]) else ANY

    def _infer_Seq(self, e: ex.Seq) -> Ty:
        for item in e.items:
            self.infer(item)
        return ANY

    def _infer_Record(self, e: ex.Record) -> Ty:
        for _, value in e.fields:
            self.infer(value)
        return ANY

    def _infer_Member(self, e: ex.Member) -> Ty:
        return ANY


def _is_time_condition(e: ex.Expr) -> bool:
    """``[t == 0]``: the index of an initial or boundary condition (IBCondition)."""
    return isinstance(e, ex.BinOp) and e.op == "==" and e.left == ex.Name(("t",))
