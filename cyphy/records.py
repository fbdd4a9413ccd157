"""Dataclasses whose methods are compiled on first use (start-up).

``@dataclass(frozen=True, slots=True)`` compiles six methods per class with ``exec`` when the
class is created (``__init__``, ``__repr__``, ``__eq__``, ``__hash__``, ``__setattr__``,
``__delattr__``): about a millisecond a class, a tenth of a second for the hundred classes of
the syntax tree and the expressions, paid by every command before the first file is read,
though a command with a warm parse cache builds few of those nodes (the cached trees are
unpickled without ``__init__``, see :mod:`cyphy.pickling`).

:func:`record` makes the same class: the fields, their order, defaults, ``kw_only``,
``compare``/``repr``/``hash`` flags, ``__slots__`` and ``__match_args__`` come from
:func:`dataclasses.dataclass` itself (so :func:`dataclasses.fields`, :func:`dataclasses.replace`
and :func:`dataclasses.is_dataclass` work unchanged). Only the four methods whose text depends
on the fields are generated late: each starts as a stub that compiles the method the
dataclass would have written, puts it on the class in its own place, and calls it; later calls
go straight to the compiled method. The frozen ``__setattr__``/``__delattr__`` and the
pickling ``__getstate__``/``__setstate__`` are shared functions. One difference: the
``__repr__`` has no guard against a record that contains itself (a dataclass prints ``...``
there); the trees made of records hold tuples, which cannot. A method the class defines
itself is kept, as with a dataclass.

``record(frozen=False, slots=False, eq=False)`` and the other combinations of those three
flags make the other dataclasses the same way (the elaborated model's elements, the checks'
contexts, the command's options): about forty more classes that ``cyphy check`` creates and
uses a few of; a mutable record's ``__init__`` assigns as the dataclass's does, and an
``eq`` record that is not frozen is unhashable, as a dataclass is. ``order`` and
``unsafe_hash`` are not offered: use :func:`dataclasses.dataclass` for them.
"""

from __future__ import annotations

from dataclasses import MISSING, FrozenInstanceError, dataclass, fields
from types import MemberDescriptorType
from typing import Any, Callable, TypeVar, overload

C = TypeVar("C", bound=type)

#: The methods generated late, each by its builder below.
_LATE = ("__init__", "__repr__", "__eq__", "__hash__")
#: The placeholder ``__doc__`` that stops :func:`dataclasses.dataclass` from calling
#: ``inspect.signature`` (slow) to write one; replaced by a text of the same form.
_NO_DOC = "\0"


def _frozen_setattr(self: object, name: str, value: object) -> None:
    raise FrozenInstanceError(f"cannot assign to field {name!r}")


def _frozen_delattr(self: object, name: str) -> None:
    raise FrozenInstanceError(f"cannot delete field {name!r}")


def _getstate(self: object) -> list[Any]:
    """The state pickled for a record (the same as a frozen slotted dataclass's)."""
    return [getattr(self, f.name) for f in fields(self)]  # type: ignore[arg-type]


def _setstate(self: object, state: list[Any]) -> None:
    for f, value in zip(fields(self), state):  # type: ignore[arg-type]
        object.__setattr__(self, f.name, value)


def _compile(cls: type, name: str, source: str, namespace: dict[str, Any]) -> Callable[..., Any]:
    """The function ``name`` defined by ``source``, named as a method of ``cls``."""
    scope: dict[str, Any] = {}
    exec(source, namespace, scope)
    function: Callable[..., Any] = scope[name]
    function.__qualname__ = f"{cls.__qualname__}.{name}"
    return function


def _build_init(cls: type) -> Callable[..., Any]:
    """``__init__`` as :func:`dataclasses.dataclass` writes it: positional then keyword-only
    parameters, defaults and default factories, every field set in field order (through
    its slot's own setter for a frozen slotted class, ``object.__setattr__`` for another
    frozen one, by assignment otherwise), then ``__post_init__`` when the class has one."""
    namespace: dict[str, Any] = {"__object_setattr": object.__setattr__, "__MISSING": MISSING}
    frozen = cls.__setattr__ is _frozen_setattr  # type: ignore[comparison-overlap]
    positional: list[str] = []
    keyword: list[str] = []
    body: list[str] = []
    for f in fields(cls):
        default = f"__default_{f.name}"
        factory = f"__factory_{f.name}"
        if f.default_factory is not MISSING:
            namespace[factory] = f.default_factory
        elif f.default is not MISSING:
            namespace[default] = f.default
        if f.init:
            if f.default_factory is not MISSING:
                parameter = f"{f.name}=__MISSING"
                value = f"{factory}() if {f.name} is __MISSING else {f.name}"
            elif f.default is not MISSING:
                parameter, value = f"{f.name}={default}", f.name
            else:
                parameter, value = f.name, f.name
            (keyword if f.kw_only else positional).append(parameter)
        elif f.default_factory is not MISSING:
            value = f"{factory}()"
        elif f.default is not MISSING:
            value = default
        else:
            continue
        setter = slot_setter(cls, f.name) if frozen else None
        if setter is not None:
            namespace[f"__set_{f.name}"] = setter
            body.append(f"    __set_{f.name}(self, {value})")
        elif frozen:
            body.append(f"    __object_setattr(self, {f.name!r}, {value})")
        else:
            body.append(f"    self.{f.name} = {value}")
    if hasattr(cls, "__post_init__"):
        body.append("    self.__post_init__()")
    parameters = ", ".join(["self", *positional, *(["*", *keyword] if keyword else [])])
    source = f"def __init__({parameters}):\n" + ("\n".join(body) or "    pass") + "\n"
    return _compile(cls, "__init__", source, namespace)


