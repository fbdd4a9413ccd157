"""A persistent cache of the symbolic equations of motion
(:func:`cyphy.semantics.dynamics.rigid_body.motion_equations`): a command does not derive
again what it derived before.

Writing a tree's equations out takes SymPy (0.5-0.9 s to import here) and its expansion
(0.4-0.8 s for the marXbot's two wheels), every run of ``gen --isabelle``,
``--cyphycircus``, ``--latex``, ``solve`` … ; unpickling them takes milliseconds, and SymPy
is then not imported at all. A stale or wrong hit would make a theory silently wrong, worse
than any slowness, so the key is a hash of **everything** the derivation reads (and more):

* the kinematic tree the derivation runs on (:func:`key`), as the data its numbers are
  computed from (:class:`~cyphy.semantics.dynamics.tree.TreeJoint` without NumPy, so that a
  hit imports neither NumPy nor SymPy): the gravity vector and, per joint in tree order,
  every field of the tree joint (name, device prefix, kind, parent, the poses of its body,
  of its parent body and of the joint frame, as the exact bits of their floats), each link
  of its body (qualified name, span, pose, inertial: the masses, centres of mass and
  inertias), and the element it comes from: its qualified name, its span (equations carry
  it), its definition, AXIS, annotation (axes, damping and springs, the passive efforts),
  and its device's prefix and ports (names, kinds, types, mangled names, values, initial
  values: the axes, and the variables the equations name);
* a fingerprint of the sources that decide the tree's numbers, the derivation and the
  pickled classes (the dynamics modules, the translator to and from SymPy, the expression
  AST, spans, the model's elements, values, poses and inertias, this module and the
  storage) and of the libraries' versions (Python, NumPy, SymPy, mpmath, read from their
  files), in the name of the entries' folder.

Anything the encoder does not know (a new kind of value in a port) makes the key
unavailable: the equations are then derived and not stored, never keyed on less. Errors
(``DynamicsError``) are not stored: a hit is always a derivation that succeeded on exactly
these inputs. Entries hold the equations and the index of each one's joint in the tree.

The storage (location ``$CYPHY_CACHE_DIR``, else ``$XDG_CACHE_HOME/cyphy``, else
``~/.cache/cyphy``; folders ``motion-<fingerprint>``; ``CYPHY_NO_CACHE=1`` turns it off)
is :mod:`cyphy.disk_cache`'s, shared with the parse cache.
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import importlib.util
import sys
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable

from cyphy import disk_cache, progress
from cyphy import expr as ex
from cyphy.model.array import Array
from cyphy.model.elements import Device, Joint, Link
from cyphy.model.values import is_numpy
from cyphy.semantics.dynamics.tree import KinematicTree, TreeJoint

_PACKAGE = Path(__file__).resolve().parent.parent.parent
_SOURCES = ("semantics/dynamics/*.py", "translate/to_sympy.py", "model/evaluate.py",
            "model/elements.py", "model/inertia.py", "model/poses.py", "model/array.py",
            "model/values.py", "model/roots.py", "lang/ast/*.py", "expr.py",
            "diagnostics.py", "codes.py", "pickling.py", "records.py", "disk_cache.py")
#: The libraries whose versions decide the equations (NumPy's arithmetic of the tree's
#: numbers, SymPy's expansion and its printing of floats, mpmath's digits), read from their
#: files without importing them.
_LIBRARIES = (("numpy", "version.py"), ("sympy", "release.py"), ("mpmath", "__init__.py"))

#: One equation of the tree and the index of its joint in ``KinematicTree.joints``.
Derived = list[tuple[ex.Expr, int]]


@lru_cache(maxsize=1)
def fingerprint() -> str | None:
    """A hash of the sources and library versions that decide a derivation; None without
    the sources (then nothing is cached)."""
    versions = [sys.version]
    for name, file in _LIBRARIES:
        spec = importlib.util.find_spec(name)  # finds the package, imports nothing
        origin = Path(spec.origin) if spec is not None and spec.origin else None
        try:
            versions.append((origin.parent / file).read_text("utf-8") if origin else "absent")
        except OSError:
            versions.append("unreadable")
    return disk_cache.fingerprint(_PACKAGE, _SOURCES, "\0".join(versions).encode())


def derived(tree: KinematicTree, derive: Callable[[], Derived]) -> Derived:
    """``derive()``'s equations of ``tree``, from the cache when these exact inputs were
    derived before; a miss derives and stores them."""
    root = disk_cache.cache_root()
    sources = fingerprint() if root is not None else None
    digest = key(tree) if sources is not None else None
    if root is None or sources is None or digest is None:
        return derive()
    folder = disk_cache.folder(root, "motion", sources)
    entry = disk_cache.entry_path(folder, digest.hex())
    loaded = disk_cache.load(entry, digest, lambda value: _valid(value, len(tree)))
    if loaded is not disk_cache.MISS:
        return loaded  # type: ignore[no-any-return]
    equations = derive()
    progress.step("writing the cache of equations of motion")
    disk_cache.store(folder, entry, digest, equations)
    return equations


def _valid(value: Any, joints: int) -> bool:
    """Whether an unpickled entry is a list of (equation, joint index) of this tree."""
    return isinstance(value, list) and all(
        isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], ex.Expr)
        and type(item[1]) is int and 0 <= item[1] < joints for item in value)


def key(tree: KinematicTree) -> bytes | None:
    """The SHA-256 of everything the derivation of ``tree``'s equations reads (see the
    module's docstring), or None when some of it is of a kind the encoder does not know."""
    out: list[str] = []
    try:
        _encode(tree.gravity, out)
        out.append(str(len(tree.joints)))
        for joint in tree.joints:
            _encode_joint(joint, out)
    except (TypeError, RecursionError):
        return None
    return hashlib.sha256("\x1f".join(out).encode("utf-8", "surrogatepass")).digest()


