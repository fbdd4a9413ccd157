"""Well-formedness conditions of ``wellformedness.md``: one function per condition, each
registered under its id (the paper's where it has one), in modules named for their family.

Importing this package registers every rule; :func:`check_wellformed` runs them all.
"""

from cyphy.wellformed.registry import RULES, WFContext, check_wellformed, rule

# The rule families register themselves on import.
# In the order of wellformedness.md, which is the order `--list-rules` prints.
from cyphy.wellformed import pmodel  # noqa: E402,F401,I001
from cyphy.wellformed import links  # noqa: E402,F401
from cyphy.wellformed import connections  # noqa: E402,F401
from cyphy.wellformed import parts  # noqa: E402,F401
from cyphy.wellformed import indexing  # noqa: E402,F401
from cyphy.wellformed import replication  # noqa: E402,F401
from cyphy.wellformed import annotations  # noqa: E402,F401
from cyphy.wellformed import mappings  # noqa: E402,F401
from cyphy.wellformed import mapping_indices  # noqa: E402,F401
from cyphy.wellformed import mapping_uses  # noqa: E402,F401
from cyphy.wellformed import values  # noqa: E402,F401
from cyphy.wellformed import units  # noqa: E402,F401
from cyphy.wellformed import mapping_units  # noqa: E402,F401
from cyphy.wellformed import machines  # noqa: E402,F401
from cyphy.wellformed import machine_types  # noqa: E402,F401
from cyphy.wellformed import modules  # noqa: E402,F401
from cyphy.wellformed import machine_cycles  # noqa: E402,F401
from cyphy.wellformed import machine_constants  # noqa: E402,F401

__all__ = ["RULES", "WFContext", "check_wellformed", "rule"]
