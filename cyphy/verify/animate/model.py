"""What ``animate`` runs, as either dialect's reader gives it: the definitions (their trees in
the executor's forms), the constants, and the composition ``N = (D [| cs |] P) \\ cs``."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass
class Definition:
    """One ``definition NAME :: type where "NAME params = body"``, parsed."""

    name: str
    params: list[str]
    tree: Any  # a lark Tree of utp_terms.lark's ``action``
    path: Path
    line: int


@dataclass
class Process:
    """A process of the composition: its main action and its state's fields (name → type)."""

    name: str
    main: str
    fields: dict[str, str]


@dataclass
class TheoryModel:
    """What a generated theory states, as far as running it needs."""

    path: Path
    definitions: dict[str, Definition]
    values: dict[str, Any]          # constants with values: floats, ints, lists, tuples
    open_constants: dict[str, int]  # declared without a value → line
    channels: set[str]              # the synchronisation set cs
    processes: list[Process]        # [D, P], in the composition's order
    composition: str
    axioms: list[tuple[Any, int]] = field(default_factory=list)  # parsed hol terms, line
    dialect: str = "utp"  # or "axiomatic" (ax_reader.py)
    truths: set[str] = field(default_factory=set)  # the open constants declared bool
    wholes: dict[str, str] = field(default_factory=dict)  # those declared int or nat → which


def line_of(text: str, pattern: str) -> int:
    """The 1-based line where ``pattern`` first matches (0: nowhere)."""
    m = re.search(pattern, text, re.M)
    return text.count("\n", 0, m.start()) + 1 if m else 0


def declared(text: str, name: str, types: str) -> bool:
    """Whether the theory declares ``name`` with one of ``types`` (``real|nat``)."""
    return re.search(rf"^(consts )?\s*{re.escape(name)} :: \"?({types})\b", text,
                     re.M) is not None
