"""CyPhyCircus actions in the syntax of isabelle-utp/Ax_CyPhyCircus (the axiomatic dialect).

The same action AST as :class:`cyphy.backends.isabelle.terms.IsabellePrinter` prints for utp-main's
2020 Circus, in the notation that Ax_CyPhyCircus binds to its axiomatised ``cyphyaction``
operators through IsaCircus's generic syntax (``../shared/spec/isabelle.md`` sections 1.3 and
2.5): ``c\\<^bold>!(e) \\<rightarrow> P``, ``c\\<^bold>?x \\<rightarrow> P``, ``(b) \\<^bold>& P``,
``P \\<lhd> b \\<rhd> Q``, ``\\<interleave>``, ``\\<triangle>``, ``\\<triangle>\\<^sub>p (b)``,
``\\<mu> X. P``, ``x := e``, ``(x, y):[p, q]`` and the evolution ``[\\<Lambda> x` = f, …]``.

Only what differs is overridden. Expressions are plain HOL terms throughout (the dialect's
syntax translations lift them over the state: a state variable is written by its lens name,
as in the Ranger examples), so the printer stays in the parent's ``hol`` mode. The evolution
is printed from the explicit ODEs of :mod:`cyphy.semantics.dynamics.evolve_odes`, given to the printer:
the AST's DAE form has no counterpart in this dialect.
"""

from __future__ import annotations

from typing import Any

from cyphy import expr as ex
from cyphy.semantics.dynamics.evolve_odes import ExplicitOde
from cyphy.backends.isabelle.terms import IsabellePrinter, Symbols, UnsupportedNode
from cyphy.semantics.circus import ast as c

#: Constants and syntax words of Ax_CyPhyCircus (its axiomatization, lines 34-61, and
#: adhoc_overloading, lines 64-84), IsaCircus_Syntax and Abstract_Prog_Syntax that a
#: generated name must not take (``Evolve`` is the operator the evolution uses); the outer
#: keywords of the sessions below it (a definition's name cannot be one): Circus_Toolkit's
#: Recursive.thy:5 and Action_Command.thy:5, Shallow-Expressions' Expressions.thy:5 and
#: Named_Expressions.thy:5, Optics' Channel_Type.thy:5, Dataspace.thy:5, Lens_Instances.thy:5
#: and Alphabet_Scene_Spaces.thy:5, Z_Toolkit's Def_Const, Enum_Type,
#: Partial_Function_Command, Record_Default_Instance and Tabulate_Command (line 5 each);
#: the mixfix words of Optics (Lens_Laws.thy:14-66: get, put, lset, pget, src, create,
#: update; Prisms.thy:14-20: match, build, matches), Z_Toolkit (Function_Toolkit.thy:67:
#: partitions) and Shallow-Expressions (Local_State.thy:20: localstate);
#: and the constants the printed notation denotes (Shallow-Expressions' SEXP, subst_id,
#: subst_upd, var_pair; Optics' zero_lens; Channels_Events' chinst1, csbasic, csinsert (the
#: channel set \<lbrace>…\<rbrace>, lines 74-105); HOL's powr, arctan,
#: uminus, Ex), which a definition of the same name would shadow.
AX_RESERVED = frozenset("""
cyphyaction cyphyprocess cSpec cAssigns cSeq cCond cAlternList cVarBlock cStop cChaos cGuard
cAssume cInputPrefix cOutputPrefix cSyncPrefix cExtChoice cExtChoiceIdx cRename cHide
cParallelAct cParallel cInterrupt cEvolve cInterruptCond cTimeout cSkip Spec Guard Assume
InputPrefix OutputPrefix SyncPrefix ExtChoice ExtChoiceIdx Rename Hide ParallelAct Parallel
Interrupt Replicate Evolve Timeout InterruptCond ucond useq uassigns uskip utest uwhile uuntil
repeat until swap elseif old channel chantype expr subst_id
recursive actions expr_constructor expr_function edefinition expression over zstore zexpr
alphabet_scene_space dataspace constants variables channels statespace def_consts enumtype
zfun precondition postcondition record_default tabulate
get put lset pget src create update match build matches partitions localstate
SEXP subst_upd var_pair zero_lens chinst1 csbasic csinsert powr arctan uminus Ex
""".split())


