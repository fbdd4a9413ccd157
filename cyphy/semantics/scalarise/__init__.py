"""Vector and matrix equations as component equations, for targets that have only scalars.

The model's equations mix scalars, vectors and matrices (``fV == pV + A * v``,
``tau == transpose(F) * A``). A target without vectors (Isabelle's ``real``-valued state, or any
prover that must not read ``*`` on ``real list`` as something else) needs one scalar equation
per component. This pass infers the shape of every subterm (``()`` a scalar, ``(n,)`` a vector,
``(m, n)`` a matrix), refuses what does not fit (a ``+`` of different sizes, a product whose
inner sizes differ, a vector where a scalar is needed) and writes component ``k`` of each side.

Components are named as ``cyphy solve`` names them (:mod:`cyphy.semantics.dynamics.reduce`): a
vector or matrix variable ``X`` has the scalar variables ``X_1`` … ``X_n``, counted from 1,
row by row. A constant keeps its one name and is indexed (``Index(A, (2,))`` is ``A``'s third
item, counted from 0 as HOL's ``nth`` counts), so its definition stays one list.

The library's vector and matrix functions whose components are arithmetic in their arguments'
components (``physmod::math``: ``skew``, ``ad``, ``ScrewAxis``, ``cross``, ``dot``, ``norm``,
``Rot``, ``Adjoint``, ``identity``, ``zeroes``) are written out as the literal they denote
(:data:`~cyphy.semantics.scalarise.expansions.EXPANSIONS`), so ``ad(fV) * A * v`` has a
component form; products with a literal 0 leave no term.

The pass is four modules, each importing only those before it: :mod:`.shapes` (shapes, the
components' names, the error), :mod:`.expansions` (the library functions as literals),
:mod:`.scalariser` (one expression's shape and components) and :mod:`.process` (a whole
p-model process with scalar state).
"""
