"""Print expressions back in the RoboSim notation (for ``cyphy show`` and messages).

One method per node class, brackets from the precedence table that the parser uses, so that
printing and parsing again gives an equal tree (a test checks the round trip).
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.lang import ast

# Binding powers as in the parser's precedence climbing (cyphy/lang/parser.py). Every printer
# of expressions that writes infix text (notation, CyPhyCircus text, CZT LaTeX) uses them.
BINDING_POWER = {"<=>": 10, "=>": 10, "\\/": 20, "/\\": 30, "==": 50, "!=": 50, "<": 50,
                 "<=": 50, ">": 50, ">=": 50, "+": 60, "-": 60, "cat": 60, "*": 70, "/": 70,
                 "%": 70, "^": 90}
RIGHT_ASSOCIATIVE = {"<=>", "=>", "^"}
PREFIX_POWER = {"not": 40, "-": 80}
ATOM = 100


class NotationPrinter:
    """``to_notation(expr)``: the expression as RoboSim text.

    Also the base of the other infix printers: they change ``operators`` (how each binary
    operator is written), ``prefixes`` and the methods of the nodes they write differently,
    and inherit the brackets."""

    operators: dict[str, str] = {op: op for op in BINDING_POWER}
    prefixes: dict[str, str] = {"not": "not ", "-": "-"}

    def print(self, e: ex.Expr) -> str:
        return self._print(e)[0]

    def _print(self, e: ex.Expr) -> tuple[str, int]:
        method = getattr(self, "_print_" + type(e).__name__)
        return method(e)  # type: ignore[no-any-return]

    def wrap(self, e: ex.Expr, min_bp: int) -> str:
        """``e``, in brackets when its operator binds more loosely than ``min_bp``."""
        text, bp = self._print(e)
        return f"({text})" if bp < min_bp else text

    def _print_Num(self, e: ex.Num) -> tuple[str, int]:
        return e.text, ATOM

    def _print_Quantity(self, e: ex.Quantity) -> tuple[str, int]:
        value = e.value
        body = value.text if isinstance(value, ex.Num) else f"({self.print(value)})"
        sep = " " if len(e.unit) > 3 else ""
        return f"{body}{sep}{e.unit}", ATOM

    def _print_Str(self, e: ex.Str) -> tuple[str, int]:
        return '"' + e.value.replace("\\", "\\\\").replace('"', '\\"') + '"', ATOM

    def _print_Bool(self, e: ex.Bool) -> tuple[str, int]:
        return ("true" if e.value else "false"), ATOM

    def _print_Name(self, e: ex.Name) -> tuple[str, int]:
        return e.text, ATOM

    def _print_BinOp(self, e: ex.BinOp) -> tuple[str, int]:
        bp = BINDING_POWER[e.op]
        left_min, right_min = (bp + 1, bp) if e.op in RIGHT_ASSOCIATIVE else (bp, bp + 1)
        left, right = self.wrap(e.left, left_min), self.wrap(e.right, right_min)
        return f"{left} {self.operators[e.op]} {right}", bp

    def _print_UnaryOp(self, e: ex.UnaryOp) -> tuple[str, int]:
        bp = PREFIX_POWER[e.op]
        return f"{self.prefixes[e.op]}{self.wrap(e.operand, bp)}", bp

    def _postfix_base(self, e: ex.Expr) -> str:
        return self.wrap(e, ATOM)

    def _print_Call(self, e: ex.Call) -> tuple[str, int]:
        args = ", ".join(self.print(a) for a in e.args)
        return f"{self._postfix_base(e.func)}({args})", ATOM

    def _print_Index(self, e: ex.Index) -> tuple[str, int]:
        args = ", ".join(self.print(a) for a in e.args)
        return f"{self._postfix_base(e.base)}[{args}]", ATOM

    def _print_Member(self, e: ex.Member) -> tuple[str, int]:
        return f"{self._postfix_base(e.base)}.{e.name}", ATOM

    def _print_Derivative(self, e: ex.Derivative) -> tuple[str, int]:
        return f"derivative({self.print(e.operand)})", ATOM

    def _print_Integral(self, e: ex.Integral) -> tuple[str, int]:
        bounds = [e.lower, e.upper] if e.lower is not None and e.upper is not None else []
        args = ", ".join(self.print(a) for a in [e.operand, *bounds])
        return f"integral({args})", ATOM

    def _rows(self, rows: tuple[tuple[ex.Expr, ...], ...]) -> str:
        return "; ".join(", ".join(self.print(x) for x in row) for row in rows)

    def _print_Vector(self, e: ex.Vector) -> tuple[str, int]:
        return f"(|{self._rows(e.rows)}|)", ATOM

    def _print_Matrix(self, e: ex.Matrix) -> tuple[str, int]:
        return f"[|{self._rows(e.rows)}|]", ATOM

    def _print_Seq(self, e: ex.Seq) -> tuple[str, int]:
        # Sequence elements are sums: anything looser needs brackets before `>` closes it.
        return "<" + ", ".join(self.wrap(x, 60) for x in e.items) + ">", ATOM

    def _print_Record(self, e: ex.Record) -> tuple[str, int]:
        fields = ", ".join(f"{n} = {self.print(v)}" for n, v in e.fields)
        return f"{'::'.join(e.type_name)} (|{fields}|)", ATOM

    def _print_PlatformRef(self, e: ex.PlatformRef) -> tuple[str, int]:
        binding = f"?{e.binding}" if e.binding is not None else ""
        return f"${e.text}{binding}", ATOM

    def _print_IfExpr(self, e: ex.IfExpr) -> tuple[str, int]:
        return (f"if {self.print(e.cond)} then {self.print(e.then)} else "
                f"{self.print(e.orelse)} end"), ATOM


def to_notation(e: ex.Expr) -> str:
    return NotationPrinter().print(e)


def statement_to_notation(s: ast.Statement) -> str:
    """A statement of an action as written: ``x = 1``, ``$move(lv, 0)``, ``#C``, ``exec``."""
    if isinstance(s, ast.Assign):
        return f"{to_notation(s.target)} = {to_notation(s.value)}"
    if isinstance(s, ast.CallStatement):
        return to_notation(s.call)
    if isinstance(s, ast.SendStatement):
        return f"{to_notation(s.event)}!{NotationPrinter().wrap(s.value, ATOM)}"
    if isinstance(s, ast.ClockReset):
        return f"#{s.clock}"
    if isinstance(s, ast.ExecStatement):
        return "exec"
    if isinstance(s, ast.WaitStatement):
        return f"wait({to_notation(s.cycles)})"
    return "skip"


def action_to_notation(statements: tuple[ast.Statement, ...]) -> str:
    return "; ".join(statement_to_notation(s) for s in statements)


def type_to_notation(t: ast.TypeRef | None) -> str:
    """A declared type as written: ``real``, ``vector(real, 3)``, ``Seq(matrix(real, 4, 4))``."""
    if t is None:
        return "?"
    if isinstance(t, ast.PrimitiveType):
        return t.name
    if isinstance(t, ast.NamedType):
        return "::".join(t.name)
    if isinstance(t, ast.VectorType):
        size = f", {to_notation(t.size)}" if t.size is not None else ""
        return f"vector({type_to_notation(t.element)}{size})"
    if isinstance(t, ast.MatrixType):
        return (f"matrix({type_to_notation(t.element)}, {to_notation(t.rows)}, "
                f"{to_notation(t.cols)})")
    kind = "Seq" if isinstance(t, ast.SeqType) else "Set"
    return f"{kind}({type_to_notation(t.element)})"
