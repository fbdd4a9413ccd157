"""What the CyPhyCircus printers share: actions written with binding powers, so brackets go
exactly where a reader (ours, or CZT) needs them.

The text and LaTeX printers differ in their tokens (``;`` or ``\\circseq``, ``□`` or
``\\extchoice``), in how names and types are spelled and in a few constructs; everything else
is here, one method per action node, with the expressions printed by the target's
:class:`~cyphy.lang.notation.NotationPrinter` subclass.
"""

from __future__ import annotations

import textwrap
from typing import Callable

from cyphy import expr as ex
from cyphy.lang.notation import ATOM, BINDING_POWER, NotationPrinter
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.rules import DEVIATIONS

AND_BP = BINDING_POWER["/\\"]

# Action binding powers, loosest first; 100 is an atom, 99 an action that must be bracketed
# only where an atom is required (a recursion's body, a parallel operand).
HIDE, INTERLEAVE, CHOICE, INTERRUPT, SEQ, PREFIX, ATOMIC = 10, 20, 30, 40, 50, 60, 100


class ActionPrinter:
    """The base of the CyPhyCircus printers; subclasses set the tokens and hooks."""

    expressions: type[NotationPrinter] = NotationPrinter  # with a ``primed`` argument
    SKIP, STOP = "Skip", "Stop"
    THEN, SEQ, CHOICE, INTERLEAVE, INTERRUPT = " → ", " ; ", " □ ", " ||| ", " △ "
    MU, SPOT, VAR, ASSIGN = "μ ", " • ", "var ", " := "
    AND = " ∧ "

    # ----- hooks
    def name(self, text: str) -> str:
        return text

    def type(self, t: c.Type) -> str:
        raise NotImplementedError

    def channel(self, channel: str, tag: str | None) -> str:
        raise NotImplementedError

    def exists(self, bindings: str, body: str) -> str:
        raise NotImplementedError

    def guard(self, cond: str, action: str) -> str:
        raise NotImplementedError

    def chanset(self, channels: tuple[str, ...]) -> str:
        raise NotImplementedError

    # ----- expressions and predicates
    def expr(self, e: ex.Expr, primed: frozenset[str] = frozenset()) -> str:
        return self.expressions(primed).print(e)  # type: ignore[call-arg]

    def bindings(self, bs: tuple[c.Binding, ...]) -> str:
        return "; ".join(f"{self.name(b.name)} : {self.type(b.type)}" for b in bs)

    def conjunction(self, items: tuple[ex.Expr, ...], primed: frozenset[str] = frozenset()
                    ) -> str:
        """Conjuncts bracketed when they are themselves conjunctions or looser, so that a
        reader splits the list back exactly."""
        printer = self.expressions(primed)  # type: ignore[call-arg]
        return self.AND.join(printer.wrap(e, AND_BP + 1) for e in items) or "true"

    def predicate(self, p: c.Predicate, primed: frozenset[str] = frozenset()) -> str:
        if not isinstance(p, c.Exists):
            return self.expr(p, primed)
        body = self.conjunction(p.body, primed)
        return self.exists(self.bindings(p.bound), body) if p.bound else body

    # ----- actions
    def action(self, a: c.Action) -> str:
        return self._action(a)[0]

    def _action(self, a: c.Action) -> tuple[str, int]:
        method: Callable[[c.Action], tuple[str, int]] = getattr(self, "_a_" + type(a).__name__)
        return method(a)

    def _wrap(self, a: c.Action, min_bp: int) -> str:
        text, bp = self._action(a)
        return f"({text})" if bp < min_bp else text

    def comm(self, m: c.Comm) -> str:
        out = self.channel(m.channel, m.tag)
        printer = self.expressions()
        for f in m.fields:
            if isinstance(f, c.In):
                out += f"?{self.name(f.name)}"
            else:
                out += ("!" if isinstance(f, c.Out) else ".") + printer.wrap(f.value, ATOM)
        return out

    def _join(self, token: str, items: tuple[c.Action, ...], bp: int) -> tuple[str, int]:
        return token.join(self._wrap(i, bp + 1) for i in items), bp

    def _a_Skip(self, a: c.Skip) -> tuple[str, int]:
        return self.SKIP, ATOMIC

    def _a_Stop(self, a: c.Stop) -> tuple[str, int]:
        return self.STOP, ATOMIC

    def _a_Prefix(self, a: c.Prefix) -> tuple[str, int]:
        return f"{self.comm(a.comm)}{self.THEN}{self._wrap(a.then, PREFIX)}", PREFIX

    def _a_Seq(self, a: c.Seq) -> tuple[str, int]:
        return self._join(self.SEQ, a.items, SEQ)

    def _a_ExtChoice(self, a: c.ExtChoice) -> tuple[str, int]:
        return self._join(self.CHOICE, a.items, CHOICE)

    def _a_Interleave(self, a: c.Interleave) -> tuple[str, int]:
        return self._join(self.INTERLEAVE, a.items, INTERLEAVE)

    def _a_Interrupt(self, a: c.Interrupt) -> tuple[str, int]:
        return self._join(self.INTERRUPT, (a.left, a.right), INTERRUPT)

    def _a_InterruptCond(self, a: c.InterruptCond) -> tuple[str, int]:
        return (f"{self._wrap(a.action, INTERRUPT + 1)}{self.INTERRUPT}"
                f"({self.predicate(a.cond)})"), INTERRUPT

    def _a_Hide(self, a: c.Hide) -> tuple[str, int]:
        return f"{self._wrap(a.action, HIDE + 1)} {self.chanset(a.channels)}", HIDE

    def _a_Guard(self, a: c.Guard) -> tuple[str, int]:
        return self.guard(self.predicate(a.cond), self._wrap(a.action, PREFIX)), PREFIX

    def _a_Mu(self, a: c.Mu) -> tuple[str, int]:
        return f"{self.MU}{self.name(a.var)}{self.SPOT}{self._wrap(a.body, ATOMIC)}", ATOMIC - 1

    def _a_VarBlock(self, a: c.VarBlock) -> tuple[str, int]:
        return (f"{self.VAR}{self.bindings((a.var,))}{self.SPOT}"
                f"{self._wrap(a.body, ATOMIC)}"), ATOMIC - 1

    def _a_Call(self, a: c.Call) -> tuple[str, int]:
        if not a.args:
            return self.name(a.name), ATOMIC
        return f"{self.name(a.name)}({', '.join(self.expr(x) for x in a.args)})", ATOMIC

    def _a_Wait(self, a: c.Wait) -> tuple[str, int]:
        return f"Wait({self.expr(a.count)})", ATOMIC

    def _a_Assign(self, a: c.Assign) -> tuple[str, int]:
        targets = ", ".join(self.name(t) for t in a.targets)
        return f"{targets}{self.ASSIGN}{', '.join(self.expr(v) for v in a.values)}", PREFIX


def deviation_comments(marker: str, width: int = 92) -> list[str]:
    """Where the program departs from the paper (:data:`~cyphy.semantics.circus.rules.
    DEVIATIONS`), as comment lines that start with ``marker``, for the top of a printed
    program."""

    return [marker + line for d in DEVIATIONS
            for line in textwrap.wrap("Deviation from the paper: " + d, width - len(marker))]
