"""Fast pickling for the frozen, slotted dataclasses of the syntax tree (cached parses).

Python gives a slotted dataclass ``__getstate__``/``__setstate__`` methods that call
``dataclasses.fields()`` for every object; unpickling the tree of a large model then costs
more than parsing it again would save. Here each class's field names are computed once, and
an object is rebuilt by setting its slots directly (no ``__init__``: the values were
validated when the tree was first built). Fields that are not part of ``__init__`` are caches
(``_views``): they are not pickled and come back as their defaults.

An object is pickled as ``restore(cls, *values)``: one argument tuple per object, not a class
and a tuple of values in a tuple. The pickler and the unpickler both keep every tuple they
meet until the whole tree is written or read (their memo), so each tuple per node is paid for
by the whole tree at once: on a 10,000-link model (1.5 million nodes) the second tuple was
about 100 MB of the peak, and the memory it left behind stayed fragmented.
"""

from __future__ import annotations

import pickle
from contextlib import contextmanager
from dataclasses import MISSING, fields
from operator import attrgetter
from typing import Any, Callable, Iterator

from cyphy.records import slot_setter

#: Per class: the setters of its pickled fields (the slots' own descriptors, which a frozen
#: class's ``__setattr__`` does not guard), and (setter, default) of its cache fields.
_Setter = Callable[[Any, Any], None]
_LAYOUT: dict[type, tuple[tuple[_Setter, ...], tuple[tuple[_Setter, Any], ...]]] = {}
#: Per class, the function that reads its pickled fields as a tuple (``attrgetter`` reads
#: them in C: storing a large model's tree spends a third of its time in ``__reduce__``).
_VALUES: dict[type, Callable[[Any], tuple[Any, ...]]] = {}


def _pickled_names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls) if f.init)


def _slot_setter(cls: type, name: str) -> _Setter:
    setter = slot_setter(cls, name)
    if setter is None:
        raise TypeError(f"{cls.__name__}.{name} is not a slot")
    return setter


def _layout(cls: type) -> tuple[tuple[_Setter, ...], tuple[tuple[_Setter, Any], ...]]:
    """(setters of the pickled fields, (setter, default) of the cache fields) of a class."""
    found = _LAYOUT.get(cls)
    if found is None:
        pickled = tuple(_slot_setter(cls, name) for name in _pickled_names(cls))
        caches = tuple((_slot_setter(cls, f.name), None if f.default is MISSING else f.default)
                       for f in fields(cls) if not f.init)
        found = _LAYOUT[cls] = (pickled, caches)
    return found


def restore(cls: type, *values: Any) -> Any:
    """The object of class ``cls`` with these field values (the inverse of ``__reduce__``)."""
    obj = object.__new__(cls)
    setters, caches = _layout(cls)
    for setter, value in zip(setters, values):
        setter(obj, value)
    for setter, default in caches:
        setter(obj, default)
    return obj


class FastPickle:
    """Mixin for frozen slotted dataclasses: pickled as their class and field values."""

    __slots__ = ()

    def __reduce__(self) -> tuple[Any, ...]:
        cls = type(self)
        values = _VALUES.get(cls)
        if values is None:
            values = _VALUES[cls] = _values_of(cls, _pickled_names(cls))
        return restore, values(self)


class SeparatePickle(FastPickle):
    """Mixin for the nodes a large tree has thousands of, each a subtree of a few dozen
    nodes (a p-model's links and what they hold): pickled as a pickle of their own, which the
    outer pickle holds as one ``bytes``.

    A pickler remembers every object it has written until the end (its memo: an entry per
    object, and the argument tuple of each ``__reduce__`` kept alive), so pickling a whole
    tree at once needed as much memory again as the tree (5,000 links: 0.14 GB more during the
    parse cache's write). A separate pickle's memo is freed when it is done; the outer one
    holds one entry and the bytes per subtree. What is lost is only sharing across subtrees
    (equal strings in two links unpickle as two strings), so only the outermost such node is
    separate: a link's bodies and joints are in its pickle (one per body as well made reading
    the cache half as slow again, 25,000 small pickles at 5,000 links instead of 5,000)."""

    __slots__ = ()

    def __reduce__(self) -> tuple[Any, ...]:
        reduced = FastPickle.__reduce__(self)
        if _within:  # a block inside a block is part of the outer one's pickle
            return reduced
        _within.append(self)
        try:
            return _separate, (pickle.dumps(reduced[1], protocol=pickle.HIGHEST_PROTOCOL),)
        finally:
            _within.pop()
            _written[0] += 1
            if _reports and _written[0] % REPORT_EVERY == 0:
                _reports[-1](_written[0])


#: The object whose separate pickle is being written, if any (pickling runs in one thread).
_within: list[object] = []
#: Separate pickles written since the innermost :func:`reporting` began, and its callbacks.
_written = [0]
_reports: list[Callable[[int], None]] = []
#: How many separate pickles between two reports.
REPORT_EVERY = 500


@contextmanager
def reporting(report: Callable[[int], None]) -> Iterator[None]:
    """Call ``report(n)`` after every :data:`REPORT_EVERY` separate pickles while the block
    runs (``n`` written so far): writing a 90,000-link tree takes tens of seconds, and the
    progress line would stand still meanwhile."""
    _reports.append(report)
    _written[0] = 0
    try:
        yield
    finally:
        _reports.pop()


def _separate(data: bytes) -> Any:
    """The object pickled by :meth:`SeparatePickle.__reduce__`."""
    return restore(*pickle.loads(data))


def _values_of(cls: type, names: tuple[str, ...]) -> Callable[[Any], tuple[Any, ...]]:
    """The function from an object to the arguments of :func:`restore` (its class first)."""
    if len(names) > 1:
        get = attrgetter(*names)
        return lambda obj: (cls, *get(obj))
    if names:  # attrgetter of one name returns the value itself, not a tuple
        one = attrgetter(names[0])
        return lambda obj: (cls, one(obj))
    return lambda obj: (cls,)
