"""Guards, values and statements of one machine, or of one operation definition it calls,
over the state of the ``D`` that :mod:`cyphy.semantics.circus.dmodel_cycle` writes out.

Kept apart from the unrolling (which decides *where* the machine goes in a cycle) because
this is *what* each step reads and writes, and it differs only in its scope: the machine
reads its own variables, clocks and constants (``<D>_x``), an operation definition its own
variables, parameters, clocks and constants (``<D>_<op>_x``), as the interpreter's
environment (:meth:`~cyphy.semantics.machines.cycle.MachineInterpreter._env`) holds one or
the other, never both. A :class:`Terms` is one such scope.

A vector variable of numbers is held entry by entry (``<D>_v_1`` … ``<D>_v_n``): D's state is
scalar, as P's is (:mod:`cyphy.semantics.scalarise`), and the interpreter's vectors are read
and written at constant indices or whole (:meth:`Terms.components`).
"""

from __future__ import annotations

from typing import Callable, Mapping

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.model.evaluate import EvalError, evaluate
from cyphy.model.machines import Machine, expressions
from cyphy.model.math_functions import MATH_FUNCTIONS
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel import literal
from cyphy.semantics.circus.values import held_type, type_of, value_expr
from cyphy.semantics.machines import scalars
from cyphy.semantics.machines.cycle import MachineError, MachineInterpreter

_CONNECTIVES = ("/\\", "\\/", "=>", "<=>")
#: The library's functions (``physmod::math``) of numbers to a number, which D applies as the
#: interpreter does; the others take or give vectors and matrices, which D holds entry by
#: entry, and are refused.
SCALAR_FUNCTIONS = frozenset({"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sqrt",
                              "exp", "log", "abs", "sgn"})
#: How a :class:`Terms` reports what it cannot write: message, span, hint.
Refuse = Callable[[str, object, str], MachineError]


def name_expr(text: str) -> ex.Name:
    return ex.Name((text,))


def constant(value: object, type_: c.Type) -> ex.Expr:
    """A value the interpreter computed, as ``D`` holds it (a Boolean, else a real)."""
    if isinstance(value, bool) or type_ == c.BOOL:
        return ex.Bool(bool(value))
    return literal(float(value), type_)  # type: ignore[arg-type]


def default(decl: ast.VarDecl) -> ex.Expr:
    """The value the interpreter gives a variable declared without one: false, else 0."""
    held = held_type(decl.type)
    return ex.Bool(False) if held == c.BOOL else constant(0.0, held)


