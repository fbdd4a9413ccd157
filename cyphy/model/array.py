"""The vectors and matrices of constant values: an immutable, pure-Python array of floats.

``cyphy check`` and ``cyphy gen --sdf`` evaluate a model's constants (poses, sizes, inertias)
and nothing more; importing NumPy for that cost them 0.3 s of processor time at start-up,
more than the rest of the command (issue 24). An :class:`Array` holds its entries as a flat
tuple of floats and a ``shape`` of one or two sizes; it indexes, iterates and compares like the
read-only NumPy array it replaced, and converts to one (``numpy.asarray(value)``, through
``__array__``) for the layers that compute with arrays (dynamics, simulation, reduction).

Only operations whose result is the same float, bit for bit, as NumPy's are written here:
entry-wise sums, differences, scaling, negation, transposition, blocks. A matrix product is a
sum of products, and NumPy's (OpenBLAS, with fused multiply-adds) rounds differently from a
plain loop in most cases; the operators that need one (``*`` of two arrays, ``^``, ``inverse``,
``det``, ``Rot``…) convert to NumPy on the spot (:func:`numpy_array`, :func:`from_numpy`), so
the printed poses and inertias stay byte-identical and only models that multiply matrices pay
for NumPy.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Any, Iterator, Sequence

Shape = tuple[int] | tuple[int, int]


class Array:
    """A 1-D vector or 2-D matrix of floats, immutable (and so hashable and shareable).

    ``shape`` is ``(n,)`` or ``(rows, cols)``; ``flat`` the entries row by row. Indexing
    counts from 0 as Python does (``v[0]``, ``m[1, 2]``, ``m[0]`` a row, slices); the
    evaluator translates the notation's 1-based indices.
    """

    __slots__ = ("shape", "flat")

    shape: Shape
    flat: tuple[float, ...]

    def __init__(self, flat: tuple[float, ...], shape: Shape) -> None:
        """Trusted: ``flat`` is a tuple of floats of ``shape``'s size (use :meth:`of`)."""
        object.__setattr__(self, "flat", flat)
        object.__setattr__(self, "shape", shape)

    @classmethod
    def of(cls, data: Any) -> Array:
        """The array of ``data``: a sequence of numbers (a vector), a sequence of equally
        long sequences of numbers (a matrix), an :class:`Array`, or anything with a
        ``tolist()`` (a NumPy array). ``ValueError`` for a ragged or deeper nesting, and for
        entries that are not real numbers."""
        if isinstance(data, Array):
            return data
        if hasattr(data, "tolist"):
            data = data.tolist()
        if not isinstance(data, (list, tuple)):
            raise ValueError(f"a vector or matrix needs a sequence of numbers, not {data!r}")
        if data and all(isinstance(row, (list, tuple, Array)) for row in data):
            rows = [row.tolist() if isinstance(row, Array) else row for row in data]
            width = len(rows[0])
            if any(len(row) != width for row in rows) or \
                    any(isinstance(x, (list, tuple)) for row in rows for x in row):
                raise ValueError("the rows of a matrix must be equally long lists of numbers")
            return cls(tuple(_real(x) for row in rows for x in row), (len(rows), width))
        return cls(tuple(_real(x) for x in data), (len(data),))

    # ------------------------------------------------------------------ NumPy's read side

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def size(self) -> int:
        return len(self.flat)

    def __len__(self) -> int:
        return self.shape[0]

    def rows(self) -> list[tuple[float, ...]]:
        """The rows of a matrix (a vector is one row)."""
        if len(self.shape) == 1:
            return [self.flat]
        width = self.shape[1]
        return [self.flat[i:i + width] for i in range(0, len(self.flat), width)]

    def tolist(self) -> list[Any]:
        """A list of floats (a vector) or of rows (a matrix), as ``ndarray.tolist``."""
        if len(self.shape) == 1:
            return list(self.flat)
        return [list(row) for row in self.rows()]

    def ravel(self) -> Array:
        """The entries as a vector, row by row."""
        return self if len(self.shape) == 1 else Array(self.flat, (len(self.flat),))

    @property
    def T(self) -> Array:  # noqa: N802 - NumPy's name
        """The transpose; a vector is its own, as in NumPy."""
        if len(self.shape) == 1:
            return self
        return Array(tuple(x for column in zip(*self.rows()) for x in column),
                     (self.shape[1], self.shape[0]))

    def __iter__(self) -> Iterator[Any]:
        """Floats of a vector, rows (vectors) of a matrix."""
        if len(self.shape) == 1:
            return iter(self.flat)
        return (Array(row, (self.shape[1],)) for row in self.rows())

    def __getitem__(self, key: Any) -> Any:
        if len(self.shape) == 1:
            if isinstance(key, tuple):
                (key,) = key
            if isinstance(key, slice):
                part = self.flat[key]
                return Array(part, (len(part),))
            return self.flat[_index(key, self.shape[0])]
        rows, cols = self.shape
        row_key, col_key = (*key, slice(None))[:2] if isinstance(key, tuple) \
            else (key, slice(None))
        if isinstance(row_key, slice):
            picked = [self.flat[i * cols:(i + 1) * cols] for i in range(rows)[row_key]]
            if isinstance(col_key, slice):
                chosen = [row[col_key] for row in picked]
                width = len(range(cols)[col_key])
                return Array(tuple(x for row in chosen for x in row), (len(chosen), width))
            j = _index(col_key, cols)
            return Array(tuple(row[j] for row in picked), (len(picked),))
        i = _index(row_key, rows)
        row = self.flat[i * cols:(i + 1) * cols]
        if isinstance(col_key, slice):
            part = row[col_key]
            return Array(part, (len(part),))
        return row[_index(col_key, cols)]

    def __array__(self, dtype: Any = None, copy: Any = None) -> Any:
        """A read-only NumPy array of the entries, for ``numpy.asarray(value)``."""
        array = numpy_array(self)
        return array if dtype is None else array.astype(dtype)

    # ------------------------------------------------------------------ values

    def __eq__(self, other: object) -> bool:
        """Equal shape and entries (a bool, not NumPy's array of bools)."""
        if not isinstance(other, Array):
            return NotImplemented
        return self.shape == other.shape and self.flat == other.flat

    def __hash__(self) -> int:
        return hash((self.shape, self.flat))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("an Array is immutable")

    def __reduce__(self) -> tuple[type, tuple[tuple[float, ...], Shape]]:
        return (Array, (self.flat, self.shape))

    def __repr__(self) -> str:
        return f"Array({self.tolist()!r})"

    # ------------------------------------------------------------------ exact arithmetic

    def map(self, fn: Any) -> Array:
        """``fn`` applied to each entry (a float to a float), same shape."""
        return Array(tuple(fn(x) for x in self.flat), self.shape)

    def zip_with(self, other: Array, fn: Any) -> Array:
        """``fn`` applied to entries at the same place of two arrays of one shape."""
        return Array(tuple(fn(x, y) for x, y in zip(self.flat, other.flat)), self.shape)


