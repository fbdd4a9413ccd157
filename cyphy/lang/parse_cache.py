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
  written;
* files with syntax errors are not stored (their diagnostics are cheap to recompute);
* the cache is only ever an optimisation: an unreadable, corrupt or unwritable cache is
  ignored, silently, and the file is parsed.

Location: ``$CYPHY_CACHE_DIR``, else ``$XDG_CACHE_HOME/cyphy``, else ``~/.cache/cyphy``.
``CYPHY_NO_CACHE=1`` turns it off. Entries are pickles: one is read only when this user
owns it and nobody else may write it.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import shutil
import tempfile
import time
from functools import lru_cache
from pathlib import Path

from cyphy.lang.ast import ParseResult

_PACKAGE = Path(__file__).resolve().parent.parent
_SOURCES = ("lang/robosim.lark", "lang/parser.py", "lang/ast.py", "expr.py", "diagnostics.py",
            "codes.py", "pickling.py", "lang/parse_cache.py")
_STALE_AFTER_S = 7 * 24 * 3600


@lru_cache(maxsize=1)
def fingerprint() -> str:
    """A hash of the sources that decide what a parse returns (and of the pickle protocol)."""
    h = hashlib.sha256(str(pickle.HIGHEST_PROTOCOL).encode())
    for name in _SOURCES:
        h.update((_PACKAGE / name).read_bytes())
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


def parse(text: str, path: str) -> ParseResult:
    """The syntax tree and diagnostics of ``text`` read from ``path``, from the cache when
    this exact text was parsed at this path before."""
    root = cache_root()
    if root is None:
        return _parse(text, path)
    folder = root / f"parse-{fingerprint()}"
    entry = folder / (hashlib.sha256(path.encode()).hexdigest()[:32] + ".pickle")
    digest = hashlib.sha256(text.encode()).digest()
    try:
        with entry.open("rb") as f:  # the text's hash, then the pickled result
            if _trusted(os.fstat(f.fileno())) and f.read(len(digest)) == digest:
                return pickle.load(f)
    except Exception:  # missing, corrupt or from an incompatible run: parse instead
        pass
    parsed = _parse(text, path)
    if parsed.file is not None:
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
    from cyphy.lang.parser import parse_text  # Lark is imported only when something is parsed

    return parse_text(text, path)


def _store(folder: Path, entry: Path, digest: bytes, parsed: ParseResult) -> None:
    """Write one entry atomically (a concurrent reader sees the old entry or the new one)."""
    try:
        if not folder.is_dir():
            folder.mkdir(parents=True, exist_ok=True)
            _remove_stale(folder)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(digest)  # read first: a changed file costs no unpickling
                pickle.dump(parsed, f, protocol=pickle.HIGHEST_PROTOCOL)
            os.replace(tmp, entry)
        except BaseException:
            os.unlink(tmp)
            raise
    except (OSError, pickle.PicklingError):
        pass


def _remove_stale(current: Path) -> None:
    """Remove the folders of other fingerprints that nobody has written to for a week."""
    limit = time.time() - _STALE_AFTER_S
    for other in current.parent.glob("parse-*"):
        try:
            if other != current and other.stat().st_mtime < limit:
                shutil.rmtree(other, ignore_errors=True)
        except OSError:
            pass
