"""What name resolution records and walks: the :class:`Resolution` later stages read, the
chain of local :class:`Scope` s, element paths as steps, and the small helpers of the checks
(a block's children, the names an expression uses, hints for unknown names)."""

from __future__ import annotations

from dataclasses import field
from typing import Iterable, Iterator, Union

from cyphy import expr as ex
from cyphy.diagnostics import Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.workspace import Declaration
from cyphy.records import record

BUILTIN_NAMES = {"t"}  # time, used undeclared in equations and mappings
Container = Union[ast.PModel, ast.Block, ast.Part]


@record(frozen=False, slots=False)
class Resolution:
    """What references resolved to, keyed by ``id`` of the referring node."""

    targets: dict[int, Declaration] = field(default_factory=dict)
    file_of: dict[int, ast.SourceFile] = field(default_factory=dict)
    uses: list[tuple[Span, ast.QName, object]] = field(default_factory=list)
    """Every resolved use of a name, for editors (go to definition, references, hover): the
    span of the referring node, the name, and what it denotes (a top-level declaration, or a
    local one: a variable, a block, an index)."""

    def get(self, node: object) -> Declaration | None:
        return self.targets.get(id(node))


@record(frozen=False, slots=False)
class Scope:
    """Names declared by enclosing blocks: name → what declares it (a VarDecl, IndexDecl…)."""

    names: dict[str, object]
    parent: Scope | None = None

    def find(self, name: str) -> object | None:
        s: Scope | None = self
        while s is not None:
            if name in s.names:
                return s.names[name]
            s = s.parent
        return None

    def all_names(self) -> set[str]:
        out: set[str] = set()
        s: Scope | None = self
        while s is not None:
            out.update(s.names)
            s = s.parent
        return out

    def child(self, names: dict[str, object]) -> Scope:
        return Scope(names, self)


def steps_of(e: ex.Expr) -> list[tuple[str, Span, bool]] | None:
    """An element path as (name, span, indexed) steps: ``Core::Proximity[1].voltage`` →
    Core, Proximity (indexed), voltage. None when ``e`` is not a path."""
    if isinstance(e, ex.Name):
        return [(p, e.span, False) for p in e.parts]
    if isinstance(e, ex.Member):
        base = steps_of(e.base)
        return None if base is None else base + [(e.name, e.span, False)]
    if isinstance(e, ex.Index):
        base = steps_of(e.base)
        if not base:
            return None
        name, span, _ = base[-1]
        return base[:-1] + [(name, span, True)]
    return None


def block_children(node: Container) -> dict[str, list[ast.Block | ast.Part]]:
    out: dict[str, list[ast.Block | ast.Part]] = {}
    for m in node.members:
        if isinstance(m, (ast.Block, ast.Part)):
            out.setdefault(m.name, []).append(m)
    return out


def names_in(e: ex.Expr) -> Iterator[ex.Name]:
    """Names an expression uses, skipping the field names of ``.member`` (they belong to the
    value on their left)."""
    for node in e.walk():
        if isinstance(node, ex.Name):
            yield node


def path_roots(e: ex.Expr) -> Iterator[ex.Expr]:
    """Maximal path-shaped subexpressions (``a::b.c``, ``a[1].v``, ``f``) of ``e``."""
    if isinstance(e, (ex.Name, ex.Member, ex.Index)) and steps_of(e) is not None:
        yield e
        for node in e.walk():
            if isinstance(node, ex.Index):
                for a in node.args:
                    yield from path_roots(a)
        return
    for child in e.children():
        yield from path_roots(child)


MEMBER_WORD = {ast.Shape: "geometry", ast.Inertial: "inertial information",
                ast.Bounce: "bounce", ast.LaserRetro: "laser retro"}


def indices_of(blocks: Iterable[ast.Block]) -> dict[str, object]:
    return {i.var: i for b in blocks for i in b.indices}


def all_blocks_of(node: Container) -> dict[str, list[ast.Block]]:
    out: dict[str, list[ast.Block]] = {}
    stack: list[object] = list(node.members)
    while stack:
        m = stack.pop()
        if isinstance(m, ast.Block):
            out.setdefault(m.name, []).append(m)
            stack.extend(m.members)
    return out


def describe(node: ast.PModel | ast.Block | ast.Part) -> str:
    if isinstance(node, ast.PModel):
        return f"p-model {node.name}"
    if isinstance(node, ast.Part):
        return f"part {node.name}"
    return f"{node.kind.value} {node.name}"


#: Names a newcomer writes for values RoboSim does not have (Python's, C's, IEEE 754's).
NON_FINITE = frozenset({"nan", "NaN", "NAN", "inf", "Inf", "INF", "infinity", "Infinity"})


def name_hint(name: str, candidates: Iterable[str]) -> str:
    """The hint for an unknown value name: RoboSim has no ``nan`` or ``inf`` (rather than
    "did you mean 'tan'?"), else the close names."""
    if name in NON_FINITE:
        return (f"RoboSim has no '{name}': every value is a finite number (a quantity "
                "without a known value is a const without one, given by --const)")
    return did_you_mean(name, candidates)
