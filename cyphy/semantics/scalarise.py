"""Vector and matrix equations as component equations, for targets that have only scalars.

The model's equations mix scalars, vectors and matrices (``fV == pV + A * v``,
``tau == transpose(F) * A``). A target without vectors (Isabelle's ``real``-valued state, or any
prover that must not read ``*`` on ``real list`` as something else) needs one scalar equation
per component. This pass infers the shape of every subterm (``()`` a scalar, ``(n,)`` a vector,
``(m, n)`` a matrix), refuses what does not fit (a ``+`` of different sizes, a product whose
inner sizes differ, a vector where a scalar is needed) and writes component ``k`` of each side.

Components are named as ``cyphy solve`` names them (:mod:`cyphy.semantics.dynamics.reduce`): a
vector or matrix variable ``X`` has the scalar variables ``X_1`` … ``X_n``, counted from 1,
row by row. A constant keeps its one name and is indexed (``Index(A, (2,))`` is ``A``'s third
item, counted from 0 as HOL's ``nth`` counts), so its definition stays one list.

The library's vector and matrix functions whose components are arithmetic in their arguments'
components (``physmod::math``: ``skew``, ``ad``, ``ScrewAxis``, ``cross``, ``dot``, ``norm``,
``Rot``, ``Adjoint``, ``identity``, ``zeroes``) are written out as the literal they denote
(:data:`EXPANSIONS`), so ``ad(fV) * A * v`` has a component form; products with a literal 0
leave no term.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.values import within

Shape = tuple[int, ...]
SCALAR: Shape = ()

#: Functions whose result has the shape of their (scalar) arguments: component-free.
SCALAR_FUNCTIONS = frozenset({"sin", "cos", "tan", "asin", "acos", "atan", "arctan", "atan2",
                              "sqrt", "exp", "log", "ln", "abs", "sign", "min", "max", "floor",
                              "ceil"})


def _zero(e: ex.Expr) -> bool:
    return isinstance(e, ex.Num) and e.text.replace(".", "", 1).strip("0") == ""


def _neg(e: ex.Expr) -> ex.Expr:
    return e if _zero(e) else ex.UnaryOp("-", e)


def _mul(a: ex.Expr, b: ex.Expr) -> ex.Expr:
    return ex.Num("0") if _zero(a) or _zero(b) else ex.BinOp("*", a, b)


def _sum(terms: list[ex.Expr]) -> ex.Expr:
    """``a + b + …`` without the literal zeros (``0`` when nothing is left)."""
    kept = [t for t in terms if not _zero(t)]
    if not kept:
        return ex.Num("0")
    out = kept[0]
    for t in kept[1:]:
        out = ex.BinOp("+", out, t)
    return out


def _skew(v: list[ex.Expr]) -> list[list[ex.Expr]]:
    """``physmod::math::skew``: the matrix of ``v ×``."""
    zero = ex.Num("0")
    return [[zero, _neg(v[2]), v[1]], [v[2], zero, _neg(v[0])], [_neg(v[1]), v[0], zero]]


def _ad(v: list[ex.Expr]) -> list[list[ex.Expr]]:
    """``physmod::math::ad``: ``[| skew(w), 0; skew(v), skew(w) |]`` of ``V = (w; v)``."""
    w, u = _skew(v[:3]), _skew(v[3:])
    zero = [ex.Num("0")] * 3
    return [w[i] + zero for i in range(3)] + [u[i] + w[i] for i in range(3)]


def _rot(w: list[ex.Expr], theta: ex.Expr) -> list[list[ex.Expr]]:
    """``physmod::math::Rot``: Rodrigues' ``I + sin θ [w] + (1 - cos θ) [w]²``, with
    ``([w]²)_ij = w_i w_j - δ_ij (w·w)``."""
    k = _skew(w)
    s = ex.Call(ex.Name(("sin",)), (theta,))
    c1 = ex.BinOp("-", ex.Num("1"), ex.Call(ex.Name(("cos",)), (theta,)))
    ww = _sum([_mul(x, x) for x in w])
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            square = _mul(w[i], w[j]) if i != j else ex.BinOp("-", _mul(w[i], w[j]), ww)
            terms = [ex.Num("1") if i == j else ex.Num("0"), _mul(s, k[i][j]),
                     ex.BinOp("*", c1, square)]
            row.append(_sum(terms))
        rows.append(row)
    return rows


def _adjoint(t: list[list[ex.Expr]]) -> list[list[ex.Expr]]:
    """``physmod::math::Adjoint``: ``[| R, 0; skew(p)*R, R |]`` of ``T = (R, p)``."""
    r = [row[:3] for row in t[:3]]
    k = _skew([t[i][3] for i in range(3)])
    kr = [[_sum([_mul(k[i][m], r[m][j]) for m in range(3)]) for j in range(3)]
          for i in range(3)]
    zero = [ex.Num("0")] * 3
    return [r[i] + zero for i in range(3)] + [kr[i] + r[i] for i in range(3)]


#: Library functions written out as literals: name → (argument shapes, None for a scalar or
#: a literal size; the literal as rows, or a scalar expression, from the arguments'
#: components: a vector's as a list, a matrix's as rows, a scalar as itself).
EXPANSIONS: dict[str, tuple[tuple[Shape | None, ...], Callable[..., object]]] = {
    "skew": (((3,),), _skew),
    "ad": (((6,),), _ad),
    "ScrewAxis": (((3,), (3,)), lambda w, v: [w + v]),
    "cross": (((3,), (3,)), lambda u, v: [[
        ex.BinOp("-", _mul(u[1], v[2]), _mul(u[2], v[1])),
        ex.BinOp("-", _mul(u[2], v[0]), _mul(u[0], v[2])),
        ex.BinOp("-", _mul(u[0], v[1]), _mul(u[1], v[0]))]]),
    "dot": ((None, None), lambda u, v: _sum([_mul(a, b) for a, b in zip(u, v)])),
    "norm": ((None,), lambda v: ex.Call(ex.Name(("sqrt",)), (_sum([_mul(a, a) for a in v]),))),
    "Rot": (((3,), ()), _rot),
    "Adjoint": (((4, 4),), _adjoint),
    "identity": (((),), lambda n: [[ex.Num("1" if i == j else "0") for j in range(n)]
                                   for i in range(n)]),
    "zeroes": (((), ()), lambda m, n: [[ex.Num("0")] * n for _ in range(m)]),
}
_SIZE_ARGUMENTS = frozenset({"identity", "zeroes"})


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


def _size(shape: Shape) -> int:
    out = 1
    for n in shape:
        out *= n
    return out


def _describe(shape: Shape) -> str:
    if not shape:
        return "a scalar"
    if len(shape) == 1:
        return f"a {shape[0]}-vector"
    return f"a {shape[0]}x{shape[1]} matrix"


def _as_matrix(shape: Shape) -> Shape:
    """A vector is a column in a product."""
    return (shape[0], 1) if len(shape) == 1 else shape


@dataclass
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
            if name in _SIZE_ARGUMENTS:
                if not (isinstance(a, ex.Num) and a.is_integer):
                    raise ScalariseError(a, f"the size given to {name} is not a literal")
                args.append(int(a.text))
                continue
            shape = self.shape(a)
            fits = len(shape) == 1 if want is None else (
                shape == want if not want or not shape else _as_matrix(shape) == _as_matrix(want))
            if not fits:
                expected = "a vector" if want is None else _describe(want)
                raise ScalariseError(a, f"{name} takes {expected} here, not {_describe(shape)}")
            if not shape:
                args.append(self._scalar(a))
            elif len(shape) == 1:
                args.append([self.component(a, (k,)) for k in range(_size(shape))])
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
            raise ScalariseError(e, f"{len(e.args)} indices into {_describe(base)}")
        return SCALAR

    def _shape_Call(self, e: ex.Call) -> Shape:
        name = e.func.text if isinstance(e.func, ex.Name) else None
        expanded = self.expansion(e)
        if expanded is not None:
            return self.shape(expanded)
        shapes = [self.shape(a) for a in e.args]
        if name == "transpose" and len(shapes) == 1:
            m = _as_matrix(shapes[0]) if shapes[0] else (1, 1)
            return (m[1], m[0])
        if any(_size(s) != 1 for s in shapes if s):
            raise ScalariseError(e, f"{name or 'a function'} applied to a vector or matrix has "
                                 "no component form here (only +, -, *, /, transpose and "
                                 "indexing are written componentwise)")
        return SCALAR

    def _shape_BinOp(self, e: ex.BinOp) -> Shape:
        left, right = self.shape(e.left), self.shape(e.right)
        if e.op in ("+", "-"):
            if _size(left) == _size(right) == 1:
                return left if len(left) >= len(right) else right
            if left and right and _as_matrix(left) == _as_matrix(right):
                return left if len(left) >= len(right) else right
            raise ScalariseError(e, f"'{e.op}' between {_describe(left)} and "
                                 f"{_describe(right)}")
        if e.op == "*":
            if not left or not right:
                return left or right
            a, b = _as_matrix(left), _as_matrix(right)
            if a[1] != b[0]:
                raise ScalariseError(e, f"product of {_describe(left)} and {_describe(right)}: "
                                     f"the left's {a[1]} columns are not the right's {b[0]} "
                                     "rows")
            return (a[0],) if len(right) == 1 else (a[0], b[1])
        if e.op == "/":
            if _size(right) != 1:
                raise ScalariseError(e, f"division by {_describe(right)}")
            return left
        if e.op != "==" and (_size(left) != 1 or _size(right) != 1):
            raise ScalariseError(e, f"'{e.op}' on {_describe(left if left else right)}")
        return SCALAR

    # ------------------------------------------------------------------ components

    def component(self, e: ex.Expr, index: tuple[int, ...]) -> ex.Expr:
        """Component ``index`` (from 0; ``()`` for a scalar or a one-item array) of ``e``,
        as a scalar expression."""
        shape = self.shape(e)
        if not shape:
            return self._scalar(e)
        if not index:
            if _size(shape) != 1:
                raise ScalariseError(e, f"{_describe(shape)} where a scalar is needed")
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
                                 f"{_describe(shape)}")
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
        inner = _as_matrix(left)[1]
        terms = [_mul(self.component(e.left, (i, k) if len(left) == 2 else (i,)),
                      self.component(e.right, (k, j) if len(right) == 2 else (k,)))
                 for k in range(inner)]
        return _sum(terms)

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
            if _size(left) <= 1 and _size(right) <= 1:
                return [ex.BinOp("==", self._at(p.left, (0,) if left else ()),
                                 self._at(p.right, (0,) if right else ()), span=p.span)]
            if _as_matrix(left) != _as_matrix(right):
                raise ScalariseError(p, f"an equation between {_describe(left)} and "
                                     f"{_describe(right)}")
            shape = left if len(left) >= len(right) else right
            return [ex.BinOp("==", self.component(p.left, (k,)), self.component(p.right, (k,)),
                             span=p.span) for k in range(_size(shape))]
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


# --------------------------------------------------------------------------- processes


@dataclass(frozen=True)
class ScalarProcess:
    """The p-model process with scalar state: ``process`` has every vector or matrix field
    of fixed size replaced by its components, and (with ``evolving_as_state``) the locals
    whose derivative appears, and one variable per running integral, added to the private
    state (``promoted``); ``held``: the numeric state variables that discrete actions write
    and no derivative determines, which every evolution keeps constant (``x' = 0``)."""

    process: c.BasicProcess
    promoted: tuple[str, ...]
    held: tuple[str, ...]


def scalar_process(pm: c.BasicProcess, evolving_as_state: bool = True) -> ScalarProcess:
    """The pass itself; raises :class:`ScalariseError` where shapes do not fit."""
    shapes: dict[str, Shape] = {}
    unsized: set[str] = set()

    def note(name: str, t: c.Type, value: ex.Expr | None = None) -> None:
        if not isinstance(t, c.TSeq):
            return
        shape = shape_of_type(t)
        if shape is None and value is not None:
            try:
                shape = Scalariser({}, frozenset()).shape(value)
            except ScalariseError:
                shape = None
        if shape:
            shapes[name] = shape
        else:
            unsized.add(name)

    for f in (*pm.state.fields, *pm.local.fields):
        note(f.name, f.type)
    for k in pm.constants:
        note(k.name, k.type, k.value)
    variables = {f.name for f in (*pm.state.fields, *pm.local.fields)}
    sc = Scalariser(shapes, frozenset(n for n in shapes if n in variables), frozenset(unsized))
    taken = variables | {k.name for k in pm.constants} | {d.name for d in pm.actions}
    for name in sorted(sc.split):
        clash = taken.intersection(components(name, shapes[name]))
        if clash:
            raise ScalariseError(ex.Name((name,)), f"the components of {name} would be named "
                                 f"like {', '.join(sorted(clash))}, which the model has")
    integrals: list[str] = []

    def integral_states(equations: list[ex.Expr]) -> list[ex.Expr]:
        added: list[ex.Expr] = []

        def replace_integral(n: ex.Expr) -> ex.Expr | None:
            if not (isinstance(n, ex.Integral) and n.lower is None and n.upper is None):
                return None
            base = n.operand.text if isinstance(n.operand, ex.Name) else "integral"
            name, k = f"{base}_int", 1
            while name in taken:
                k += 1
                name = f"{base}_int{k}"
            taken.add(name)
            integrals.append(name)
            state = ex.Name((name,), span=n.span)
            added.append(ex.BinOp("==", ex.Derivative(state, span=n.span), n.operand,
                                  span=n.span))
            return state

        out = [ex.transform(e, replace_integral)
               if any(isinstance(n, ex.Integral) for n in e.walk()) else e for e in equations]
        return out + added

    def rewrite(a: c.Action) -> c.Action | None:
        if isinstance(a, c.Evolution):
            equations = [q for e in a.equations for q in sc.predicate(e)]
            if evolving_as_state:
                equations = integral_states(equations)
            return replace(a, equations=tuple(equations))
        if isinstance(a, c.Spec):
            frame = tuple(k for n in a.frame
                          for k in (components(n, shapes[n]) if n in sc.split else [n]))
            return replace(a, frame=frame, pre=sc.condition(a.pre), post=sc.condition(a.post))
        if isinstance(a, (c.Cond, c.Guard)):
            return replace(a, cond=sc.condition(a.cond))
        if isinstance(a, c.IndexedExtChoice):
            return replace(a, where=sc.condition(a.where))
        if isinstance(a, c.Assign):
            targets, values = [], []
            for t, v in zip(a.targets, a.values):
                if t in sc.split:
                    names = components(t, shapes[t])
                    targets += names
                    values += [sc.component(v, (k,)) for k in range(len(names))]
                else:
                    targets.append(t)
                    values.append(sc.whole(v))
            return replace(a, targets=tuple(targets), values=tuple(values))
        if isinstance(a, c.Prefix):
            fields = tuple(f if isinstance(f, c.In) else replace(f, value=sc.whole(f.value))
                           for f in a.comm.fields)
            return replace(a, comm=replace(a.comm, fields=fields))
        if isinstance(a, c.Call) and a.args:
            return replace(a, args=tuple(sc.whole(x) for x in a.args))
        return None

    from cyphy.semantics.circus.walk import action_nodes, map_action

    actions = tuple(replace(d, body=map_action(d.body, rewrite)) for d in pm.actions)
    main = map_action(pm.main, rewrite)

    def fields_of(schema: c.Schema) -> list[c.SchemaField]:
        out = []
        for f in schema.fields:
            if f.name in sc.split:
                out += [c.SchemaField(k, c.REAL, f.visible)
                        for k in components(f.name, shapes[f.name])]
            else:
                out.append(f)
        return out

    state, local = fields_of(pm.state), fields_of(pm.local)
    evolutions = [n for d in (*actions, c.ActionDef("", (), main))
                  for n in action_nodes(d.body) if isinstance(n, c.Evolution)]
    derived = {n.operand.text for ev in evolutions for e in ev.equations for n in e.walk()
               if isinstance(n, ex.Derivative) and isinstance(n.operand, ex.Name)}
    promoted: list[str] = []
    if evolving_as_state:
        promoted = [f.name for f in local if f.name in derived] + integrals
        state += [c.SchemaField(n, c.REAL) for n in promoted]
        local = [f for f in local if f.name not in derived]
        actions = tuple(initialised(d, _continuous_states(evolutions, promoted), pm.initial,
                                    pm.ranges) for d in actions)
    written = {t for d in (*actions, c.ActionDef("", (), main)) for n in action_nodes(d.body)
               for t in (n.targets if isinstance(n, c.Assign) else
                         n.frame if isinstance(n, c.Spec) else ())}
    # only numbers have a rate to hold at 0; a Boolean set-point is left to the equations;
    # a visible variable is the world's (a scenario's Init may start it, nothing holds it)
    held = tuple(f.name for f in state if f.name in written and f.name not in derived
                 and f.type in (c.REAL, c.INT, c.NAT) and not f.visible and evolving_as_state)
    if held:
        hold = tuple(ex.BinOp("==", ex.Derivative(ex.Name((h,))), ex.Num("0")) for h in held)

        def add_hold(a: c.Action) -> c.Action | None:
            if isinstance(a, c.Evolution):
                return replace(a, equations=a.equations + hold)
            return None

        actions = tuple(replace(d, body=map_action(d.body, add_hold)) for d in actions)
        main = map_action(main, add_hold)
    process = replace(pm, state=replace(pm.state, fields=tuple(state)),
                      local=replace(pm.local, fields=tuple(local)), actions=actions, main=main)
    return ScalarProcess(process, tuple(promoted), held)


def type_shape(t: ast.TypeRef | None) -> tuple[int, ...] | None:
    """The shape a declared vector or matrix type of literal sizes fixes (None otherwise)."""
    def size(e: ex.Expr | None) -> int | None:
        return int(e.text) if isinstance(e, ex.Num) and e.is_integer else None

    if isinstance(t, ast.VectorType) and size(t.size):
        return (size(t.size),)  # type: ignore[return-value]
    if isinstance(t, ast.MatrixType) and size(t.rows) and size(t.cols):
        return (size(t.rows), size(t.cols))  # type: ignore[return-value]
    return None


def _continuous_states(evolutions: list[c.Evolution], promoted: list[str]) -> list[str]:
    """The promoted variables that are states of an ODE: the derivative of each is on the
    left of an equation (``x' = v``, ``J * av' = T``; a running integral's own equation is
    one). A local whose derivative is only read (``Kd * e'``) is algebraic: its equation
    gives its value, which an initial assignment could contradict."""
    on_left = {n.operand.text for ev in evolutions for e in ev.equations
               if isinstance(e, ex.BinOp) and e.op == "==" for n in e.left.walk()
               if isinstance(n, ex.Derivative) and isinstance(n.operand, ex.Name)}
    return [n for n in promoted if n in on_left]


def initialised(d: c.ActionDef, states: list[str], initial: tuple[tuple[str, ex.Expr], ...],
                 ranges: tuple[tuple[str, ex.Expr, ex.Expr], ...] = ()) -> c.ActionDef:
    """``Init`` with every continuous state assigned too: a scenario's value or its declared
    initial value, else 0 (spec Rule 2: private variables start at 0; a running integral is
    the integral from 0), or, for a scenario's interval, a specification that starts it in
    the interval. Without it the ODEs' states, once they are state, would start anywhere.
    ``Init`` is an assignment, followed by the scenario's specification when it has one."""
    parts = d.body.items if isinstance(d.body, c.Seq) else (d.body,)
    if d.name != "Init" or not isinstance(parts[0], c.Assign) or not states:
        return d
    assign, rest = parts[0], parts[1:]
    values, boxes = dict(initial), {n: (lo, hi) for n, lo, hi in ranges}
    framed = {n for p in rest if isinstance(p, c.Spec) for n in p.frame}
    missing = [n for n in states if n not in assign.targets and n not in framed]
    points = [n for n in missing if n not in boxes]
    boxed = [(n, *boxes[n]) for n in missing if n in boxes]
    assign = c.Assign(assign.targets + tuple(points), assign.values + tuple(
        values.get(n, ex.Num("0")) for n in points))
    parts = (assign, *rest, *((within(boxed),) if boxed else ()))
    return replace(d, body=parts[0] if len(parts) == 1 else c.Seq(parts))
