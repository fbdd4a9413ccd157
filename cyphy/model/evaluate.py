"""Numeric evaluation of constant expressions (sdf.md decision 5, notation.md A.11).

SDF needs numbers where a model writes expressions: ``(0.085*cos(2*i*PI/24))m``, ``HEIGHT/2``,
``[| 0, -Axis[3], Axis[2]; … |]``. RoboTool prints 0 for every call and ignores unit suffixes;
this module evaluates them properly.

Values (:data:`Value`):

* ``int`` and ``float`` are the notation's ``int``/``nat`` and ``real``. An integer literal is an
  ``int``, any other literal a ``float``; ``+ - * %`` and ``^`` with a non-negative exponent keep
  two ints an int (so ``2*3`` is ``6``, an exact index or count); ``/`` is real division, always
  a float (``7/2 == 3.5``, ``6/2 == 3.0``); ``%`` is Python's remainder, whose sign follows the
  divisor as Isabelle's ``mod`` does. A quantity with a unit (``3cm``) is a real.
* ``bool`` and ``str`` are ``boolean`` and ``string``; they take part in comparisons, connectives
  and conditions only, never in arithmetic (Python's ``True + 1`` is refused).
* :data:`Vec`, an immutable :class:`~cyphy.model.array.Array` of floats (``numpy.asarray``
  turns it into a ``float64`` array): 1-D for ``(|a, b, c|)`` and a single-row
  ``[|a, b, c|]``, 2-D for several rows (``[|1; 2; 3|]`` is a 3x1 matrix). Entries are reals.
  Immutable so that a value shared through ``env`` cannot be changed behind the caller's
  back. A 1-D vector acts as a column in ``M * v`` and as a row in ``v * M``.

Indexing counts from 1, as RoboChart and the library do (``Axis[3]`` is the z component of
``Axis = (|1, 0, 0|)``): ``v[i]`` is a component, ``M[i, j]`` an entry, ``M[i]`` row ``i``.
``submatrix`` alone counts from 0, because the library declares it so.

Every problem with the input (an unknown name, division by zero, ``sqrt(-1)``, a wrong number of
arguments, a condition that is not a boolean, a derivative…) raises :class:`EvalError` with the
span of the offending node; nothing else escapes :func:`evaluate`. Internally, operators and
functions raise ``ValueError`` without a location and the node that called them turns it into an
``EvalError`` with its own span, so every check is written once and still points at the source.

This module must stay cheap to import: no NumPy (only the matrix products, powers and
inverses of :mod:`~cyphy.model.operators` and :mod:`~cyphy.model.math_functions` load it,
when a model uses them), no SymPy. An entry that overflows is infinite and reported by
``require_finite`` at the node that computed it.
"""

from __future__ import annotations

import operator
from types import MappingProxyType
from typing import Callable, Mapping

from cyphy.diagnostics import Span, did_you_mean
from cyphy.model.array import Array
from cyphy.model.math_functions import MATH_FUNCTIONS, arity, arity_text
from cyphy.model.operators import SHORT_CIRCUIT, STRICT_OPS
from cyphy.model.values import (
    NO_SPAN,
    EvalError,
    Invalid,
    UnboundName,
    Value,
    boolean,
    describe,
    from_env,
    frozen,
    integer,
    is_number,
    literal_value,
    arithmetic,
    require_finite,
    scalar,
)
from cyphy.model.units import units
from cyphy.expr import (
    BinOp,
    Bool,
    Call,
    Derivative,
    Expr,
    IfExpr,
    Index,
    Integral,
    Matrix,
    Member,
    Name,
    Num,
    Quantity,
    Record,
    Seq,
    Str,
    UnaryOp,
    Vector,
    path_of,
)

# --------------------------------------------------------------------------- units

UNIT_FACTORS: Mapping[str, float] = MappingProxyType(
    {name: unit.factor for name, unit in units().items()})
"""SI factor of each unit suffix the grammar accepts (from Pint, ``cyphy/model/units.py``): a
quantity is its value times the factor."""


# --------------------------------------------------------------------------- evaluation


_METHOD_NAMES: dict[type, str] = {}
"""The ``_eval_`` method of each node class, found once along its MRO."""


