"""Indices and poses: IX1, IX2, PO1.

The helpers at the top (what a block sees, typing and evaluating an expression there, whether a
diagnostic was already reported) are shared with ``connections.py``, ``parts.py`` and
``annotations.py``. Evaluation imports NumPy, so it is imported only when a value is needed.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any, Callable, Union

from cyphy import expr as ex
from cyphy.diagnostics import Code, Report, Severity, Span
from cyphy.lang import ast
from cyphy.lang.scopes import is_constant, is_value
from cyphy.lang.typing import Kind, TypeChecker, Ty, same_shape, type_of_declared
from cyphy.limits import max_copies
from cyphy.model.evaluate import EvalError, UnboundName, coerce, describe, evaluate
from cyphy.wellformed.registry import BlockSite, WFContext, rule

if TYPE_CHECKING:
    from cyphy.model.evaluate import Value

Names = dict[str, object]
"""What the names visible at a place denote: a VarDecl, an IndexDecl… (inner ones win)."""

Lookup = Callable[[ex.Name], object]

POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")
_VARIABLE_WORD = {ast.DeclKind.INPUT: "an input", ast.DeclKind.OUTPUT: "an output",
                  ast.DeclKind.INOUT: "an InOut variable", ast.DeclKind.LOCAL: "a local variable",
                  ast.DeclKind.VAR: "a variable"}


# --------------------------------------------------------------------------- shared helpers


def reported(ctx: WFContext, code_id: str, span: Span) -> bool:
    """Whether a diagnostic ``code_id`` was already reported inside ``span`` (S1 for a
    connection target, S3 for a value): one problem gets one diagnostic. The spans reported
    are indexed by code and file, and the index follows the report as it grows, so that a
    model with many diagnostics is not scanned once per question."""
    index: _ReportIndex = ctx.cache.setdefault("reported", _ReportIndex())
    return any(_within(inner, span) for inner in index.spans(ctx.report, code_id, span.file))


class _ReportIndex:
    def __init__(self) -> None:
        self.seen = 0
        self.by_code_file: dict[tuple[str, str], list[Span]] = {}

    def spans(self, report: Report, code_id: str, file: str) -> list[Span]:
        new = report.reported_since(self.seen)
        self.seen += len(new)
        for d in new:
            self.by_code_file.setdefault((d.code.id, d.span.file), []).append(d.span)
        return self.by_code_file.get((code_id, file), [])


def _within(inner: Span, outer: Span) -> bool:
    return (inner.file == outer.file
            and (outer.line, outer.column) <= (inner.line, inner.column)
            and (inner.end_line, inner.end_column) <= (outer.end_line, outer.end_column))


def definition_of(ctx: WFContext, block: ast.Block) -> ast.Definition | None:
    target = ctx.target(block) if block.ref is not None else None
    return target if isinstance(target, ast.Definition) else None


def own_declarations(ctx: WFContext, block: ast.Block) -> list[ast.VarDecl]:
    """The variables and constants a block declares: in its ``def``, directly, and in the
    definition a reference block points at."""
    decls: list[ast.VarDecl] = []
    definition = definition_of(ctx, block)
    if definition is not None:
        decls.extend(m for m in definition.members if isinstance(m, ast.VarDecl))
    for d in block.definitions:
        decls.extend(m for m in d.members if isinstance(m, ast.VarDecl))
    decls.extend(block.declarations)
    return decls


def pmodel_names(pm: ast.PModel) -> Names:
    return {d.name: d for d in pm.declarations}


def inner_names(ctx: WFContext, outer: Names, block: ast.Block) -> Names:
    """What the members of ``block`` see: the enclosing names, its index and declarations."""
    names = dict(outer)
    names.update({i.var: i for i in block.indices})
    names.update({d.name: d for d in own_declarations(ctx, block)})
    return names


def site_names(ctx: WFContext, site: BlockSite, inside: bool = True) -> Names:
    """The names visible in a block (``inside``) or where its index range is written.

    Several rules ask for the names of every block, so the names inside each block are
    built once per run and shared: the returned dict must not be changed."""
    memo: dict[int, tuple[object, Names]] = ctx.cache.setdefault("names inside", {})

    def remembered(node: ast.PModel | ast.Block, make: Callable[[], Names]) -> Names:
        hit = memo.get(id(node))
        if hit is None or hit[0] is not node:
            hit = memo[id(node)] = (node, make())
        return hit[1]

    names = remembered(site.pmodel, lambda: pmodel_names(site.pmodel))
    for block in (*site.ancestors, site.block) if inside else site.ancestors:
        names = remembered(block, lambda outer=names, b=block: inner_names(ctx, outer, b))
    return names


def part_names(pm: ast.PModel, part: ast.Part) -> Names:
    names = pmodel_names(pm)
    names.update({i.var: i for i in part.indices})
    return names


def lookup_in(ctx: WFContext, file: ast.SourceFile, names: Names) -> Lookup:
    """A name lookup for :class:`TypeChecker`: the local names first, then the package."""

    def lookup(name: ex.Name) -> object:
        if len(name.parts) == 1 and name.parts[0] in names:
            return names[name.parts[0]]
        found = ctx.scopes.lookup(file, name.parts, is_value)
        return found[0] if found else None

    return lookup


def infer(value: ex.Expr, lookup: Lookup) -> Ty:
    """The kind of ``value`` (S3 reports typing errors; here they are not reported again)."""
    return TypeChecker(lookup, Report()).infer(value)


def type_problem(value: ex.Expr, declared: ast.TypeRef | None, lookup: Lookup) -> str | None:
    """Why ``value`` cannot be a value of type ``declared`` ("a boolean, not a number"), or None
    when it can or cannot be told."""
    want, got = type_of_declared(declared), infer(value, lookup)
    if Kind.ANY in (want.kind, got.kind):
        return None
    if want.kind is not got.kind or not same_shape(want.shape, got.shape):
        return f"{got.describe()}, not {want.describe()}"
    if isinstance(declared, ast.PrimitiveType) and declared.name in ("int", "nat"):
        literal = value.operand if isinstance(value, ex.UnaryOp) and value.op == "-" else value
        whole = "an integer" if declared.name == "int" else "a natural number"
        if isinstance(literal, ex.Num) and not float(literal.text).is_integer():
            return f"the real {literal.text}, not {whole}"  # 4.0 is a whole number: accepted
        if declared.name == "nat" and literal is not value and isinstance(literal, ex.Num):
            return f"a negative number, not {whole}"
    return None


def _describe_value(value: object) -> str:
    return describe(value)


class ConstantEnv(Mapping[str, Any]):
    """The values of the constants visible at a place, computed on demand for
    :func:`cyphy.model.evaluate.evaluate`. A constant without a value (and not given with
    ``--const``), a variable, an index variable or a name that does not resolve has no value, so
    an expression that needs one raises ``UnboundName`` and the caller skips it."""

    def __init__(self, ctx: WFContext, file: ast.SourceFile, names: Names,
                 cache: dict[int, object] | None = None) -> None:
        self.ctx = ctx
        self.file = file
        self.names = names
        self.cache: dict[int, object] = {} if cache is None else cache

    def __getitem__(self, key: str) -> Any:
        parts = tuple(key.split("::"))
        if len(parts) == 1 and key in self.names:
            decl = self.names[key]
            if isinstance(decl, ast.VarDecl) and decl.kind is ast.DeclKind.CONST:
                return self._value(decl, self)
            raise KeyError(key)
        found = self.ctx.scopes.lookup(self.file, parts, is_constant)
        if not found or not isinstance(found[0], ast.VarDecl):
            raise KeyError(key)
        decl = found[0]
        file = self.ctx.file_of(decl) or self.file
        return self._value(decl, ConstantEnv(self.ctx, file, {}, self.cache))

    def _value(self, decl: ast.VarDecl, env: ConstantEnv) -> object:
        key = id(decl)
        if key in self.cache:
            value = self.cache[key]
            if value is None:
                raise KeyError(decl.name)
            return value
        self.cache[key] = None  # a constant defined in terms of itself has no value
        value = self._compute(decl, env)
        self.cache[key] = value
        if value is None:
            raise KeyError(decl.name)
        return value

    def _compute(self, decl: ast.VarDecl, env: ConstantEnv) -> object:
        if decl.value is None:
            value: object = self._given(decl.name)
            if value is None:
                return None
        else:
            try:
                value = evaluate(decl.value, env)
            except EvalError:
                return None
        if isinstance(decl.type, ast.PrimitiveType):
            try:
                value = coerce(value, decl.type.name, decl.span)  # type: ignore[arg-type]
            except EvalError:
                return None
        return value

    def _given(self, name: str) -> object:
        """A ``--const`` value for a constant without one (the bare name or a ``::`` suffix)."""
        for key, value in self.ctx.consts.items():
            if key == name or key.endswith("::" + name):
                return value
        return None

    def __contains__(self, key: object) -> bool:
        try:
            self[key]  # type: ignore[index]
        except KeyError:
            return False
        return True

    def __iter__(self) -> Iterator[str]:
        return iter(self.names)

    def __len__(self) -> int:
        return len(self.names)


def evaluate_in(ctx: WFContext, file: ast.SourceFile, names: Names, value: ex.Expr
                ) -> tuple[Value | None, str | None]:
    """``(value, None)``, or ``(None, why)`` when ``value`` has no value that can be computed
    here: ``why`` is None when a constant lacks a value (nothing to report), else the error."""

    try:
        return evaluate(value, ConstantEnv(ctx, file, names)), None
    except UnboundName:
        return None, None
    except EvalError as err:
        return None, err.message


def variables_used(value: ex.Expr, names: Names) -> Iterator[tuple[ex.Name, ast.VarDecl]]:
    """The names in ``value`` that denote variables (inputs, outputs, locals…), not constants."""
    for node in value.walk():
        if isinstance(node, ex.Name) and len(node.parts) == 1:
            decl = names.get(node.parts[0])
            if isinstance(decl, ast.VarDecl) and decl.kind is not ast.DeclKind.CONST:
                yield node, decl


def variable_word(decl: ast.VarDecl) -> str:
    return _VARIABLE_WORD.get(decl.kind, "a variable")


# --------------------------------------------------------------------------- IX1


_IX1_EMPTY = Code("IX1", Severity.WARNING, "an index range is empty")
Indexed = Union[ast.Block, ast.Part]


def indices(ctx: WFContext) -> Iterator[tuple[ast.SourceFile, ast.PModel, Indexed,
                                               ast.IndexDecl, Names]]:
    """Every index declaration with the names visible where its range is written."""
    for site in ctx.blocks():
        if site.block.indices:
            outer = site_names(ctx, site, inside=False)
            for index in site.block.indices:
                yield site.file, site.pmodel, site.block, index, outer
    for file, pm in ctx.pmodels():
        for part in pm.parts:
            for index in part.indices:
                yield file, pm, part, index, pmodel_names(pm)


def _what(node: Indexed) -> str:
    return f"part {node.name}" if isinstance(node, ast.Part) else f"{node.kind.value} {node.name}"


@rule("IX1", "an index range has integer constant bounds with a <= b, and at most "
      "--max-copies values")
def check_IX1_index_range(ctx: WFContext) -> None:
    """An index range ``[a, b)`` or ``[a, b]`` has bounds that are integer constant
    expressions, with ``a <= b``. An empty range (``[a, a)``) is a warning: the block has no
    copies. Bounds that need a constant without a value are not checked."""
    for file, _, node, index, outer in indices(ctx):
        values: list[int] = []
        for which, bound in (("lower", index.lower), ("upper", index.upper)):
            variables = list(variables_used(bound, outer))
            if variables:
                name, decl = variables[0]
                ctx.error("IX1", name, f"the {which} bound of index {index.var} of {_what(node)} "
                          f"uses '{name.text}', {variable_word(decl)}, not a constant",
                          "index bounds are integer constants (or literals)")
                break
            if any(isinstance(outer.get(n.parts[0]), ast.IndexDecl)
                   for n in bound.walk() if isinstance(n, ex.Name) and len(n.parts) == 1):
                break  # depends on an enclosing index: one range per copy, not checked here
            value, why = evaluate_in(ctx, file, outer, bound)
            if value is None:
                if why is not None and not reported(ctx, "S3", bound.span):
                    ctx.error("IX1", bound, f"the {which} bound of index {index.var} of "
                              f"{_what(node)} cannot be evaluated: {why}",
                              "index bounds are integer constant expressions")
                break
            if isinstance(value, bool) or not isinstance(value, int):
                if not reported(ctx, "S3", bound.span):
                    hint = ("write an integer" if isinstance(bound, ex.Num)
                            else "declare the constants it uses 'int' or 'nat'"
                            if isinstance(value, float) else "index bounds are integers")
                    ctx.error("IX1", bound, f"the {which} bound of index {index.var} of "
                              f"{_what(node)} is {_describe_value(value)}, not an integer", hint)
                break
            values.append(value)
        if len(values) != 2:
            continue
        lo, hi = values
        close = "]" if index.closed else ")"
        if lo > hi:
            ctx.error("IX1", index, f"index {index.var} of {_what(node)} ranges over "
                      f"[{lo}, {hi}{close}: the lower bound is greater than the upper bound",
                      "write the smaller bound first")
        elif hi - lo + (1 if index.closed else 0) > max_copies():
            ctx.error("IX1", index, f"index {index.var} of {_what(node)} ranges over "
                      f"[{lo}, {hi}{close}: {hi - lo + (1 if index.closed else 0)} copies, "
                      f"more than the limit of {max_copies()}",
                      "use a smaller range, or raise the limit with --max-copies N")
        elif lo == hi and not index.closed:
            ctx.report.report(_IX1_EMPTY, f"index {index.var} of {_what(node)} ranges over the "
                              f"empty range [{lo}, {hi}): {node.name} has no copies", index.span,
                              f"write [{lo}, {hi}] for one copy, or remove the block")


# --------------------------------------------------------------------------- IX2


def _index_owners(pm: ast.PModel) -> dict[str, list[Indexed]]:
    """The blocks and parts of ``pm`` that declare each index variable."""
    owners: dict[str, list[Indexed]] = {}
    stack: list[object] = list(pm.members)
    while stack:
        m = stack.pop()
        if isinstance(m, (ast.Block, ast.Part)):
            for i in m.indices:
                owners.setdefault(i.var, []).append(m)
            if isinstance(m, ast.Block):
                stack.extend(m.members)
    return owners


def _block_names(pm: ast.PModel) -> set[str]:
    names: set[str] = set()
    stack: list[object] = list(pm.members)
    while stack:
        m = stack.pop()
        if isinstance(m, (ast.Block, ast.Part)):
            names.add(m.name)
            if isinstance(m, ast.Block):
                stack.extend(m.members)
    return names


def _expressions(ctx: WFContext, pm: ast.PModel) -> Iterator[tuple[ex.Expr, Names]]:
    """Every expression written in ``pm`` with the names visible there (an index range sees
    the names around its block, not the block's own index)."""
    top = pmodel_names(pm)

    def members(node: ast.Block | ast.Part, outer: Names) -> Iterator[tuple[ex.Expr, Names]]:
        inner = (inner_names(ctx, outer, node) if isinstance(node, ast.Block)
                 else {**outer, **{i.var: i for i in node.indices}})
        for m in node.members:
            if isinstance(m, ast.IndexDecl):
                yield from ((e, outer) for e in ast.expressions_in(m))
            elif isinstance(m, ast.Block):
                yield from members(m, inner)
            elif not isinstance(m, (ast.PartFixed, ast.PartFlexible)):
                yield from ((e, inner) for e in ast.expressions_in(m))

    for m in pm.members:
        if isinstance(m, (ast.Block, ast.Part)):
            yield from members(m, top)
        else:
            yield from ((e, top) for e in ast.expressions_in(m))


@rule("IX2", "an index variable is used only inside its indexed block")
def check_IX2_index_scope(ctx: WFContext) -> None:
    """The variable of ``index i : [a, b)`` is used only inside the indexed block: its pose,
    equations, annotations, instantiations and the blocks it contains. A use anywhere else (a
    sibling block, the p-model's equations or solutions, the block's own index range) has no
    value. Where S1 already reports the name as unknown, nothing more is reported."""
    for file, pm in ctx.pmodels():
        owners = _index_owners(pm)
        if not owners:
            continue
        blocks = _block_names(pm)
        for e, names in _expressions(ctx, pm):
            for node in e.walk():
                if not isinstance(node, ex.Name) or len(node.parts) != 1:
                    continue
                n = node.parts[0]
                if n not in owners or n in names or n in blocks:
                    continue
                if ctx.scopes.lookup(file, (n,), is_value) or reported(ctx, "S1", node.span):
                    continue
                where = owners[n][0]
                ctx.error("IX2", node, f"'{n}' is the index variable of {_what(where)} "
                          f"(line {where.span.line}) and is used outside it",
                          f"use '{n}' only inside {where.name} (its pose, equations, "
                          "annotations and the blocks it contains)")


# --------------------------------------------------------------------------- PO1


def _poses(ctx: WFContext) -> Iterator[tuple[ast.SourceFile, str, ast.Pose,
                                             Callable[[], Names]]]:
    """Every pose of the user's files (of blocks, parts and inertial information), with what it
    belongs to and the names visible in it (asked for only when a value is not a literal)."""
    for site in ctx.blocks():
        what = f"{site.block.kind.value} {site.block.name}"
        names = (lambda site=site: site_names(ctx, site))
        for pose in site.block.poses:
            yield site.file, what, pose, names
        for d in site.block.definitions:
            for m in d.members:
                if isinstance(m, ast.Inertial) and m.pose is not None:
                    yield site.file, f"the inertial information of {what}", m.pose, names
    for file, pm in ctx.pmodels():
        for part in pm.parts:
            for pose in part.poses:
                yield (file, f"part {part.name}", pose,
                       lambda pm=pm, part=part: part_names(pm, part))
    for file, definition in ctx.definitions():
        declared = {m.name: m for m in definition.members if isinstance(m, ast.VarDecl)}
        for m in definition.members:
            if isinstance(m, ast.Inertial) and m.pose is not None:
                yield (file, f"the inertial information of {definition.kind.value} definition "
                       f"{definition.name}", m.pose, lambda declared=declared: declared)


@rule("PO1", "a pose gives each coordinate at most once, as a real constant")
def check_PO1_pose_fields(ctx: WFContext) -> None:
    """A pose gives each of x, y, z, roll, pitch and yaw at most once (missing ones are 0), and
    each value is a real-valued constant expression: it uses constants, literals and index
    variables, never the block's inputs, outputs or locals, and evaluates (once every constant
    has a value) to a number, not a boolean, string, vector or matrix. Values that S3 already
    reports as not numbers are not reported again."""
    for file, what, pose, names_here in _poses(ctx):
        seen: dict[str, ast.PoseField] = {}
        for f in pose.fields:
            if f.key in seen:
                first = seen[f.key].span
                ctx.error("PO1", f, f"the pose of {what} gives '{f.key}' twice (first at "
                          f"{first.line}:{first.column})", f"keep one '{f.key} = …'")
                continue
            if f.key in POSE_KEYS:
                seen[f.key] = f
            if isinstance(f.value, ex.Num):
                continue  # a literal number, the common case: nothing to look up
            names = names_here()
            variables = list(variables_used(f.value, names))
            if variables:
                name, decl = variables[0]
                ctx.error("PO1", name, f"pose field '{f.key}' of {what} uses '{name.text}', "
                          f"{variable_word(decl)}, not a constant",
                          "poses are constant: use constants, literals or the index variable")
                continue
            if infer(f.value, lookup_in(ctx, file, names)).kind is not Kind.ANY:
                continue  # a number, or not one and S3 says so
            value, _ = evaluate_in(ctx, file, names, f.value)
            if value is None or (isinstance(value, (int, float)) and not isinstance(value, bool)):
                continue
            if not reported(ctx, "S3", f.value.span):
                ctx.error("PO1", f.value, f"pose field '{f.key}' of {what} is "
                          f"{_describe_value(value)}, not a real number",
                          "give a real-valued expression")

