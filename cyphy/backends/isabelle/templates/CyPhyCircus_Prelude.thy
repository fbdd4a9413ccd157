(* CyPhyCircus_Prelude: what CyPhyCircus needs on top of the Circus of utp-main (2020).

   Shipped unchanged with every theory that cyphy generates (cyphy gen --isabelle).
   utp-main's UTP-Circus session gives Circus actions as normal stateful-failure reactive
   designs, but not the hybrid and timed operators of CyPhyCircus: continuous evolution,
   interrupts (by an action and by a condition), a Wait that counts tock events, and a
   recursion whose result is known to be NCSP. They are introduced here, each with the
   [closure] fact that lets "simp add: closure" prove every generated action NCSP.

   The first three are axiomatised: only their healthiness is stated, nothing about their
   behaviour. The axioms are consistent (take EvolveC F = Skip, P \<triangle>\<^sub>C Q = P ;; Q and
   InterruptCondC P b = P). *)

theory CyPhyCircus_Prelude
  imports "UTP-Circus.utp_circus" "HOL.Transcendental"
begin recall_syntax

(* UTP's syntax recalled: utp-main c9122f14 purges HOL's notation for \<and>, \<or>, \<not>
   (utp/utp_pred.thy:32-35) and for the lattice symbols (utp/utp_pred.thy:122-135) to give
   those symbols to UTP's predicates. HOL.Transcendental is outside utp_circus's imports, and
   a theory's grammar is the union of its parents', so the merge above brings HOL's
   productions back and every UTP predicate would parse two ways. recall_syntax
   (toolkit/Total_Recall.thy:15, 43-45) re-applies the purges, as utp-main's own theories
   that import plain HOL do (hybrid/utp_hyrel.thy:12). *)

text \<open>utp-main's toolkit imports HOL.Deriv (toolkit/utp_toolkit.thy, line 12), not
  HOL.Transcendental: sin, cos, tan, arctan, exp, ln, sqrt and powr (a real exponent) come
  from the second import. HOL's mod needs a semiring with division, which real is not: real
  remainders use fmod.\<close>

definition fmod :: "real \<Rightarrow> real \<Rightarrow> real" where
  "fmod x y = x - y * of_int \<lfloor>x / y\<rfloor>"

section \<open>Hybrid operators (axiomatised)\<close>

text \<open>@{text "EvolveC F"}: the state evolves over time so that, at every instant, the
  relation @{text F} holds between the values of the variables (undashed) and their time
  derivatives (dashed).\<close>

axiomatization
  EvolveC :: "'s hrel \<Rightarrow> ('s, 'e) action" and
  InterruptC :: "('s, 'e) action \<Rightarrow> ('s, 'e) action \<Rightarrow> ('s, 'e) action"
    (infixl "\<triangle>\<^sub>C" 68) and
  InterruptCondC :: "('s, 'e) action \<Rightarrow> 's upred \<Rightarrow> ('s, 'e) action"
where
  EvolveC_NCSP [closure]: "EvolveC F is NCSP" and
  InterruptC_NCSP [closure]: "\<lbrakk> P is NCSP; Q is NCSP \<rbrakk> \<Longrightarrow> P \<triangle>\<^sub>C Q is NCSP" and
  InterruptCondC_NCSP [closure]: "P is NCSP \<Longrightarrow> InterruptCondC P b is NCSP"

section \<open>Recursion\<close>

text \<open>utp-main has no NCSP law for the fixed point @{text "\<mu>\<^sub>C"}; wrapping it in
  NCSP makes the result healthy by construction (for a productive body the wrapper should
  change nothing).\<close>

definition MuC :: "(('s, 'e) action \<Rightarrow> ('s, 'e) action) \<Rightarrow> ('s, 'e) action" where
  "MuC F = NCSP (\<mu>\<^sub>C F)"

lemma MuC_NCSP [closure]: "MuC F is NCSP"
  unfolding MuC_def by (rule Healthy_Idempotent[OF NCSP_Idempotent])

section \<open>Waiting for tock events\<close>

text \<open>@{text "WaitC t n"} engages in @{text n} events @{text t} (the tock of the
  d-model's clock) and terminates.\<close>

primrec WaitC :: "'e \<Rightarrow> nat \<Rightarrow> ('s, 'e) action" where
  "WaitC t 0 = Skip" |
  "WaitC t (Suc n) = PrefixCSP \<guillemotleft>t\<guillemotright> (WaitC t n)"

lemma WaitC_NCSP [closure]: "WaitC t n is NCSP"
  by (induct n) (simp_all add: closure)

end
