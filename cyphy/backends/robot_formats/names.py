"""The complete name table of a tree-format export (``<Model>.names.json`` of ``gen --urdf``
and ``gen --mjcf``): every link, body and joint the file names, not only those that stand
for one RoboSim element. A joint of several coordinates is written as several (a universal
joint as two hinges, a ball joint in URDF as three revolute joints through massless links,
a floating base as MuJoCo's free joint): each extra name maps to its coordinate in the
notation's vector form, ``Model::Link::Wrist[2]`` (``cyphy solve``'s ``Wrist_theta_2``), a
massless link between them to ``Model::Link::Wrist (link 1)``, and MuJoCo's free joint to
``Model::Root (floating base)``: every value is one name's, so the table inverts."""

from __future__ import annotations

import re
from typing import Iterable

from cyphy.semantics.sdf.tree import Node

_EXTRA = re.compile(r"^(?P<base>.+?)__(?P<index>\d+)(?P<link>_link)?(?:_\d+)?$")
_TAGS = frozenset({"link", "body", "joint", "freejoint"})


def complete_names(table: dict[str, str], roots: Iterable[Node]) -> dict[str, str]:
    """``table`` (exported name → qualified name) with every other name the files give to a
    link, body or joint: ``J__2`` → ``<J's qualified name>[2]``, ``J__2_link`` →
    ``<J's> (link 2)``, ``B__free`` → ``<B's> (floating base)``."""
    out = dict(table)
    for node in _walk(roots):
        name = node.attrs.get("name")
        if node.tag not in _TAGS or name is None or name in out:
            continue
        if node.tag == "freejoint" and name.endswith("__free") and name[:-6] in table:
            out[name] = f"{table[name[:-6]]} (floating base)"
            continue
        found = _EXTRA.match(name)
        if found and found["base"] in table:
            base = table[found["base"]]
            out[name] = f"{base} (link {found['index']})" if found["link"] else \
                f"{base}[{found['index']}]"
    return out


def _walk(roots: Iterable[Node]) -> Iterable[Node]:
    for root in roots:
        yield root
        yield from _walk(c for c in root.children if isinstance(c, Node))
