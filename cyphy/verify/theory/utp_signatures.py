"""The signature table of ``cyphy check-theory``'s utp-dialect checker (utp_types.py): the
type of every constant, operator and syntax translation the Isabelle printer uses, each with
the library source it was read from, and the classes' instances that model overloading."""

from __future__ import annotations

U = "utp-main c9122f14 "
H = "Isabelle 2d6638d src/HOL/"
#: name → (type, where it was read). Type variables may carry classes: ``'a::plus``.
SIGNATURES: dict[str, tuple[str, str]] = {
    # HOL: Isabelle's src/HOL at github:digama0/isabelle 2d6638d (a 2024 snapshot; these
    # declarations and their notation are as in Isabelle2020). Overloaded constants are
    # class operations: the class is the sort their type variable carries.
    "+": ("'a::plus \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:195 (class plus, line 194)"),
    "-": ("'a::minus \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:198 (class minus, line 197)"),
    "*": ("'a::times \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Groups.thy:204 (class times, line 203)"),
    "/": ("'a::inverse \\<Rightarrow> 'a \\<Rightarrow> 'a",
          H + "Fields.thy:26 (abbreviation inverse_divide (infixl \"'/\" 70) of class inverse, "
          "line 22; Rings.thy:683's divide is written div)"),
    "^": ("'a::power \\<Rightarrow> nat \\<Rightarrow> 'a",
          H + "Power.thy:17 (class power, line 14)"),
    "powr": ("real \\<Rightarrow> real \\<Rightarrow> real",
             H + "Transcendental.thy:1567 (class ln; real's instance, line 1575)"),
    "uminus": ("'a::uminus \\<Rightarrow> 'a", H + "Groups.thy:201 (class uminus, line 200)"),
    "=": ("'a \\<Rightarrow> 'a \\<Rightarrow> bool", H + "HOL.thy:87 (eq; notation line 91)"),
    "\\<noteq>": ("'a \\<Rightarrow> 'a \\<Rightarrow> bool", H + "HOL.thy:168 (not_equal)"),
    "<": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
          H + "Orderings.thy:177 (less of class ord)"),
    ">": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool", H + "Orderings.thy:191 (greater)"),
    "\\<le>": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
               H + "Orderings.thy:176 (less_eq of class ord)"),
    "\\<ge>": ("'a::ord \\<Rightarrow> 'a \\<Rightarrow> bool",
               H + "Orderings.thy:187 (greater_eq)"),
    "\\<longrightarrow>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool",
                           H + "HOL.thy:86 (implies)"),
    "\\<longleftrightarrow>": ("bool \\<Rightarrow> bool \\<Rightarrow> bool",
                               H + "HOL.thy:179 (iff)"),
    "@": ("'a list \\<Rightarrow> 'a list \\<Rightarrow> 'a list", H + "List.thy:75 (append)"),
    "!": ("'a list \\<Rightarrow> nat \\<Rightarrow> 'a", H + "List.thy:125 (nth)"),
    "Cons": ("'a \\<Rightarrow> 'a list \\<Rightarrow> 'a list", H + "List.thy:13"),
    "Nil": ("'a list", H + "List.thy:12"),
    "real": ("nat \\<Rightarrow> real", H + "Real.thy:952 (abbreviation real, of_nat)"),
    "real_of_int": ("int \\<Rightarrow> real", H + "Real.thy:955 (abbreviation real_of_int, of_int)"),
    "True": ("bool", H + "HOL.thy:100"), "False": ("bool", H + "HOL.thy:109"),
    "UNIV": ("'a set", H + "Set.thy:576"),
    "sin": ("real \\<Rightarrow> real", H + "Transcendental.thy:3271 (at real)"),
    "cos": ("real \\<Rightarrow> real", H + "Transcendental.thy:3274 (at real)"),
    "tan": ("real \\<Rightarrow> real", H + "Transcendental.thy:4645 (at real)"),
    "arctan": ("real \\<Rightarrow> real", H + "Transcendental.thy:5087"),
    "exp": ("real \\<Rightarrow> real", H + "Transcendental.thy:1152 (at real)"),
    "ln": ("real \\<Rightarrow> real",
           H + "Transcendental.thy:1564 (class ln; at real, line 1575)"),
    "sqrt": ("real \\<Rightarrow> real", H + "NthRoot.thy:397"),
    "abs": ("'a::abs \\<Rightarrow> 'a", H + "Groups.thy:1167 (class abs, line 1166)"),
    # utp-main c9122f14
    "lit": ("'t \\<Rightarrow> ('t, 'a) uexpr", U + "utp/utp_expr.thy:50"),
    "var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t, 'a) uexpr", U + "utp/utp_expr.thy:45"),
    "in_var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t \\<Longrightarrow> 'a \\<times> 'b)",
               U + "utp/utp_var.thy:53 ($x, utp_var.thy:250)"),
    "out_var": ("('t \\<Longrightarrow> 'b) \\<Rightarrow> ('t \\<Longrightarrow> 'a \\<times> 'b)",
                U + "utp/utp_var.thy:56 ($x\\<acute>, utp_var.thy:251)"),
    "pr_var": ("('t \\<Longrightarrow> 'a) \\<Rightarrow> ('t \\<Longrightarrow> 'a)",
               U + "utp/utp_var.thy:69 (&x, utp_var.thy:249)"),
    "uop": ("('a \\<Rightarrow> 'b) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> ('b, 's) uexpr",
            U + "utp/utp_expr.thy:61"),
    "bop": ("('a \\<Rightarrow> 'b \\<Rightarrow> 'c) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
            "('b, 's) uexpr \\<Rightarrow> ('c, 's) uexpr", U + "utp/utp_expr.thy:66"),
    "trop": ("('a \\<Rightarrow> 'b \\<Rightarrow> 'c \\<Rightarrow> 'd) \\<Rightarrow> ('a, 's) uexpr "
             "\\<Rightarrow> ('b, 's) uexpr \\<Rightarrow> ('c, 's) uexpr \\<Rightarrow> "
             "('d, 's) uexpr", U + "utp/utp_expr.thy:70"),
    "=\\<^sub>u": ("('a, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> (bool, 's) uexpr",
                   U + "utp/utp_expr.thy:100"),
    "\\<noteq>\\<^sub>u": ("('a, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                           "(bool, 's) uexpr", U + "utp/utp_pred.thy:342"),
    "<\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                   "(bool, 's) uexpr", U + "utp/utp_expr.thy:262"),
    ">\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                   "(bool, 's) uexpr", U + "utp/utp_expr.thy:263"),
    "\\<le>\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                        "(bool, 's) uexpr", U + "utp/utp_expr.thy:264"),
    "\\<ge>\\<^sub>u": ("('a::ord, 's) uexpr \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                        "(bool, 's) uexpr", U + "utp/utp_expr.thy:265"),
    "\\<and>": ("'a::uconj \\<Rightarrow> 'a \\<Rightarrow> 'a",
                U + "utp/utp_pred.thy:38 (adhoc: conj, conj_upred, lines 47 and 334)"),
    "\\<or>": ("'a::uconj \\<Rightarrow> 'a \\<Rightarrow> 'a", U + "utp/utp_pred.thy:39"),
    "\\<Rightarrow>": ("'s upred \\<Rightarrow> 's upred \\<Rightarrow> 's upred",
                       U + "utp/utp_pred.thy:40 (adhoc: impl, line 336)"),
    "\\<Leftrightarrow>": ("'s upred \\<Rightarrow> 's upred \\<Rightarrow> 's upred",
                           U + "utp/utp_pred.thy:41 (adhoc: iff_upred, line 337)"),
    "\\<not>": ("'a::uconj \\<Rightarrow> 'a", U + "utp/utp_pred.thy:42 (adhoc: Not, not_upred)"),
    "true": ("'s upred", U + "utp/utp_pred.thy:234 (utrue, line 331)"),
    "false": ("'s upred", U + "utp/utp_pred.thy:235 (ufalse, line 332)"),
    "shEx": ("('b \\<Rightarrow> 's upred) \\<Rightarrow> 's upred",
             U + "utp/utp_pred.thy:54 (\\<^bold>\\<exists> x \\<bullet> P, line 76)"),
    "utuple": ("('a, 's) uexpr \\<Rightarrow> ('b, 's) uexpr \\<Rightarrow> ('a \\<times> 'b, 's) uexpr",
               U + "utp/utp_expr.thy:248"),
    "lens_plus": ("('a \\<Longrightarrow> 'c) \\<Rightarrow> ('b \\<Longrightarrow> 'c) \\<Rightarrow> "
                  "('a \\<times> 'b \\<Longrightarrow> 'c)",
                  U + "optics/Lens_Algebra.thy:38 ({x, y}\\<^sub>v: utp_var.thy:277, 332)"),
    "zero_lens": ("unit \\<Longrightarrow> 'a", U + "optics/Lens_Algebra.thy:72 (0\\<^sub>L)"),
    "salpha_none": ("unit \\<Longrightarrow> 'a",
                    U + "utp/utp_var.thy:265 (\\<emptyset>, translated to 0\\<^sub>L, line 328)"),
    "salphacomp": ("('a \\<Longrightarrow> 'c) \\<Rightarrow> ('b \\<Longrightarrow> 'c) \\<Rightarrow> "
                   "('a \\<times> 'b \\<Longrightarrow> 'c)",
                   U + "utp/utp_var.thy:262 ((x;y), translated to +\\<^sub>L, line 319)"),
    "Skip": ("('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_healths.thy:29"),
    "Stop": ("('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_healths.thy:26"),
    ";;": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
           U + "utp/utp_rel.thy:93 (useq at hrel)"),
    "\\<box>": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                U + "theories/sf_rdes/utp_sfrd_extchoice.thy:25"),
    "EXTCHOICE": ("'i set \\<Rightarrow> ('i \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> "
                  "('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_extchoice.thy:11 "
                  "(\\<box> x\\<in>A \\<bullet> P: syntax line 18, translation line 22)"),
    "|||": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
            U + "theories/circus/utp_circus_parallel.thy:846"),
    "inter_circus": ("('s, 'e) action \\<Rightarrow> ('a \\<Longrightarrow> 's) \\<Rightarrow> "
                     "('b \\<Longrightarrow> 's) \\<Rightarrow> ('s, 'e) action \\<Rightarrow> "
                     "('s, 'e) action", U + "theories/circus/utp_circus_parallel.thy:839"),
    "cond_srea": ("('s, 'e) action \\<Rightarrow> 's upred \\<Rightarrow> ('s, 'e) action "
                  "\\<Rightarrow> ('s, 'e) action",
                  U + "theories/reactive/utp_rea_prog.thy:298 (syntax line 306)"),
    "GuardCSP": ("'s upred \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                 U + "theories/sf_rdes/utp_sfrd_prog.thy:415 (&\\<^sub>C, line 422)"),
    "PrefixCSP": ("('e, 's) uexpr \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                  U + "theories/sf_rdes/utp_sfrd_prog.thy:708 (\\<^bold>\\<rightarrow>: "
                  "theories/circus/utp_circus_prefix.thy:8, output !(e): line 31)"),
    "InputCSP": ("('a \\<Rightarrow> 'e) \\<Rightarrow> ('a \\<Rightarrow> 's upred) \\<Rightarrow> "
                 "('a \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> ('s, 'e) action",
                 U + "theories/sf_rdes/utp_sfrd_prog.thy:864 (?(x): "
                 "theories/circus/utp_circus_prefix.thy:21)"),
    "assigns_csp": ("('a \\<Longrightarrow> 's) \\<Rightarrow> ('a, 's) uexpr \\<Rightarrow> "
                    "('s, 'e) action",
                    U + "theories/sf_rdes/utp_sfrd_prog.thy:290-291 (syntax; AssignsCSP, line 284, "
                    "by the translation of line 294)"),
    "SpecC": ("('a \\<Longrightarrow> 's) \\<Rightarrow> 's upred \\<Rightarrow> 's upred "
              "\\<Rightarrow> ('s, 'e) action", U + "theories/sf_rdes/utp_sfrd_prog.thy:49"),
    # the prelude shipped with cyphy (cyphy/backends/isabelle/templates/CyPhyCircus_Prelude.thy)
    "EvolveC": ("('s \\<times> 's) upred \\<Rightarrow> ('s, 'e) action", "prelude: axiomatization"),
    "InterruptC": ("('s, 'e) action \\<Rightarrow> ('s, 'e) action \\<Rightarrow> ('s, 'e) action",
                   "prelude: axiomatization"),
    "InterruptCondC": ("('s, 'e) action \\<Rightarrow> 's upred \\<Rightarrow> ('s, 'e) action",
                       "prelude: axiomatization"),
    "MuC": ("(('s, 'e) action \\<Rightarrow> ('s, 'e) action) \\<Rightarrow> ('s, 'e) action",
            "prelude: definition MuC"),
    "WaitC": ("'e \\<Rightarrow> nat \\<Rightarrow> ('s, 'e) action", "prelude: primrec WaitC"),
    "fmod": ("real \\<Rightarrow> real \\<Rightarrow> real", "prelude: definition fmod"),
}

#: class → type constructors in it; ``uexpr`` is in a class when its value type is
#: (utp/utp_expr.thy:131-177, utp/utp_expr_insts.thy:10-76 at c9122f14).
INSTANCES: dict[str, set[str]] = {
    "plus": {"real", "nat", "int", "uexpr"}, "minus": {"real", "nat", "int", "uexpr"},
    "times": {"real", "nat", "int", "uexpr"},
    "uminus": {"real", "int", "uexpr"}, "power": {"real", "nat", "int", "uexpr"},
    "abs": {"real", "int", "uexpr"}, "ord": {"real", "nat", "int"},
    "numeral": {"real", "nat", "int", "uexpr"},
    # Fields.thy:22 (class inverse: what / needs); real is a field (Real.thy), nat and int
    # are not, so 1 / 2 :: nat is rejected, as Isabelle rejects it; uexpr: utp_expr_insts.thy:37
    "inverse": {"real", "uexpr"},
    "uconj": {"bool", "uexpr"},  # conj at bool, conj_upred at (bool, 's) uexpr
    # the axiomatic dialect's (ax_types.py): real and, component-wise, products
    # are real_normed_vectors (HOL/Real_Vector_Spaces.thy, HOL-Analysis Product_Vector.thy);
    # cyphyaction is a complete_lattice (Ax_CyPhyCircus.thy:18-21)
    "real_normed_vector": {"real", "prod"}, "complete_lattice": {"cyphyaction"},
}
#: classes a product is in when its components are.
_COMPONENTWISE = {"real_normed_vector"}
#: classes whose uexpr instance needs the value type in the class (bool for uconj).
_LIFTED = {"plus", "minus", "times", "inverse", "uminus", "power", "abs", "numeral"}
