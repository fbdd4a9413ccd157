"""Isabelle printers: the Isabelle/UTP session of the semantics (``theory``, ``terms``,
``names``), its Ax_CyPhyCircus dialect (``ax_theory``, ``ax_terms``), the consistency of its
axioms (``axioms``), the library's reserved words (``library_words``, a data table), and the
diagnostics ``gen --isabelle`` reports (``session``)."""
