"""The constants of an elaboration: :class:`Binding` (one constant of one instance, evaluated
on demand), :class:`Env` (the names in scope, innermost first) and :class:`Context` (what one
elaboration shares: the ``--const`` values, the constants found missing, the evaluated
literals). Constants are evaluated lazily, so that they may use one another in any order, and
each once, however many blocks read it.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping


from cyphy import codes
from cyphy import expr as ex
from cyphy.constant_keys import names_constant
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.scopes import Scopes, is_constant, is_template
from cyphy.lang.workspace import Workspace
from cyphy.model.evaluate import (
    EvalError, UnboundName, Value, coerce, evaluate_fast, free_names, literal_value,
)
from cyphy.model.value_text import format_value, same_value
from cyphy.records import record

EVAL = codes.code("E-EVAL", codes.E, "a constant expression cannot be evaluated")
CONST_NAME = codes.code("E-CONST-NAME", codes.E,
                        "a --const or --consts name that names no constant of the model")


@record(frozen=False, slots=False, eq=False)
class Binding:
    """A constant: its value expression, the scope to evaluate it in, and its names."""

    decl: ast.VarDecl
    expr: ex.Expr | None
    env: Env | None
    qualified: str  # instance-qualified: marXbotBase::LTreel::HEIGHT
    definition: str  # definition-qualified: Treel::HEIGHT
    value: Value | None = None
    state: str = "new"  # new, busy, done, missing


class Env(Mapping[str, Value]):
    """Names in scope for evaluation, innermost first; constants are evaluated on demand and
    cached. A constant with no value is recorded as missing and is not ``in`` the env, so
    evaluation raises :class:`UnboundName` for it."""

    def __init__(self, ctx: Context, file: ast.SourceFile, parent: Env | None = None,
                 names: dict[str, Binding | Value] | None = None) -> None:
        self.ctx = ctx
        self.file = file
        self.parent = parent
        self.names: dict[str, Binding | Value] = names or {}

    def child(self, names: dict[str, Binding | Value]) -> Env:
        return Env(self.ctx, self.file, self, names)

    def _find(self, name: str) -> Binding | Value | None:
        env: Env | None = self
        while env is not None:
            if name in env.names:
                return env.names[name]
            env = env.parent
        return self.ctx.global_binding(self.file, name)

    def __contains__(self, name: object) -> bool:
        if not isinstance(name, str):
            return False
        found = self._find(name)
        if isinstance(found, Binding):
            return self.ctx.value_of(found) is not None
        return found is not None

    def __getitem__(self, name: str) -> Value:
        found = self._find(name)
        if isinstance(found, Binding):
            value = self.ctx.value_of(found)
            if value is None:
                raise KeyError(name)
            return value
        if found is None:
            raise KeyError(name)
        return found

    def __iter__(self) -> Iterator[str]:
        seen: set[str] = set()
        env: Env | None = self
        while env is not None:
            for n in env.names:
                if n not in seen:
                    seen.add(n)
                    yield n
            env = env.parent

    def __len__(self) -> int:
        return sum(1 for _ in self)


class Context:
    def __init__(self, ws: Workspace, resolution: Resolution, report: Report,
                 consts: Mapping[str, Value]) -> None:
        self.ws = ws
        self.resolution = resolution
        self.report = report
        self.scopes = Scopes(ws)
        self.consts = dict(consts)
        self.used_consts: set[str] = set()
        # --const keys that name instantiated constants (the instantiation wins): key → them
        self.instantiated: dict[str, list[Binding]] = {}
        self.replaced: set[Span] = set()  # declarations already reported W-CONST-REPLACED
        self.declared: set[tuple[str, str, str]] = set()  # (qualified, definition, name)
        self.missing: dict[str, list[Span]] = {}
        self.constants: dict[str, Value] = {}
        self.literals: dict[ex.Expr, Value] = {}
        self._templates: dict[tuple[str, ast.QName], str] = {}
        self._globals: dict[tuple[str, str], Binding | None] = {}
        self.file_of: dict[int, ast.SourceFile] = {}
        for f in ws.files.values():
            for item in f.items:
                self.file_of[id(item)] = f

    # ----- constants
    def binding(self, decl: ast.VarDecl, env: Env | None, qualified: str, definition: str,
                override: ex.Expr | None = None, override_env: Env | None = None) -> Binding:
        self.declared.add((qualified, definition, decl.name))
        if override is not None:
            return Binding(decl, override, override_env, qualified, definition)
        return Binding(decl, decl.value, env, qualified, definition)

    def global_binding(self, file: ast.SourceFile, name: str) -> Binding | None:
        key = (file.path, name)
        if key not in self._globals:
            found = self.scopes.lookup(file, tuple(name.split("::")), is_constant)
            binding = None
            if found and isinstance(found[0], ast.VarDecl):
                decl = found[0]
                decl_file = self.file_of.get(id(decl), file)
                package = "::".join(decl_file.package)
                qualified = f"{package}::{decl.name}" if package else decl.name
                env = Env(self, decl_file)
                binding = Binding(decl, decl.value, env, qualified, qualified)
                self.declared.add((qualified, qualified, decl.name))
            self._globals[key] = binding
        return self._globals[key]

    def template_name(self, file: ast.SourceFile, name: ast.QName) -> str:
        """The name of the template ``name`` denotes from ``file`` (looked up once: every
        joint of a model names the same few templates)."""
        key = (file.path, name)
        if key not in self._templates:
            found = self.scopes.lookup(file, name, is_template)
            self._templates[key] = found[0].name if found else name[-1]  # type: ignore[union-attr]
        return self._templates[key]

    def value_of(self, b: Binding) -> Value | None:
        if b.state == "done":
            return b.value
        if b.state in ("missing", "busy"):
            if b.state == "busy":
                self.report.report(EVAL, f"constant '{b.qualified}' is defined in terms of "
                                   "itself", b.decl.span, "break the cycle")
                b.state = "missing"
            return None
        b.state = "busy"
        value: Value | None = None
        given = self._user_value(b) if b.expr is None or b.expr is b.decl.value else None
        if given is None and b.expr is not None and b.expr is not b.decl.value:
            self._note_instantiated(b)
        if given is not None:  # --const wins over the declaration's own value
            value = given
            if b.expr is not None:
                self._warn_replaced(b, given)
        elif b.expr is None:
            if value is None:
                b.state = "missing"
                self.missing.setdefault(b.definition, []).append(b.decl.span)
                return None
        else:
            assert b.env is not None
            value = self.evaluate(b.expr, b.env)
        if value is not None and isinstance(b.decl.type, ast.PrimitiveType):
            try:
                value = coerce(value, b.decl.type.name, b.decl.span)
            except EvalError as err:
                self.report.report(EVAL, f"constant '{b.qualified}': {err.message}", err.span,
                                   err.hint)
                value = None
        b.value, b.state = value, ("done" if value is not None else "missing")
        if value is not None:
            self.constants[b.qualified] = value
        return value

    def _warn_replaced(self, b: Binding, given: Value) -> None:
        """W-CONST-REPLACED, once per declaration, when the given value differs from the
        declared one: a bare ``PI`` in a scenario silently replacing common.pm's ``PI =
        3.1415`` moves every pose that uses it. A declared value that cannot be evaluated
        alone (it needs another constant's value) is not compared: no new error for it."""
        if b.decl.span in self.replaced:
            return
        try:
            declared = evaluate_fast(b.expr, b.env or {})  # type: ignore[arg-type]
        except (EvalError, UnboundName, ValueError, TypeError):
            return
        if same_value(declared, given):
            return
        self.replaced.add(b.decl.span)
        self.report.report(codes.CONST_REPLACED,
                           f"constant '{b.qualified}' is declared {format_value(declared)}; "
                           f"the given value {format_value(given)} replaces it",
                           b.decl.span, "give the declared value, or leave the constant "
                           "out of --const/--consts/[consts] to keep it")

    def _note_instantiated(self, b: Binding) -> None:
        """Remember the ``--const`` keys that name ``b``, a constant an instantiation sets:
        the instantiation wins, so a key that names nothing else changes nothing."""
        for key in self.consts:
            if names_constant(key, b.decl.name, b.qualified, b.definition):
                self.instantiated.setdefault(key, []).append(b)

    def report_instantiated(self) -> None:
        """W-CONST-INSTANTIATED for each ``--const``/``--consts``/``[consts]`` key that names
        constants an instantiation sets to another value: the key does not reach them, even
        where it sets other constants. Without it, ``--const Kp=100`` on a motor that
        instantiates ``Kp = 2.0`` ran with 2.0 and said nothing."""
        for key, bindings in sorted(self.instantiated.items()):
            given = self.consts[key]
            bindings = [b for b in bindings if b.value is None or not same_value(b.value, given)]
            if not bindings:
                continue  # the instantiations give that very value
            first = bindings[0]
            span = first.expr.span if first.expr is not None and \
                first.expr.span.line else first.decl.span
            more = f" and {len(bindings) - 1} more" if len(bindings) > 1 else ""
            elsewhere = " (it sets the others it names)" if key in self.used_consts else ""
            self.report.report(codes.CONST_INSTANTIATED,
                               f"the given value of {key} does not reach '{first.qualified}'"
                               f"{more}{elsewhere}: an instantiation sets it, and wins over "
                               "--const, --consts and a scenario's [consts]", span,
                               "change the instantiation in the model to change the value")

    def _user_value(self, b: Binding) -> Value | None:
        """The ``--const`` value for a constant, the most specific key winning: the instance
        name, the definition name, a ``::`` suffix of either, or the bare name."""
        best: tuple[int, str] | None = None
        for key in self.consts:
            if names_constant(key, b.decl.name, b.qualified, b.definition):
                if best is None or len(key) > best[0]:
                    best = (len(key), key)
        if best is None:
            return None
        self.used_consts.add(best[1])
        return self.consts[best[1]]

    def report_unknown_consts(self, span: Span, reported: frozenset[str] = frozenset()
                              ) -> None:
        """Report (``E-CONST-NAME``) each ``--const``/``--consts`` name that names none of
        the constants the model declares (a typo would otherwise be silently ignored);
        the commands that elaborate stop on it as on any error."""
        candidates = {n for names in self.declared for n in names}
        unknown = [key for key in sorted(self.consts) if key not in self.used_consts and
                   key not in reported and
                   not any(names_constant(key, name, qualified, definition)
                           for qualified, definition, name in self.declared)]
        if unknown:  # a constant of another part of the files (a d-model's) is no typo
            # lazy: constants.py imports the parser (Lark), which a warm run must not load
            from cyphy.model.constants import declared_constants

            elsewhere = declared_constants(self.ws.files.values())
            candidates |= elsewhere
            unknown = [key for key in unknown if key.split("::")[-1] not in elsewhere]
        for key in unknown:
            self.report.report(CONST_NAME, f"--const {key}: the model has no constant named "
                               f"{key}", span, did_you_mean(key, candidates) or
                               "name a constant the model declares (its bare name, or "
                               "qualified: Model::Link::NAME)")

    def evaluate(self, e: ex.Expr | None, env: Env) -> Value | None:
        """The value of ``e``, or None when it needs a constant without a value (recorded)
        or cannot be evaluated (reported)."""
        if e is None:
            return None
        if isinstance(e, ex.Num):  # most values are literals: skip the evaluator
            try:
                return literal_value(e.text)
            except ValueError as err:
                self.report.report(EVAL, str(err), e.span, "write a smaller number")
                return None
        if isinstance(e, (ex.Vector, ex.Matrix)) and numbers_only(e):
            # A literal axis or matrix is written once per joint of a model, thousands of
            # times over: one value (read-only) per distinct literal.
            known = self.literals.get(e)
            if known is None:
                known = self._evaluate(e, env)
                if known is not None:
                    self.literals[e] = known
            return known
        return self._evaluate(e, env)

    def _evaluate(self, e: ex.Expr, env: Env) -> Value | None:
        try:
            return evaluate_fast(e, env)
        except UnboundName as err:
            if self._known_missing(err.name, env):
                self._look_up_all(e, env)
                return None
            self.report.report(EVAL, err.message, err.span, err.hint)
        except EvalError as err:
            self.report.report(EVAL, err.message, err.span, err.hint)
        return None

    def _look_up_all(self, e: ex.Expr, env: Env) -> None:
        """Evaluation stops at the first constant without a value; the other constants ``e``
        names are looked up too, so that they are recorded as missing now and a generator
        lists every constant it needs at once, not one more per run (issue 27)."""
        for name in sorted(free_names(e)):
            found = env._find(name)
            if isinstance(found, Binding):
                self.value_of(found)

    def _known_missing(self, name: str, env: Env) -> bool:
        found = env._find(name)
        return isinstance(found, Binding) and found.state == "missing"


def numbers_only(e: ex.Vector | ex.Matrix) -> bool:
    return all(isinstance(item, ex.Num) for row in e.rows for item in row)