def _real(x: Any) -> float:
    if isinstance(x, str) or not hasattr(x, "__float__"):
        raise ValueError(f"a vector or matrix entry must be a number, not {x!r}")
    return float(x)


def _index(key: Any, size: int) -> int:
    i = key.__index__()
    if not -size <= i < size:
        raise IndexError(f"index {i} is out of range for size {size}")
    return i % size


def matrix(rows: Sequence[Sequence[float]]) -> Array:
    """A matrix of rows of floats (trusted: equally long, floats)."""
    return Array(tuple(x for row in rows for x in row), (len(rows), len(rows[0])))


def vector(entries: Sequence[float]) -> Array:
    """A vector of floats (trusted)."""
    return Array(tuple(entries), (len(entries),))


def numpy_array(value: Array) -> Any:
    """``value`` as a read-only ``float64`` NumPy array."""
    import numpy as np  # lazy: only the computations that need NumPy's own rounding load it

    array = np.array(value.flat, dtype=np.float64).reshape(value.shape)
    array.flags.writeable = False
    return array


@contextmanager
def strict_numpy() -> Iterator[Any]:
    """NumPy (the module), with overflow, division by zero and invalid operations raised as
    ``FloatingPointError`` (an ``ArithmeticError``, which the evaluator reports at the node)
    instead of warnings on stderr and infinite entries."""
    import numpy as np  # lazy: only models that multiply or invert matrices load NumPy

    with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
        yield np


def from_numpy(array: Any) -> Array:
    """The :class:`Array` of a 1-D or 2-D NumPy result."""
    return Array(tuple(array.ravel().tolist()), tuple(array.shape))  # type: ignore[arg-type]
