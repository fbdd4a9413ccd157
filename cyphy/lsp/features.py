"""What the editor asks, answered from one check of a project folder: diagnostics, hover text,
the outline and completions, as plain data (the server turns them into LSP messages).

One :class:`Analysis` is the result of ``cyphy check`` on the open files of one folder, with
the editor's unsaved texts in place of the files on disk, so its diagnostics are exactly the
command's.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

from cyphy import expr as ex
from cyphy.diagnostics import Diagnostic, Report, Span
from cyphy.lang import ast
from cyphy.lang.workspace import LIBRARY_ROOT
from cyphy.lsp.index import Index, build_index, offset
from cyphy.model.elaborate import elaborate_pmodel
from cyphy.model.evaluate import EvalError, evaluate
from cyphy.pipeline.check import CheckOptions, CheckResult, check


@dataclass
class Analysis:
    """One check of a folder's open files and what an editor reads from it. The index of
    names is built on the first request that needs it: diagnostics, sent at every pause in
    typing, do not wait for it."""

    result: CheckResult
    _index: Index | None = field(default=None, repr=False)
    _poses: dict[int, str] | None = field(default=None, repr=False)

    @property
    def index(self) -> Index:
        if self._index is None:
            self._index = build_index(self.result.workspace, self.result.resolution)
        return self._index

    def diagnostics_of(self, path: str) -> list[Diagnostic]:
        return [d for d in self.result.report.diagnostics if d.span.file == path]


def analyse(targets: Sequence[str], overrides: Mapping[str, str],
            search_paths: Sequence[str] = (), consistency: bool = False) -> Analysis:
    """``cyphy check TARGETS`` with the unsaved texts ``overrides`` (path → text)."""
    result = check(list(targets), CheckOptions(search_paths=tuple(search_paths),
                                               overrides=dict(overrides),
                                               consistency=consistency))
    return Analysis(result)


# --------------------------------------------------------------------------- hover

_SI_SYMBOL = {"[mass]": "kg", "[length]": "m", "[time]": "s", "[current]": "A",
              "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}


def si_unit(suffix: str) -> str | None:
    """The SI unit a value written with ``suffix`` is evaluated in (``cm`` → ``m``,
    ``N`` → ``kg m s^-2``; an angle, dimensionless, → ``rad``), from the unit table."""
    # lazy: the unit table is read only when a constant is hovered
    from cyphy.model.units import units

    unit = units().get(suffix)
    if unit is None:
        return None
    if not unit.dimension.exponents:
        return "rad"  # the only dimensionless suffixes are angles
    return " ".join(_SI_SYMBOL.get(k, k) + ("" if v == 1 else f"^{v:g}")
                    for k, v in unit.dimension.exponents)


def hover(analysis: Analysis, path: str, line: int, column: int) -> tuple[str, Span] | None:
    """Markdown describing the name at a 1-based position, and the name's span."""
    site = analysis.index.site_at(path, line, column)
    if site is None:
        return None
    target = site.target
    parts = [f"```robosim\n{_signature(analysis, target)}\n```", _kind(target)]
    if isinstance(target, ast.VarDecl) and target.kind is ast.DeclKind.CONST:
        parts.append(_constant_value(analysis, target))
    if isinstance(target, ast.Block) and target.kind is ast.BlockKind.LINK:
        pose = _pose_of(analysis, target)
        if pose:
            parts.append(pose)
    where = target.span.file if isinstance(target, ast.Node) else ""
    if where.startswith(str(LIBRARY_ROOT)):
        parts.append(f"defined in the built-in library: `{Path(where).relative_to(LIBRARY_ROOT)}`")
    return "\n\n".join(p for p in parts if p), site.span


def _kind(target: object) -> str:
    if isinstance(target, (ast.Block, ast.Definition)):
        what = "definition" if isinstance(target, ast.Definition) else (
            "reference" if target.ref else "local")
        return f"*{target.kind.value}* ({what})"
    if isinstance(target, ast.VarDecl):
        return f"*{target.kind.value}* variable" if target.kind is not ast.DeclKind.CONST \
            else "*constant*"
    words = re.sub(r"(?<!^)(?=[A-Z])", " ", type(target).__name__).lower()
    return f"*{words}*"