class AxiomaticPrinter(IsabellePrinter):
    """The Ax_CyPhyCircus notation; ``odes`` are Evolve's explicit ODEs (None: an
    evolution cannot be printed)."""

    INTERLEAVE = "\\<interleave>"
    GUARD = "\\<^bold>&"
    CHOICE_DOT = "."
    COND = ("\\<lhd>", "\\<rhd>")
    INTERRUPT = "\\<triangle>"
    ASSIGN = ":="
    EXISTS = "\\<exists>"
    TRUE = "True"
    ARROW = "\\<rightarrow>"

    def __init__(self, symbols: Symbols, odes: list[ExplicitOde] | None = None,
                 **settings: Any) -> None:
        super().__init__(symbols, **settings)
        self.odes = odes

    def _globals(self) -> set[str]:
        return super()._globals() | AX_RESERVED

    def action(self, a: c.Action) -> str:
        with self._in_mode("hol", coerce_nat=True):
            return self._print(a)

    # ------------------------------------------------------------------ expressions

    def _print_Derivative(self, e: ex.Derivative) -> str:
        raise UnsupportedNode(e, "a derivative outside the evolution")

    def _print_Integral(self, e: ex.Integral) -> str:
        raise UnsupportedNode(e, "an integral outside the evolution")

    # ------------------------------------------------------------------ actions

    def _input_event(self, ctor: str, idents: list[str]) -> str:
        bound = idents[0] if len(idents) == 1 else f"({', '.join(idents)})"
        return f"{ctor}\\<^bold>?{bound}"

    def _output_event(self, ctor: str, output: bool, values: list[ex.Expr]) -> str:
        mark = "\\<^bold>!" if output else "\\<^bold>."
        return f"{ctor}{mark}({', '.join(self._print(v) for v in values)})"

    def _print_Parallel(self, a: c.Parallel) -> str:
        """``P \\<lbrakk>ns1 | {} | ns2\\<rbrakk> Q``: IsaCircus_Syntax reads the name sets
        there as ``svids`` (Circus_Toolkit IsaCircus_Syntax.thy:80), whose forms are a variable
        ``x`` and a tuple ``(x, y)`` (Shallow-Expressions Variables.thy:212-218): neither the
        term ``((x, y))\\<^sub>v`` nor the zero lens is one. A side with no names is written
        with the operator the notation denotes, ``cParallelAct ns1 ns2 {} P Q``
        (Ax_CyPhyCircus.thy:52), whose name sets are lens terms."""
        if a.channels:
            raise UnsupportedNode(a, "synchronisation on channels inside an action")
        left, right = self._print(a.left), self._print(a.right)
        if a.left_names and a.right_names:
            return (f"({left} \\<lbrakk>{self._svid(a.left_names)} | {{}} | "
                    f"{self._svid(a.right_names)}\\<rbrakk> {right})")
        return (f"(cParallelAct {self._lens(a.left_names)} {self._lens(a.right_names)} {{}} "
                f"{left} {right})")

    def _svid(self, names: tuple[str, ...]) -> str:
        idents = [self.symbols.names[n] for n in names]
        return idents[0] if len(idents) == 1 else "(" + ", ".join(idents) + ")"

    def _lens(self, names: tuple[str, ...]) -> str:
        """A name set as the lens of its variables, as the dialect's own example writes
        them (examples/Ranger_CyPhyCircus.thy: a variable ``x``, a tuple ``((x, y))\\<^sub>v``);
        empty: Optics' zero lens ``0\\<^sub>L`` (optics/Lens_Algebra.thy)."""
        if not names:
            return "0\\<^sub>L"
        idents = [self.symbols.names[n] for n in names]
        return idents[0] if len(idents) == 1 else "((" + ", ".join(idents) + "))\\<^sub>v"

    def _print_Mu(self, a: c.Mu) -> str:
        with self.binding([a.var]) as (ident,):
            return f"(\\<mu> {ident}. {self._print(a.body)})"

    def _print_InterruptCond(self, a: c.InterruptCond) -> str:
        return f"({self._print(a.action)} \\<triangle>\\<^sub>p {self._print(a.cond)})"

    def _print_Wait(self, a: c.Wait) -> str:
        with self._in_mode("hol", coerce_nat=False):
            count = self._print(a.count)
        return f"({self.symbols.names['WaitT']} {count})"

    def _print_Spec(self, a: c.Spec) -> str:
        """``cSpec frame (pre)\\<^sub>e (post)\\<^sub>e``: Ax_CyPhyCircus declares ``cSpec``
        (Ax_CyPhyCircus.thy, line 35) but its ``adhoc_overloading`` (lines 64-84) does not
        bind the generic ``Spec`` of the ``w:[p, q]`` notation to it, so the notation would
        denote an unrelated constant. Pre- and postcondition are predicates on one state
        (the postcondition on the after-state), quoted as Shallow-Expressions does."""
        frame = self._lens(a.frame)
        return f"(cSpec {frame} ({self._print(a.pre)})\\<^sub>e ({self._print(a.post)})\\<^sub>e)"

    def _print_Evolution(self, a: c.Evolution) -> str:
        if self.odes is None:
            raise UnsupportedNode(a, "the evolution has no explicit ODEs")
        sep = ",\n      " if len(self.odes) > 2 else ", "
        odes = sep.join(f"{self.symbols.names[o.variable]}` = {self._print(o.rhs)}"
                        for o in self.odes)
        return f"[\\<Lambda> {odes}]"
