"""The two parse engines give the same results (cyphy/lang/grammar.py): lark-cython's C lexer and
LALR loop, used for every parse when it is installed, against Lark's own pure-Python ones, on
every model file of the examples, the tests' data, the library and the corpus (when
``../shared`` is there), each whole and cut short at several points (syntax errors). Compared
are the syntax trees with every field, spans included (the AST's equality skips spans), and
the diagnostics; and cyphy parses the same without lark-cython at all."""

from __future__ import annotations

import dataclasses
import enum
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from conftest import CORPUS, EXAMPLES, ROOT

from cyphy.lang import parser
from cyphy.lang.grammar import compiled, pure
from lark.exceptions import UnexpectedInput

pytestmark = pytest.mark.skipif(compiled() is None, reason="lark-cython is not installed")

SUFFIXES = (".pm", ".rst", ".rsm")
#: Where each file is cut short: fractions of its length (mid-token, mid-block, mid-line).
CUTS = (0.13, 0.37, 0.5, 0.71, 0.93)


def _files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*") if p.suffix in SUFFIXES and p.is_file())


def _ours() -> list[Path]:
    return (_files(EXAMPLES) + _files(ROOT / "tests" / "data")
            + _files(ROOT / "cyphy" / "lang" / "library"))


def _corpus() -> list[Path]:
    shared = CORPUS.parent
    return _files(shared) if shared.is_dir() else []


def canonical(node: Any) -> Any:
    """Every field of every node, spans included, as nested tuples (so that two trees equal
    here agree on everything the later stages and the diagnostics read)."""
    if dataclasses.is_dataclass(node) and not isinstance(node, type):
        return (type(node).__name__,
                tuple((f.name, canonical(getattr(node, f.name)))
                      for f in dataclasses.fields(node)))
    if isinstance(node, (tuple, list)):
        return (type(node).__name__, tuple(canonical(x) for x in node))
    if isinstance(node, enum.Enum):
        return (type(node).__name__, node.value)
    assert node is None or type(node) in (str, int, float, bool), (type(node), node)
    return node


def _texts(path: Path) -> list[tuple[str, str]]:
    text = path.read_text(encoding="utf-8", errors="replace")
    return [(f"{path.name} whole", text)] + [
        (f"{path.name} cut at {cut}", text[:int(len(text) * cut)]) for cut in CUTS]


def _outcome(engine: Any, text: str) -> Any:
    try:
        return canonical(parser.parse_with(engine, text, "m.pm"))
    except UnexpectedInput as err:  # only whether both fail matters: pure Lark describes it
        return ("syntax error", type(err).__name__)


def _compare(paths: list[Path], monkeypatch: pytest.MonkeyPatch | None) -> tuple[int, int]:
    """Both engines on every text; with ``monkeypatch``, ``parse_text`` too, with and without
    lark-cython. (Parses, syntax errors) counted."""
    fast, slow = compiled(), pure()
    assert fast is not None
    parses = failures = 0
    for path in paths:
        for label, text in _texts(path):
            got, expected = _outcome(fast, text), _outcome(slow, text)
            assert got == expected, label
            parses += 1
            failures += got[0] == "syntax error"
            if monkeypatch is None:
                continue
            # What a user gets: parse_text, with lark-cython and with pure Lark alone.
            with_fast = canonical(parser.parse_text(text, "m.pm"))
            with monkeypatch.context() as m:
                m.setattr(parser, "compiled", lambda: None)
                assert canonical(parser.parse_text(text, "m.pm")) == with_fast, label
    return parses, failures


def test_the_engines_agree_on_our_files_whole_and_cut_short(monkeypatch):
    paths = _ours()
    assert len(paths) >= 40, paths
    parses, failures = _compare(paths, monkeypatch)
    # Most cut-short texts are syntax errors, every whole file parses: both paths exercised.
    assert failures >= len(paths) * 3, (parses, failures)
    assert parses - failures >= len(paths), (parses, failures)


@pytest.mark.skipif(not CORPUS.parent.is_dir(), reason="../shared/corpus is absent")
def test_the_engines_agree_on_the_corpus_whole_and_cut_short():
    paths = _corpus()
    assert len(paths) >= 100, len(paths)
    parses, failures = _compare(paths, None)
    assert failures >= len(paths) * 3 and parses - failures >= len(paths), (parses, failures)


def test_a_compiled_parse_leaves_no_token_in_the_tree():
    text = (EXAMPLES / "dcmotor" / "DCMotorBase.rsm").read_text()
    fast = compiled()
    assert fast is not None
    result = parser.parse_with(fast, text, "m.pm")
    assert result.file is not None and not parser.contains_lark_objects(result)


def test_the_diagnostics_of_a_syntax_error_are_pure_larks():
    """lark-cython's errors carry no interactive parser: the file is parsed again by Lark."""
    text = "pmodel P {\n  local link L {\n    pose { x = 1 y = }\n  }\n}\n"
    with pytest.raises(UnexpectedInput):
        parser.parse_with(compiled(), text, "m.pm")
    result = parser.parse_text(text, "m.pm")
    assert result.file is None
    (diag,) = result.diagnostics
    assert (diag.span.line, diag.span.column, diag.code.id) == (3, 22, "E-SYNTAX"), diag
    assert diag.message == "unexpected '}'", diag


def test_cyphy_parses_without_lark_cython():
    """A machine without lark-cython (it is imported only if present) parses with pure Lark
    and gets the same tree: the child process cannot import it."""
    path = EXAMPLES / "dcmotor" / "DCMotorBase.rsm"
    code = (
        "import sys; sys.modules['lark_cython'] = None; sys.path.insert(0, 'tests')\n"
        "from cyphy.lang import grammar, parser\n"
        "assert grammar.compiled() is None and grammar.lark_cython is None\n"
        f"r = parser.parse_text(open({str(path)!r}).read(), 'm.pm')\n"
        "from test_parse_engines import canonical\n"
        "print(repr(canonical(r)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)},
                         timeout=120)
    assert out.returncode == 0, out.stderr
    here = parser.parse_text(path.read_text(), "m.pm")
    assert here.file is not None
    assert out.stdout.strip() == repr(canonical(here))
