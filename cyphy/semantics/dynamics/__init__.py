"""Dynamics of the elaborated model, imported one way: ``errors`` (why equations cannot be
assembled) ← ``tree`` (the kinematic tree as data, without NumPy; its numbers in
``tree_numbers``) ← ``rigid_body`` (the recursive algorithms, numeric or symbolic) ←
``motion`` (the tree's equations written out, cached by ``motion_cache``), ``articulated``
and ``link_equations`` (the articulated-body algorithm as named definitions, the links'
equations) ← ``equations`` (the system of a model, a mapping call) ← ``reduce`` and
``evolve_odes`` (explicit ODEs with SymPy)."""
