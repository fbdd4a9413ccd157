"""The storage that cyphy's persistent caches share (the parse cache,
:mod:`cyphy.lang.parse_cache`, and the equations of motion,
:mod:`cyphy.semantics.dynamics.motion_cache`): where entries live, which ones may be read,
how they are written, and how the folders are kept small.

* The root is ``$CYPHY_CACHE_DIR``, else ``$XDG_CACHE_HOME/cyphy``, else ``~/.cache/cyphy``;
  ``CYPHY_NO_CACHE=1`` turns every cache off (:func:`cache_root` is then None).
* Each cache keeps its entries in a folder ``<kind>-<fingerprint>`` (:func:`folder`), the
  fingerprint a hash of the sources that decide what an entry holds (:func:`fingerprint`):
  a changed cyphy never meets an old entry. The folder holds the marker ``CACHEDIR.TAG``
  (the Cache Directory Tagging format, which backup tools also honour); folders of the same
  kind and other fingerprints untouched for a week are removed when a new folder is made,
  but only folders that cyphy made (they hold the marker) and in them only cyphy's own
  entries: ``CYPHY_CACHE_DIR`` may point at a folder that holds other data.
* An entry is a header (a digest its reader compares before anything is unpickled) and a
  pickle. A pickle can run code, so an entry is read only when this user owns it and nobody
  else may write it (:func:`load`); it is written atomically (a concurrent reader sees the old
  entry or the new one).
* The entries of one folder are kept under ``$CYPHY_CACHE_MAX_MB`` (default 512 MB): when a
  write passes it, the least recently written entries are removed.
* A cache is only ever an optimisation: an unreadable, corrupt or unwritable entry or folder
  is ignored, silently, and the caller computes the value instead.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import tempfile
import time
from pathlib import Path
from typing import Any, Callable, Iterable

_STALE_AFTER_S = 7 * 24 * 3600
#: The file that marks a folder as cyphy's; only folders holding it are ever cleaned.
MARKER = "CACHEDIR.TAG"
_MARKER_TEXT = ("Signature: 8a477f597d28d172789f06886806bc55\n"
                "# This folder is a cache of cyphy (see cyphy/disk_cache.py).\n")
#: The files of cyphy's caches: pickles, Jinja2's compiled templates, temporary files.
_ENTRY_SUFFIXES = (".pickle", ".jinja", ".tmp")
_DEFAULT_MAX_MB = 512
_sizes: dict[Path, int] = {}  # bytes in each folder written to by this process
#: What :func:`load` returns when there is no usable entry (None may be a cached value).
MISS: Any = object()


def cache_root() -> Path | None:
    """The cache folder, or None when caching is turned off."""
    if os.environ.get("CYPHY_NO_CACHE"):
        return None
    configured = os.environ.get("CYPHY_CACHE_DIR")
    if configured:
        return Path(configured)
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "cyphy"


def fingerprint(package: Path, patterns: Iterable[str], extra: bytes = b"") -> str | None:
    """A hash of the files of ``package`` that ``patterns`` name (a folder's modules in name
    order), of ``extra`` (versions of the libraries that decide an entry) and of the pickle
    protocol that entries are written with; None when a pattern names no file or one cannot
    be read (an installation without its sources: a changed cyphy would not be seen, so
    nothing is cached)."""
    h = hashlib.sha256(str(pickle.HIGHEST_PROTOCOL).encode() + b"\0" + extra)
    try:
        for pattern in patterns:
            sources = sorted(package.glob(pattern))
            if not sources:
                return None
            for source in sources:
                h.update(source.read_bytes())
    except OSError:
        return None
    return h.hexdigest()[:20]


def folder(root: Path, kind: str, fingerprint: str) -> Path:
    """The folder of one cache's entries for one fingerprint."""
    return root / f"{kind}-{fingerprint}"


def entry_path(folder: Path, name: str) -> Path:
    """The entry of ``name`` (a path, a key) in ``folder``: a fixed-length file name."""
    return folder / (hashlib.sha256(name.encode()).hexdigest()[:32] + ".pickle")


def load(entry: Path, header: bytes, accept: Callable[[Any], bool]) -> Any:
    """The value stored in ``entry`` when its header is ``header`` and ``accept`` takes what it
    unpickles; else :data:`MISS`. The header is read first: an entry of other contents costs
    no unpickling."""
    try:
        with entry.open("rb") as f:
            if trusted(f) and f.read(len(header)) == header:
                loaded = pickle.load(f)
                if accept(loaded):
                    return loaded
    except Exception:  # missing, corrupt or from an incompatible run: computed instead
        pass
    return MISS


def trusted(file: Any) -> bool:
    """Whether the open ``file`` may be loaded: only entries that this user wrote and nobody
    else can change are unpickled or run (a pickle, a compiled template, is code), so a cache
    folder shared with others is ignored, not a risk."""
    getuid = getattr(os, "getuid", None)
    if getuid is None:  # Windows: the user's own profile folder
        return True
    stat = os.fstat(file.fileno())
    return stat.st_uid == getuid() and not stat.st_mode & 0o022


def store(folder: Path, entry: Path, header: bytes, value: Any) -> None:
    """Write one entry atomically; a failure (an unwritable folder, a value too deep to
    pickle) leaves the cache as it was."""
    try:
        make_folder(folder)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(header)  # read first: an entry of other contents costs no unpickling
                pickle.dump(value, f, protocol=pickle.HIGHEST_PROTOCOL)
                written = f.tell()
            os.replace(tmp, entry)
        except BaseException:
            os.unlink(tmp)
            raise
        _cap(folder, written)
    except (OSError, pickle.PicklingError, RecursionError):
        pass  # computed again next time


def make_folder(folder: Path) -> None:
    """Create ``folder`` (and its parents) with cyphy's marker, when it has none yet; the same
    cache's folders of other fingerprints that nobody used for a week are then removed.
    ``OSError`` when it cannot be made."""
    if not (folder / MARKER).is_file():
        folder.mkdir(parents=True, exist_ok=True)
        (folder / MARKER).write_text(_MARKER_TEXT, encoding="utf-8")
        _remove_stale(folder)


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
    """Remove the entries of the same cache's other fingerprints' folders that nobody has
    written to for a week, and those folders when that empties them. A folder without
    cyphy's marker is not cyphy's and is left alone, whatever its name."""
    limit = time.time() - _STALE_AFTER_S
    kind = current.name.rsplit("-", 1)[0]
    for other in current.parent.glob(f"{kind}-*"):
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