class _Evaluator:
    """Evaluates one expression: ``_eval_<Class>`` per node class, found along the MRO."""

    def __init__(self, env: Mapping[str, object], functions: Mapping[str, Callable[..., Value]]):
        self.env = env
        self.functions = functions

    def eval(self, node: Expr) -> Value:
        """Evaluate ``node``; a ``ValueError`` or arithmetic error raised for it, but not yet
        located, becomes an :class:`EvalError` with this node's span."""
        name = _METHOD_NAMES.get(type(node))
        if name is None:
            name = next("_eval_" + cls.__name__ for cls in type(node).__mro__
                        if hasattr(self, "_eval_" + cls.__name__))
            _METHOD_NAMES[type(node)] = name
        method = getattr(self, name)
        try:
            value = method(node)
            require_finite(value)
            return value
        except (ValueError, ArithmeticError) as err:
            if isinstance(err, ZeroDivisionError):
                message = "division by zero"
            elif isinstance(err, OverflowError):
                message = "numeric overflow: the result is too large"
            elif isinstance(err, ArithmeticError):
                message = f"numeric error: {err}"
            else:
                message = str(err)
            raise EvalError(message, node.span, getattr(err, "hint", "")) from None

    def _eval_Expr(self, node: Expr) -> Value:
        raise ValueError(f"{type(node).__name__} expressions cannot be evaluated to a number")

    def _eval_Num(self, node: Num) -> Value:
        return literal_value(node.text)

    def _eval_Str(self, node: Str) -> Value:
        return node.value

    def _eval_Bool(self, node: Bool) -> Value:
        return node.value

    def _lookup(self, name: str, span: Span) -> Value:
        if name not in self.env:
            raise UnboundName(name, span, did_you_mean(name, self.env))
        return from_env(name, self.env[name])

    def _eval_Name(self, node: Name) -> Value:
        return self._lookup(node.text, node.span)

    def _eval_Member(self, node: Member) -> Value:
        """A path ``a.b`` is the name ``a::b``: ``.`` and ``::`` navigate alike (A.12.6)."""
        path = path_of(node)
        if path is None:
            raise ValueError(f"field '{node.name}' of a computed value cannot be evaluated")
        return self._lookup("::".join(path), node.span)

    def _eval_Quantity(self, node: Quantity) -> Value:
        factor = UNIT_FACTORS.get(node.unit)
        if factor is None:
            raise Invalid(
                f"unknown unit '{node.unit}'", "known units: " + ", ".join(sorted(UNIT_FACTORS))
            )
        value = arithmetic(node.unit, self.eval(node.value))
        if is_number(value):
            return float(value) * factor  # type: ignore[arg-type]
        return value.map(lambda x: x * factor)  # type: ignore[union-attr]

    def _eval_UnaryOp(self, node: UnaryOp) -> Value:
        operand = self.eval(node.operand)
        if node.op == "not":
            return not boolean("the operand of 'not'", operand)
        value = arithmetic("-", operand)
        return -value if is_number(value) else value.map(operator.neg)  # type: ignore

    def _eval_BinOp(self, node: BinOp) -> Value:
        left = self.eval(node.left)
        if node.op in SHORT_CIRCUIT:
            settling, result = SHORT_CIRCUIT[node.op]
            if boolean(f"an operand of '{node.op}'", left) == settling:
                return result
            return boolean(f"an operand of '{node.op}'", self.eval(node.right))
        operator = STRICT_OPS.get(node.op)
        if operator is None:
            raise ValueError(f"unknown operator '{node.op}'")
        return operator(left, self.eval(node.right))

    def _eval_IfExpr(self, node: IfExpr) -> Value:
        """Only the chosen branch is evaluated: ``if x > 0 then sqrt(x) else 0 end`` is safe."""
        condition = boolean("the condition of 'if'", self.eval(node.cond))
        return self.eval(node.then if condition else node.orelse)

    def _eval_Vector(self, node: Vector | Matrix) -> Value:
        rows = [[self.eval(item) for item in row] for row in node.rows]
        for row in rows:
            for item in row:
                scalar("a vector or matrix entry", item)
        widths = sorted({len(row) for row in rows})
        if len(widths) > 1:
            raise ValueError(f"the rows of a matrix have different lengths ({widths})")
        return frozen(rows[0] if len(rows) == 1 else rows)

    _eval_Matrix = _eval_Vector

    def _eval_Index(self, node: Index) -> Value:
        """1-based, as RoboChart: ``v[1]`` is the first component, ``M[i]`` row ``i``."""
        base = self.eval(node.base)
        positions = [self.eval(arg) for arg in node.args]
        if not isinstance(base, Array):
            raise ValueError(f"only vectors and matrices can be indexed, not {describe(base)}")
        if len(positions) > base.ndim:
            raise ValueError(f"{describe(base)} takes at most {base.ndim} index(es)")
        offsets = []
        for position, size in zip(positions, base.shape):
            i = integer("an index", position)
            if not 1 <= i <= size:
                raise ValueError(f"index {i} is out of range 1..{size} for {describe(base)}")
            offsets.append(i - 1)
        item = base[tuple(offsets)]
        return item if isinstance(item, Array) else float(item)

    def _eval_Call(self, node: Call) -> Value:
        """A call of a named function; a curried ``f(a)(b, c)`` is ``f(a, b, c)`` (that is how
        the models write ``submatrix(M)(0, 0, 3, 3)``)."""
        func, args = node.func, node.args
        while isinstance(func, Call):
            func, args = func.func, func.args + args
        if not isinstance(func, Name):
            raise ValueError("only a named function can be called")
        name = func.text
        fn = self.functions.get(name)
        if fn is None:
            if name in self.env:
                raise ValueError(f"'{name}' is a constant, not a function")
            raise Invalid(f"unknown function '{name}'", did_you_mean(name, self.functions))
        values = [self.eval(arg) for arg in args]
        signature = arity(fn)
        if signature is not None:
            try:
                signature.bind(*values)
            except TypeError:
                raise ValueError(
                    f"{name} takes {arity_text(signature)}, got {len(values)}"
                ) from None
        try:
            return fn(*values)
        except ValueError as err:
            raise Invalid(f"{name} {err}", getattr(err, "hint", "")) from None

    def _eval_Derivative(self, node: Derivative) -> Value:
        raise ValueError("a derivative has no constant value")

    def _eval_Integral(self, node: Integral) -> Value:
        raise ValueError("an integral has no constant value")

    def _eval_Seq(self, node: Seq) -> Value:
        raise ValueError("a sequence cannot be used as a number")

    def _eval_Record(self, node: Record) -> Value:
        raise ValueError(f"a record ({'::'.join(node.type_name)}) cannot be used as a number")


