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

from cyphy import expr as ex
from cyphy.backends.circus.actions import (ATOMIC, INTERLEAVE, PREFIX, ActionPrinter,
                                          deviation_comments)
from cyphy.lang.notation import ATOM, NotationPrinter
from cyphy.semantics.circus import ast as c

_TYPES = {"real": "\\real", "nat": "\\nat", "int": "\\num", "bool": "\\boolean"}


def name(text: str) -> str:
    """A mangled name in Z LaTeX: underscores escaped."""
    return text.replace("_", "\\_")


#: LaTeX's special characters in text mode, each as the command that prints it.
_TEXT_ESCAPES = {"\\": "\\textbackslash{}", "{": "\\{", "}": "\\}", "$": "\\$", "%": "\\%",
                 "#": "\\#", "&": "\\&", "_": "\\_", "^": "\\textasciicircum{}",
                 "~": "\\textasciitilde{}", "<": "\\textless{}", ">": "\\textgreater{}",
                 "|": "\\textbar{}"}


def text_mode(text: str) -> str:
    """A string constant as LaTeX text that prints it as written: special characters
    escaped, control characters (which TeX cannot print) as ``?``."""
    return "".join(_TEXT_ESCAPES.get(ch, "?" if ord(ch) < 32 or ord(ch) == 127 else ch)
                   for ch in text)


def channel_name(channel: str, tag: str | None) -> str:
    return name(channel if tag is None else f"{channel}_{tag}")


class LatexExpression(NotationPrinter):
    """Expressions in Z LaTeX; ``primed`` names are after-state values (``x'``)."""

    operators = {"<=>": "\\iff", "=>": "\\implies", "\\/": "\\lor", "/\\": "\\land",
                 "==": "=", "!=": "\\neq", "<": "<", "<=": "\\leq", ">": ">", ">=": "\\geq",
                 "+": "+", "-": "-", "cat": "\\cat", "*": "*", "/": "\\realdiv", "%": "\\mod",
                 "^": "\\rpow"}
    prefixes = {"not": "\\lnot ", "-": "\\negate "}

    def __init__(self, primed: frozenset[str] = frozenset()) -> None:
        self.primed = primed

    def _print_Num(self, e: ex.Num) -> tuple[str, int]:
        return e.text.replace(".", "\\decimalpoint "), ATOM

    def _print_Bool(self, e: ex.Bool) -> tuple[str, int]:
        return ("\\true" if e.value else "\\false"), ATOM

    def _print_Str(self, e: ex.Str) -> tuple[str, int]:
        return "\\mbox{``" + text_mode(e.value) + "''}", ATOM

    def _print_Name(self, e: ex.Name) -> tuple[str, int]:
        return name(e.text) + ("'" if e.text in self.primed else ""), ATOM

    def _print_Index(self, e: ex.Index) -> tuple[str, int]:
        return f"{self.wrap(e.base, ATOM)}({', '.join(self.print(a) for a in e.args)})", ATOM

    def _print_Member(self, e: ex.Member) -> tuple[str, int]:
        return f"{self.wrap(e.base, ATOM)}.{name(e.name)}", ATOM

    def _print_Derivative(self, e: ex.Derivative) -> tuple[str, int]:
        return f"\\derivative{{{self.print(e.operand)}}}", ATOM

    def _print_Integral(self, e: ex.Integral) -> tuple[str, int]:
        bounds = [b for b in (e.lower, e.upper) if b is not None]
        return f"\\integral({', '.join(self.print(a) for a in (e.operand, *bounds))})", ATOM

    def _print_Seq(self, e: ex.Seq) -> tuple[str, int]:
        return "\\langle " + ", ".join(self.print(i) for i in e.items) + " \\rangle", ATOM

    def _print_IfExpr(self, e: ex.IfExpr) -> tuple[str, int]:
        return (f"(\\IF {self.print(e.cond)} \\THEN {self.print(e.then)} "
                f"\\ELSE {self.print(e.orelse)})"), ATOM


def latex_type(t: c.Type) -> str:
    if isinstance(t, c.TBasic):
        return _TYPES.get(t.name, name(t.name))
    if isinstance(t, c.TSeq):
        inner = latex_type(t.of)
        return f"\\seq {inner}" if isinstance(t.of, c.TBasic) else f"\\seq ({inner})"
    return " \\cross ".join(latex_type(i) for i in t.items)


_CYPHY_ONLY = (c.Evolution, c.InterruptCond, c.Interrupt)
_BREAK = " \\\\\n\t1 "  # a line break in a CZT paragraph, indented


