"""Dynamics of the elaborated model, imported one way: ``errors`` (why equations cannot be
assembled) ← ``rigid_body`` (the kinematic tree and the recursive algorithms, numeric or
symbolic) ← ``articulated`` and ``link_equations`` (the articulated-body algorithm as named
definitions, the links' equations) ← ``equations`` (the system of a model, a mapping call)
← ``reduce`` and ``evolve_odes`` (explicit ODEs with SymPy)."""
