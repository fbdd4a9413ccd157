"""``cyphy check-theory``: a static check of an Isabelle session, not Isabelle.

Isabelle cannot be installed on the machines cyphy is developed on, so this package reads a
session's ``ROOT`` and theories the way Isabelle's front end would and reports, with
file:line, what a real Isabelle2020 + utp-main c9122f14 run is known to reject: a UTP grammar
merged with plain HOL's without ``recall_syntax`` (and the terms that then parse two ways),
duplicate names, names used before their definition, terms that do not type-check against a
signature table read from the library sources, reserved words bound as identifiers, and
proofs citing facts the session does not define. It proves nothing: whether ``simp`` closes
a lemma is only known by running Isabelle.
"""