def _signature(analysis: Analysis, target: object) -> str:
    """The declaration as written: its first line, or for a definition (whose inputs and
    outputs make its signature) every line that declares something."""
    if not isinstance(target, ast.Node) or target.span.line <= 0:
        return getattr(target, "name", "?")
    text = analysis.index.texts.get(target.span.file)
    if text is None:
        return getattr(target, "name", "?")
    start = offset(text, target.span.line, target.span.column)
    end = offset(text, target.span.end_line, target.span.end_column)
    lines = [ln.strip() for ln in text[start:end].splitlines() if ln.strip()]
    if not lines:
        return getattr(target, "name", "?")
    if isinstance(target, ast.Definition):
        decl = re.compile(r"^(input|output|InOut|const|local|var)\b")
        body = [ln for ln in lines[1:] if decl.match(ln)]
        return "\n".join([lines[0], *("  " + b for b in body[:20]),
                          *(["}"] if body else [])])
    if isinstance(target, ast.VarDecl) and not lines[0].startswith(target.kind.value):
        return f"{target.kind.value} {lines[0]}"  # one of a list: `const a: real, b: real`
    return lines[0]


def _constant_value(analysis: Analysis, decl: ast.VarDecl) -> str:
    """The constant's value, evaluated with the values of the constants it names (as
    resolved), in SI units; or why it has none."""
    if decl.value is None:
        return "no value: each p-model or part that uses it must give one"
    try:
        value = evaluate(decl.value, _environment(analysis, decl.value, 0))
    except (EvalError, RecursionError):
        return "value: not a constant expression"
    unit = si_unit(decl.value.unit) if isinstance(decl.value, ex.Quantity) else None
    shown = repr(value.tolist()) if hasattr(value, "tolist") else repr(value)
    return f"value: `{shown}{' ' + unit if unit else ''}`" + (
        f" (written in {decl.value.unit})" if unit and unit != decl.value.unit else "")


def _environment(analysis: Analysis, e: ex.Expr, depth: int) -> dict[str, object]:
    # lazy: as in _constant_value
    from cyphy.model.evaluate import EvalError, evaluate

    env: dict[str, object] = {}
    if depth > 32:
        return env
    for node in e.walk():
        if not isinstance(node, ex.Name):
            continue
        site = analysis.index.site_at(node.span.file, node.span.line, node.span.column)
        target = site.target if site is not None else None
        if isinstance(target, ast.VarDecl) and target.value is not None:
            try:
                env[node.text] = evaluate(target.value,
                                          _environment(analysis, target.value, depth + 1))
            except EvalError:
                pass
    return env


def _pose_of(analysis: Analysis, block: ast.Block) -> str:
    """The link's pose in its p-model's frame, from the elaborated p-model that declares it
    (every copy of an indexed link)."""
    if analysis._poses is None:
        analysis._poses = _elaborated_poses(analysis)
    return analysis._poses.get(id(block), "")


def _elaborated_poses(analysis: Analysis) -> dict[int, str]:
    result = analysis.result
    if result.resolution is None:
        return {}
    poses: dict[int, list[str]] = {}
    by_span = {}
    for file in result.workspace.user_files():
        for item in file.declarations():
            if not isinstance(item, ast.PModel):
                continue
            for b in _blocks(item):
                by_span[b.span] = b
            try:
                model = elaborate_pmodel(result.workspace, result.resolution, Report(), item,
                                         file, devices=False)
            except Exception:  # a half-written model: no pose rather than no hover
                continue
            for link in model.links:
                block = by_span.get(link.span)
                if block is None or link.pose is None:
                    continue
                numbers = ", ".join(f"{v:.6g}" for v in link.pose.to_xyz_rpy())
                poses.setdefault(id(block), []).append(
                    f"`{link.name}`: ({numbers})")
    return {k: "pose in the p-model's frame (x, y, z, roll, pitch, yaw; m, rad):\n\n"
            + "\n\n".join(v[:8]) + ("\n\n…" if len(v) > 8 else "") for k, v in poses.items()}


