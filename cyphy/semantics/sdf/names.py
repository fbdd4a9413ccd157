"""SDF names of the elaborated elements (sdf.md decision 3).

Readable names (the default): the qualified name below the model, ``::`` turned into ``__``
and each index value appended to its name with ``_`` (``LTreel__Wheel``, ``Core__Proximity_3``);
a body's collision and visual add ``_collision`` and ``_visual``. Short names
(``--short-names``, ``--target coppeliasim``): RoboTool's codes (sdf-robotool.md §2.2), one
counter for links and joints (``1-Wheel``) and one for bodies (``1--wheel``), assigned in
writing order; sensors and actuators keep their simple name (index values appended with
``_``, never ``::``, which Gazebo reserves).

Either way every name is recorded with the qualified RoboSim name it stands for: the table
that ``<model>.names.json`` holds. Should two elements still get the same name, the second gets
``_2`` (then ``_3`` …), so names stay unique within the model.
"""

from __future__ import annotations

from cyphy.model.elements import Element, glued


class Names:
    """Assigns and records SDF names; ``table`` maps each SDF name to its qualified name."""

    def __init__(self, short: bool) -> None:
        self.short = short
        self.table: dict[str, str] = {}
        self._by_key: dict[tuple[str, int], str] = {}
        self._bodies: dict[int, tuple[str, str]] = {}
        self._counter = 0
        self._body_counter = 0

    def _unique(self, name: str, qualified: str) -> str:
        candidate, k = name, 1
        while candidate in self.table:
            k += 1
            candidate = f"{name}_{k}"
        self.table[candidate] = qualified
        return candidate

    def _readable(self, element: Element) -> str:
        return "__".join(glued(element.qname[1:], "_")) or element.qname[0]

    def link(self, element: Element) -> str:
        """The name of a link (memoised: joints ask for their parent and child)."""
        key = ("link", id(element))
        if key not in self._by_key:
            if self.short:
                self._counter += 1
                base = f"{self._counter}-{element.simple_name}"
            else:
                base = self._readable(element)
            self._by_key[key] = self._unique(base, element.name)
        return self._by_key[key]

    def joint(self, element: Element, qualified: str, suffix: str = "") -> str:
        """A joint or fixed joint; ``suffix`` tells apart the copies of one joint that Rule 5
        makes for a replicated target."""
        if self.short:
            self._counter += 1
            base = f"{self._counter}-{element.simple_name}"
        else:
            base = self._readable(element) + suffix
        return self._unique(base, qualified)

    def fixed(self, parent: Element, child: Element, qualified: str) -> str:
        if self.short:
            self._counter += 1
            return self._unique(f"{self._counter}-fixedJoint", qualified)
        return self._unique(f"{self._readable(parent)}__fixed__{self._readable(child)}",
                            qualified)

    def tree(self, model: str, first: Element) -> str:
        """A ``<model>`` of ``--split-trees``: the p-model's name and its tree's first link."""
        return self._unique(f"{model}__{self.link(first)}", model)

    def body(self, element: Element) -> tuple[str, str]:
        """(collision name, visual name) of a body (memoised for contact sensors)."""
        key = id(element)
        if key not in self._bodies:
            if self.short:
                self._body_counter += 1
                base = f"{self._body_counter}--{element.simple_name}"
            else:
                base = self._readable(element)
            self._bodies[key] = (self._unique(base + "_collision", element.name),
                                 self._unique(base + "_visual", element.name))
        return self._bodies[key]

    def device(self, element: Element) -> str:
        """A sensor or actuator."""
        if self.short:
            own = element.qname[len(element.qname) - len(element.index) - 1:]
            base = "_".join(own)
        else:
            base = self._readable(element)
        return self._unique(base, element.name)
