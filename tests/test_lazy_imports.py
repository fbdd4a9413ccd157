"""An import written inside a function says why (issue 24): ``# lazy: <reason>`` on its line or
on the comment line right above it. Imports hidden in functions once hid import cycles; now a
function-level import is kept only where it saves start-up (a heavy or optional library, a
part of the package that a command does not need) and the reason is written where it is.

The command line and the API facade (``cli/``, ``api/``) import inside functions by design:
each command and each entry point loads its stage on first use, so they are not read here.
"""

from __future__ import annotations

import ast
from pathlib import Path

from import_graph import modules

#: Edges that load on first use by design (see the module docstring).
EXEMPT = ("cyphy.cli", "cyphy.api")
#: Parts not audited yet: other sessions are splitting these modules while this test lands, so
#: their imports are given reasons after the split. Like ``KNOWN_LONG``, the set may only
#: shrink: a part with no unexplained import left fails the test until it is removed here.
NOT_YET_AUDITED: tuple[str, ...] = ()
MARK = "# lazy:"


def _within(module: str, parts: tuple[str, ...]) -> bool:
    return any(module == p or module.startswith(p + ".") for p in parts)


def unexplained_imports(source: str) -> list[int]:
    """The line numbers of the imports inside functions of ``source`` that carry no reason."""
    lines = source.splitlines()
    found: list[int] = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)) and in_function:
                here = lines[child.lineno - 1]
                above = lines[child.lineno - 2].strip() if child.lineno > 1 else ""
                reason = here.partition(MARK)[2] if MARK in here else (
                    above[len(MARK):] if above.startswith(MARK) else "")
                if not reason.strip():
                    found.append(child.lineno)
            visit(child, in_function or isinstance(child, (ast.FunctionDef,
                                                            ast.AsyncFunctionDef, ast.Lambda)))

    visit(ast.parse(source), False)
    return found


def _unexplained() -> dict[str, list[int]]:
    out = {}
    for module, path in modules().items():
        if _within(module, EXEMPT):
            continue
        lines = unexplained_imports(Path(path).read_text(encoding="utf-8"))
        if lines:
            out[module] = lines
    return out


def test_every_function_level_import_gives_its_reason() -> None:
    missing = {m: n for m, n in _unexplained().items() if not _within(m, NOT_YET_AUDITED)}
    assert missing == {}, f"add '{MARK} <reason>' or move the import to the module's top: {missing}"


def test_the_parts_not_yet_audited_only_shrink() -> None:
    left = _unexplained()
    done = [p for p in NOT_YET_AUDITED if not any(_within(m, (p,)) for m in left)]
    assert not done, f"no unexplained import left in {done}: remove them from NOT_YET_AUDITED"


def test_the_probe_finds_an_import_without_a_reason() -> None:
    source = (
        "import os\n"
        "def a():\n    import json\n"
        "def b():\n    import sympy  # lazy: half a second\n"
        "def c():\n    # lazy: optional library\n    import pinocchio\n"
        "def d():\n    def inner():\n        from x import y  # lazy:\n    return inner\n"
        "class K:\n    def m(self):\n        import z3\n"
        "if True:\n    import math\n"
    )
    assert unexplained_imports(source) == [3, 11, 15]
