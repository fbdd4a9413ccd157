"""CyPhyCircus names for RoboSim's qualified names, unique and recorded in a table.

Device ports come mangled from elaboration (``LMotor_das``, ``Proximity1_voltage``; where
two instances share a name, the enclosing part or link names are prepended there). The rest
(constants of the p-model's blocks and of the mapping, mapping locals) are mangled here in
the same way: the shortest suffix of the qualified name's components that no other element
uses, joined by ``_``. The table (qualified → mangled) is written beside every output, so
properties can be stated against it.
"""

from __future__ import annotations

import re

_NOT_IDENT = re.compile(r"[^A-Za-z0-9_]+")


def capitalised(name: str) -> str:
    """``obstacle`` → ``Obstacle`` (action names such as ``ObstacleToDModel``)."""
    return name[:1].upper() + name[1:]


def identifier(text: str) -> str:
    """A CyPhyCircus identifier for a component: other characters become ``_``, runs of
    ``_`` collapse, edges lose theirs, and a leading digit gets a letter."""
    out = re.sub(r"_+", "_", _NOT_IDENT.sub("_", text)).strip("_") or "x"
    return out if out[0].isalpha() else "n" + out


class NameTable:
    """Qualified RoboSim names and the CyPhyCircus names given to them, both ways unique."""

    def __init__(self) -> None:
        self._by_qualified: dict[str, str] = {}
        self._owner: dict[str, str] = {}
        self._definition: dict[str, str] = {}

    def claim(self, qualified: str, mangled: str) -> str:
        """Record a name chosen elsewhere (a device port mangled by elaboration)."""
        self._by_qualified.setdefault(qualified, mangled)
        self._owner.setdefault(mangled, qualified)
        return mangled

    def mangle(self, qualified: str, components: list[str]) -> str:
        """The shortest unique ``_``-joined suffix of ``components`` for ``qualified`` (the
        same name again for the same qualified name); a counter only when every suffix
        is taken."""
        if qualified in self._by_qualified:
            return self._by_qualified[qualified]
        parts = [identifier(p) for p in components if p]
        # The last component alone would be ambiguous (`HEIGHT`); start with two when there are.
        for depth in range(min(2, len(parts)), len(parts) + 1):
            candidate = "_".join(parts[-depth:])
            if candidate not in self._owner:
                return self.claim(qualified, candidate)
        base, n = "_".join(parts), 2
        while f"{base}_{n}" in self._owner:
            n += 1
        return self.claim(qualified, f"{base}_{n}")

    def define(self, qualified: str, definition: str) -> None:
        """Record the definition-qualified name of an instance's constant
        (``SpeedControlMotor::R`` for ``marXbotBase::Core::LHinge::LMotor::R``): a scenario's
        ``[consts]`` may name it so, as ``--const`` may (``cyphy animate --scenario``)."""
        self._definition[qualified] = definition

    def definition(self, qualified: str) -> str:
        """The definition-qualified name recorded for ``qualified``, or ``""``."""
        return self._definition.get(qualified, "")

    def owner(self, mangled: str) -> str | None:
        """The qualified name that ``mangled`` was given to, if any."""
        return self._owner.get(mangled)

    def lookup(self, qualified: str) -> str:
        return self._by_qualified[qualified]

    def get(self, qualified: str) -> str | None:
        return self._by_qualified.get(qualified)

    def items(self) -> list[tuple[str, str]]:
        """(qualified, mangled) pairs sorted by qualified name: a deterministic table."""
        return sorted(self._by_qualified.items())
