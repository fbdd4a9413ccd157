"""Shared test fixtures: where the examples and the (optional) conformance corpus live."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import pytest

# The tests (and the cyphy processes they start) use a parse cache of their own, not the
# user's: what they find there is then only what this run put there.
os.environ["CYPHY_CACHE_DIR"] = tempfile.mkdtemp(prefix="cyphy-test-cache-")

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
# benchmarks/motors.py builds models that tests use too (the motors bench, the SSpeed table)
sys.path.insert(0, str(ROOT / "benchmarks"))
CORPUS = ROOT.parent / "shared" / "corpus" / "pmodel-examples"

needs_corpus = pytest.mark.skipif(
    not CORPUS.is_dir(), reason="../shared/corpus is absent (a fresh clone has none)"
)


def corpus_model_files() -> list[Path]:
    if not CORPUS.is_dir():
        return []
    return sorted(p for p in CORPUS.rglob("*") if p.suffix in (".pm", ".rst"))


def corpus_project_folders() -> list[Path]:
    """Folders that hold model files: each is one RoboTool project."""
    return sorted({p.parent for p in corpus_model_files()})


def flowstar_binary() -> Path | None:
    """The real Flow* binary, found as ``cyphy reach`` finds it (``$CYPHY_FLOWSTAR``, the
    folder ``.ci/install`` builds it into, ``flowstar`` on PATH); ``None`` when there is none
    (its tests then skip)."""
    from cyphy.verify.flowstar.locate import find_flowstar
    from cyphy.verify.flowstar.verdict import FlowstarMissing

    try:
        return Path(find_flowstar())
    except FlowstarMissing:
        return None


needs_flowstar = pytest.mark.skipif(
    flowstar_binary() is None,
    reason="no Flow* binary (.ci/install builds one from ../shared/tools/flowstar)")


@pytest.fixture
def cyphy_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A cache folder of the test's own (``CYPHY_CACHE_DIR``, caching on), not made yet."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("CYPHY_CACHE_DIR", str(folder))
    monkeypatch.delenv("CYPHY_NO_CACHE", raising=False)
    return folder


@pytest.fixture(autouse=True)
def _fresh_rendering() -> None:
    """Each test starts with the command line's rendering state at its defaults: an
    in-process ``main([..., "-q"])`` sets ``RENDERING.quiet`` for whatever runs next in the
    process (a real ``cyphy`` process runs one command), so a later test that expects
    warnings or progress would depend on the order the tests run in."""
    from cyphy.diagnostics import RENDERING, Rendering

    for name, value in vars(Rendering()).items():
        setattr(RENDERING, name, value)


def sigint_as_at_a_terminal() -> None:
    """``preexec_fn`` of a child that a test interrupts with SIGINT: the default disposition,
    as a user's terminal gives. A runner started in the background by a shell without job
    control ignores SIGINT, and its children inherit that across exec, so Ctrl-C would not
    reach them at all."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)