class Terms:
    """The translation of one scope's expressions and statements (see the module
    docstring): ``name`` is D's (its events' fields ``<D>_e``, a package's open constant
    ``<D>_k``), ``prefix`` the scope's fields' (``<D>``, ``<D>_<machine>``, ``…_<op>``),
    ``constants`` the values the scope sees (the interpreter's ``constants`` or
    ``op_constants[op]``)."""

    def __init__(self, name: str, prefix: str, scope: Machine, interpreter: MachineInterpreter,
                 constants: Mapping[str, object], events: list[str],
                 typed: dict[str, c.Type], writes: dict[str, tuple[c.Type, ...]],
                 refuse: Refuse) -> None:
        self.name, self.prefix, self.scope = name, prefix, scope
        self.interpreter, self.constants = interpreter, constants
        self.events, self.typed, self.writes = events, typed, writes
        self.refuse = refuse
        #: how messages name the scope
        self.where = "the machine" if scope.decl.kind != "operation" else \
            f"operation {scope.name}"
        params = {p.name for p in scope.decl.params}
        #: the scope's variables, an operation's parameters among them (the interpreter
        #: binds them as variables at each call), each a field of D's state
        self.variables: dict[str, ast.VarDecl] = {
            **scope.variables, **{n: d for n, d in scope.constants.items() if n in params}}
        #: the vector variables and their sizes: a field per entry, ``<x>_1`` … ``<x>_n``
        self.sizes = {x: self._size(x, d) for x, d in self.variables.items()
                      if isinstance(d.type, ast.VectorType)}

    def _size(self, name: str, decl: ast.VarDecl) -> int:
        t = decl.type
        assert isinstance(t, ast.VectorType)
        try:
            n = self.interpreter._value(t.size, self.constants) if t.size is not None else None
        except MachineError:
            n = None
        if held_type(t.element) != c.REAL or isinstance(n, bool) or \
                not isinstance(n, (int, float)) or n < 1 or n != int(n):
            raise self.refuse(f"vector {name} of {self.where}: D holds a vector of numbers "
                              "of a constant size, an entry per field", decl.span, "")
        return int(n)

    def fields(self, name: str) -> list[str]:
        """The fields that hold a variable: itself, or a vector's entries."""
        size = self.sizes.get(name)
        return [self.field(name)] if size is None else \
            [self.field(f"{name}_{k}") for k in range(1, size + 1)]

    def field(self, name: str) -> str:
        """The field of D's state that holds the scope's variable, parameter or clock."""
        return f"{self.prefix}_{name}"

    def open_name(self, name: str) -> str:
        """The theory's constant for an open constant: the scope's own is named as its
        variables are, one declared outside it (a package's) once for all of D's machines."""
        own = name in self.scope.constants and name not in self.variables
        return f"{self.prefix if own else self.name}_{name.replace('::', '_')}"

    def initial(self, x: str, value: object) -> list[ex.Expr]:
        """A machine variable's value in ``Init``, a vector's entry by entry: the
        interpreter's ``value``, or its expression where it reads an open constant (None)."""
        if value is None:
            return self.declared_value(x)
        if x in self.sizes:
            return [constant(float(v), c.REAL) for v in value.ravel()]  # type: ignore
        return [constant(value, held_type(self.variables[x].type))]

    def declared_value(self, x: str) -> list[ex.Expr]:
        """The variable's declared initial value over D's state, a vector's entry by entry,
        or the interpreter's default where it declares none (an operation's variables are
        set so at each call)."""
        decl = self.variables[x]
        if decl.value is None:
            return [default(decl)] * len(self.fields(x))
        if x in self.sizes:
            return self.components(decl.value, self.sizes[x])
        return [self.value(decl.value, decl)]

    def refers(self, name: str) -> bool:
        """Whether the scope declares ``name`` or names it (then an open constant of that
        name is one of the theory's constants that the scope reads)."""
        if name in self.scope.constants and name not in self.variables:  # (a parameter)
            return True
        exprs = [e for e, _ in expressions(self.scope)]
        exprs += [d.value for d in [*self.scope.constants.values(),
                                    *self.scope.variables.values()] if d.value is not None]
        return any(isinstance(n, ex.Name) and n.text == name for e in exprs for n in e.walk())

    def cycles(self, st: ast.WaitStatement) -> int:
        """``wait(n)``'s ``n``, a constant natural number of the scope."""
        try:
            n = self.interpreter._value(st.cycles, self.constants)
        except MachineError:
            n = None
        if isinstance(n, bool) or not isinstance(n, (int, float)) or n < 0 or n != int(n):
            raise self.refuse("wait(n) is written in D only with n a constant natural "
                              "number", st.span, "")
        return int(n)

    # ----- guards and expressions
    def guard(self, t: ast.Transition) -> tuple[ex.Expr, list[c.Action]]:
        """The guard over D's state and the assignments of the names ``$e?x`` binds."""
        parts = [e for e in (t.trigger, t.condition) if e is not None]
        bound: dict[str, str] = {}
        bindings: list[c.Action] = []
        for part in parts:
            top = set(map(id, ex.conjuncts(part)))
            for n in part.walk():
                if isinstance(n, ex.PlatformRef) and n.binding is not None:
                    event = n.name[-1]
                    if id(n) not in top:
                        raise self.refuse(f"transition {t.name} binds {n.binding} from "
                                          f"${event} outside a conjunct of its guard: the "
                                          "value is bound only when the event occurs", n.span,
                                          f"write the guard as ${event}?{n.binding} /\\ …")
                    if event in self.typed:
                        bound[n.binding] = f"{self.name}_{event}_value"
                        bindings.append(c.Assign((self.field(n.binding),),
                                                 (name_expr(bound[n.binding]),)))
                    elif event in self.events:  # (an event not mapped never occurs)
                        raise self.refuse(f"transition {t.name} binds {n.binding} from the "
                                          f"untyped event {event}", n.span, "")
        if not parts:
            return ex.Bool(True), bindings
        guard = ex.conjunction([self.predicate(p, bound) for p in parts])
        return guard, bindings

    def predicate(self, e: ex.Expr, bound: dict[str, str]) -> ex.Expr:
        """A condition as a predicate: Z has no Boolean-valued terms in predicate position,
        so an event and a Boolean variable are compared with true."""
        if isinstance(e, ex.BinOp) and e.op in _CONNECTIVES:
            return ex.BinOp(e.op, self.predicate(e.left, bound),
                            self.predicate(e.right, bound))
        if isinstance(e, ex.UnaryOp) and e.op == "not":
            return ex.UnaryOp("not", self.predicate(e.operand, bound))
        if isinstance(e, ex.PlatformRef):
            event = e.name[-1]
            if event not in self.events:  # not mapped: it never occurs
                return ex.Bool(False)
            return ex.BinOp("==", name_expr(f"{self.name}_{event}"), ex.Bool(True))
        if isinstance(e, ex.Bool):
            return e
        declared = {**self.interpreter.open, **self.variables}
        if isinstance(e, ex.Name) and e.text in declared and \
                type_of(declared[e.text].type) == c.BOOL:
            return ex.BinOp("==", self.expr(e, bound), ex.Bool(True))
        return self.expr(e, bound)

    def expr(self, e: ex.Expr, bound: dict[str, str] | None = None) -> ex.Expr:
        """A value over D's state: variables and clocks are D's, constants their values."""
        bound = bound or {}
        period = self.interpreter.period
        clocks = self.scope.clocks

        def rewrite(n: ex.Expr) -> ex.Expr | None:
            if isinstance(n, ex.Call) and isinstance(n.func, ex.Name) and \
                    n.func.text == "since" and len(n.args) == 1 and \
                    isinstance(n.args[0], ex.Name) and n.args[0].text in clocks:
                count = name_expr(self.field(n.args[0].text))
                return count if period == 1 else ex.BinOp("*", count, value_expr(period))
            if isinstance(n, ex.PlatformRef):
                raise self.refuse(f"${n.text} is used as a value", n.span,
                                  "test events in guards only")
            if isinstance(n, ex.Index) and isinstance(n.base, ex.Name) and \
                    n.base.text in self.sizes:
                return name_expr(self._entry(n.base.text, n.args, n.span))
            if isinstance(n, ex.Index) and isinstance(n.base, ex.Name) and \
                    self._vector_constant(n.base.text):  # gains[2]: a number
                try:
                    entry = evaluate(n, {n.base.text: self.constants[n.base.text]})
                except EvalError:
                    entry = None
                if isinstance(entry, (bool, int, float)):
                    return constant(entry, c.REAL)
                raise self.refuse(f"{n.base.text}[…]: D reads a constant vector's entries at "
                                  "constant indices", n.span, "")
            if isinstance(n, ex.Name):
                if n.text in bound:
                    return name_expr(bound[n.text])
                if n.text in self.variables:
                    return None if n.text in self.sizes else name_expr(self.field(n.text))
                value = self.constants.get(n.text)
                if isinstance(value, (bool, int, float)):
                    return constant(value, c.REAL)
                if self._vector_constant(n.text):
                    return None  # only its entries are numbers (checked below)
                if n.text in self.interpreter.open:
                    return name_expr(self.open_name(n.text))
                decl = self.scope.constants.get(n.text)
                if decl is not None and decl.value is not None and \
                        n.text in self.interpreter.unknown:  # computed from an open one
                    return self.expr(decl.value)
                if n.text in SCALAR_FUNCTIONS or n.text == "since" or n.text in clocks:
                    return None  # applied, or since(C): rewritten at the call (bottom-up)
                if n.text in MATH_FUNCTIONS:
                    raise self.refuse(f"the function {n.text} takes or gives vectors or "
                                      "matrices, which D holds entry by entry", n.span,
                                      "compute with the entries (v[1], v[2], …)")
                raise self.refuse(f"'{n.text}' has no value in {self.where}", n.span, "")
            return None

        out = ex.transform(e, rewrite)
        left = next((n for n in out.walk() if isinstance(n, ex.Name) and (
            n.text == "since" or n.text in clocks)), None)
        if left is not None:
            raise self.refuse(f"'{left.text}' is used outside since(C)", left.span, "")
        applied = {id(n.func) for n in out.walk() if isinstance(n, ex.Call)}
        bare = next((n for n in out.walk() if isinstance(n, ex.Name) and
                     n.text in SCALAR_FUNCTIONS and id(n) not in applied), None)
        if bare is not None:
            raise self.refuse(f"the function {bare.text} is used as a value", bare.span, "")
        whole = next((n for n in out.walk() if isinstance(n, ex.Name) and (
            n.text in self.sizes or self._vector_constant(n.text))), None)
        if whole is not None:
            raise self.refuse(f"the vector {whole.text} is used where D needs a number",
                              whole.span, f"read one entry, {whole.text}[1]")
        return out

    def _vector_constant(self, name: str) -> bool:
        return name not in self.variables and scalars.is_vector(self.constants.get(name))

    def _entry(self, name: str, args: tuple[ex.Expr, ...], span: object) -> str:
        """The field of ``name[k]`` (``args`` translated): ``k`` a constant from 1."""
        try:
            k = evaluate(args[0], {}) if len(args) == 1 else None
        except EvalError:
            k = None
        size = self.sizes[name]
        if isinstance(k, bool) or not isinstance(k, (int, float)) or k != int(k) or \
                not 1 <= k <= size:
            raise self.refuse(f"{name}[…]: D reads and writes a vector's entries at a constant "
                              f"index from 1 to {size}", span, "")
        return self.fields(name)[int(k) - 1]

    def components(self, e: ex.Expr, size: int) -> list[ex.Expr]:
        """A vector's value entry by entry, each over D's state: a vector variable, a
        constant, a literal ``(|a, b|)``, and sums, differences, negations and scalings of
        them; anything else is refused."""
        if isinstance(e, ex.Name) and self.sizes.get(e.text) == size:
            return [name_expr(f) for f in self.fields(e.text)]
        value = self.constants.get(e.text) if isinstance(e, ex.Name) else None
        if scalars.is_vector(value) and value.size == size:  # type: ignore[union-attr]
            return [constant(float(x), c.REAL) for x in value.ravel()]  # type: ignore
        if isinstance(e, ex.Vector):
            items = [x for row in e.rows for x in row]
            if len(items) == size and (len(e.rows) == 1 or all(len(r) == 1 for r in e.rows)):
                return [self.expr(x) for x in items]
        if isinstance(e, ex.UnaryOp) and e.op == "-":
            return [ex.UnaryOp("-", x) for x in self.components(e.operand, size)]
        if isinstance(e, ex.BinOp) and e.op in ("+", "-"):
            return [ex.BinOp(e.op, a, b) for a, b in zip(self.components(e.left, size),
                                                         self.components(e.right, size))]
        if isinstance(e, ex.BinOp) and e.op in ("*", "/") and self._vector(e.left):
            k = self.expr(e.right)
            return [ex.BinOp(e.op, a, k) for a in self.components(e.left, size)]
        if isinstance(e, ex.BinOp) and e.op == "*" and self._vector(e.right):
            k = self.expr(e.left)
            return [ex.BinOp("*", k, b) for b in self.components(e.right, size)]
        raise self.refuse(f"this vector of {size} entries is not written in D: a vector "
                          "variable, constant or literal, or sums and scalings of them",
                          getattr(e, "span", None), "")

    def _vector(self, e: ex.Expr) -> bool:
        """Whether ``e`` is vector-valued, as :meth:`components` reads it."""
        if isinstance(e, ex.Name):
            return e.text in self.sizes or self._vector_constant(e.text)
        if isinstance(e, ex.Vector):
            return True
        if isinstance(e, ex.UnaryOp):
            return self._vector(e.operand)
        if isinstance(e, ex.BinOp) and e.op in ("+", "-"):
            return self._vector(e.left) or self._vector(e.right)
        if isinstance(e, ex.BinOp) and e.op in ("*", "/"):
            return self._vector(e.left) or (e.op == "*" and self._vector(e.right))
        return False

    def value(self, e: ex.Expr, decl: ast.VarDecl) -> ex.Expr:
        """``e`` as the value of the variable ``decl`` (a Boolean one is a predicate)."""
        return self.predicate(e, {}) if held_type(decl.type) == c.BOOL else self.expr(e)

    # ----- statements
    def statement(self, s: ast.Statement) -> c.Action:
        """A statement that is not a call of an operation definition (the unrolling runs
        those) nor ``exec``/``wait`` (the unrolling's ends of the cycle)."""
        if isinstance(s, ast.Assign):
            t = s.target
            if isinstance(t, ex.Index) and isinstance(t.base, ex.Name) and \
                    t.base.text in self.sizes:  # one entry: v[k] = e
                entry = self._entry(t.base.text, tuple(self.expr(a) for a in t.args), t.span)
                return c.Assign((entry,), (self.expr(s.value),))
            if isinstance(t, ex.Name) and t.text in self.sizes:  # every entry, at once
                fields = self.fields(t.text)
                return c.Assign(tuple(fields), tuple(self.components(s.value, len(fields))))
            if not isinstance(s.target, ex.Name) or s.target.text not in self.variables:
                raise self.refuse(f"only a variable of {self.where} can be assigned",
                                  s.span, "")
            return c.Assign((self.field(s.target.text),),
                            (self.value(s.value, self.variables[s.target.text]),))
        if isinstance(s, ast.ClockReset):
            return c.Assign((self.field(s.clock),), (ex.Num("0"),))
        if isinstance(s, ast.SkipStatement):
            return c.Skip()
        if isinstance(s, ast.SendStatement):
            name = s.event.name[-1] if isinstance(s.event, ex.PlatformRef) else "?"
            return self.send(name, (s.value,))
        if isinstance(s, ast.CallStatement):
            call = s.call
            if isinstance(call, ex.PlatformRef):
                return self.send(call.name[-1], ())
            if isinstance(call, ex.Call) and isinstance(call.func, ex.PlatformRef):
                return self.send(call.func.name[-1], call.args)
            platform = self.scope.platform  # `move(0, av)`: RoboTool's call without `$`
            if isinstance(call, ex.Call) and isinstance(call.func, ex.Name) and \
                    call.func.parts[-1] in {**platform.operations, **platform.output_events}:
                return self.send(call.func.parts[-1], call.args)
            raise self.refuse("this call is not a call of the platform", s.span, "")
        raise self.refuse("this statement is not written in D", s.span, "")

    def send(self, name: str, args: tuple[ex.Expr, ...]) -> c.Action:
        types = self.writes.get(name)
        if types is None and name in self.interpreter.observable:
            return c.Skip()  # an output event the mapping does not map: observable only
        if types is None or len(types) != len(args):
            raise ValueError(name)
        values = tuple(c.Out(self.argument(a, t)) for a, t in zip(args, types))
        return c.Prefix(c.Comm("registerWrite", name, values), c.Skip())

    def argument(self, a: ex.Expr, type_: c.Type) -> ex.Expr:
        """A constant argument as the automaton's ``D`` writes it (a literal of the
        parameter's type), any other as an expression over the state."""
        translated = self.expr(a)
        if not any(isinstance(n, ex.Name) for n in translated.walk()):
            try:
                value = self.interpreter._value(a, self.constants)
            except MachineError:
                value = None
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                return literal(float(value), type_)
        if type_ in (c.INT, c.NAT):
            raise self.refuse(f"an argument of {'int' if type_ == c.INT else 'nat'} type "
                              "reads the machine's state or an open constant, with which D "
                              "computes as reals: the conversion is not written", a.span, "")
        return translated