def _encode_joint(joint: TreeJoint, out: list[str]) -> None:
    out.append("TreeJoint")
    for f in dataclasses.fields(joint):
        if f.name not in ("element", "links"):
            out.append(f.name)
            _encode(getattr(joint, f.name), out)
    out.append(f"links[{len(joint.links)}")
    for link in joint.links:
        for value in (link.qname, link.span, link.pose, link.inertial):
            _encode(value, out)
    out.append("]")
    element = joint.element
    if isinstance(element, Joint):
        out.append("Joint")
        for value in (element.qname, element.span, element.index, element.definition,
                      element.axis, element.annotation, element.target_copy):
            _encode(value, out)
    elif isinstance(element, Link):
        out.append("Link")
        for value in (element.qname, element.span, element.pose, element.inertial):
            _encode(value, out)
    else:
        raise TypeError(f"a tree joint's element of type {type(element).__name__}")
    _encode_device(element.device, out)


def _encode_device(device: Device | None, out: list[str]) -> None:
    if device is None:
        out.append("no device")
        return
    out.append("Device")
    _encode(device.prefix, out)
    _encode(device.ports, out)


def _encode(value: Any, out: list[str]) -> None:
    """Append an unambiguous text of ``value`` (its type, then its contents) to ``out``;
    ``TypeError`` for a type not listed here."""
    if value is None or isinstance(value, (bool, int, str)):
        out.append(f"{type(value).__name__}:{value!r}")
    elif isinstance(value, float):
        out.append(f"float:{value.hex()}")
    elif isinstance(value, Array):
        out.append(f"Array:{value.shape}:" + ",".join(x.hex() for x in value.flat))
    elif is_numpy(value, "ndarray"):  # given in an environment: NumPy is loaded then
        if value.dtype.hasobject:  # type: ignore[attr-defined]
            raise TypeError("an array of objects")
        out.append(f"ndarray:{value.dtype.str}:{value.shape}:"  # type: ignore[attr-defined]
                   f"{value.tobytes().hex()}")  # type: ignore[attr-defined]
    elif type(value).__module__ == "numpy" and hasattr(value, "item"):  # a NumPy scalar
        _encode(value.item(), out)  # type: ignore[attr-defined]
    elif isinstance(value, enum.Enum):
        out.append(f"{type(value).__qualname__}.{value.name}")
    elif isinstance(value, (tuple, list)):
        out.append(f"{type(value).__name__}[{len(value)}")
        for item in value:
            _encode(item, out)
        out.append("]")
    elif isinstance(value, dict):
        out.append(f"dict[{len(value)}")
        items: list[tuple[str, str]] = []
        for k, v in value.items():
            key_text: list[str] = []
            value_text: list[str] = []
            _encode(k, key_text)
            _encode(v, value_text)
            items.append(("\x1f".join(key_text), "\x1f".join(value_text)))
        for k_text, v_text in sorted(items):
            out.extend((k_text, v_text))
        out.append("]")
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        cls = type(value)
        out.append(f"{cls.__module__}.{cls.__qualname__}(")
        for f in dataclasses.fields(value):
            if f.init:  # the others are caches of the fields
                out.append(f.name)
                _encode(getattr(value, f.name), out)
        out.append(")")
    else:
        raise TypeError(f"a value of type {type(value).__name__}")