def _blocks(node: ast.PModel | ast.Block) -> list[ast.Block]:
    out: list[ast.Block] = []
    for m in node.members:
        if isinstance(m, ast.Block):
            out.append(m)
            out.extend(_blocks(m))
    return out


# --------------------------------------------------------------------------- outline


@dataclass
class Symbol:
    name: str
    detail: str
    kind: str  # one of: module, class, field, constant, variable, event, method, enum, …
    span: Span
    selection: Span
    children: list["Symbol"] = field(default_factory=list)


_SYMBOL_KIND = {ast.PModel: "module", ast.Part: "object", ast.Block: "class",
                ast.Definition: "class", ast.StateMachine: "class", ast.State: "enum_member",
                ast.Controller: "module", ast.Module: "package", ast.RoboticPlatform: "module",
                ast.Interface: "interface", ast.EventDecl: "event",
                ast.OperationSig: "method", ast.Transition: "function", ast.DataType: "struct",
                ast.Enumeration: "enum", ast.TypeDecl: "type_parameter",
                ast.FunctionDecl: "function", ast.AnnotationTemplate: "struct",
                ast.ClockDecl: "variable"}


def document_symbols(index: Index, file: ast.SourceFile) -> list[Symbol]:
    """The outline: p-models, their parts, links and what links hold, definitions, machines
    and their states, interfaces and their events, top-level constants."""
    return [s for item in file.items for s in _symbols(index, item)]


def _symbols(index: Index, node: object) -> list[Symbol]:
    if isinstance(node, ast.VarDecl):
        kind = "constant" if node.kind is ast.DeclKind.CONST else "variable"
        return [_symbol(index, node, kind, node.kind.value, [])]
    kind = _SYMBOL_KIND.get(type(node))
    if kind is None or not isinstance(node, ast.Node):
        return []
    members = getattr(node, "members", ())
    children = [s for m in members if not isinstance(m, ast.DefBlock) for s in _symbols(
        index, m)] if not isinstance(node, ast.Transition) else []
    for d in getattr(node, "definitions", ()) if isinstance(node, ast.Block) else ():
        children.extend(s for m in d.members for s in _symbols(index, m))
    detail = _detail(node)
    return [_symbol(index, node, kind, detail, children)]


def _detail(node: object) -> str:
    if isinstance(node, (ast.Block, ast.Definition)):
        ref = getattr(node, "ref", None)
        return node.kind.value + (f" = {'::'.join(ref)}" if ref else "")
    if isinstance(node, ast.Part):
        return "part = " + "::".join(node.pmodel)
    return re.sub(r"(?<!^)(?=[A-Z])", " ", type(node).__name__).lower()


def _symbol(index: Index, node: ast.Node, kind: str, detail: str,
            children: list[Symbol]) -> Symbol:
    name = getattr(node, "name", "") or "?"
    selection = index.definition_of(node) or node.span
    return Symbol(str(name), detail, kind, node.span, selection, children)


# --------------------------------------------------------------------------- completion


@dataclass(frozen=True)
class Completion:
    label: str
    kind: str  # keyword, module, class, constant, variable, field, …
    detail: str = ""


_GRAMMAR = Path(__file__).resolve().parent.parent / "lang" / "robosim.lark"


def keywords() -> list[str]:
    """The words the grammar reserves (its quoted literals that are words)."""
    text = _GRAMMAR.read_text(encoding="utf-8")
    return sorted({m for m in re.findall(r'"([A-Za-z_][A-Za-z_0-9]*)"i?', text)})