def evaluate(
    expr: Expr,
    env: Mapping[str, object],
    functions: Mapping[str, Callable[..., Value]] | None = None,
) -> Value:
    """The value of ``expr``; raises :class:`EvalError` (never anything else) when it has none.

    Names are looked up in ``env`` by their text (``"::".join(parts)``; a path ``a.b`` as
    ``a::b``), so the caller decides which spellings a constant answers to (``HEIGHT`` and
    ``Treel::HEIGHT``) and which ``PI`` applies. ``env`` values may be Python or NumPy numbers,
    booleans, strings and 1-D or 2-D arrays. A missing name raises :class:`UnboundName`.
    ``functions`` are merged over :data:`MATH_FUNCTIONS`; a function gets evaluated arguments and
    signals bad input with ``ValueError`` (its message reads after the function's name).
    Evaluation recurses, so nesting deeper than a few hundred levels raises ``EvalError`` too;
    constant expressions are far shallower.
    """
    table = {**MATH_FUNCTIONS, **functions} if functions else MATH_FUNCTIONS
    evaluator = _Evaluator(env, table)
    try:
        return evaluator.eval(expr)
    except RecursionError:
        raise EvalError("the expression is too deeply nested to evaluate", expr.span) from None


Compiled = Callable[[Mapping[str, object]], Value]
_COMPILED: dict[int, tuple[Expr, Compiled | None]] = {}


