"""``cyphy.records.record`` behaves as ``@dataclass(frozen=True, slots=True)``: the oracle is
the standard library's dataclass of the same class body, compared observable by observable."""

from __future__ import annotations

import copy
import dataclasses
import pickle
from dataclasses import FrozenInstanceError, dataclass, field
from typing import Any, Callable

import pytest

from cyphy.records import record

REAL = dataclass(frozen=True, slots=True)


def make(decorate: Callable[[type], Any]) -> dict[str, Any]:
    """The same small hierarchy of classes, made by ``decorate``."""

    @decorate
    class Base:
        span: int = field(default=0, compare=False, repr=False, kw_only=True)

    @decorate
    class Leaf(Base):
        name: str
        size: float = 1.5
        tags: tuple[str, ...] = ()

    @decorate
    class Cached(Base):
        """Has a documented body and a cache field that is not initialised."""

        items: list[int] = field(default_factory=list, hash=False)
        _views: dict[str, int] | None = field(default=None, init=False, repr=False,
                                              compare=False)

        def __post_init__(self) -> None:
            object.__setattr__(self, "_views", {"n": len(self.items)})

    @decorate
    class Own(Base):
        value: int

        def __repr__(self) -> str:
            return f"<own {self.value}>"

        def __eq__(self, other: object) -> bool:
            return isinstance(other, Own) and abs(self.value - other.value) < 2

    return {"Base": Base, "Leaf": Leaf, "Cached": Cached, "Own": Own}


def observe(cls: dict[str, Any]) -> list[Any]:
    """Everything the tests compare, with the class-specific parts replaced by text."""
    leaf, cached, own = cls["Leaf"], cls["Cached"], cls["Own"]
    a, b, c = leaf("a"), leaf("a", 2.0, ("t",), span=7), leaf("a", span=9)
    seen: list[Any] = [repr(a), repr(b), a == c, a == b, hash(a) == hash(c), a != b,
                       leaf.__match_args__, leaf.__slots__, [f.name for f in dataclasses.fields(a)],
                       repr(dataclasses.replace(b, name="z")), b.span, dataclasses.astuple(b)]
    x = cached([1, 2])
    seen += [repr(x), x._views, cached().items == [], cached().items is not cached().items,
             x == cached([1, 2]), x == cached([3])]
    try:
        seen.append(hash(x))
    except TypeError as error:
        seen.append(f"TypeError {error}".replace("Cached", "<cls>"))
    seen += [repr(own(3)), own(3) == own(4), own(3) == own(9), own.__hash__ is None]
    for call in (lambda: leaf(), lambda: leaf("a", 1.0, (), 4), lambda: leaf(name="a", nope=1)):
        try:
            call()
        except TypeError as error:
            seen.append(str(error))
    for mutate in (lambda: setattr(a, "name", "b"), lambda: delattr(a, "size")):
        with pytest.raises(FrozenInstanceError) as caught:
            mutate()
        seen.append(str(caught.value))
    seen += [leaf.__eq__(a, 3) is NotImplemented, a == ("a", 1.5, ())]
    return seen


def test_record_behaves_as_a_frozen_slotted_dataclass() -> None:
    assert observe(make(record)) == observe(make(REAL))


def test_pickling_and_copying_keep_every_field() -> None:
    leaf = make(record)["Leaf"]
    globals()["Leaf"] = leaf  # pickle finds a class by its module and name
    leaf.__qualname__ = "Leaf"
    try:
        b = leaf("a", 2.0, ("t",), span=7)
        for again in (pickle.loads(pickle.dumps(b)), copy.copy(b), copy.deepcopy(b)):
            assert again == b and again.span == 7 and type(again) is leaf
    finally:
        del globals()["Leaf"]


def test_methods_are_compiled_once_and_inherited_as_a_dataclass_would() -> None:
    classes = make(record)
    leaf, base = classes["Leaf"], classes["Base"]
    stub = leaf.__init__
    leaf("a")
    compiled = leaf.__init__
    assert compiled is not stub and compiled.__qualname__.endswith("Leaf.__init__")
    leaf("b")
    assert leaf.__init__ is compiled

    class Plain(leaf):  # type: ignore[misc, valid-type]
        """Not a record: inherits the record's methods."""

    assert Plain("c") == Plain("c") and repr(Plain("c")).endswith(".Plain(name='c', size=1.5, tags=())")
    assert base(span=3) == base(span=4)  # a record without compared fields


def test_a_record_refuses_what_a_frozen_dataclass_refuses() -> None:
    with pytest.raises(TypeError, match="__setattr__"):
        @record
        class Bad:
            x: int

            def __setattr__(self, name: str, value: object) -> None:
                pass


def observe_any(decorate: Callable[[type], Any], frozen: bool) -> list[Any]:
    """What the tests compare for any combination of flags: construction, defaults and
    factories, ``__post_init__``, repr, equality, hashing, assignment, copying."""

    @decorate
    class Base:
        span: int = field(default=0, compare=False, repr=False, kw_only=True)

    @decorate
    class Item(Base):
        name: str
        size: float = 1.5
        items: list[int] = field(default_factory=list)
        _views: int = field(default=0, init=False, repr=False, compare=False)

        def __post_init__(self) -> None:
            object.__setattr__(self, "_views", len(self.items))

    a, b = Item("a", items=[1, 2]), Item("a", items=[1, 2], span=3)
    seen: list[Any] = [repr(a), a == b, a != Item("b"), a == ("a", 1.5, [1, 2]), a._views,
                       Item("x").items is not Item("x").items, Item.__match_args__,
                       [f.name for f in dataclasses.fields(a)], getattr(Item, "__slots__", None),
                       repr(dataclasses.replace(b, name="z")), b.span, "__dict__" in dir(a)]
    try:
        seen.append(hash(a) == hash(b))
    except TypeError as error:
        seen.append(f"TypeError {error}".replace("Item", "<cls>"))
    try:
        a.size = 9.0
        seen.append(a.size)
    except FrozenInstanceError as error:
        seen.append(str(error))
    for again in (copy.copy(b), copy.deepcopy(b)):
        seen += [again == b, again.span, again.items, again._views]
    for call in (lambda: Item(), lambda: Item("a", 1.0, [], 4)):
        try:
            call()
        except TypeError as error:
            seen.append(str(error))
    seen.append(frozen)
    return seen


@pytest.mark.parametrize("frozen", [True, False])
@pytest.mark.parametrize("slots", [True, False])
@pytest.mark.parametrize("eq", [True, False])
def test_every_combination_of_flags_behaves_as_its_dataclass(frozen: bool, slots: bool,
                                                            eq: bool) -> None:
    """``record(frozen=…, slots=…, eq=…)`` against ``dataclass`` with the same flags."""
    ours = observe_any(record(frozen=frozen, slots=slots, eq=eq), frozen)
    theirs = observe_any(dataclass(frozen=frozen, slots=slots, eq=eq), frozen)
    assert ours == theirs
