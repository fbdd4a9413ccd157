"""Translators of the shared expression AST (:mod:`cyphy.expr`) to SymPy (``to_sympy``) and
Z3 (``to_z3``), below the checks and the semantics that use them. Each imports its library
when imported: import them lazily where start-up matters."""
