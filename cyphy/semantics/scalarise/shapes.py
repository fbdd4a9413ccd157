"""Shapes (``()`` a scalar, ``(n,)`` a vector, ``(m, n)`` a matrix), the names of the scalar
components, and the error of a shape that does not fit: what every part of the pass and its
callers (the reduction, the consistency encoding, the ODEs) share.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.semantics.circus import ast as c

Shape = tuple[int, ...]
SCALAR: Shape = ()


class ScalariseError(Exception):
    """An expression whose shapes do not fit, or that has no component form; ``node`` is
    where (its span points at the source)."""

    def __init__(self, node: ex.Expr, message: str) -> None:
        super().__init__(message)
        self.node = node


def shape_of_type(t: c.Type) -> Shape | None:
    """The shape a declared type fixes: ``()`` for scalars, None for a size left open."""
    if isinstance(t, c.TSeq):
        if isinstance(t.of, c.TSeq):
            if t.size is None or t.of.size is None:
                return None
            return (t.size, t.of.size)
        return None if t.size is None else (t.size,)
    return SCALAR


def component_name(name: str, k: int) -> str:
    """The scalar variable of the ``k``-th component (from 0) of ``name``: ``name_{k+1}``."""
    return f"{name}_{k + 1}"


def components(name: str, shape: Shape) -> list[str]:
    size = 1
    for n in shape:
        size *= n
    return [component_name(name, k) for k in range(size)] if shape else [name]


def size_of(shape: Shape) -> int:
    out = 1
    for n in shape:
        out *= n
    return out


def describe(shape: Shape) -> str:
    if not shape:
        return "a scalar"
    if len(shape) == 1:
        return f"a {shape[0]}-vector"
    return f"a {shape[0]}x{shape[1]} matrix"


def as_matrix(shape: Shape) -> Shape:
    """A vector is a column in a product."""
    return (shape[0], 1) if len(shape) == 1 else shape


def type_shape(t: ast.TypeRef | None) -> tuple[int, ...] | None:
    """The shape a declared vector or matrix type of literal sizes fixes (None otherwise)."""
    def size(e: ex.Expr | None) -> int | None:
        return int(e.text) if isinstance(e, ex.Num) and e.is_integer else None

    if isinstance(t, ast.VectorType) and size(t.size):
        return (size(t.size),)  # type: ignore[return-value]
    if isinstance(t, ast.MatrixType) and size(t.rows) and size(t.cols):
        return (size(t.rows), size(t.cols))  # type: ignore[return-value]
    return None
