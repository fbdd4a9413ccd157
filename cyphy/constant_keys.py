"""How a ``--const``/``--consts``/scenario ``[consts]`` key names a constant, in one place:
``simulate`` and ``reach`` (elaboration) and ``animate`` (a theory's ``names.tsv``) must read
the same key as the same constants."""

from __future__ import annotations


def names_constant(key: str, bare: str, *qualified: str) -> bool:
    """Whether ``key`` names the constant whose bare name is ``bare`` and whose qualified
    names (instance- and definition-qualified; empty ones are skipped) are ``qualified``:
    the bare name, one of those names, or a ``::`` suffix of one."""
    return key == bare or any(full and (full == key or full.endswith("::" + key))
                              for full in qualified)
