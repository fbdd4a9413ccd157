"""The CyPhyCircus program as Unicode text that reads like the paper's Figure 18.

One method per node type (SymPy-printer style). Brackets come from binding powers, so the
text parses back into an equal AST (:mod:`cyphy.backends.circus_reader`, tested on every
program the rules build). Time derivatives are primed (``timer' = 1``) inside ``Λ``; in a
specification statement's postcondition a primed frame name is its after-state value, as in
Z; the two never meet because mapping equations have no derivatives.
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.semantics import circus as c

# Expression binding powers (loosest first), as in the RoboSim notation's parser.
_BP = {"<=>": 10, "=>": 10, "\\/": 20, "/\\": 30, "==": 50, "!=": 50, "<": 50, "<=": 50,
       ">": 50, ">=": 50, "+": 60, "-": 60, "cat": 60, "*": 70, "/": 70, "%": 70, "^": 90}
_RIGHT = {"<=>", "=>", "^"}
_PREFIX_BP = {"not": 40, "-": 80}
_ATOM = 100
AND_BP = _BP["/\\"]

OPERATORS = {"<=>": "⇔", "=>": "⇒", "\\/": "∨", "/\\": "∧", "==": "=", "!=": "≠", "<": "<",
             "<=": "≤", ">": ">", ">=": "≥", "+": "+", "-": "-", "cat": "⁀", "*": "*",
             "/": "/", "%": "mod", "^": "^"}
TYPES = {"real": "ℝ", "nat": "ℕ", "int": "ℤ", "bool": "𝔹"}


class ExpressionText:
    """Expressions in Unicode: ``∧ ∨ ¬ ≤ ≥ ≠``, ``x'`` for the derivative, ``⟨a, b⟩`` for
    sequences. ``primed`` names print primed (after-state values)."""

    def __init__(self, primed: frozenset[str] = frozenset()) -> None:
        self.primed = primed

    def print(self, e: ex.Expr) -> str:
        return self._print(e)[0]

    def wrap(self, e: ex.Expr, min_bp: int) -> str:
        text, bp = self._print(e)
        return f"({text})" if bp < min_bp else text

    def _print(self, e: ex.Expr) -> tuple[str, int]:
        method: Callable[[ex.Expr], tuple[str, int]] = getattr(self, "_print_" + type(e).__name__)
        return method(e)

    def _print_Num(self, e: ex.Num) -> tuple[str, int]:
        return e.text, _ATOM

    def _print_Bool(self, e: ex.Bool) -> tuple[str, int]:
        return ("true" if e.value else "false"), _ATOM

    def _print_Str(self, e: ex.Str) -> tuple[str, int]:
        return '"' + e.value.replace("\\", "\\\\").replace('"', '\\"') + '"', _ATOM

    def _print_Name(self, e: ex.Name) -> tuple[str, int]:
        return e.text + ("'" if e.text in self.primed else ""), _ATOM

    def _print_BinOp(self, e: ex.BinOp) -> tuple[str, int]:
        bp = _BP[e.op]
        left_min, right_min = (bp + 1, bp) if e.op in _RIGHT else (bp, bp + 1)
        return f"{self.wrap(e.left, left_min)} {OPERATORS[e.op]} {self.wrap(e.right, right_min)}", bp

    def _print_UnaryOp(self, e: ex.UnaryOp) -> tuple[str, int]:
        bp = _PREFIX_BP[e.op]
        return ("¬ " if e.op == "not" else "-") + self.wrap(e.operand, bp), bp

    def _print_Call(self, e: ex.Call) -> tuple[str, int]:
        args = ", ".join(self.print(a) for a in e.args)
        return f"{self.wrap(e.func, _ATOM)}({args})", _ATOM

    def _print_Index(self, e: ex.Index) -> tuple[str, int]:
        args = ", ".join(self.print(a) for a in e.args)
        return f"{self.wrap(e.base, _ATOM)}[{args}]", _ATOM

    def _print_Member(self, e: ex.Member) -> tuple[str, int]:
        return f"{self.wrap(e.base, _ATOM)}.{e.name}", _ATOM

    def _print_Derivative(self, e: ex.Derivative) -> tuple[str, int]:
        return f"{self.wrap(e.operand, _ATOM)}'", _ATOM

    def _print_Integral(self, e: ex.Integral) -> tuple[str, int]:
        bounds = [b for b in (e.lower, e.upper) if b is not None]
        args = ", ".join(self.print(a) for a in (e.operand, *bounds))
        return f"∫({args})", _ATOM

    def _print_Seq(self, e: ex.Seq) -> tuple[str, int]:
        return "⟨" + ", ".join(self.print(i) for i in e.items) + "⟩", _ATOM

    def _print_IfExpr(self, e: ex.IfExpr) -> tuple[str, int]:
        return (f"(if {self.print(e.cond)} then {self.print(e.then)} "
                f"else {self.print(e.orelse)})"), _ATOM


def type_text(t: c.Type) -> str:
    if isinstance(t, c.TBasic):
        return TYPES.get(t.name, t.name)
    if isinstance(t, c.TSeq):
        inner = type_text(t.of)
        return f"seq {inner}" if isinstance(t.of, c.TBasic) else f"seq ({inner})"
    return " × ".join(type_text(i) if not isinstance(i, c.TProduct) else f"({type_text(i)})"
                      for i in t.items)


def bindings_text(bindings: tuple[c.Binding, ...]) -> str:
    return "; ".join(f"{b.name} : {type_text(b.type)}" for b in bindings)


# Action binding powers: the loosest operator of an action, for brackets.
_HIDE, _INTERLEAVE, _CHOICE, _INTERRUPT, _SEQ, _PREFIX, _ATOM_ACTION = 10, 20, 30, 40, 50, 60, 100


class CircusText:
    """A whole program (or any node) as text."""

    def __init__(self, indent: str = "  ") -> None:
        self.indent = indent

    # ----- expressions and predicates
    def expr(self, e: ex.Expr, primed: frozenset[str] = frozenset()) -> str:
        return ExpressionText(primed).print(e)

    def predicate(self, p: c.Predicate, primed: frozenset[str] = frozenset()) -> str:
        if not isinstance(p, c.Exists):
            return self.expr(p, primed)
        printer = ExpressionText(primed)
        body = " ∧ ".join(printer.wrap(e, AND_BP + 1) for e in p.body) or "true"
        if not p.bound:
            return body
        return f"∃ {bindings_text(p.bound)} • {body}"

    # ----- actions
    def action(self, a: c.Action) -> str:
        return self._action(a)[0]

    def _action(self, a: c.Action) -> tuple[str, int]:
        method: Callable[[c.Action], tuple[str, int]] = getattr(self, "_a_" + type(a).__name__)
        return method(a)

    def _wrap(self, a: c.Action, min_bp: int) -> str:
        text, bp = self._action(a)
        return f"({text})" if bp < min_bp else text

    def _a_Skip(self, a: c.Skip) -> tuple[str, int]:
        return "Skip", _ATOM_ACTION

    def _a_Stop(self, a: c.Stop) -> tuple[str, int]:
        return "Stop", _ATOM_ACTION

    def comm(self, m: c.Comm) -> str:
        out = m.channel + (f".{m.tag}" if m.tag is not None else "")
        for f in m.fields:
            if isinstance(f, c.In):
                out += f"?{f.name}"
            else:
                mark = "!" if isinstance(f, c.Out) else "."
                out += mark + ExpressionText().wrap(f.value, _ATOM)
        return out

    def _a_Prefix(self, a: c.Prefix) -> tuple[str, int]:
        return f"{self.comm(a.comm)} → {self._wrap(a.then, _PREFIX)}", _PREFIX

    def _a_Seq(self, a: c.Seq) -> tuple[str, int]:
        return " ; ".join(self._wrap(i, _SEQ + 1) for i in a.items), _SEQ

    def _a_ExtChoice(self, a: c.ExtChoice) -> tuple[str, int]:
        return " □ ".join(self._wrap(i, _CHOICE + 1) for i in a.items), _CHOICE

    def _a_Interleave(self, a: c.Interleave) -> tuple[str, int]:
        return " ||| ".join(self._wrap(i, _INTERLEAVE + 1) for i in a.items), _INTERLEAVE

    def _a_IndexedExtChoice(self, a: c.IndexedExtChoice) -> tuple[str, int]:
        where = self.predicate(a.where)
        return (f"□ {a.var.name} : {{{a.var.name} : {type_text(a.var.type)} | {where}}} • "
                f"{self._wrap(a.body, _PREFIX)}"), _ATOM_ACTION - 1

    def _a_Parallel(self, a: c.Parallel) -> tuple[str, int]:
        left, right = self._wrap(a.left, _ATOM_ACTION), self._wrap(a.right, _ATOM_ACTION)
        ns1, ns2 = ", ".join(a.left_names), ", ".join(a.right_names)
        return (f"{left} ⟦ {{{ns1}}} | {{| {', '.join(a.channels)} |}} | {{{ns2}}} ⟧ "
                f"{right}"), _INTERLEAVE

    def _a_Hide(self, a: c.Hide) -> tuple[str, int]:
        return f"{self._wrap(a.action, _HIDE + 1)} \\ {{| {', '.join(a.channels)} |}}", _HIDE

    def _a_Cond(self, a: c.Cond) -> tuple[str, int]:
        return (f"if {self.predicate(a.cond)} then {self._wrap(a.then, _PREFIX)} "
                f"else {self._wrap(a.orelse, _PREFIX)}"), _ATOM_ACTION - 1

    def _a_Guard(self, a: c.Guard) -> tuple[str, int]:
        return f"({self.predicate(a.cond)}) & {self._wrap(a.action, _PREFIX)}", _PREFIX

    def _a_Mu(self, a: c.Mu) -> tuple[str, int]:
        return f"μ {a.var} • {self._wrap(a.body, _ATOM_ACTION)}", _ATOM_ACTION - 1

    def _a_Call(self, a: c.Call) -> tuple[str, int]:
        if not a.args:
            return a.name, _ATOM_ACTION
        return f"{a.name}({', '.join(self.expr(x) for x in a.args)})", _ATOM_ACTION

    def _a_Interrupt(self, a: c.Interrupt) -> tuple[str, int]:
        return (f"{self._wrap(a.left, _INTERRUPT + 1)} △ {self._wrap(a.right, _INTERRUPT + 1)}",
                _INTERRUPT)

    def _a_InterruptCond(self, a: c.InterruptCond) -> tuple[str, int]:
        return (f"{self._wrap(a.action, _INTERRUPT + 1)} △ ({self.predicate(a.cond)})",
                _INTERRUPT)

    def _a_Wait(self, a: c.Wait) -> tuple[str, int]:
        return f"Wait({self.expr(a.count)})", _ATOM_ACTION

    def _a_Assign(self, a: c.Assign) -> tuple[str, int]:
        values = ", ".join(self.expr(v) for v in a.values)
        return f"{', '.join(a.targets)} := {values}", _PREFIX

    def _a_Spec(self, a: c.Spec) -> tuple[str, int]:
        primed = frozenset(a.frame)
        return (f"{', '.join(a.frame)} : [{self.predicate(a.pre)}, "
                f"{self.predicate(a.post, primed)}]"), _ATOM_ACTION

    def _a_Evolution(self, a: c.Evolution) -> tuple[str, int]:
        printer = ExpressionText()
        body = " ∧ ".join(printer.wrap(e, AND_BP + 1) for e in a.equations) or "true"
        if a.locals is not None:
            body = f"∃ {a.locals} • {body}"
        return f"[Λ {a.state} | {body}]", _ATOM_ACTION

    def _a_VarBlock(self, a: c.VarBlock) -> tuple[str, int]:
        return (f"var {a.var.name} : {type_text(a.var.type)} • "
                f"{self._wrap(a.body, _ATOM_ACTION)}"), _ATOM_ACTION - 1

    # ----- declarations
    def program(self, p: c.Program) -> str:
        i = self.indent
        g = p.globals
        lines = [f"{bindings_text(g.constants)} | "
                 + " ∧ ".join(ExpressionText().wrap(w, AND_BP + 1) for w in g.where), ""]
        for ch in p.channels:
            if not ch.variants:
                lines.append(f"channel {ch.name}")
            for v in ch.variants:
                name = ch.name + (f".{v.tag}" if v.tag is not None else "")
                types = " × ".join(type_text(t) for t in v.types)
                lines.append(f"channel {name}" + (f" : {types}" if types else ""))
        lines.append("")
        for f in p.functions:
            lines.append(f"function {f.name}/{f.arity}")
        if p.functions:
            lines.append("")
        lines.append(f"process {p.dmodel.name}")
        lines.append("")
        proc = p.pmodel
        lines.append(f"process {proc.name} ≙ begin")
        for k in proc.constants:
            value = f" = {self.expr(k.value)}" if k.value is not None else ""
            lines.append(f"{i}const {k.name} : {type_text(k.type)}{value}")
        lines.append(f"{i}state {self.schema(proc.state)}")
        lines.append(f"{i}{self.schema(proc.local)}")
        for d in proc.actions:
            params = f"{bindings_text(d.params)} • " if d.params else ""
            lines.append(f"{i}{d.name} ≙ {params}{self.action(d.body)}")
        lines.append(f"{i}• {self.action(proc.main)}")
        lines.append("end")
        lines.append("")
        lines.append(f"process {p.system.name} ≙ {self.process_expr(p.system.body)}")
        return "\n".join(lines) + "\n"

    def schema(self, s: c.Schema) -> str:
        fields = "; ".join(("visible " if f.visible else "") + f"{f.name} : {type_text(f.type)}"
                           for f in s.fields)
        return f"{s.name} ≙ [{fields}]"

    def process_expr(self, e: c.ProcessExpr) -> str:
        if isinstance(e, c.PRef):
            return e.name
        if isinstance(e, c.PParallel):
            return (f"({self.process_expr(e.left)} ⟦ {{| {', '.join(e.channels)} |}} ⟧ "
                    f"{self.process_expr(e.right)})")
        return f"{self.process_expr(e.process)} \\ {{| {', '.join(e.channels)} |}}"


def program_to_text(program: c.Program) -> str:
    return CircusText().program(program)
