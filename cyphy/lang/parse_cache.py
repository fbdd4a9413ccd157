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
owns it and nobody else may write it.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import tempfile
import time
from functools import lru_cache
from pathlib import Path

from cyphy import progress
from cyphy.lang.ast import ParseResult

_PACKAGE = Path(__file__).resolve().parent.parent
_SOURCES = ("lang/robosim.lark", "lang/grammar.py", "lang/parser.py", "lang/reductions.py",
            "lang/syntax_errors.py", "lang/builder/*.py",
            "lang/ast/*.py", "expr.py", "diagnostics.py", "codes.py", "pickling.py", "records.py",
            "lang/parse_cache.py")
_STALE_AFTER_S = 7 * 24 * 3600
#: The file that marks a folder as cyphy's (the Cache Directory Tagging format, which backup
#: tools also honour); only folders holding it are ever cleaned.
MARKER = "CACHEDIR.TAG"
_MARKER_TEXT = ("Signature: 8a477f597d28d172789f06886806bc55\n"
                "# This folder is a cache of cyphy's parser (see cyphy/lang/parse_cache.py).\n")
_ENTRY_SUFFIXES = (".pickle", ".tmp")
_DEFAULT_MAX_MB = 512
_sizes: dict[Path, int] = {}  # bytes in each folder written to by this process


@lru_cache(maxsize=1)
def fingerprint() -> str:
    """A hash of the sources that decide what a parse returns (and of the pickle protocol)."""
    h = hashlib.sha256(str(pickle.HIGHEST_PROTOCOL).encode())
    for pattern in _SOURCES:  # a folder's modules in name order
        for source in sorted(_PACKAGE.glob(pattern)):
            h.update(source.read_bytes())
    return h.hexdigest()[:20]


def cache_root() -> Path | None:
    """The cache folder, or None when caching is turned off."""
    if os.environ.get("CYPHY_NO_CACHE"):
        return None
    configured = os.environ.get("CYPHY_CACHE_DIR")
    if configured:
        return Path(configured)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "cyphy"


def parse(text: str, path: str, store: bool = True) -> ParseResult:
    """The syntax tree and diagnostics of ``text`` read from ``path``, from the cache when
    this exact text was parsed at this path before. Without ``store`` a new result is not
    written to disk: an editor's unsaved text changes at every keystroke, and the saved
    file is what a later command reads."""
    root = cache_root()
    if root is None:
        return _parse(text, path)
    if not _KEEP_RECENT:
        return _parse_cached(root, text, path, store)
    recent = _RECENT.get(path)
    if recent is not None and recent[0] == text:
        return recent[1]
    parsed = _parse_cached(root, text, path, store)
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


def _parse_cached(root: Path, text: str, path: str, store: bool) -> ParseResult:
    folder = root / f"parse-{fingerprint()}"
    entry = folder / (hashlib.sha256(path.encode()).hexdigest()[:32] + ".pickle")
    digest = hashlib.sha256(text.encode()).digest()
    try:
        with entry.open("rb") as f:  # the text's hash, then the pickled result
            if _trusted(os.fstat(f.fileno())) and f.read(len(digest)) == digest:
                loaded = pickle.load(f)
                if isinstance(loaded, ParseResult):
                    return loaded
    except Exception:  # missing, corrupt or from an incompatible run: parse instead
        pass
    parsed = _parse(text, path)
    if store and parsed.file is not None:
        progress.step("writing the parse cache")
        _store(folder, entry, digest, parsed)
    return parsed


def _trusted(stat: os.stat_result) -> bool:
    """Only entries that this user wrote and nobody else can change are unpickled (a pickle
    can run code): a cache folder shared with others is then ignored, not a risk."""
    getuid = getattr(os, "getuid", None)
    if getuid is None:  # Windows: the user's own profile folder
        return True
    return stat.st_uid == getuid() and not stat.st_mode & 0o022


def _parse(text: str, path: str) -> ParseResult:
    # lazy: the parser imports Lark (and builds the grammar): only a cache miss parses
    from cyphy.lang.parser import parse_text

    return parse_text(text, path)


def _store(folder: Path, entry: Path, digest: bytes, parsed: ParseResult) -> None:
    """Write one entry atomically (a concurrent reader sees the old entry or the new one)."""
    try:
        if not (folder / MARKER).is_file():
            folder.mkdir(parents=True, exist_ok=True)
            (folder / MARKER).write_text(_MARKER_TEXT, encoding="utf-8")
            _remove_stale(folder)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(digest)  # read first: a changed file costs no unpickling
                pickle.dump(parsed, f, protocol=pickle.HIGHEST_PROTOCOL)
                written = f.tell()
            os.replace(tmp, entry)
        except BaseException:
            os.unlink(tmp)
            raise
        _cap(folder, written)
    except (OSError, pickle.PicklingError, RecursionError):
        pass  # a tree too deep to pickle is parsed again next time


def _entries(folder: Path) -> list[os.DirEntry[str]]:
    with os.scandir(folder) as it:
        return [e for e in it if e.is_file(follow_symlinks=False)
                and e.name.endswith(_ENTRY_SUFFIXES)]


def _cap(folder: Path, written: int) -> None:
    """Keep the folder's entries under the size limit, removing the oldest first (down to
    three quarters of it, so that the next writes do not each scan the folder)."""
    limit = int(float(os.environ.get("CYPHY_CACHE_MAX_MB") or _DEFAULT_MAX_MB) * 1024 * 1024)
    if folder not in _sizes:
        _sizes[folder] = sum(e.stat().st_size for e in _entries(folder))
    else:
        _sizes[folder] += written
    if _sizes[folder] <= limit:
        return
    entries = sorted(_entries(folder), key=lambda e: e.stat().st_mtime)
    total = sum(e.stat().st_size for e in entries)
    for e in entries:
        if total <= limit * 3 // 4:
            break
        try:
            size = e.stat().st_size
            os.unlink(e.path)
            total -= size
        except OSError:
            continue
    _sizes[folder] = sum(e.stat().st_size for e in _entries(folder))


def _remove_stale(current: Path) -> None:
    """Remove the entries of other fingerprints' folders that nobody has written to for a
    week, and those folders when that empties them. A folder without cyphy's marker is not
    cyphy's and is left alone, whatever its name."""
    limit = time.time() - _STALE_AFTER_S
    for other in current.parent.glob("parse-*"):
        try:
            if other == current or not (other / MARKER).is_file() \
                    or other.stat().st_mtime >= limit:
                continue
            for e in _entries(other):
                os.unlink(e.path)
            (other / MARKER).unlink()
            other.rmdir()  # fails, harmlessly, when something else is in it
        except OSError:
            pass
