"""Consistency of platform mappings with Z3 (``cyphy check --consistency``): C1-C5.

:mod:`.encode` turns a mapping element into Z3 terms; :mod:`.checks` asks the questions.
Importing this package imports Z3.
"""

from cyphy.semantics.consistency.checks import DEFAULT_TIMEOUT_MS, check_consistency

__all__ = ["DEFAULT_TIMEOUT_MS", "check_consistency"]
