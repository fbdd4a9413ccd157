"""The import graph of the ``cyphy`` package, read from the source with ``ast`` (imports inside
functions and under ``TYPE_CHECKING`` included: each is a dependency a reader must follow), and
the layers it must respect. Used by ``tests/test_layers.py`` and ``docs/architecture_graph.py``;
run it to print the edges that break the layering and the cycles:

    python3 tests/import_graph.py
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "cyphy"

#: The layers, lowest first: a module may import its own layer and those before it, never one
#: after it. ``foundation`` is the package's top-level modules (diagnostics, codes, expr, …);
#: ``pipeline`` composes the stages (check, elaborate) that both ``verify`` and ``api`` use.
LAYERS = ("foundation", "lang", "model", "translate", "wellformed", "semantics", "backends",
          "pipeline", "verify", "api", "lsp", "cli")


def module_name(path: Path, package: Path = PACKAGE) -> str:
    """``cyphy/api/__init__.py`` → ``cyphy.api``; ``cyphy/cli/gen.py`` → ``cyphy.cli.gen``."""
    parts = list(path.relative_to(package.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules(package: Path = PACKAGE) -> dict[str, Path]:
    """Every module of the package by its dotted name."""
    return {module_name(p, package): p for p in sorted(package.rglob("*.py"))}


def layer(module: str) -> str:
    """The layer a module belongs to: its first subpackage, or ``foundation`` for the
    package's own modules (``cyphy.__main__``, the ``python -m cyphy`` entry, is ``cli``)."""
    parts = module.split(".")
    if module == "cyphy.__main__":
        return "cli"
    if len(parts) > 1 and parts[1] in LAYERS:
        return parts[1]
    return "foundation"


def _imported(node: ast.Import | ast.ImportFrom, module: str, is_package: bool,
              known: set[str]) -> set[str]:
    """The package's modules an import statement names (the module itself when
    ``from m import name`` takes a name defined in ``m``)."""
    if isinstance(node, ast.Import):
        names = [alias.name for alias in node.names]
        return {_deepest(n, known) for n in names if n == "cyphy" or n.startswith("cyphy.")}
    if node.level:  # relative: from the module's package
        base = module.split(".") if is_package else module.split(".")[:-1]
        base = base[:len(base) - node.level + 1]
        source = ".".join(base + ([node.module] if node.module else []))
    else:
        source = node.module or ""
    if source != "cyphy" and not source.startswith("cyphy."):
        return set()
    out = set()
    for alias in node.names:
        candidate = f"{source}.{alias.name}"
        out.add(candidate if candidate in known else _deepest(source, known))
    return out


def _deepest(name: str, known: set[str]) -> str:
    while name not in known and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


def graph(package: Path = PACKAGE) -> dict[str, set[str]]:
    """Module → the package's modules it imports (itself excluded)."""
    found = modules(package)
    known = set(found)
    edges: dict[str, set[str]] = {}
    for name, path in found.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        targets: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                targets |= _imported(node, name, path.name == "__init__.py", known)
        edges[name] = targets - {name}
    return edges


def upward_edges(edges: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Imports from a lower layer into a higher one."""
    rank = {name: i for i, name in enumerate(LAYERS)}
    return sorted((a, b) for a, targets in edges.items() for b in targets
                  if rank[layer(b)] > rank[layer(a)])


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan's algorithm,
    iterative): each is a set of modules that import each other, directly or not."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found: list[list[str]] = []
    counter = 0
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in edges:
                    continue
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return sorted(found)


def line_counts(package: Path = PACKAGE) -> dict[str, int]:
    """Each module's number of lines."""
    return {name: len(path.read_text(encoding="utf-8").splitlines())
            for name, path in modules(package).items()}


def main() -> int:
    edges = graph()
    up = upward_edges(edges)
    found = cycles(edges)
    for a, b in up:
        print(f"upward: {a} ({layer(a)}) -> {b} ({layer(b)})")
    for component in found:
        print("cycle: " + " <-> ".join(component))
    print(f"{len(edges)} modules, {sum(map(len, edges.values()))} imports, "
          f"{len(up)} upward, {len(found)} cycles")
    return 1 if up or found else 0


if __name__ == "__main__":
    sys.exit(main())
