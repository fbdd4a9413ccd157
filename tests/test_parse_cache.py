"""The persistent parse cache: hits give the same tree without parsing, anything odd about the
cache falls back to parsing, and a warm run does not even import Lark."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from cyphy import api, disk_cache
from cyphy.lang import parse_cache
from cyphy.lang.ast import ParseResult
from cyphy.lang.parser import parse_text

GOOD = "package p\npmodel M {\n\tlocal link L { def { } }\n}\n"
BAD = "package p\npmodel M {\n\tlocal link { }\n}\n"


def entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("parse-*/*.pickle"))


def no_parsing(monkeypatch: pytest.MonkeyPatch) -> None:
    def fail(text: str, path: str) -> ParseResult:
        raise AssertionError(f"{path} was parsed, not read from the cache")

    monkeypatch.setattr(parse_cache, "_parse", fail)


def test_a_hit_returns_the_parsed_tree_without_parsing(cyphy_cache: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    first = parse_cache.parse(GOOD, "m.rsm")
    expected = parse_text(GOOD, "m.rsm")
    assert first == expected
    assert len(entries(cyphy_cache)) == 1 and entries(cyphy_cache)[0].parent.name == \
        f"parse-{parse_cache.fingerprint()}"
    no_parsing(monkeypatch)
    assert parse_cache.parse(GOOD, "m.rsm") == first


def test_changed_text_or_other_path_is_parsed_again(cyphy_cache: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    parse_cache.parse(GOOD, "m.rsm")
    changed = GOOD.replace("link L", "link K")
    loads: list[object] = []
    real_load = disk_cache.pickle.load
    monkeypatch.setattr(disk_cache.pickle, "load", lambda f: loads.append(f) or real_load(f))
    file = parse_cache.parse(changed, "m.rsm").file
    assert loads == []  # the stale entry's hash is read, not its tree
    assert file is not None and "K" in repr(file) and " L " not in changed
    assert len(entries(cyphy_cache)) == 1  # one entry per path, overwritten
    other = parse_cache.parse(GOOD, "n.rsm").file
    assert other is not None and other.path == "n.rsm"  # spans name their own file
    assert len(entries(cyphy_cache)) == 2


def test_files_with_syntax_errors_are_not_stored(cyphy_cache: Path) -> None:
    parsed = parse_cache.parse(BAD, "bad.rsm")
    assert parsed.file is None and parsed.diagnostics[0].code.id == "E-SYNTAX"
    assert entries(cyphy_cache) == []


def test_a_corrupt_entry_is_parsed_again_and_replaced(cyphy_cache: Path) -> None:
    parse_cache.parse(GOOD, "m.rsm")
    (entry,) = entries(cyphy_cache)
    entry.write_bytes(b"not a pickle")
    file = parse_cache.parse(GOOD, "m.rsm").file
    assert file == parse_text(GOOD, "m.rsm").file
    assert entry.read_bytes() != b"not a pickle"


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_an_entry_others_may_write_is_not_unpickled(cyphy_cache: Path,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    parse_cache.parse(GOOD, "m.rsm")
    (entry,) = entries(cyphy_cache)
    entry.chmod(0o666)
    loads: list[object] = []
    monkeypatch.setattr(disk_cache.pickle, "load", lambda f: loads.append(f))
    file = parse_cache.parse(GOOD, "m.rsm").file
    assert file == parse_text(GOOD, "m.rsm").file and loads == []


def test_an_unusable_cache_folder_is_ignored(tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("CYPHY_CACHE_DIR", str(blocker))  # a file, not a folder
    file = parse_cache.parse(GOOD, "m.rsm").file
    assert file == parse_text(GOOD, "m.rsm").file


def test_no_cache_writes_nothing(cyphy_cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    assert parse_cache.parse(GOOD, "m.rsm").file is not None
    assert not cyphy_cache.exists()


def test_stale_fingerprint_folders_are_removed(cyphy_cache: Path) -> None:
    old, recent = cyphy_cache / "parse-old", cyphy_cache / "parse-recent"
    for folder in (old, recent):
        folder.mkdir(parents=True)
        (folder / disk_cache.MARKER).write_text("Signature: 8a477f597d28d172789f06886806bc55")
        (folder / "0123.pickle").write_bytes(b"x")
    os.utime(old, (0, 0))
    parse_cache.parse(GOOD, "m.rsm")
    assert not old.exists() and recent.exists()
    assert (cyphy_cache / f"parse-{parse_cache.fingerprint()}" / disk_cache.MARKER).is_file()


def test_cleanup_leaves_what_cyphy_did_not_make(cyphy_cache: Path) -> None:
    """A stale folder without cyphy's marker is someone's data (issue 20: it was deleted);
    in a marked one, only cyphy's entries go."""
    theirs, mixed = cyphy_cache / "parse-results", cyphy_cache / "parse-mixed"
    theirs.mkdir(parents=True)
    (theirs / "data.csv").write_text("1,2\n")
    mixed.mkdir()
    (mixed / disk_cache.MARKER).write_text("Signature: 8a477f597d28d172789f06886806bc55")
    (mixed / "0123.pickle").write_bytes(b"x")
    (mixed / "notes.txt").write_text("mine")
    for folder in (theirs, mixed):
        os.utime(folder, (0, 0))
    parse_cache.parse(GOOD, "m.rsm")
    assert (theirs / "data.csv").read_text() == "1,2\n"
    assert (mixed / "notes.txt").is_file() and not (mixed / "0123.pickle").exists()


