"""One expression's shape and scalar components: :class:`Scalariser` infers the shape of
every subterm, refuses what does not fit and writes component ``k`` of each side.
"""

from __future__ import annotations

from typing import Callable

from cyphy import expr as ex
from cyphy.records import record
from cyphy.semantics.circus import ast as c
from cyphy.semantics.scalarise.expansions import EXPANSIONS, SIZE_ARGUMENTS, add_all, times
from cyphy.semantics.scalarise.shapes import (SCALAR, Shape, ScalariseError, as_matrix,
                                              component_name, components, describe, size_of)


@record(frozen=False, slots=False)
class Scalariser:
    """``shapes``: the names that are vectors or matrices, with their shapes; ``split``: those
    among them that become scalar variables (state and locals; the others, constants, are
    indexed)."""

    shapes: dict[str, Shape]
    split: frozenset[str]
    unsized: frozenset[str] = frozenset()  # vectors and matrices of no fixed size

    # ------------------------------------------------------------------ shapes

    def __post_init__(self) -> None:
        self._memo: dict[int, tuple[ex.Expr, Shape]] = {}
        self._expanded: dict[int, tuple[ex.Expr, ex.Expr]] = {}
        self._produced: dict[int, ex.Index] = {}  # indices written by the pass (from 0)

    def _indexed(self, base: ex.Expr, index: tuple[int, ...], span: object) -> ex.Index:
        """A constant's item as HOL's ``nth`` counts (from 0), remembered as the pass's own
        so that reading it again (inside an expanded literal) does not count it from 1."""
        out = ex.Index(base, tuple(ex.Num(str(i)) for i in index), span=span)  # type: ignore
        self._produced[id(out)] = out
        return out

    def expansion(self, e: ex.Expr) -> ex.Expr | None:
        """The literal (or scalar expression) a library call of :data:`EXPANSIONS` denotes,
        built from its arguments' components (memoised: shapes are asked of its nodes)."""
        if not (isinstance(e, ex.Call) and isinstance(e.func, ex.Name)
                and e.func.text in EXPANSIONS):
            return None
        found = self._expanded.get(id(e))
        if found is not None and found[0] is e:
            return found[1]
        name = e.func.text
        wanted, build = EXPANSIONS[name]
        if len(e.args) != len(wanted):
            raise ScalariseError(e, f"{name} takes {len(wanted)} argument"
                                 f"{'s' if len(wanted) != 1 else ''}")
        args: list[object] = []
        for a, want in zip(e.args, wanted):
            if name in SIZE_ARGUMENTS:
                if not (isinstance(a, ex.Num) and a.is_integer):
                    raise ScalariseError(a, f"the size given to {name} is not a literal")
                args.append(int(a.text))
                continue
            shape = self.shape(a)
            fits = len(shape) == 1 if want is None else (
                shape == want if not want or not shape else as_matrix(shape) == as_matrix(want))
            if not fits:
                expected = "a vector" if want is None else describe(want)
                raise ScalariseError(a, f"{name} takes {expected} here, not {describe(shape)}")
            if not shape:
                args.append(self._scalar(a))
            elif len(shape) == 1:
                args.append([self.component(a, (k,)) for k in range(size_of(shape))])
            else:
                args.append([[self.component(a, (i, j)) for j in range(shape[1])]
                             for i in range(shape[0])])
        value = build(*args)
        out: ex.Expr
        if isinstance(value, list):
            rows = tuple(tuple(r) for r in value)
            out = ex.Vector(rows, span=e.span) if len(rows) == 1 else ex.Matrix(rows, span=e.span)
        else:
            out = value  # type: ignore[assignment]
        self._expanded[id(e)] = (e, out)
        return out

    def shape(self, e: ex.Expr) -> Shape:
        """The shape of ``e`` (memoised per node: components ask it of every subterm)."""
        found = self._memo.get(id(e))
        if found is not None and found[0] is e:
            return found[1]
        method: Callable[[ex.Expr], Shape] | None = getattr(
            self, "_shape_" + type(e).__name__, None)
        if method is None:
            if any(self.shape(ch) for ch in e.children()):
                raise ScalariseError(e, f"{type(e).__name__} of a vector has no component form")
            shape = SCALAR
        else:
            shape = method(e)
        self._memo[id(e)] = (e, shape)
        return shape

    def has_arrays(self, e: ex.Expr) -> bool:
        """Whether ``e`` mentions a vector or matrix at all (most equations do not)."""
        return any(isinstance(n, (ex.Vector, ex.Matrix, ex.Seq, ex.Index))
                   or (isinstance(n, ex.Call) and isinstance(n.func, ex.Name)
                       and n.func.text in EXPANSIONS)
                   or (isinstance(n, ex.Name) and (n.text in self.shapes
                                                   or n.text in self.unsized))
                   for n in e.walk())

    def _shape_Num(self, e: ex.Num) -> Shape:
        return SCALAR

    def _shape_Bool(self, e: ex.Bool) -> Shape:
        return SCALAR

    def _shape_Name(self, e: ex.Name) -> Shape:
        if e.text in self.unsized:
            raise ScalariseError(e, f"'{e.text}' is a vector or matrix whose size is not "
                                 "declared, so it cannot be written componentwise")
        return self.shapes.get(e.text, SCALAR)

    def _shape_Vector(self, e: ex.Vector) -> Shape:
        for row in e.rows:
            for item in row:
                if self.shape(item):
                    raise ScalariseError(item, "a vector inside a vector literal")
        widths = {len(r) for r in e.rows}
        if len(widths) != 1:
            raise ScalariseError(e, "the rows of a matrix literal have different lengths")
        return (len(e.rows[0]),) if len(e.rows) == 1 else (len(e.rows), widths.pop())

    _shape_Matrix = _shape_Vector

    def _shape_Seq(self, e: ex.Seq) -> Shape:
        return self._shape_Vector(ex.Vector((e.items,), span=e.span))

    def _shape_UnaryOp(self, e: ex.UnaryOp) -> Shape:
        return self.shape(e.operand)

    def _shape_Derivative(self, e: ex.Derivative) -> Shape:
        return self.shape(e.operand)

    def _shape_Integral(self, e: ex.Integral) -> Shape:
        return self.shape(e.operand)

    def _shape_Index(self, e: ex.Index) -> Shape:
        if isinstance(e.base, ex.Name) and e.base.text in self.unsized:
            return SCALAR  # an item of a vector of open size: read with nth
        base = self.shape(e.base)
        if base and len(e.args) != len(base):
            raise ScalariseError(e, f"{len(e.args)} indices into {describe(base)}")
        return SCALAR

    def _shape_Call(self, e: ex.Call) -> Shape:
        name = e.func.text if isinstance(e.func, ex.Name) else None
        expanded = self.expansion(e)
        if expanded is not None:
            return self.shape(expanded)
        shapes = [self.shape(a) for a in e.args]
        if name == "transpose" and len(shapes) == 1:
            m = as_matrix(shapes[0]) if shapes[0] else (1, 1)
            return (m[1], m[0])
        if any(size_of(s) != 1 for s in shapes if s):
            raise ScalariseError(e, f"{name or 'a function'} applied to a vector or matrix has "
                                 "no component form here (only +, -, *, /, transpose and "
                                 "indexing are written componentwise)")
        return SCALAR

    def _shape_BinOp(self, e: ex.BinOp) -> Shape:
        left, right = self.shape(e.left), self.shape(e.right)
        if e.op in ("+", "-"):
            if size_of(left) == size_of(right) == 1:
                return left if len(left) >= len(right) else right
            if left and right and as_matrix(left) == as_matrix(right):
                return left if len(left) >= len(right) else right
            raise ScalariseError(e, f"'{e.op}' between {describe(left)} and "
                                 f"{describe(right)}")
        if e.op == "*":
            if not left or not right:
                return left or right
            a, b = as_matrix(left), as_matrix(right)
            if a[1] != b[0]:
                raise ScalariseError(e, f"product of {describe(left)} and {describe(right)}: "
                                     f"the left's {a[1]} columns are not the right's {b[0]} "
                                     "rows")
            return (a[0],) if len(right) == 1 else (a[0], b[1])
        if e.op == "/":
            if size_of(right) != 1:
                raise ScalariseError(e, f"division by {describe(right)}")
            return left
        if e.op != "==" and (size_of(left) != 1 or size_of(right) != 1):
            raise ScalariseError(e, f"'{e.op}' on {describe(left if left else right)}")
        return SCALAR

    # ------------------------------------------------------------------ components

    def component(self, e: ex.Expr, index: tuple[int, ...]) -> ex.Expr:
        """Component ``index`` (from 0; ``()`` for a scalar or a one-item array) of ``e``,
        as a scalar expression."""
        shape = self.shape(e)
        if not shape:
            return self._scalar(e)
        if not index:
            if size_of(shape) != 1:
                raise ScalariseError(e, f"{describe(shape)} where a scalar is needed")
            index = (0,) * len(shape)
        if len(index) == 1 and len(shape) == 2:  # a flat index into a matrix (row by row)
            index = divmod(index[0], shape[1])
        if len(index) == 2 and len(shape) == 1:  # a vector read as a column (or a row)
            index = (index[0] + index[1],)
        return self._component(e, index)

    def _index(self, e: ex.Index) -> ex.Expr:
        """``x[i]`` or ``M[i, j]`` (the notation counts from 1): the component variable of a
        split vector, or the constant indexed from 0 as HOL's ``nth`` does."""
        base = e.base
        if not (isinstance(base, ex.Name) and (base.text in self.shapes
                                               or base.text in self.unsized)):
            raise ScalariseError(e, "an index into something that is not a vector or "
                                 "matrix of the model")
        if not all(isinstance(a, ex.Num) and a.is_integer and int(a.text) >= 1
                   for a in e.args):
            raise ScalariseError(e, "an index that is not a literal (counted from 1)")
        index = tuple(int(a.text) - 1 for a in e.args)  # type: ignore[union-attr]
        shape = self.shapes.get(base.text)
        if shape is not None and any(i >= n for i, n in zip(index, shape)):
            raise ScalariseError(e, f"index {', '.join(str(i + 1) for i in index)} out of "
                                 f"{describe(shape)}")
        if shape is not None and base.text in self.split:
            return self._component(base, index)
        return self._indexed(base, index, e.span)

    def _scalar(self, e: ex.Expr) -> ex.Expr:
        """A scalar expression whose subterms may be one-item arrays or indices."""
        if isinstance(e, ex.Index):
            return e if self._produced.get(id(e)) is e else self._index(e)
        expanded = self.expansion(e)
        if expanded is not None:
            return self._scalar(expanded) if not self.shape(expanded) else \
                self.component(expanded, ())
        if not any(self.shape(ch) or isinstance(ch, ex.Index) for ch in e.walk()
                   if ch is not e):
            return e
        kids = {id(ch): self.component(ch, ()) for ch in e.children()}
        return ex.transform(e, lambda n: kids.get(id(n)))

    def _component(self, e: ex.Expr, index: tuple[int, ...]) -> ex.Expr:
        if isinstance(e, ex.Name):
            own = self.shapes[e.text]
            flat = index[0] if len(index) == 1 else index[0] * own[1] + index[1]
            if e.text in self.split:
                return ex.Name((component_name(e.text, flat),), span=e.span)
            return self._indexed(e, index, e.span)
        if isinstance(e, (ex.Vector, ex.Matrix)):
            row = e.rows[0] if len(e.rows) == 1 else e.rows[index[0]]
            return self.component(row[index[-1]], ())
        if isinstance(e, ex.Seq):
            return self.component(e.items[index[-1]], ())
        if isinstance(e, ex.UnaryOp):
            return ex.UnaryOp(e.op, self._at(e.operand, index), span=e.span)
        if isinstance(e, ex.Derivative):
            return ex.Derivative(self._at(e.operand, index), span=e.span)
        if isinstance(e, ex.Integral):
            return ex.Integral(self._at(e.operand, index), span=e.span)
        expanded = self.expansion(e)
        if expanded is not None:
            return self.component(expanded, index)
        if isinstance(e, ex.Call):  # transpose: the only other array-valued call
            inner = self.shape(e.args[0])
            if len(inner) == 1:
                return self.component(e.args[0], (index[-1],))
            return self.component(e.args[0], (index[1], index[0]))
        if isinstance(e, ex.BinOp):
            return self._binop(e, index)
        raise ScalariseError(e, f"{type(e).__name__} has no component form")

    def _at(self, e: ex.Expr, index: tuple[int, ...]) -> ex.Expr:
        return self.component(e, index) if self.shape(e) else self._scalar(e)

    def _binop(self, e: ex.BinOp, index: tuple[int, ...]) -> ex.Expr:
        left, right = self.shape(e.left), self.shape(e.right)
        if e.op in ("+", "-", "/") or not left or not right:
            return ex.BinOp(e.op, self._at(e.left, index), self._at(e.right, index),
                            span=e.span)
        # a product of two arrays: the sum over the inner index
        i, j = index if len(index) == 2 else (index[0], 0)
        inner = as_matrix(left)[1]
        terms = [times(self.component(e.left, (i, k) if len(left) == 2 else (i,)),
                      self.component(e.right, (k, j) if len(right) == 2 else (k,)))
                 for k in range(inner)]
        return add_all(terms)

    # ------------------------------------------------------------------ predicates

    def predicate(self, p: ex.Expr) -> list[ex.Expr]:
        """The scalar conjuncts of a predicate: an equation between vectors or matrices
        becomes one equation per component; a conjunction is split."""
        if not self.has_arrays(p):
            return [p]
        if isinstance(p, ex.BinOp) and p.op == "/\\":
            return self.predicate(p.left) + self.predicate(p.right)
        if isinstance(p, ex.BinOp) and p.op == "==":
            left, right = self.shape(p.left), self.shape(p.right)
            if size_of(left) <= 1 and size_of(right) <= 1:
                return [ex.BinOp("==", self._at(p.left, (0,) if left else ()),
                                 self._at(p.right, (0,) if right else ()), span=p.span)]
            if as_matrix(left) != as_matrix(right):
                raise ScalariseError(p, f"an equation between {describe(left)} and "
                                     f"{describe(right)}")
            shape = left if len(left) >= len(right) else right
            return [ex.BinOp("==", self.component(p.left, (k,)), self.component(p.right, (k,)),
                             span=p.span) for k in range(size_of(shape))]
        self.shape(p)
        return [self._scalar(p)]

    def whole(self, e: ex.Expr) -> ex.Expr:
        """``e`` where a split vector or matrix is used whole (an output value, an action
        argument): the split variable as the sequence of its components."""
        def expand(n: ex.Expr) -> ex.Expr | None:
            if isinstance(n, ex.Index):
                return self._index(n)
            if isinstance(n, ex.Name) and n.text in self.split:
                return ex.Seq(tuple(ex.Name((k,), span=n.span)
                                    for k in components(n.text, self.shapes[n.text])),
                              span=n.span)
            return None
        return ex.transform(e, expand)

    def condition(self, p: c.Predicate) -> c.Predicate:
        """A predicate with every equation between arrays written per component."""
        if isinstance(p, c.Exists):
            bound = tuple(k for b in p.bound
                          for k in ([c.Binding(n, c.REAL)
                                     for n in components(b.name, self.shapes[b.name])]
                                    if b.name in self.split else [b]))
            return c.Exists(bound, tuple(q for e in p.body for q in self.predicate(e)))
        items = self.predicate(p)
        return items[0] if len(items) == 1 else ex.conjunction(items)
