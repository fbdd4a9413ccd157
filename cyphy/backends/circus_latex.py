"""The CyPhyCircus program as LaTeX in the CZT Circus conventions (``isabelle.md`` §3).

Z and Circus paragraphs in their environments (``axdef``, ``schema``, ``circus``,
``circusaction``), the CZT macro names (``\\circprocess``, ``\\circbegin``, ``\\circstate``,
``\\then``, ``\\circseq``, ``\\interleave``, ``\\circmu``, ``\\circinterrupt``…), and what CZT
cannot parse (visible fields, ``\\Lambda``, ``\\derivative``, interrupts) between
``\\circtoolsoff`` and ``\\circtoolson``. A toolkit section declares what Z lacks (``\\real``,
``\\decimalpoint``, ``\\realdiv``, ``\\derivative``) and ``Wait``, the tock-counting wait.

Channel variants are separate channels (``registerRead\\_obstacle``): their payloads differ
in type, and a dotted name would be binding selection in Z. ``cyphycircus.sty`` (written
beside the document) defines every macro, so ``pdflatex`` typesets the file without CZT.
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.semantics import circus as c

_BP = {"<=>": 10, "=>": 10, "\\/": 20, "/\\": 30, "==": 50, "!=": 50, "<": 50, "<=": 50,
       ">": 50, ">=": 50, "+": 60, "-": 60, "cat": 60, "*": 70, "/": 70, "%": 70, "^": 90}
_RIGHT = {"<=>", "=>", "^"}
_ATOM = 100
_AND = 30
_OPS = {"<=>": "\\iff", "=>": "\\implies", "\\/": "\\lor", "/\\": "\\land", "==": "=",
        "!=": "\\neq", "<": "<", "<=": "\\leq", ">": ">", ">=": "\\geq", "+": "+", "-": "-",
        "cat": "\\cat", "*": "*", "/": "\\realdiv", "%": "\\mod", "^": "\\rpow"}
_TYPES = {"real": "\\real", "nat": "\\nat", "int": "\\num", "bool": "\\boolean"}


def name(text: str) -> str:
    """A mangled name in Z LaTeX: underscores escaped."""
    return text.replace("_", "\\_")


def channel_name(channel: str, tag: str | None) -> str:
    return name(channel if tag is None else f"{channel}_{tag}")


class LatexExpression:
    """Expressions in Z LaTeX; ``primed`` names are after-state values (``x'``)."""

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
        return e.text.replace(".", "\\decimalpoint "), _ATOM

    def _print_Bool(self, e: ex.Bool) -> tuple[str, int]:
        return ("\\true" if e.value else "\\false"), _ATOM

    def _print_Str(self, e: ex.Str) -> tuple[str, int]:
        return "\\mbox{``" + e.value.replace("\\", "") + "''}", _ATOM

    def _print_Name(self, e: ex.Name) -> tuple[str, int]:
        return name(e.text) + ("'" if e.text in self.primed else ""), _ATOM

    def _print_BinOp(self, e: ex.BinOp) -> tuple[str, int]:
        bp = _BP[e.op]
        left_min, right_min = (bp + 1, bp) if e.op in _RIGHT else (bp, bp + 1)
        return f"{self.wrap(e.left, left_min)} {_OPS[e.op]} {self.wrap(e.right, right_min)}", bp

    def _print_UnaryOp(self, e: ex.UnaryOp) -> tuple[str, int]:
        if e.op == "not":
            return f"\\lnot {self.wrap(e.operand, 40)}", 40
        return f"\\negate {self.wrap(e.operand, 80)}", 80

    def _print_Call(self, e: ex.Call) -> tuple[str, int]:
        return f"{self.wrap(e.func, _ATOM)}({', '.join(self.print(a) for a in e.args)})", _ATOM

    def _print_Index(self, e: ex.Index) -> tuple[str, int]:
        return f"{self.wrap(e.base, _ATOM)}({', '.join(self.print(a) for a in e.args)})", _ATOM

    def _print_Member(self, e: ex.Member) -> tuple[str, int]:
        return f"{self.wrap(e.base, _ATOM)}.{name(e.name)}", _ATOM

    def _print_Derivative(self, e: ex.Derivative) -> tuple[str, int]:
        return f"\\derivative{{{self.print(e.operand)}}}", _ATOM

    def _print_Integral(self, e: ex.Integral) -> tuple[str, int]:
        bounds = [b for b in (e.lower, e.upper) if b is not None]
        return f"\\integral({', '.join(self.print(a) for a in (e.operand, *bounds))})", _ATOM

    def _print_Seq(self, e: ex.Seq) -> tuple[str, int]:
        return "\\langle " + ", ".join(self.print(i) for i in e.items) + " \\rangle", _ATOM

    def _print_IfExpr(self, e: ex.IfExpr) -> tuple[str, int]:
        return (f"(\\IF {self.print(e.cond)} \\THEN {self.print(e.then)} "
                f"\\ELSE {self.print(e.orelse)})"), _ATOM


def latex_type(t: c.Type) -> str:
    if isinstance(t, c.TBasic):
        return _TYPES.get(t.name, name(t.name))
    if isinstance(t, c.TSeq):
        inner = latex_type(t.of)
        return f"\\seq {inner}" if isinstance(t.of, c.TBasic) else f"\\seq ({inner})"
    return " \\cross ".join(latex_type(i) for i in t.items)


def _bindings(bs: tuple[c.Binding, ...]) -> str:
    return "; ".join(f"{name(b.name)} : {latex_type(b.type)}" for b in bs)


_HIDE, _INTERLEAVE, _CHOICE, _INTERRUPT, _SEQ, _PREFIX, _ATOMIC = 10, 20, 30, 40, 50, 60, 100
_CYPHY_ONLY = (c.Evolution, c.InterruptCond, c.Interrupt)


class CircusLatex:
    """A whole program as a LaTeX document (``document``) or its CZT paragraphs."""

    def predicate(self, p: c.Predicate, primed: frozenset[str] = frozenset()) -> str:
        printer = LatexExpression(primed)
        if not isinstance(p, c.Exists):
            if isinstance(p, ex.Bool):
                return "true" if p.value else "false"
            return printer.print(p)
        body = " \\\\\n\t1 \\land ".join(printer.wrap(e, _AND + 1) for e in p.body) or "true"
        return f"(\\exists {_bindings(p.bound)} @ {body})" if p.bound else body

    def action(self, a: c.Action) -> str:
        return self._action(a)[0]

    def _action(self, a: c.Action) -> tuple[str, int]:
        method: Callable[[c.Action], tuple[str, int]] = getattr(self, "_a_" + type(a).__name__)
        return method(a)

    def _wrap(self, a: c.Action, min_bp: int) -> str:
        text, bp = self._action(a)
        return f"({text})" if bp < min_bp else text

    def _a_Skip(self, a: c.Skip) -> tuple[str, int]:
        return "\\Skip", _ATOMIC

    def _a_Stop(self, a: c.Stop) -> tuple[str, int]:
        return "\\Stop", _ATOMIC

    def comm(self, m: c.Comm) -> str:
        out = channel_name(m.channel, m.tag)
        for f in m.fields:
            if isinstance(f, c.In):
                out += f"?{name(f.name)}"
            else:
                out += ("!" if isinstance(f, c.Out) else ".") + \
                    LatexExpression().wrap(f.value, _ATOM)
        return out

    def _a_Prefix(self, a: c.Prefix) -> tuple[str, int]:
        return f"{self.comm(a.comm)} \\then {self._wrap(a.then, _PREFIX)}", _PREFIX

    def _a_Seq(self, a: c.Seq) -> tuple[str, int]:
        return " \\circseq \\\\\n\t1 ".join(self._wrap(i, _SEQ + 1) for i in a.items), _SEQ

    def _a_ExtChoice(self, a: c.ExtChoice) -> tuple[str, int]:
        return " \\extchoice ".join(self._wrap(i, _CHOICE + 1) for i in a.items), _CHOICE

    def _a_Interleave(self, a: c.Interleave) -> tuple[str, int]:
        return " \\interleave ".join(self._wrap(i, _INTERLEAVE + 1) for i in a.items), \
            _INTERLEAVE

    def _a_IndexedExtChoice(self, a: c.IndexedExtChoice) -> tuple[str, int]:
        v = name(a.var.name)
        return (f"\\Extchoice {v} : \\{{ {v} : {latex_type(a.var.type)} | "
                f"{self.predicate(a.where)} \\}} \\circspot {self._wrap(a.body, _PREFIX)}"), \
            _ATOMIC - 1

    def _a_Parallel(self, a: c.Parallel) -> tuple[str, int]:
        ns1 = ", ".join(name(n) for n in a.left_names)
        ns2 = ", ".join(name(n) for n in a.right_names)
        cs = ", ".join(name(n) for n in a.channels)
        return (f"{self._wrap(a.left, _ATOMIC)} \\lpar \\{{{ns1}\\}} | \\lchanset {cs} "
                f"\\rchanset | \\{{{ns2}\\}} \\rpar {self._wrap(a.right, _ATOMIC)}"), _INTERLEAVE

    def _a_Hide(self, a: c.Hide) -> tuple[str, int]:
        cs = ", ".join(name(n) for n in a.channels)
        return f"{self._wrap(a.action, _HIDE + 1)} \\circhide \\lchanset {cs} \\rchanset", _HIDE

    def _a_Cond(self, a: c.Cond) -> tuple[str, int]:
        cond = self.predicate(a.cond)
        return (f"\\circif {cond} \\circthen {self._wrap(a.then, _PREFIX)} \\\\\n\t1 "
                f"\\circelse \\lnot ({cond}) \\circthen {self._wrap(a.orelse, _PREFIX)} "
                f"\\circfi"), _ATOMIC

    def _a_Guard(self, a: c.Guard) -> tuple[str, int]:
        return (f"\\lcircguard {self.predicate(a.cond)} \\rcircguard \\circguard "
                f"{self._wrap(a.action, _PREFIX)}"), _PREFIX

    def _a_Mu(self, a: c.Mu) -> tuple[str, int]:
        return f"\\circmu {name(a.var)} \\circspot {self._wrap(a.body, _ATOMIC)}", _ATOMIC - 1

    def _a_Call(self, a: c.Call) -> tuple[str, int]:
        if not a.args:
            return name(a.name), _ATOMIC
        args = ", ".join(LatexExpression().print(x) for x in a.args)
        return f"{name(a.name)}({args})", _ATOMIC

    def _a_Interrupt(self, a: c.Interrupt) -> tuple[str, int]:
        return (f"{self._wrap(a.left, _INTERRUPT + 1)} \\circinterrupt "
                f"{self._wrap(a.right, _INTERRUPT + 1)}"), _INTERRUPT

    def _a_InterruptCond(self, a: c.InterruptCond) -> tuple[str, int]:
        return (f"{self._wrap(a.action, _INTERRUPT + 1)} \\circinterrupt "
                f"({self.predicate(a.cond)})"), _INTERRUPT

    def _a_Wait(self, a: c.Wait) -> tuple[str, int]:
        return f"Wait({LatexExpression().print(a.count)})", _ATOMIC

    def _a_Assign(self, a: c.Assign) -> tuple[str, int]:
        values = ", ".join(LatexExpression().print(v) for v in a.values)
        return f"{', '.join(name(t) for t in a.targets)} := {values}", _PREFIX

    def _a_Spec(self, a: c.Spec) -> tuple[str, int]:
        frame = ", ".join(name(n) for n in a.frame)
        return (f"{frame} \\prefixcolon [{self.predicate(a.pre)}, \\\\\n\t1 "
                f"{self.predicate(a.post, frozenset(a.frame))}]"), _ATOMIC

    def _a_Evolution(self, a: c.Evolution) -> tuple[str, int]:
        printer = LatexExpression()
        body = " \\\\\n\t1 \\land ".join(printer.wrap(e, _AND + 1) for e in a.equations)
        if a.locals is not None:
            body = f"\\exists {name(a.locals)} @ {body}"
        return f"\\lschexpract [\\Lambda {name(a.state)} | {body}] \\rschexpract", _ATOMIC

    def _a_VarBlock(self, a: c.VarBlock) -> tuple[str, int]:
        return (f"\\circvar {name(a.var.name)} : {latex_type(a.var.type)} \\circspot "
                f"{self._wrap(a.body, _ATOMIC)}"), _ATOMIC - 1

    # ----- the document
    def document(self, p: c.Program) -> str:
        section = name(p.system.name)
        out = ["% CyPhyCircus semantics generated by cyphy; CZT Circus conventions.",
               "% Typeset with pdflatex (cyphycircus.sty defines every macro used).",
               "\\documentclass{article}", "\\usepackage{cyphycircus}", "\\begin{document}", "",
               TOOLKIT, "",
               "\\begin{zsection}", f"  \\SECTION {section} \\parents cyphycircus\\_toolkit",
               "\\end{zsection}", ""]
        out += self._globals(p)
        out += self._channels(p)
        out += self._process(p.pmodel)
        out += [f"% {name(p.dmodel.name)}: the d-model's process. Its tock-CSP semantics is "
                "not generated;", "% Chaos stands for it (every process refines Chaos).",
                "\\begin{circus}",
                f"  \\circprocess {name(p.dmodel.name)} \\circdef \\circbegin \\circspot "
                "\\Chaos \\circend", "\\end{circus}", ""]
        body = p.system.body
        out += ["\\begin{circus}",
                f"  \\circprocess {section} \\circdef {self._process_expr(body, p)}",
                "\\end{circus}", "", "\\end{document}"]
        return "\n".join(out) + "\n"

    def _globals(self, p: c.Program) -> list[str]:
        e = LatexExpression()
        decls = " \\\\\n  ".join(f"{name(b.name)} : {latex_type(b.type)}"
                                 for b in p.globals.constants)
        where = " \\\\\n  ".join(e.print(w) for w in p.globals.where)
        out = ["\\begin{axdef}", f"  {decls}", "\\where", f"  {where}", "\\end{axdef}", ""]
        for f in p.functions:
            args = " \\cross ".join(["X"] * max(f.arity, 1))
            out += ["\\begin{gendef}[X]", f"  {name(f.name)} : {args} \\fun X",
                    "\\end{gendef}", ""]
        consts = p.pmodel.constants
        if consts:
            decls = " \\\\\n  ".join(f"{name(k.name)} : {latex_type(k.type)}" for k in consts)
            values = [f"{name(k.name)} = {e.print(k.value)}" for k in consts
                      if k.value is not None]
            out += ["\\begin{axdef}", f"  {decls}"]
            if values:
                out += ["\\where", "  " + " \\\\\n  ".join(values)]
            out += ["\\end{axdef}", ""]
        return out

    def _channels(self, p: c.Program) -> list[str]:
        lines = []
        for ch in p.channels:
            variants = ch.variants or (c.ChannelVariant(None, ()),) if ch.name == "tock" \
                else ch.variants
            for v in variants:
                types = " \\cross ".join(latex_type(t) for t in v.types)
                lines.append(f"\\circchannel {channel_name(ch.name, v.tag)}"
                             + (f" : {types}" if types else ""))
        return ["\\begin{circus}", "  " + " \\\\\n  ".join(lines), "\\end{circus}", ""]

    def _process(self, proc: c.BasicProcess) -> list[str]:
        out = ["\\begin{circus}", f"  \\circprocess {name(proc.name)} \\circdef \\circbegin",
               "\\end{circus}", ""]
        out += ["\\circtoolsoff", self._schema(proc.state), "\\circtoolson", "",
                "\\begin{circusaction}", f"  \\circstate {name(proc.state.name)}",
                "\\end{circusaction}", ""]
        if proc.local.fields:
            out += [self._schema(proc.local), ""]
        if any(isinstance(n, c.Wait) for n in c.walk(proc)):
            out += ["\\begin{circusaction}", "  " + WAIT, "\\end{circusaction}", ""]
        for d in [*proc.actions, None]:
            body = proc.main if d is None else d.body
            text = self.action(body)
            head = "\\circspot " if d is None else f"{name(d.name)} \\circdef "
            if d is not None and d.params:
                head += f"{_bindings(d.params)} \\circspot "
            cyphy_only = any(isinstance(n, _CYPHY_ONLY) for n in c.walk(body))
            block = ["\\begin{circusaction}", f"  {head}{text}", "\\end{circusaction}"]
            out += (["\\circtoolsoff", *block, "\\circtoolson"] if cyphy_only else block) + [""]
        out += ["\\begin{circus}", "  \\circend", "\\end{circus}", ""]
        return out

    def _schema(self, s: c.Schema) -> str:
        fields = " \\\\\n  ".join(("\\mathbf{visible}\\; " if f.visible else "")
                                  + f"{name(f.name)} : {latex_type(f.type)}" for f in s.fields)
        return f"\\begin{{schema}}{{{name(s.name)}}}\n  {fields}\n\\end{{schema}}"

    def _process_expr(self, e: c.ProcessExpr, p: c.Program) -> str:
        if isinstance(e, c.PRef):
            return name(e.name)
        cs = ", ".join(channel_name(ch.name, v.tag) for ch in p.channels
                       if ch.name in e.channels
                       for v in (ch.variants or (c.ChannelVariant(None, ()),)))
        if isinstance(e, c.PParallel):
            return (f"({self._process_expr(e.left, p)} \\lpar \\lchanset {cs} \\rchanset "
                    f"\\rpar {self._process_expr(e.right, p)})")
        return f"{self._process_expr(e.process, p)} \\circhide \\lchanset {cs} \\rchanset"


WAIT = ("Wait \\circdef n : \\nat \\circspot \\circif n > 0 \\circthen tock \\then Wait(n - 1) "
        "\\circelse n = 0 \\circthen \\Skip \\circfi")

TOOLKIT = r"""\begin{zsection}
  \SECTION cyphycircus\_toolkit \parents circus\_toolkit
\end{zsection}

%%Zword \real real
%%Zinword \decimalpoint decimalpoint
%%Zinword \realdiv realdiv
%%Zinword \rpow rpow
%%Zpreword \derivative derivative
%%Zpreword \integral integral
\begin{axdef}
  \real : \power \arithmos
\end{axdef}

\begin{gendef}[X]
  \derivative, \integral : X \fun X
\end{gendef}"""


STYLE = r"""% cyphycircus.sty: the CZT Circus macros that cyphy's LaTeX output uses, defined for
% plain pdflatex (no CZT needed). Generated by cyphy; layout only, no checking.
\NeedsTeXFormat{LaTeX2e}
\ProvidesPackage{cyphycircus}[2026/11/22 cyphy CyPhyCircus macros]
\RequirePackage{latexsym}
\ifdefined\pdfobjcompresslevel\pdfobjcompresslevel=0\fi % page objects readable
\newcommand{\cyphyenv}{\par\noindent\small$\begin{array}{@{}l@{}}}
\newcommand{\cyphyboxenv}{\par\noindent\small$\begin{array}{|@{\ }l@{}}}
\newcommand{\cyphyend}{\end{array}$\par\medskip}
\newenvironment{zsection}{\par\noindent\begingroup\ttfamily}{\endgroup\par\medskip}
\newcommand{\SECTION}{\textbf{section}~}
\newcommand{\parents}{~\textbf{parents}~}
\newenvironment{zed}{\cyphyenv}{\cyphyend}
\newenvironment{circus}{\cyphyenv}{\cyphyend}
\newenvironment{circusaction}{\cyphyenv}{\cyphyend}
\newenvironment{axdef}{\cyphyboxenv}{\cyphyend}
\newenvironment{gendef}[1][]{\cyphyboxenv}{\cyphyend}
\newenvironment{schema}[1]{\cyphyboxenv\multicolumn{1}{@{}l}{\mbox{---\ #1\ ---}}\\}{\cyphyend}
\newcommand{\where}{\\\hline}
\newcommand{\also}{\\}
\renewcommand{\t}[1]{\quad}
\newcommand{\circtoolsoff}{}
\newcommand{\circtoolson}{}
\newcommand{\real}{\mathbf{R}}
\newcommand{\nat}{\mathbf{N}}
\newcommand{\num}{\mathbf{Z}}
\newcommand{\arithmos}{\mathbf{A}}
\newcommand{\boolean}{\mathbf{B}}
\newcommand{\power}{\mathbf{P}\,}
\newcommand{\cross}{\times}
\newcommand{\fun}{\rightarrow}
\newcommand{\seq}{\mathrm{seq}\,}
\newcommand{\true}{\mathit{True}}
\newcommand{\false}{\mathit{False}}
\newcommand{\negate}{-}
\newcommand{\decimalpoint}{.}
\newcommand{\realdiv}{/}
\newcommand{\rpow}{\uparrow}
\newcommand{\cat}{\frown}
\providecommand{\implies}{\Rightarrow}
\newcommand{\derivative}[1]{\dot{#1}}
\newcommand{\integral}{\int\!}
\newcommand{\IF}{\mathbf{if}~}
\newcommand{\THEN}{~\mathbf{then}~}
\newcommand{\ELSE}{~\mathbf{else}~}
\newcommand{\circchannel}{\mathbf{channel}~}
\newcommand{\circprocess}{\mathbf{process}~}
\newcommand{\circdef}{\mathrel{\widehat=}}
\newcommand{\circbegin}{\mathbf{begin}}
\newcommand{\circend}{\mathbf{end}}
\newcommand{\circstate}{\mathbf{state}~}
\newcommand{\circspot}{\mathrel{\bullet}}
\newcommand{\circseq}{\mathbin{;}}
\newcommand{\then}{\rightarrow}
\newcommand{\extchoice}{\mathbin{\Box}}
\newcommand{\Extchoice}{\Box\,}
\newcommand{\interleave}{\mathbin{|||}}
\newcommand{\lpar}{\mathbin{[\![}}
\newcommand{\rpar}{\mathbin{]\!]}}
\newcommand{\lchanset}{\{\!|}
\newcommand{\rchanset}{|\!\}}
\newcommand{\circhide}{\mathbin{\backslash}}
\newcommand{\circinterrupt}{\mathbin{\triangle}}
\newcommand{\circmu}{\mu\,}
\newcommand{\lcircguard}{(}
\newcommand{\rcircguard}{)}
\newcommand{\circguard}{\mathbin{\&}}
\newcommand{\circif}{\mathbf{if}~}
\newcommand{\circthen}{\rightarrow}
\newcommand{\circelse}{~\Box~}
\newcommand{\circfi}{~\mathbf{fi}}
\newcommand{\circvar}{\mathbf{var}~}
\newcommand{\prefixcolon}{:}
\newcommand{\lschexpract}{}
\newcommand{\rschexpract}{}
\newcommand{\Skip}{\mathbf{Skip}}
\newcommand{\Stop}{\mathbf{Stop}}
\newcommand{\Chaos}{\mathbf{Chaos}}
\endinput
"""


def program_to_latex(program: c.Program) -> str:
    return CircusLatex().document(program)