def completions(analysis: Analysis | None, path: str, text: str, line: int,
                column: int) -> list[Completion]:
    """What may be written at a 1-based position of ``text`` (the editor's current text)."""
    at = offset(text, line, column)
    before = text[max(0, at - 200):at]
    qualified = re.search(r"((?:\w+::)+)(\w*)$", before)
    if qualified and analysis is not None:
        return _package_members(analysis, tuple(qualified.group(1).split("::")[:-1]))
    if analysis is None:
        return [Completion(k, "keyword") for k in keywords()]
    out = [Completion(k, "keyword") for k in keywords()]
    out.extend(_annotation_fields(analysis, text, at))
    out.extend(_names_in_scope(analysis, path, line, column))
    seen: set[tuple[str, str]] = set()
    unique = []
    for c in out:
        if (c.label, c.kind) not in seen:
            seen.add((c.label, c.kind))
            unique.append(c)
    return unique


def _package_members(analysis: Analysis, package: tuple[str, ...]) -> list[Completion]:
    ws = analysis.result.workspace
    out = []
    for name in ws.packages:  # sub-packages: `physmod::` offers `joints`, `sdf`, …
        if len(name) == len(package) + 1 and name[:-1] == package:
            out.append(Completion(name[-1], "module", "package " + "::".join(name)))
    pkg = ws.packages.get(package)
    if pkg is not None:
        for member, decls in sorted(pkg.members.items()):
            out.append(Completion(member, _completion_kind(decls[0]), _detail(decls[0])))
    return out


def _completion_kind(decl: object) -> str:
    if isinstance(decl, ast.VarDecl):
        return "constant" if decl.kind is ast.DeclKind.CONST else "variable"
    if isinstance(decl, (ast.Definition, ast.Block, ast.PModel)):
        return "class"
    if isinstance(decl, ast.FunctionDecl):
        return "function"
    return "reference"


def _names_in_scope(analysis: Analysis, path: str, line: int, column: int) -> list[Completion]:
    """The package-level names the file sees (its package, its imports, the global
    package), then the names declared by the p-model, blocks and definitions around the
    position."""
    # lazy: keeps the server's start light
    from cyphy.lang.scopes import Scopes

    ws = analysis.result.workspace
    file = ws.files.get(path)
    if file is None:
        return []
    out: list[Completion] = []
    for level in Scopes(ws).levels(file):
        for name, decls in sorted(level.items()):
            if decls:
                out.append(Completion(name, _completion_kind(decls[0]), _detail(decls[0])))
    for node in _enclosing(file, line, column):
        for m in _local_members(node):
            name = getattr(m, "name", None)
            if isinstance(name, str):
                out.append(Completion(name, _completion_kind(m), _detail(m)))
    return out


def _local_members(node: object) -> list[object]:
    members = list(getattr(node, "members", ()))
    for m in list(members):
        if isinstance(m, ast.DefBlock):
            members.extend(m.members)
    return members


def _enclosing(file: ast.SourceFile, line: int, column: int) -> list[object]:
    """The nodes with members whose span holds the position, outermost first."""
    out: list[object] = []
    level: Sequence[object] = file.items
    while True:
        inner = [n for n in level if isinstance(n, ast.Node) and hasattr(n, "members")
                 and (n.span.line, n.span.column) <= (line, column)
                 <= (n.span.end_line, n.span.end_column)]
        if not inner:
            return out
        out.append(inner[0])
        level = getattr(inner[0], "members")


_ANNOTATION = re.compile(r"(?:\bannotation\s+|=\s*)(\w+)\s*\{[^{}]*$")


def _annotation_fields(analysis: Analysis, text: str, at: int) -> list[Completion]:
    """Inside ``annotation Name { … }`` (or a nested ``= Name { … }``): the parameters of
    annotation template ``Name`` and of the templates it extends."""
    m = _ANNOTATION.search(text[max(0, at - 2000):at])
    if m is None:
        return []
    templates = {name: decl for _, name, decl in analysis.result.workspace.all_declarations()
                 if isinstance(decl, ast.AnnotationTemplate)}
    out, name, seen = [], m.group(1), set()
    while name in templates and name not in seen:
        seen.add(name)
        decl = templates[name]
        out.extend(Completion(p.name, "field", f"{name} parameter") for p in decl.params)
        name = decl.extends[-1] if decl.extends else ""
    return out
