"""Values for constants that have none: ``--const NAME=VALUE`` and ``--consts FILE``.

A value is written in the notation (``0.05``, ``5cm``, ``(|0, 1, 0|)``, ``true``) and
evaluated; a file is TOML or JSON mapping names to numbers, booleans, strings or lists.
"""

from __future__ import annotations

import dataclasses
import json
import tomllib
from pathlib import Path
from typing import Iterable

from cyphy.diagnostics import did_you_mean
from cyphy.lang import ast
from cyphy.lang.parser import parse_text
from cyphy.model.array import Array
from cyphy.model.evaluate import EvalError, Value, evaluate


class ConstantsError(Exception):
    """A ``--const`` or ``--consts`` argument that cannot be read (a usage error)."""


def parse_value(text: str) -> Value:
    result = parse_text(f"const value: real = {text}", "<--const>")
    if result.file is None or result.diagnostics or len(result.file.items) != 1:
        raise ConstantsError(f"cannot read the value '{text}'")
    item = result.file.items[0]
    assert isinstance(item, ast.VarDecl) and item.value is not None
    try:
        return evaluate(item.value, {})
    except EvalError as err:
        raise ConstantsError(f"cannot evaluate the value '{text}': {err.message}") from None


def _from_data(name: str, value: object) -> Value:
    if isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, list):
        if any(isinstance(row, list) and any(isinstance(x, list) for x in row)
               for row in value):
            raise ConstantsError(f"'{name}': a vector or a matrix (list of rows) is expected")
        try:
            return Array.of(value)
        except (TypeError, ValueError, OverflowError):
            raise ConstantsError(f"'{name}': a list must hold numbers") from None
    raise ConstantsError(f"'{name}': unsupported value {value!r}")


def parse_const_options(pairs: Iterable[str], file: str | None) -> dict[str, Value]:
    """The constants given on the command line; ``--const`` wins over ``--consts``."""
    values: dict[str, Value] = {}
    if file is not None:
        path = Path(file)
        try:
            text = path.read_text(encoding="utf-8")
            data = json.loads(text) if path.suffix == ".json" else tomllib.loads(text)
        except (OSError, ValueError) as err:
            raise ConstantsError(f"cannot read --consts {file}: {err}") from None
        if not isinstance(data, dict):
            raise ConstantsError(f"--consts {file} must map names to values")
        values.update({str(k): _from_data(str(k), v) for k, v in data.items()})
    for pair in pairs:
        name, sep, value = pair.partition("=")
        if not sep or not name.strip():
            raise ConstantsError(f"--const takes NAME=VALUE, not '{pair}'")
        values[name.strip()] = parse_value(value.strip())
    return values


def declared_constants(files: Iterable[object]) -> set[str]:
    """The names of every constant declared in the files (p-models, packages, the library's
    devices): what a ``--const`` key can name. A walk over the syntax trees' fields, done only
    when constants are given."""
    names: set[str] = set()
    todo: list[object] = list(files)
    seen: set[int] = set()
    while todo:
        node = todo.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, ast.VarDecl):
            if node.kind is ast.DeclKind.CONST:
                names.add(node.name)
            continue
        if isinstance(node, (list, tuple)):
            todo.extend(node)
        elif dataclasses.is_dataclass(node) and not isinstance(node, type):
            todo.extend(getattr(node, f.name) for f in dataclasses.fields(node)
                        if f.name != "span")
    return names


def unknown_constants(keys: Iterable[str], declared: set[str]) -> list[tuple[str, str]]:
    """The ``--const`` keys that name no declared constant (their last ``::`` segment is the
    constant's name), each with a hint."""
    out = []
    for key in keys:
        prefix, _, name = key.rpartition("::")
        if name not in declared:
            close = did_you_mean(name, declared)
            if close and prefix:  # the key as it would be written: Treel::HEIGHT
                close = close.replace("'", f"'{prefix}::", 1).replace(" or '",
                                                                    f" or '{prefix}::")
            out.append((key, close or ("the model's constants: " +
                                       ", ".join(sorted(declared)[:20]) if declared
                                       else "the model declares no constant")))
    return out
