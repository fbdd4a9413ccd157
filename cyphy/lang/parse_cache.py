"""A persistent cache of parsed files: a command does not parse again what it parsed before.

Parsing dominates a short command: building Lark's lexers and parsing the seven files of the
built-in library take about 300 ms, unpickling their syntax trees about 12 ms (and Lark is then
not even imported). So every successful parse is stored, as mypy and pytest keep theirs:

* one entry per file path (spans name the path), starting with the SHA-256 of the text it was
  parsed from; an entry whose hash differs from the current text is a miss (found before
  anything is unpickled) and is overwritten, so the cache holds at most one tree per file;
* entries live in a folder named for a fingerprint of the sources that decide the tree and
  its storage (the grammar, the parser, the syntax-tree and expression classes, diagnostics,
  codes, how they are pickled, and this module), so a changed cyphy never meets an old
  tree; folders of other fingerprints untouched for a week are removed when a new entry is
  written, but only folders that cyphy made (they hold the marker file ``CACHEDIR.TAG``) and
  in them only cyphy's own entries: ``CYPHY_CACHE_DIR`` may point at a folder that holds
  other data;
* the entries of one folder are kept under ``$CYPHY_CACHE_MAX_MB`` (default 512 MB): when a
  write passes it, the least recently written entries are removed;
* files with syntax errors are not stored (their diagnostics are cheap to recompute);
* a long-running process (the language server) also keeps the last result of each path in
  memory (:func:`keep_recent`);
* the cache is only ever an optimisation: an unreadable, corrupt or unwritable cache is
  ignored, silently, and the file is parsed; so is an entry that does not hold a parse
  result.

Location: ``$CYPHY_CACHE_DIR``, else ``$XDG_CACHE_HOME/cyphy``, else ``~/.cache/cyphy``.
``CYPHY_NO_CACHE=1`` turns it off. Entries are pickles: one is read only when this user
owns it and nobody else may write it. The storage (folders, markers, atomic writes, the size
limit, stale folders) is :mod:`cyphy.disk_cache`'s, shared with the cache of equations of
motion.
"""

from __future__ import annotations

import hashlib
from functools import lru_cache
from pathlib import Path

from cyphy import disk_cache, pickling, progress
from cyphy.lang.ast import ParseResult

_PACKAGE = Path(__file__).resolve().parent.parent
_SOURCES = ("lang/robosim.lark", "lang/grammar.py", "lang/lexer.py", "lang/parser.py",
            "lang/reductions.py",
            "lang/syntax_errors.py", "lang/builder/*.py",
            "lang/ast/*.py", "expr.py", "diagnostics.py", "codes.py", "pickling.py", "records.py",
            "disk_cache.py", "lang/parse_cache.py")


@lru_cache(maxsize=1)
def fingerprint() -> str | None:
    """A hash of the sources that decide what a parse returns (and of the pickle protocol),
    None without them (then nothing is cached)."""
    return disk_cache.fingerprint(_PACKAGE, _SOURCES)


def parse(text: str, path: str, store: bool = True) -> ParseResult:
    """The syntax tree and diagnostics of ``text`` read from ``path``, from the cache when
    this exact text was parsed at this path before. Without ``store`` a new result is not
    written to disk: an editor's unsaved text changes at every keystroke, and the saved
    file is what a later command reads."""
    root = disk_cache.cache_root()
    sources = fingerprint() if root is not None else None
    if root is None or sources is None:
        return _parse(text, path)
    folder = disk_cache.folder(root, "parse", sources)
    if not _KEEP_RECENT:
        return _parse_cached(folder, text, path, store)
    recent = _RECENT.get(path)
    if recent is not None and recent[0] == text:
        return recent[1]
    parsed = _parse_cached(folder, text, path, store)
    if len(_RECENT) >= _RECENT_MAX:
        _RECENT.clear()
    _RECENT[path] = (text, parsed)
    return parsed


#: The last result of each path parsed in this process, with its text, once
#: :func:`keep_recent` is called: a long-running process (the language server) checks the
#: same unchanged files at every edit, and the tree is immutable, so it is shared rather than
#: unpickled again. A command, which parses each file once, does not keep them.
_RECENT: dict[str, tuple[str, ParseResult]] = {}
_RECENT_MAX = 1024
_KEEP_RECENT = False


def keep_recent() -> None:
    """From now on, keep the last parse of each path in memory too (see :data:`_RECENT`)."""
    global _KEEP_RECENT
    _KEEP_RECENT = True


def _parse_cached(folder: Path, text: str, path: str, store: bool) -> ParseResult:
    entry = disk_cache.entry_path(folder, path)
    digest = hashlib.sha256(text.encode()).digest()  # the header: the text's hash
    loaded = disk_cache.load(entry, digest, lambda value: isinstance(value, ParseResult))
    if loaded is not disk_cache.MISS:
        return loaded  # type: ignore[no-any-return]
    parsed = _parse(text, path)
    if store and parsed.file is not None:
        progress.step("writing the parse cache")
        with pickling.reporting(lambda n: progress.step(f"writing the parse cache: {n} blocks")):
            disk_cache.store(folder, entry, digest, parsed)
    return parsed


def _parse(text: str, path: str) -> ParseResult:
    # lazy: the parser imports Lark (and builds the grammar): only a cache miss parses
    from cyphy.lang.parser import parse_text

    return parse_text(text, path)
