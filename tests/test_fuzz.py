"""Property: however a real model file is damaged, the front end answers with diagnostics,
never with a traceback (issue: random deletions, insertions and swaps of tokens)."""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cyphy import api
from cyphy.diagnostics import Severity
from cyphy.lang.parser import parse_text
from conftest import EXAMPLES, corpus_model_files

TOKEN = re.compile(r"\s+|[A-Za-z_^][A-Za-z0-9_]*|[0-9.]+(?:[eE][+-]?[0-9]+)?|\S")
SOURCES = [p for p in corpus_model_files() if p.stat().st_size < 20000] or sorted(
    EXAMPLES.rglob("*.rsm"))
TEXTS = {str(p): p.read_text(encoding="utf-8") for p in SOURCES}
EXTRA_TOKENS = ["{", "}", "(", ")", "[|", "|]", "(|", "|)", "::", ".", ",", ";", "=", "==",
                "local", "link", "pose", "x", "def", "index", "^", "/*", "//", '"', "m",
                "0.5m", "-", "<", ">", "cat", "jref", "map", "@", "\x00", "é"]


def tokens(text: str) -> list[str]:
    return TOKEN.findall(text)


@st.composite
def damaged_model(draw: st.DrawFn) -> tuple[str, str]:
    path = draw(st.sampled_from(sorted(TEXTS)))
    toks = tokens(TEXTS[path])
    for _ in range(draw(st.integers(1, 6))):
        if not toks:
            break
        i = draw(st.integers(0, len(toks) - 1))
        op = draw(st.sampled_from(["delete", "insert", "swap", "duplicate"]))
        if op == "delete":
            del toks[i]
        elif op == "insert":
            toks.insert(i, draw(st.sampled_from(EXTRA_TOKENS + toks[:50])))
        elif op == "swap":
            j = draw(st.integers(0, len(toks) - 1))
            toks[i], toks[j] = toks[j], toks[i]
        else:
            toks.insert(i, toks[i])
    return path, "".join(toks)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(damaged_model())
def test_damaged_text_gives_diagnostics_not_tracebacks(case: tuple[str, str]) -> None:
    path, text = case
    result = parse_text(text, path)
    failed = any(d.code.id in ("E-SYNTAX", "E-LEX") for d in result.diagnostics)
    assert (result.file is None) == failed
    for d in result.diagnostics:
        assert d.span.file == path and d.span.line >= 1 and d.message and d.hint


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(damaged_model())
def test_damaged_model_survives_resolution(case: tuple[str, str]) -> None:
    """The whole `cyphy check` pipeline (parse, placement, resolution) on a damaged file."""
    _, text = case
    with tempfile.TemporaryDirectory() as tmp:
        model = Path(tmp) / "damaged.pm"
        model.write_text(text, encoding="utf-8")
        result = api.check([model])
    for d in result.report.diagnostics:
        assert d.code.severity in (Severity.ERROR, Severity.WARNING)
        assert d.message
