"""Draw ``docs/architecture.svg``: the packages of ``cyphy`` (a folder, or a top-level module of
the foundation), one box per layer, the lowest (the foundation) at the top, and an arrow for each package that
imports another. Read from the source by ``tests/import_graph.py``, the reader the layering
test uses, and drawn by Graphviz's ``dot``.

    python3 docs/architecture_graph.py            # writes docs/architecture.svg
    python3 docs/architecture_graph.py --dot      # prints the Graphviz source
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from import_graph import LAYERS, graph, layer  # noqa: E402  (needs the path above)


def package(module: str) -> str:
    """The node a module is drawn in: its folder (``cyphy.semantics.dynamics``), the layer's
    package for its own modules, or ``foundation`` for the package's top-level modules."""
    parts = module.split(".")
    if layer(module) == "foundation":
        return "foundation"
    if module == "cyphy.__main__":
        return "cli"
    return ".".join(parts[1:3]) if len(parts) > 3 or (len(parts) == 3 and _is_package(module)) \
        else parts[1]


def _is_package(module: str) -> bool:
    return (HERE.parent / Path(*module.split("."))).is_dir()


def dot_source() -> str:
    edges = graph()
    nodes: dict[str, set[str]] = {name: set() for name in LAYERS}
    links: set[tuple[str, str]] = set()
    for module, targets in edges.items():
        source = package(module)
        nodes[layer(module)].add(source)
        for target in targets:
            if package(target) != source:
                links.add((source, package(target)))
    lines = ["digraph cyphy {", "  rankdir=BT; compound=true; newrank=true;",
             '  node [shape=box, fontname="Helvetica", fontsize=10];',
             '  edge [color="#00000055", arrowsize=0.6];']
    for i, name in enumerate(LAYERS):
        lines.append(f'  subgraph "cluster_{name}" {{ label="{i}. {name}"; '
                     'style=rounded; color="#888888"; fontname="Helvetica";')
        lines.extend(f'    "{n}";' for n in sorted(nodes[name]))
        lines.append("  }")
    lines.extend(f'  "{a}" -> "{b}";' for a, b in sorted(links))
    lines.append("}")
    return "\n".join(lines) + "\n"


def main() -> int:
    source = dot_source()
    if "--dot" in sys.argv[1:]:
        sys.stdout.write(source)
        return 0
    svg = subprocess.run(["dot", "-Tsvg"], input=source, text=True, capture_output=True,
                         check=True).stdout
    (HERE / "architecture.svg").write_text(svg)
    print(f"wrote {HERE / 'architecture.svg'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