def slot_setter(cls: type, name: str) -> Callable[[Any, Any], None] | None:
    """The ``__set__`` of ``cls``'s slot ``name`` (from the class that declares it, as
    attribute lookup finds it), or None when ``name`` is not a slot. It is what
    ``object.__setattr__`` calls for a slot, found once, not at every assignment: a third less
    time per field (a record's ``__init__``, a span's, an unpickled node's)."""
    for klass in cls.__mro__:
        if name in vars(klass):
            descriptor = vars(klass)[name]
            return descriptor.__set__ if isinstance(descriptor, MemberDescriptorType) else None
    return None


def _build_repr(cls: type) -> Callable[..., Any]:
    shown = ", ".join(f"{f.name}={{self.{f.name}!r}}" for f in fields(cls) if f.repr)
    source = ("def __repr__(self):\n"
              f"    return self.__class__.__qualname__ + f\"({shown})\"\n")
    return _compile(cls, "__repr__", source, {})


def _compared(cls: type, of: str) -> str:
    return "".join(f"{of}.{f.name}," for f in fields(cls) if f.compare)


def _build_eq(cls: type) -> Callable[..., Any]:
    source = ("def __eq__(self, other):\n"
              "    if other.__class__ is self.__class__:\n"
              f"        return ({_compared(cls, 'self')}) == ({_compared(cls, 'other')})\n"
              "    return NotImplemented\n")
    return _compile(cls, "__eq__", source, {})


def _build_hash(cls: type) -> Callable[..., Any]:
    hashed = "".join(f"self.{f.name}," for f in fields(cls)
                     if (f.compare if f.hash is None else f.hash))
    return _compile(cls, "__hash__", f"def __hash__(self):\n    return hash(({hashed}))\n", {})


_BUILDERS: dict[str, Callable[[type], Callable[..., Any]]] = {
    "__init__": _build_init, "__repr__": _build_repr, "__eq__": _build_eq,
    "__hash__": _build_hash}


def _late(cls: type, name: str) -> Callable[..., Any]:
    """The stub of method ``name`` of ``cls``: compiles the method, installs it on ``cls``
    (a subclass that inherits the stub gets ``cls``'s method, as it would inherit it), calls
    it."""
    def first_call(self: object, *args: Any, **kwargs: Any) -> Any:
        method = _BUILDERS[name](cls)
        setattr(cls, name, method)
        return method(self, *args, **kwargs)

    first_call.__qualname__ = f"{cls.__qualname__}.{name}"
    return first_call


def _signature_doc(cls: type) -> str:
    """The ``__doc__`` a dataclass without a docstring gets: its name and parameters."""
    parameters = [f.name if f.default is MISSING and f.default_factory is MISSING
                  else f"{f.name}=..." for f in fields(cls) if f.init]
    return f"{cls.__name__}({', '.join(parameters)})"


@overload
def record(cls: C, /) -> C: ...


@overload
def record(*, frozen: bool = True, slots: bool = True, eq: bool = True
           ) -> Callable[[C], C]: ...


def record(cls: C | None = None, /, *, frozen: bool = True, slots: bool = True,
           eq: bool = True) -> C | Callable[[C], C]:
    """``@dataclass(frozen=True, slots=True)`` (or with the flags given), with the methods
    compiled on first use."""
    if cls is None:
        return lambda c: _make(c, frozen, slots, eq)
    return _make(cls, frozen, slots, eq)


def _make(cls: C, frozen: bool, slots: bool, eq: bool) -> C:
    own = cls.__dict__
    if frozen:
        for name in ("__setattr__", "__delattr__"):
            if name in own:
                raise TypeError(f"cannot overwrite attribute {name} in class {cls.__name__}")
    late = [name for name in _LATE if eq or name not in ("__eq__", "__hash__")]
    kept = {name for name in late if name in own}
    if own.get("__hash__", MISSING) is None and "__eq__" in own:
        kept.discard("__hash__")  # Python's None for a class that defines __eq__ only
    if not own.get("__doc__"):
        cls.__doc__ = _NO_DOC
    made: Any = dataclass(init=False, repr=False, eq=False, slots=slots)(cls)
    if made.__doc__ == _NO_DOC:
        made.__doc__ = _signature_doc(made)
    if frozen:
        made.__setattr__ = _frozen_setattr
        made.__delattr__ = _frozen_delattr
    for name in late:
        if name in kept:
            continue
        if name == "__hash__" and not frozen:
            made.__hash__ = None  # a mutable dataclass with ``eq`` is unhashable
        else:
            setattr(made, name, _late(made, name))
    if frozen and slots:
        for name, method in (("__getstate__", _getstate), ("__setstate__", _setstate)):
            if name not in own:
                setattr(made, name, method)
    return made  # type: ignore[no-any-return]

