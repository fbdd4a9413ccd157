"""Names kept apart: the semantics' global names (processes, their actions, schemas and
fields, and what the printers derive from a process's name) are one namespace in Isabelle,
where each is a constant, and two things of one name are ambiguous in the CyPhyCircus text.
Names come from the user's model (the mapping, the d-model's module, events and operations),
so two may meet: the rules take the first free of ``name``, ``name_2``, ``name_3``…
"""

from __future__ import annotations

from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel import DERIVED

#: The actions that Rule 2 names itself; ``Context.action_name`` (rules.py) keeps the
#: others apart.
RULE_ACTIONS = ("Init", "SendToDModel", "ReceiveFromDModel", "Evolve")
#: Names the Isabelle printers derive from a process's name ``<P>``: the action and channel
#: types, the visible state, the main action (backends/isabelle/theory.py, ax_theory.py).
PRINTED_FROM_PROCESS = ("_action", "_chan", "Visible", "Main")


def claim_apart(base: str, taken: set[str]) -> str:
    """``base``, else the first of ``base_2``, ``base_3``… that ``taken`` lacks; added to it."""
    name, n = base, 2
    while name in taken:
        name, n = f"{base}_{n}", n + 1
    taken.add(name)
    return name


def global_names(process: c.BasicProcess) -> set[str]:
    """The names that ``D`` and ``N`` must not take: global in Isabelle, where every action,
    schema and field is a constant, and the processes' in the text. ``D`` and ``P`` may come
    from a d-model and a p-model of one name; the mapping ``N`` is named after may share a
    name with either, or with one of ``P``'s actions (``map Init …``)."""
    names = {process.name, "MainAction", "cycle", "tscale", "tock", "registerRead",
             "registerWrite"}
    names |= derived_names(process.name)
    names |= {a.name for a in process.actions}
    for schema in (process.state, process.local):
        names.add(schema.name)
        names |= {f.name for f in schema.fields}
    names |= {k.name for k in process.constants}
    return names


def derived_names(process: str) -> set[str]:
    """What a process's name makes: ``D``'s actions, state and fields
    (:data:`cyphy.semantics.circus.dmodel.DERIVED`), and the printers' types."""
    return {f"{process}{suffix}" for suffix in (*DERIVED, *PRINTED_FROM_PROCESS)}
