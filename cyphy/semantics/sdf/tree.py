"""The SDF document as the translation rules build it: elements, attributes, values, comments.

A neutral tree, so that the rules (:mod:`cyphy.semantics.sdf.rules`) decide *what* SDF says and the
writer (:mod:`cyphy.backends.robot_formats.sdf_xml`) alone decides how it is spelled: values stay Python
numbers, booleans, strings and vectors until the writer prints them.
"""

from __future__ import annotations

from dataclasses import field
from typing import Union

from cyphy.model.array import Array
from cyphy.model.poses import Pose
from cyphy.records import record

#: What an element's text may hold; the writer prints each kind (vectors with spaces).
Text = Union[None, bool, int, float, str, tuple, Array, Pose]


@record
class Comment:
    """An XML comment (the writer makes any text safe to put in one)."""

    text: str


@record(frozen=False)
class Node:
    """One SDF element: tag, attributes in writing order, text, children in writing order."""

    tag: str
    attrs: dict[str, str] = field(default_factory=dict)
    text: Text = None
    children: list[Union["Node", Comment]] = field(default_factory=list)

    def add(self, tag: str, text: Text = None, **attrs: str) -> "Node":
        """Append a child element and return it."""
        child = Node(tag, dict(attrs), text)
        self.children.append(child)
        return child

    def comment(self, text: str) -> None:
        self.children.append(Comment(text))

    def find(self, tag: str) -> "Node | None":
        for c in self.children:
            if isinstance(c, Node) and c.tag == tag:
                return c
        return None