def test_a_pickle_of_another_type_is_a_miss(cyphy_cache: Path) -> None:
    """A valid pickle that is not a parse result (issue 20: every run then exited 70)."""
    import hashlib
    import pickle

    parse_cache.parse(GOOD, "m.rsm")
    (entry,) = entries(cyphy_cache)
    entry.write_bytes(hashlib.sha256(GOOD.encode()).digest() + pickle.dumps({"a": 1}))
    entry.chmod(0o600)
    parsed = parse_cache.parse(GOOD, "m.rsm")
    assert isinstance(parsed, ParseResult) and parsed.file == parse_text(GOOD, "m.rsm").file
    assert main_check_exit(entry.parent.parent) == 0


def main_check_exit(cache_dir: Path) -> int:
    proc = subprocess.run([sys.executable, "-m", "cyphy", "check", str(EXAMPLES / "marxbot")],
                          capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, "CYPHY_CACHE_DIR": str(cache_dir),
                               "PYTHONPATH": str(ROOT)})
    return proc.returncode


def test_the_cache_is_kept_under_its_size_limit(cyphy_cache: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYPHY_CACHE_MAX_MB", "0.004")  # about 4 kB: two or three entries
    monkeypatch.setattr(disk_cache, "_sizes", {})
    for i in range(12):
        parse_cache.parse(GOOD, f"m{i}.rsm")
        os.utime(entries(cyphy_cache)[-1].parent / disk_cache.MARKER)
    total = sum(p.stat().st_size for p in entries(cyphy_cache))
    assert 0 < total <= 4.1 * 1024 and len(entries(cyphy_cache)) < 12


def test_a_cached_workspace_checks_like_a_parsed_one(cyphy_cache: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    mapping = EXAMPLES / "marxbot" / "Mapping.rsm"
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    plain = api.check([mapping], api.CheckOptions())
    monkeypatch.delenv("CYPHY_NO_CACHE")
    api.check([mapping], api.CheckOptions())  # fills the cache
    no_parsing(monkeypatch)
    cached = api.check([mapping], api.CheckOptions())
    assert cached.workspace.files == plain.workspace.files
    assert cached.report.diagnostics == plain.report.diagnostics


def test_a_warm_run_does_not_import_lark(cyphy_cache: Path) -> None:
    model = str(EXAMPLES / "marxbot" / "marXbotBase.rsm")
    script = ("import sys; from cyphy.cli import main; code = main(['check', %r]); "
              "print(code, 'lark' in sys.modules)" % model)
    env = {**os.environ, "CYPHY_CACHE_DIR": str(cyphy_cache)}
    runs = [subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env,
                           capture_output=True, text=True) for _ in range(2)]
    assert [r.stdout.splitlines()[-1] for r in runs] == ["0 True", "0 False"], runs


def test_unsaved_text_is_read_from_the_cache_but_not_stored(
        cyphy_cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """An editor's buffer (``store=False``) writes nothing; a saved file's entry still
    serves it."""
    assert parse_cache.parse(GOOD, "m.rsm", store=False) == parse_text(GOOD, "m.rsm")
    assert entries(cyphy_cache) == []
    parse_cache.parse(GOOD, "m.rsm")
    no_parsing(monkeypatch)
    assert parse_cache.parse(GOOD, "m.rsm", store=False) == parse_text(GOOD, "m.rsm")


def test_a_server_keeps_each_paths_last_parse(cyphy_cache: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(parse_cache, "_KEEP_RECENT", True)
    monkeypatch.setattr(parse_cache, "_RECENT", {})
    first = parse_cache.parse(GOOD, "m.rsm", store=False)
    no_parsing(monkeypatch)
    assert parse_cache.parse(GOOD, "m.rsm", store=False) is first  # shared, not re-read
