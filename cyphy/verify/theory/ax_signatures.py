"""The signature table of ``cyphy check-theory``'s axiomatic-dialect checker (ax_types.py): the
type of every constant and syntax translation of Ax_CyPhyCircus and its public parents that the
Isabelle printer uses, each with the source it was read from; HOL's entries are the utp
checker's; and the words no name may be (the parents' mixfix and outer keywords)."""

from __future__ import annotations

from cyphy.backends.isabelle.ax_terms import AX_RESERVED
from cyphy.backends.isabelle.library_words import HOL_SYNTAX_WORDS
from cyphy.backends.isabelle.names import OUTER_KEYWORDS
from cyphy.verify.theory.utp_signatures import SIGNATURES

AX = "Ax_CyPhyCircus 8bfbe4a "
CT = "Circus_Toolkit 97811b8 "
APS = "Abstract_Prog_Syntax b97410d "
SE = "Shallow-Expressions 4ed4348 "
OP = "Optics f48265c "
A = "('e, 's) cyphyaction"
R = "\\<Rightarrow>"

#: name → (type, where it was read). ``expr`` is ``'s ⇒ 'a`` (SE Expressions.thy:23), a
#: channel a prism ``'a \\<Longrightarrow>\\<^sub>\\<triangle> 'e`` (CT IsaCircus_Syntax.thy:36).
AX_SIGNATURES: dict[str, tuple[str, str]] = {
    "Skip": (A, AX + "Ax_CyPhyCircus.thy:61 (cSkip; adhoc Skip, line 70; "
             "Skip: " + CT + "IsaCircus_Syntax.thy:41)"),
    "Stop": (A, AX + "Ax_CyPhyCircus.thy:41 (cStop; adhoc Stop, line 71; "
             "Stop: " + CT + "IsaCircus_Syntax.thy:42)"),
    ";;": (f"{A} {R} {A} {R} {A}", AX + "Ax_CyPhyCircus.thy:37 (cSeq; adhoc useq, line 65; "
           "useq (infixr ;;): " + APS + "Abstract_Prog_Syntax.thy:15)"),
    "\\<box>": (f"{A} {R} {A} {R} {A}", AX + "Ax_CyPhyCircus.thy:48 (cExtChoice; adhoc line 73; "
                "infixl \\<box>: " + CT + "IsaCircus_Syntax.thy:50)"),
    "cParallel": (f"'e set {R} {A} {R} {A} {R} {A}",
                  AX + "Ax_CyPhyCircus.thy:53 (adhoc Parallel, line 80; \\<interleave> is "
                  "Parallel {}: " + CT + "IsaCircus_Syntax.thy:77, 96)"),
    "{}": ("'a set", "HOL/Set.thy empty"),
    "cParallelAct": ("('a \\<Longrightarrow> 's) \\<Rightarrow> ('b \\<Longrightarrow> 's) "
                     f"{R} 'e set {R} {A} {R} {A} {R} {A}",
                     AX + "Ax_CyPhyCircus.thy:52 (adhoc ParallelAct, line 81; "
                     "P \\<lbrakk>ns1|A|ns2\\<rbrakk> Q: " + CT + "IsaCircus_Syntax.thy:80, 100)"),
    "cHide": (f"{A} {R} 'e set {R} {A}",
              AX + "Ax_CyPhyCircus.thy:51 (adhoc Hide, line 79; P \\<Zhide> A is Hide P A: "
              + CT + "IsaCircus_Syntax.thy:81, 101)"),
    "csbasic": ("('a, 'e) prism \\<Rightarrow> 'e set",
                CT + "Channels_Events.thy:74 (\\<lbrace>c\\<rbrace>: _ch_enum, lines 92, 102)"),
    "csinsert": ("('a, 'e) prism \\<Rightarrow> 'e set \\<Rightarrow> 'e set",
                 CT + "Channels_Events.thy:80 (\\<lbrace>c, cs\\<rbrace>: _chans, lines 91, 105)"),
    "cCond": (f"{A} {R} ('s {R} bool) {R} {A} {R} {A}",
              AX + "Ax_CyPhyCircus.thy:38 (adhoc ucond, line 67; P \\<lhd> b \\<rhd> Q is "
              "ucond P (b)\\<^sub>e Q: " + APS + "Abstract_Prog_Syntax.thy:36, 48)"),
    "cGuard": (f"('s {R} bool) {R} {A} {R} {A}",
               AX + "Ax_CyPhyCircus.thy:43 (adhoc Guard, line 72; b \\<^bold>& P is "
               "Guard (b)\\<^sub>e P: " + CT + "IsaCircus_Syntax.thy:67, 89)"),
    "cInterrupt": (f"{A} {R} {A} {R} {A}",
                   AX + "Ax_CyPhyCircus.thy:54 (adhoc Interrupt, line 77; infixl "
                   "\\<triangle>: " + CT + "IsaCircus_Syntax.thy:56)"),
    "cInterruptCond": (f"{A} {R} ('s {R} bool) {R} {A}",
                       AX + "Ax_CyPhyCircus.thy:58 (adhoc InterruptCond, line 84); the syntax "
                       "P \\<triangle>\\<^sub>p (b): use site, examples/Ranger_CyPhyCircus.thy:30"),
    "cEvolve": ("('a::real_normed_vector \\<Longrightarrow> 's) \\<Rightarrow> "
                "('s \\<Rightarrow> 's) "
                f"{R} ('s {R} bool) {R} {A}",
                AX + "Ax_CyPhyCircus.thy:57 (adhoc Evolve, line 82); the syntax "
                "[\\<Lambda> x` = e, ...]: use site, examples/Ranger_CyPhyCircus.thy:30"),
    "\\<mu>": ("('a::complete_lattice \\<Rightarrow> 'a) \\<Rightarrow> 'a",
           "use site, " + AX + "examples/Ranger_CyPhyCircus.thy:48 (\\<mu> X. P); cyphyaction "
           "is a complete_lattice: Ax_CyPhyCircus.thy:18-21"),
    "cAssigns": (f"('s {R} 's) {R} {A}",
                 AX + "Ax_CyPhyCircus.thy:36 (adhoc uassigns, line 66; x := e is uassigns "
                 "(subst_upd subst_id x (e)\\<^sub>e): " + APS
                 + "Abstract_Prog_Syntax.thy:41, 57)"),
    "subst_id": ("'s \\<Rightarrow> 's", SE + "Substitutions.thy:17 (psubst: line 12)"),
    "subst_upd": ("('s1 \\<Rightarrow> 's2) \\<Rightarrow> ('a \\<Longrightarrow> 's2) "
                  "\\<Rightarrow> "
                  "('s1 \\<Rightarrow> 'a) \\<Rightarrow> ('s1 \\<Rightarrow> 's2)",
                  SE + "Substitutions.thy:28"),
    "var_pair": ("('a \\<Longrightarrow> 's) \\<Rightarrow> ('b \\<Longrightarrow> 's) "
                 "\\<Rightarrow> ('a \\<times> 'b \\<Longrightarrow> 's)",
                 SE + "Variables.thy:56 ((x, y) as an svid: _svid_tuple, lines 218, 286, 296; "
                 "((x, y))\\<^sub>v: _svar, line 273)"),
    "zero_lens": ("unit \\<Longrightarrow> 'a", OP + "Lens_Algebra.thy:72 (0\\<^sub>L)"),
    "cSpec": ("('a \\<Longrightarrow> 's) \\<Rightarrow> ('s \\<Rightarrow> bool) \\<Rightarrow> "
              f"('s {R} bool) {R} {A}", AX + "Ax_CyPhyCircus.thy:35"),
    "SEXP": ("('s \\<Rightarrow> 'a) \\<Rightarrow> ('s \\<Rightarrow> 'a)",
             SE + "Expressions.thy:28 ((e)\\<^sub>e: _sexp_quote, line 71)"),
    "cOutputPrefix": (f"('a, 'e) prism {R} ('s {R} 'a) {R} {A} {R} {A}",
                      AX + "Ax_CyPhyCircus.thy:46 (adhoc OutputPrefix, line 75; c\\<^bold>!(e) "
                      "\\<rightarrow> P: " + CT + "IsaCircus_Syntax.thy:75, 94)"),
    "cInputPrefix": (f"('a, 'e) prism {R} 'a set {R} ('a {R} (('s {R} bool) \\<times> {A})) "
                     f"{R} {A}",
                     AX + "Ax_CyPhyCircus.thy:45 (adhoc InputPrefix, line 74; c\\<^bold>?x "
                     "\\<rightarrow> P: " + CT + "IsaCircus_Syntax.thy:68, 90)"),
    "cSyncPrefix": (f"(unit, 'e) prism {R} {A} {R} {A}",
                    AX + "Ax_CyPhyCircus.thy:47 (adhoc SyncPrefix, line 76; c \\<rightarrow> P: "
                    + CT + "IsaCircus_Syntax.thy:76, 95)"),
    "chinst1": ("('a, 'e) prism \\<Rightarrow> 'a \\<Rightarrow> (unit, 'e) prism",
                CT + "Channels_Events.thy:30 (c\\<^bold>.v: _chan_inst, line 89, 98; _chinst, "
                "line 51)"),
    "cExtChoiceIdx": (f"'i set {R} ('i {R} {A}) {R} {A}",
                      AX + "Ax_CyPhyCircus.thy:49 (\\<box>x\\<in>A. P: " + CT
                      + "IsaCircus_Syntax.thy:83, 103)"),
    "UNIV": ("'a set", "HOL/Set.thy UNIV"),
    "Ex": ("('a \\<Rightarrow> bool) \\<Rightarrow> bool", "HOL/HOL.thy Ex (\\<exists>x. P)"),
    "\\<and>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool", "HOL/HOL.thy conj"),
    "\\<or>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool", "HOL/HOL.thy disj"),
    "\\<not>": ("bool \\<Rightarrow> bool", "HOL/HOL.thy Not"),
}
#: HOL's constants, read in Isabelle2020's HOL theories (the utp checker's entries).
_HOL = ("+", "-", "*", "/", "^", "powr", "uminus", "=", "\\<noteq>", "<", ">", "\\<le>",
        "\\<ge>", "\\<longrightarrow>", "\\<longleftrightarrow>", "@", "!", "real", "real_of_int", "True",
        "False", "sin", "cos", "tan", "arctan", "exp", "ln", "sqrt", "abs")
