"""The unit suffixes of the notation (``0.03m``, ``30deg``, ``2 second``): each one's SI factor
and physical dimension, as the Pint unit library defines them.

The table is derived from Pint once and stored beside this module (``units.json``), because
importing Pint and building its registry costs about 1.7 s and more than a second again
(measured on this project's machine), far more than ``cyphy check`` takes on a model.
``python3 -m cyphy.model.units`` rewrites the table from the installed Pint; the tests compare
the stored table with Pint's live answer, so the two cannot drift apart. A dimension is a map
from Pint's base dimensions (``[length]``, ``[mass]``, ``[time]``…) to exponents; angles are
dimensionless, as in Pint and SI.
"""

from __future__ import annotations

import json
import sys
from functools import lru_cache
from pathlib import Path
from types import MappingProxyType
from typing import Iterable, Mapping

from cyphy.records import record

TABLE = Path(__file__).with_name("units.json")


@record(slots=False)
class Dimension:
    """Exponents of base dimensions, sorted by name, zeros left out (dimensionless: empty)."""

    exponents: tuple[tuple[str, float], ...] = ()

    @staticmethod
    def of(exponents: Mapping[str, float]) -> Dimension:
        return Dimension(tuple(sorted((k, float(v)) for k, v in exponents.items() if v)))

    def __mul__(self, other: Dimension) -> Dimension:
        out = dict(self.exponents)
        for k, v in other.exponents:
            out[k] = out.get(k, 0.0) + v
        return Dimension.of(out)

    def __truediv__(self, other: Dimension) -> Dimension:
        return self * other ** -1

    def __pow__(self, n: float) -> Dimension:
        return Dimension.of({k: v * n for k, v in self.exponents})

    def __str__(self) -> str:
        """Pint's spelling: ``[mass] * [length] ** 2 / [time] ** 2``; ``dimensionless``."""
        if not self.exponents:
            return "dimensionless"
        ordered = sorted(self.exponents, key=lambda kv: (_ORDER.get(kv[0], len(_ORDER)), kv[0]))
        up = [_power(k, v) for k, v in ordered if v > 0]
        down = [_power(k, -v) for k, v in ordered if v < 0]
        text = " * ".join(up) or "1"
        return text + "".join(f" / {d}" for d in down)


_ORDER = {"[mass]": 0, "[length]": 1, "[time]": 2}  # as physicists write kg m^2 s^-2


def _power(name: str, exponent: float) -> str:
    return name if exponent == 1 else f"{name} ** {exponent:g}"


@record(slots=False)
class Unit:
    factor: float  # the value in SI base units of one of this unit
    dimension: Dimension


@lru_cache(maxsize=1)
def units() -> Mapping[str, Unit]:
    """The stored table: each suffix the grammar accepts, with its factor and dimension."""
    raw = json.loads(TABLE.read_text(encoding="utf-8"))
    return MappingProxyType({name: Unit(entry["factor"], Dimension.of(entry["dimension"]))
                             for name, entry in raw.items()})


def from_pint(names: Iterable[str]) -> dict[str, dict[str, object]]:
    """The table entries for ``names`` as Pint gives them (imports Pint: slow, tests and
    regeneration only)."""
    import pint  # lazy: Pint takes a second to load; tests and regeneration only

    registry = pint.UnitRegistry()
    out: dict[str, dict[str, object]] = {}
    for name in names:
        one = registry.Quantity(1.0, name)
        out[name] = {"factor": float(one.to_base_units().magnitude),
                     "dimension": {k: float(v) for k, v in sorted(one.dimensionality.items())}}
    return out


def main() -> int:
    """Rewrite ``units.json`` from the installed Pint for the suffixes it already lists."""
    names = json.loads(TABLE.read_text(encoding="utf-8"))
    TABLE.write_text(json.dumps(from_pint(names), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {TABLE} ({len(names)} units, Pint)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
