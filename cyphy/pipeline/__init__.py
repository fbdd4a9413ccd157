"""The stages composed: files checked, a p-model elaborated, a geometric model ready for the
exports, and what a generator returns. Below ``verify`` and ``api``, so the checkers of
generated artefacts (Flow*) and the public API build on the same pipeline; nothing here
prints or exits.
"""
