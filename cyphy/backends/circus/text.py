"""The CyPhyCircus program as Unicode text that reads like the paper's Figure 18.

One method per node type (SymPy-printer style). Brackets come from binding powers, so the
text parses back into an equal AST (:mod:`cyphy.backends.circus.reader`, tested on every
program the rules build). Time derivatives are primed (``timer' = 1``) inside ``Λ``; in a
specification statement's postcondition a primed frame name is its after-state value, as in
Z; the two never meet because mapping equations have no derivatives.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.backends.circus.actions import (ATOMIC, INTERLEAVE, PREFIX, ActionPrinter,
                                          deviation_comments)
from cyphy.lang.notation import ATOM, NotationPrinter
from cyphy.semantics.circus import ast as c

TYPES = {"real": "ℝ", "nat": "ℕ", "int": "ℤ", "bool": "𝔹"}


class ExpressionText(NotationPrinter):
    """Expressions in Unicode: ``∧ ∨ ¬ ≤ ≥ ≠``, ``x'`` for the derivative, ``⟨a, b⟩`` for
    sequences. ``primed`` names print primed (after-state values)."""

    operators = {"<=>": "⇔", "=>": "⇒", "\\/": "∨", "/\\": "∧", "==": "=", "!=": "≠",
                 "<": "<", "<=": "≤", ">": ">", ">=": "≥", "+": "+", "-": "-", "cat": "⁀",
                 "*": "*", "/": "/", "%": "mod", "^": "^"}
    prefixes = {"not": "¬ ", "-": "-"}

    def __init__(self, primed: frozenset[str] = frozenset()) -> None:
        self.primed = primed

    def _print_Name(self, e: ex.Name) -> tuple[str, int]:
        return e.text + ("'" if e.text in self.primed else ""), ATOM

    def _print_Derivative(self, e: ex.Derivative) -> tuple[str, int]:
        return f"{self.wrap(e.operand, ATOM)}'", ATOM

    def _print_Integral(self, e: ex.Integral) -> tuple[str, int]:
        bounds = [b for b in (e.lower, e.upper) if b is not None]
        return f"∫({', '.join(self.print(a) for a in (e.operand, *bounds))})", ATOM

    def _print_Seq(self, e: ex.Seq) -> tuple[str, int]:
        return "⟨" + ", ".join(self.print(i) for i in e.items) + "⟩", ATOM

    def _print_IfExpr(self, e: ex.IfExpr) -> tuple[str, int]:
        return (f"(if {self.print(e.cond)} then {self.print(e.then)} "
                f"else {self.print(e.orelse)})"), ATOM


def type_text(t: c.Type) -> str:
    if isinstance(t, c.TBasic):
        return TYPES.get(t.name, t.name)
    if isinstance(t, c.TSeq):
        inner = type_text(t.of)
        return f"seq {inner}" if isinstance(t.of, c.TBasic) else f"seq ({inner})"
    return " × ".join(type_text(i) if not isinstance(i, c.TProduct) else f"({type_text(i)})"
                      for i in t.items)


class CircusText(ActionPrinter):
    """A whole program (or any node) as text."""

    expressions = ExpressionText

    def __init__(self, indent: str = "  ") -> None:
        self.indent = indent

    def type(self, t: c.Type) -> str:
        return type_text(t)

    def channel(self, channel: str, tag: str | None) -> str:
        return channel + (f".{tag}" if tag is not None else "")

    def exists(self, bindings: str, body: str) -> str:
        return f"∃ {bindings} • {body}"

    def guard(self, cond: str, action: str) -> str:
        return f"({cond}) & {action}"

    def chanset(self, channels: tuple[str, ...]) -> str:
        return f"\\ {{| {', '.join(channels)} |}}"

    def _a_IndexedExtChoice(self, a: c.IndexedExtChoice) -> tuple[str, int]:
        where = self.predicate(a.where)
        return (f"□ {a.var.name} : {{{a.var.name} : {type_text(a.var.type)} | {where}}} • "
                f"{self._wrap(a.body, PREFIX)}"), ATOMIC - 1

    def _a_Parallel(self, a: c.Parallel) -> tuple[str, int]:
        left, right = self._wrap(a.left, ATOMIC), self._wrap(a.right, ATOMIC)
        ns1, ns2 = ", ".join(a.left_names), ", ".join(a.right_names)
        return (f"{left} ⟦ {{{ns1}}} | {{| {', '.join(a.channels)} |}} | {{{ns2}}} ⟧ "
                f"{right}"), INTERLEAVE

    def _a_Cond(self, a: c.Cond) -> tuple[str, int]:
        return (f"if {self.predicate(a.cond)} then {self._wrap(a.then, PREFIX)} "
                f"else {self._wrap(a.orelse, PREFIX)}"), ATOMIC - 1

    def _a_Spec(self, a: c.Spec) -> tuple[str, int]:
        primed = frozenset(a.frame)
        return (f"{', '.join(a.frame)} : [{self.predicate(a.pre)}, "
                f"{self.predicate(a.post, primed)}]"), ATOMIC

    def _a_Evolution(self, a: c.Evolution) -> tuple[str, int]:
        body = self.conjunction(a.equations)
        if a.locals is not None:
            body = f"∃ {a.locals} • {body}"
        return f"[Λ {a.state} | {body}]", ATOMIC

    # ----- declarations
    def program(self, p: c.Program) -> str:
        i = self.indent
        g = p.globals
        lines = [*deviation_comments("// "), "",
                 f"{self.bindings(g.constants)} | {self.conjunction(g.where)}", ""]
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
        if isinstance(p.dmodel, c.BasicProcess):
            lines += self.process(p.dmodel)
        else:
            lines.append(f"process {p.dmodel.name}")
        lines.append("")
        lines += self.process(p.pmodel)
        lines.append("")
        lines.append(f"process {p.system.name} ≙ {self.process_expr(p.system.body)}")
        return "\n".join(lines) + "\n"

    def process(self, proc: c.BasicProcess) -> list[str]:
        """``process P ≙ begin … end``, one declaration or action per line."""
        i = self.indent
        lines = [f"process {proc.name} ≙ begin"]
        for k in proc.constants:
            value = f" = {self.expr(k.value)}" if k.value is not None else ""
            lines.append(f"{i}const {k.name} : {type_text(k.type)}{value}")
        lines.append(f"{i}state {self.schema(proc.state)}")
        lines.append(f"{i}{self.schema(proc.local)}")
        for d in proc.actions:
            params = f"{self.bindings(d.params)} • " if d.params else ""
            lines.append(f"{i}{d.name} ≙ {params}{self.action(d.body)}")
        lines.append(f"{i}• {self.action(proc.main)}")
        lines.append("end")
        return lines

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
