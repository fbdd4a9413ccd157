"""Name resolution and the scope conditions S1, S2, S4 and S5 of ``wellformedness.md``.

Walks every file the user asked about and reports names that do not resolve (S1, with "did you
mean" suggestions), names declared twice in one scope (S2), equations that reach outside their
block (S4) and imports that name no package or element, or parts that contain their own
p-model (S5). What each reference resolved to is recorded in a :class:`Resolution`, which later
stages read instead of resolving again.

The checks are in :mod:`cyphy.lang.resolution`: the driver and the checks of names and
expressions (:mod:`~cyphy.lang.resolution.checker`), of p-models, d-models and platform
mappings, and what is recorded (:mod:`~cyphy.lang.resolution.names`).
"""

from __future__ import annotations

from cyphy.diagnostics import Report
from cyphy.lang.resolution.dmodels import DModelChecks
from cyphy.lang.resolution.names import Resolution, block_children, path_roots, steps_of
from cyphy.lang.resolution.pmodels import PModelChecks
from cyphy.lang.workspace import Workspace

__all__ = ["Resolution", "block_children", "check_scopes", "path_roots", "steps_of"]


class _Checker(PModelChecks, DModelChecks):
    """The resolver: the driver with the checks of every kind of element."""


def check_scopes(ws: Workspace, report: Report) -> Resolution:
    """Run S1, S2, S4 and S5 on the user's files; return what references resolved to."""
    checker = _Checker(ws, report)
    checker.run()
    return checker.resolution