def _compile(node: Expr) -> Compiled | None:
    """A closure computing ``node`` with the interpreter's own operations, for the node kinds
    that dominate repeated evaluation (poses of indexed blocks); None for anything else."""
    if isinstance(node, Num):
        try:
            value: Value = literal_value(node.text)
        except ValueError:
            return None  # the interpreter reports it
        return lambda env: value
    if isinstance(node, Name):
        key = node.text
        return lambda env: from_env(key, env[key])
    if isinstance(node, Quantity):
        inner, factor = _compile(node.value), UNIT_FACTORS.get(node.unit)
        if inner is None or factor is None:
            return None
        unit = node.unit
        return lambda env: float(scalar(unit, inner(env))) * factor
    if isinstance(node, UnaryOp) and node.op == "-":
        operand = _compile(node.operand)
        if operand is None:
            return None
        return lambda env: -scalar("-", operand(env))
    if isinstance(node, BinOp) and node.op in STRICT_OPS:
        left, right, op = _compile(node.left), _compile(node.right), STRICT_OPS[node.op]
        if left is None or right is None:
            return None
        return lambda env: op(left(env), right(env))
    if isinstance(node, Call) and isinstance(node.func, Name) \
            and node.func.text in MATH_FUNCTIONS:
        args = [_compile(a) for a in node.args]
        if any(a is None for a in args):
            return None
        fn = MATH_FUNCTIONS[node.func.text]
        return lambda env: fn(*[a(env) for a in args])  # type: ignore[misc]
    return None


def evaluate_fast(expr: Expr, env: Mapping[str, object]) -> Value:
    """:func:`evaluate` with the library's functions, compiling the expression once (cached by
    identity) for when the same expression is evaluated many times. Any failure re-runs the
    interpreter, which raises the precise :class:`EvalError`."""
    hit = _COMPILED.get(id(expr))
    if hit is None or hit[0] is not expr:
        if len(_COMPILED) > 8192:
            _COMPILED.clear()
        hit = (expr, _compile(expr))
        _COMPILED[id(expr)] = hit
    compiled = hit[1]
    if compiled is not None:
        try:
            value = compiled(env)
            require_finite(value)
            return value
        except Exception:  # noqa: BLE001 - the interpreter says exactly what is wrong
            pass
    return evaluate(expr, env)


def free_names(expr: Expr) -> set[str]:
    """The names ``expr`` needs from ``env``: every name and path, except functions called.

    Iterative, like :meth:`Expr.walk`, because generated expressions can be very deep.
    """
    names: set[str] = set()
    stack = [expr]
    while stack:
        node = stack.pop()
        if isinstance(node, Call):
            stack.extend(node.args)
            if not isinstance(node.func, Name):
                stack.append(node.func)
            continue
        path = path_of(node)
        if path is not None:
            names.add("::".join(path))
        else:
            stack.extend(node.children())
    return names


PRIMITIVE_TYPES = frozenset({"real", "int", "nat", "boolean", "string"})


def coerce(value: Value, declared: str, span: Span = NO_SPAN) -> Value:
    """``value`` as a constant of the primitive type ``declared`` holds it.

    A ``real`` set to ``7`` is ``7.0`` (sdf.md decision 5); an ``int``/``nat`` accepts a real only
    when it is whole (``4.0`` → ``4``), a ``nat`` only when it is not negative; ``boolean`` and
    ``string`` take only their own kind. A mismatch raises :class:`EvalError` at ``span``;
    ``declared`` outside :data:`PRIMITIVE_TYPES` is a programming error (``ValueError``).
    """
    if declared not in PRIMITIVE_TYPES:
        raise ValueError(f"coerce knows the primitive types only, not {declared!r}")
    if declared == "real" and is_number(value):
        try:
            return float(value)
        except OverflowError:
            raise EvalError("the value is too large for a real", span) from None
    if declared in ("int", "nat") and is_number(value):
        whole = isinstance(value, int) or float(value).is_integer()
        if not whole:
            raise EvalError(
                f"an {declared} constant must be a whole number, not {describe(value)}",
                span,
                "declare the constant real, or give it a whole number",
            )
        if declared == "nat" and value < 0:
            raise EvalError(f"a nat constant cannot be negative ({value})", span)
        return int(value)
    if declared == "boolean" and isinstance(value, bool):
        return value
    if declared == "string" and isinstance(value, str):
        return value
    raise EvalError(f"a {declared} constant cannot hold {describe(value)}", span)
