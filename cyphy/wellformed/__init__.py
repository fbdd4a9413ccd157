"""Well-formedness conditions of ``wellformedness.md``: one function per condition, each
registered under its id (the paper's where it has one), in modules named for their family.

Importing this package registers every rule; :func:`check_wellformed` runs them all.
"""

from cyphy.wellformed.registry import RULES, WFContext, check_wellformed, rule

# The rule families register themselves on import.
from cyphy.wellformed import (  # noqa: E402,F401
    annotations, connections, indexing, links, mappings, parts, pmodel, values,
)

__all__ = ["RULES", "WFContext", "check_wellformed", "rule"]
