"""Fast pickling for the frozen, slotted dataclasses of the syntax tree (cached parses).

Python gives a slotted dataclass ``__getstate__``/``__setstate__`` methods that call
``dataclasses.fields()`` for every object; unpickling the tree of a large model then costs
more than parsing it again would save. Here each class's field names are computed once, and
an object is rebuilt by setting its slots directly (no ``__init__``: the values were
validated when the tree was first built). Fields that are not part of ``__init__`` are caches
(``_views``): they are not pickled and come back as their defaults.
"""

from __future__ import annotations

from dataclasses import MISSING, fields
from operator import attrgetter
from typing import Any, Callable

_LAYOUT: dict[type, tuple[tuple[str, ...], tuple[tuple[str, Any], ...]]] = {}
#: Per class, the function that reads its pickled fields as a tuple (``attrgetter`` reads
#: them in C: storing a large model's tree spends a third of its time in ``__reduce__``).
_VALUES: dict[type, Callable[[Any], tuple[Any, ...]]] = {}


def _layout(cls: type) -> tuple[tuple[str, ...], tuple[tuple[str, Any], ...]]:
    """(names of the pickled fields, (name, default) of the cache fields) of a class."""
    found = _LAYOUT.get(cls)
    if found is None:
        pickled = tuple(f.name for f in fields(cls) if f.init)
        caches = tuple((f.name, None if f.default is MISSING else f.default)
                       for f in fields(cls) if not f.init)
        found = _LAYOUT[cls] = (pickled, caches)
    return found


def restore(cls: type, values: tuple[Any, ...]) -> Any:
    """The object of class ``cls`` with these field values (the inverse of ``__reduce__``)."""
    obj = object.__new__(cls)
    names, caches = _layout(cls)
    for name, value in zip(names, values):
        object.__setattr__(obj, name, value)
    for name, default in caches:
        object.__setattr__(obj, name, default)
    return obj


class FastPickle:
    """Mixin for frozen slotted dataclasses: pickled as their class and field values."""

    __slots__ = ()

    def __reduce__(self) -> tuple[Any, ...]:
        cls = type(self)
        values = _VALUES.get(cls)
        if values is None:
            values = _VALUES[cls] = _values_of(_layout(cls)[0])
        return restore, (cls, values(self))


def _values_of(names: tuple[str, ...]) -> Callable[[Any], tuple[Any, ...]]:
    if len(names) > 1:
        return attrgetter(*names)
    if names:  # attrgetter of one name returns the value itself, not a tuple
        get = attrgetter(names[0])
        return lambda obj: (get(obj),)
    return lambda obj: ()