for _name in _HOL:
    AX_SIGNATURES[_name] = SIGNATURES[_name]

#: What the checker assumes with no public source to read it from (README, Isabelle section).
UNCHECKED = (
    "CyPhyCircus_Toolkit: the session itself (Ax_CyPhyCircus's parent); the constants "
    "Evolve, InterruptCond, Timeout and the syntax [\\<Lambda> ...], \\<triangle>\\<^sub>p, "
    "\\<mu> X. P are typed from their use in examples/Ranger_CyPhyCircus.thy",
    "that the parent imports HOL's Transcendental (sin, cos, tan, arctan, exp, ln, sqrt, powr) "
    "and Circus_Toolkit, Abstract_Prog_Syntax, Shallow-Expressions and Optics at the versions "
    "read",
)

#: Words no name in a term may be: HOL's inner words and the mixfix words of the public
#: parents. (A delimiter glued to a bracket, ``swap(`` of Abstract_Prog_Syntax.thy:42 or
#: ``H{`` of line 82, leaves the bare word an identifier.)
AX_INNER_KEYWORDS = frozenset(
    # HOL's and Pure's mixfix words, derived from the sources (reserved_words.tsv)
    list(HOL_SYNTAX_WORDS)
    # Abstract_Prog_Syntax.thy:18 (II), 37-39 (if/then/fi, elseif, else), 44 (while/do/od),
    # 45 (repeat/until); IsaCircus_Syntax.thy:41-43 (Skip, Stop, Chaos)
    + "II fi elseif while do od repeat until Skip Stop Chaos".split()
    # delimiters before an \<index>: Optics Lens_Laws.thy:14 (get), 15 (put), 23 (lset),
    # 54 (pget), 57 (src), 60 (create), 66 (update); Prisms.thy:14 (match), 15 (build),
    # 20 (matches); Z_Toolkit Function_Toolkit.thy:67 (infix partitions); Shallow-Expressions
    # Local_State.thy:20 (localstate _ over _)
    + "get put lset pget src create update match build matches partitions localstate over"
    .split())
#: Words a declared name (a constant, field, channel, definition) must not be besides: the
#: outer keywords of Pure, HOL and the public parents.
AX_KEYWORDS = AX_INNER_KEYWORDS | OUTER_KEYWORDS | frozenset(
    # outer keywords (line 5 of each theory): Circus_Toolkit Recursive.thy, Action_Command.thy;
    # Shallow-Expressions Expressions.thy, Named_Expressions.thy, Z/Z_Store.thy; Optics
    # Channel_Type.thy, Dataspace.thy, Lens_Instances.thy, Alphabet_Scene_Spaces.thy; Z_Toolkit
    # (isabelle-utp/Z_Toolkit 36ae909, Circus_Toolkit's parent) Def_Const.thy, Enum_Type.thy,
    # Partial_Function_Command.thy, Record_Default_Instance.thy, Tabulate_Command.thy
    """recursive actions expr_constructor expr_function edefinition expression over zstore
    zexpr chantype dataspace constants variables channels alphabet statespace
    alphabet_scene_space def_consts enumtype zfun precondition postcondition record_default
    tabulate""".split())
#: Constants of the parents a theory identifier would shadow.
AX_CONSTANTS = AX_RESERVED | frozenset(n for n in AX_SIGNATURES if n.isidentifier())