class CircusLatex(ActionPrinter):
    """A whole program as a LaTeX document (``document``) or its CZT paragraphs."""

    expressions = LatexExpression
    SKIP, STOP = "\\Skip", "\\Stop"
    THEN, SEQ, CHOICE = " \\then ", " \\circseq" + _BREAK, " \\extchoice "
    INTERLEAVE, INTERRUPT = " \\interleave ", " \\circinterrupt "
    MU, SPOT, VAR = "\\circmu ", " \\circspot ", "\\circvar "
    AND = _BREAK + "\\land "

    def name(self, text: str) -> str:
        return name(text)

    def type(self, t: c.Type) -> str:
        return latex_type(t)

    def channel(self, channel: str, tag: str | None) -> str:
        return channel_name(channel, tag)

    def exists(self, bindings: str, body: str) -> str:
        return f"(\\exists {bindings} @ {body})"

    def guard(self, cond: str, action: str) -> str:
        return f"\\lcircguard {cond} \\rcircguard \\circguard {action}"

    def chanset(self, channels: tuple[str, ...]) -> str:
        return f"\\circhide \\lchanset {', '.join(name(n) for n in channels)} \\rchanset"

    def predicate(self, p: c.Predicate, primed: frozenset[str] = frozenset()) -> str:
        """A predicate that is a boolean literal is ``true``/``false`` (Z's predicates), not
        the values ``\\true``/``\\false``."""
        if isinstance(p, ex.Bool):
            return "true" if p.value else "false"
        return super().predicate(p, primed)

    def _a_IndexedExtChoice(self, a: c.IndexedExtChoice) -> tuple[str, int]:
        v = name(a.var.name)
        return (f"\\Extchoice {v} : \\{{ {v} : {latex_type(a.var.type)} | "
                f"{self.predicate(a.where)} \\}} \\circspot {self._wrap(a.body, PREFIX)}"), \
            ATOMIC - 1

    def _a_Parallel(self, a: c.Parallel) -> tuple[str, int]:
        ns1 = ", ".join(name(n) for n in a.left_names)
        ns2 = ", ".join(name(n) for n in a.right_names)
        cs = ", ".join(name(n) for n in a.channels)
        return (f"{self._wrap(a.left, ATOMIC)} \\lpar \\{{{ns1}\\}} | \\lchanset {cs} "
                f"\\rchanset | \\{{{ns2}\\}} \\rpar {self._wrap(a.right, ATOMIC)}"), INTERLEAVE

    def _a_Cond(self, a: c.Cond) -> tuple[str, int]:
        cond = self.predicate(a.cond)
        return (f"\\circif {cond} \\circthen {self._wrap(a.then, PREFIX)}{_BREAK}"
                f"\\circelse \\lnot ({cond}) \\circthen {self._wrap(a.orelse, PREFIX)} "
                f"\\circfi"), ATOMIC

    def _a_Spec(self, a: c.Spec) -> tuple[str, int]:
        frame = ", ".join(name(n) for n in a.frame)
        return (f"{frame} \\prefixcolon [{self.predicate(a.pre)},{_BREAK}"
                f"{self.predicate(a.post, frozenset(a.frame))}]"), ATOMIC

    def _a_Evolution(self, a: c.Evolution) -> tuple[str, int]:
        body = self.conjunction(a.equations)
        if a.locals is not None:
            body = f"\\exists {name(a.locals)} @ {body}"
        return f"\\lschexpract [\\Lambda {name(a.state)} | {body}] \\rschexpract", ATOMIC

    # ----- the document
    def document(self, p: c.Program) -> str:
        section = name(p.system.name)
        out = ["% CyPhyCircus semantics generated by cyphy; CZT Circus conventions.",
               "% Typeset with pdflatex (cyphycircus.sty defines every macro used).",
               *deviation_comments("% "),
               "\\documentclass{article}", "\\usepackage{cyphycircus}", "\\begin{document}", "",
               TOOLKIT, "",
               "\\begin{zsection}", f"  \\SECTION {section} \\parents cyphycircus\\_toolkit",
               "\\end{zsection}", ""]
        out += self._globals(p)
        out += self._channels(p)
        if isinstance(p.dmodel, c.BasicProcess):  # D, from the d-model's state machine
            out += self._process(p.dmodel)
        out += self._process(p.pmodel)
        if not isinstance(p.dmodel, c.BasicProcess):
            out += [f"% {name(p.dmodel.name)}: the d-model's process. The files have no state "
                    "machine to write it from;", "% Chaos stands for it (every process "
                    "refines Chaos).", "\\begin{circus}",
                    f"  \\circprocess {name(p.dmodel.name)} \\circdef \\circbegin "
                    "\\circspot \\Chaos \\circend", "\\end{circus}", ""]
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
        consts = c.program_constants(p)
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
                head += f"{self.bindings(d.params)} \\circspot "
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
