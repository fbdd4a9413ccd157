"""Jinja2's compiled templates kept in cyphy's cache
(``cyphy/backends/isabelle/bytecode_cache.py``): a warm render loads the bytecode instead of
compiling and writes the same text; an entry others may write is never loaded (it is code);
a cache that cannot be written does not stop a render."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator

import pytest
from jinja2.bccache import Bucket

from cyphy.backends.isabelle import theory

TEMPLATES = ("ROOT.j2", "theory.thy.j2", "README.j2")


@pytest.fixture(autouse=True)
def fresh_environment() -> Iterator[None]:
    """Each test builds the Jinja2 environment under its own settings."""
    theory._environment.cache_clear()
    yield
    theory._environment.cache_clear()


@pytest.fixture
def loads(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The templates whose bytecode was loaded from the cache (not compiled)."""
    found: list[str] = []
    real = Bucket.load_bytecode

    def load(self: Bucket, f: object) -> None:
        real(self, f)
        if self.code is not None:
            found.append(self.key)

    monkeypatch.setattr(Bucket, "load_bytecode", load)
    return found


def sources() -> dict[str, str]:
    """Each template's compiled code's source name and a render of the fixed ``ROOT``."""
    theory._environment.cache_clear()
    env = theory._environment()
    out = {name: env.get_template(name).filename or "" for name in TEMPLATES}
    out["render"] = env.get_template("ROOT.j2").render(session="S", theory="T", prelude="P")
    return out


def entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("jinja-*/*.jinja"))


def test_a_warm_environment_loads_the_compiled_templates(cyphy_cache: Path, loads: list[str],
                                                         monkeypatch: pytest.MonkeyPatch
                                                         ) -> None:
    first = sources()
    assert len(entries(cyphy_cache)) == len(TEMPLATES) and loads == []
    assert sources() == first and len(loads) == len(TEMPLATES)
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    assert sources() == first


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_an_entry_others_may_write_is_not_loaded(cyphy_cache: Path, loads: list[str]) -> None:
    first = sources()
    for entry in entries(cyphy_cache):
        entry.chmod(0o666)
    assert sources() == first and loads == []


def test_a_corrupt_entry_is_compiled_again(cyphy_cache: Path, loads: list[str]) -> None:
    first = sources()
    for entry in entries(cyphy_cache):
        entry.write_bytes(b"j2 not bytecode")
    assert sources() == first and loads == []
    assert all(e.read_bytes() != b"j2 not bytecode" for e in entries(cyphy_cache))  # rewritten


def test_an_unusable_cache_folder_is_ignored(tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("CYPHY_CACHE_DIR", str(blocker))  # a file, not a folder
    monkeypatch.delenv("CYPHY_NO_CACHE", raising=False)
    try:
        assert "S" in sources()["render"]
    finally:
        theory._environment.cache_clear()


def test_a_cache_that_cannot_be_written_is_ignored(cyphy_cache: Path,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """A full disk or a read-only folder (root ignores permissions, so the write is made to
    fail where Jinja2 opens its temporary file)."""
    import jinja2.bccache

    def refuse(*args: object, **kwargs: object) -> None:
        raise PermissionError("read-only")

    monkeypatch.setattr(jinja2.bccache.tempfile, "NamedTemporaryFile", refuse)
    assert "S" in sources()["render"] and entries(cyphy_cache) == []
