"""The rule registry and the context every rule reads.

A rule is a function ``check_<ID>_<what>(ctx)`` decorated with ``@rule(id, summary)``; it walks
what it needs through the context's iterators and reports with ``ctx.error(id, node, message,
hint)``. Rules never print, raise or exit (``style.md`` 8-10). The summary is the one line that
``cyphy check --list-rules`` prints; the docstring states the condition in the paper's terms.
"""

from __future__ import annotations

from dataclasses import field
from typing import Any, Callable, Iterator

from cyphy import codes, collector, progress
from cyphy.diagnostics import Code, Report, Severity, Span
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.scopes import Scopes
from cyphy.lang.workspace import Workspace
from cyphy.records import record


@record(slots=False)
class Rule:
    id: str
    summary: str
    code: Code
    check: Callable[[WFContext], None]


RULES: dict[str, Rule] = {}


def rule(id: str, summary: str, severity: Severity = Severity.ERROR
         ) -> Callable[[Callable[[WFContext], None]], Callable[[WFContext], None]]:
    """Register a check under ``id`` (also its diagnostic code)."""

    def register(fn: Callable[[WFContext], None]) -> Callable[[WFContext], None]:
        if id in RULES:
            raise ValueError(f"rule {id} registered twice")
        code = codes.REGISTRY.get(id) or codes.code(id, severity, summary)
        RULES[id] = Rule(id, summary, code, fn)
        return fn

    return register


@record
class BlockSite:
    """A block with where it is: its file, p-model and enclosing blocks (outermost first)."""

    file: ast.SourceFile
    pmodel: ast.PModel
    block: ast.Block
    ancestors: tuple[ast.Block, ...]

    @property
    def qualified(self) -> str:
        return "::".join((self.pmodel.name, *(a.name for a in self.ancestors),
                          self.block.name))

    @property
    def container(self) -> ast.Block | None:
        return self.ancestors[-1] if self.ancestors else None


@record(frozen=False, slots=False)
class WFContext:
    workspace: Workspace
    resolution: Resolution
    report: Report
    consts: dict[str, Any] = field(default_factory=dict)
    z3: bool = False
    """Rules that need Z3 run (``check --consistency``): plain ``check`` never imports it."""
    scopes: Scopes = field(init=False)
    cache: dict[str, Any] = field(default_factory=dict)
    """Results shared between rules of one run (the elaborated models)."""

    def __post_init__(self) -> None:
        self.scopes = Scopes(self.workspace)
        self._sites: list[BlockSite] | None = None
        self._sites_by_kind: dict[ast.BlockKind, list[BlockSite]] | None = None
        self._file_of: dict[int, ast.SourceFile] = {}
        for f in self.workspace.files.values():
            for item in f.items:
                self._file_of[id(item)] = f

    # ----- reporting
    def error(self, rule_id: str, node: object, message: str, hint: str) -> None:
        span = node if isinstance(node, Span) else getattr(node, "span")
        self.report.report(RULES[rule_id].code, message, span, hint)

    # ----- what the rules walk
    def files(self) -> Iterator[ast.SourceFile]:
        return self.workspace.user_files()

    def items(self, cls: type) -> Iterator[tuple[ast.SourceFile, Any]]:
        for f in self.files():
            for item in f.items:
                if isinstance(item, cls):
                    yield f, item

    def pmodels(self) -> Iterator[tuple[ast.SourceFile, ast.PModel]]:
        return self.items(ast.PModel)

    def definitions(self) -> Iterator[tuple[ast.SourceFile, ast.Definition]]:
        return self.items(ast.Definition)

    def mappings(self) -> Iterator[tuple[ast.SourceFile, ast.PlatformMapping]]:
        return self.items(ast.PlatformMapping)

    def blocks(self) -> list[BlockSite]:
        """Every block of every p-model of the user's files, outer blocks first. Walked once
        per run and shared: most rules visit every block, and a model has thousands."""
        if self._sites is None:
            self._sites = []
            for f, pm in self.pmodels():
                stack = [(b, ()) for b in reversed(pm.blocks)]
                while stack:
                    block, ancestors = stack.pop()
                    self._sites.append(BlockSite(f, pm, block, ancestors))
                    stack.extend((b, ancestors + (block,)) for b in reversed(block.blocks))
        return self._sites

    def blocks_of(self, kind: ast.BlockKind) -> list[BlockSite]:
        """The blocks of one kind (links, bodies…), in the order of :meth:`blocks`."""
        if self._sites_by_kind is None:
            self._sites_by_kind = {k: [] for k in ast.BlockKind}
            for site in self.blocks():
                self._sites_by_kind[site.block.kind].append(site)
        return self._sites_by_kind[kind]

    def target(self, node: object) -> Any:
        """What a reference resolved to (a Definition, PModel, Module…), or None."""
        return self.resolution.get(node)

    def file_of(self, decl: object) -> ast.SourceFile | None:
        return self._file_of.get(id(decl))


def per_node(fn: Callable[..., Any]) -> Callable[..., Any]:
    """Remember ``fn(node, *args)`` by the node's identity: tables a rule builds for a whole
    p-model (its links, its bodies) are asked for once per block, which on a model of
    thousands of blocks would otherwise make the checks quadratic."""
    cache: dict[tuple[Any, ...], tuple[Any, Any]] = {}

    def wrapper(node: Any, *args: Any) -> Any:
        key = (id(node), *args)
        hit = cache.get(key)
        if hit is not None and hit[0] is node:
            return hit[1]
        if len(cache) > 4096:
            cache.clear()
        value = fn(node, *args)
        cache[key] = (node, value)
        return value

    wrapper.__doc__, wrapper.__name__ = fn.__doc__, fn.__name__
    return wrapper


def check_wellformed(ctx: WFContext, only: set[str] | None = None) -> None:
    """Run every rule (or those in ``only``). The collector is paused meanwhile, as during
    elaboration: the rules build tables that live until the end of the run, and on a large
    model the collections those would trigger traverse the whole syntax tree (seconds at
    10,000 links) and find no garbage. What the run leaves is collected, young, after it."""
    with collector.paused():
        for r in RULES.values():
            if only is None or r.id in only:
                progress.stage(f"checking {r.id}: {r.summary}")
                r.check(ctx)
