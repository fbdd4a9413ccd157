"""Writing generated files: all of them or none, byte-identical from run to run.

A generator returns its files as an ordered mapping of relative paths to text. They are
written into a fresh temporary folder beside the destination first and moved into place
only when every one of them has been written, so a failure (a full disk, a bad path) never
leaves a half-written output behind. A run killed while staging (SIGTERM, SIGKILL) cannot
clean up after itself: its staging folder, named for its process id, is removed by the next
run that writes into the same folder once that process is gone.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Mapping
from cyphy import progress

#: The default output folder of each generator, beside the model, in RoboTool's names.
DEFAULT_FOLDERS = {
    "sdf": "sdf-gen",
    "cyphycircus": "cpc-gen",
    "latex": "cpc-gen",
    "isabelle": "isabelle-gen",
    "isabelle-axiomatic": "isabelle-ax-gen",
    "flowstar": "flowstar-gen",
    "urdf": "urdf-gen",
    "mjcf": "mjcf-gen",
}


#: Staging folders are ``.cyphy-staging-<pid>-<random>``: the pid tells whether their writer
#: still runs.
STAGING_PREFIX = ".cyphy-staging-"
_STAGING = re.compile(re.escape(STAGING_PREFIX) + r"(\d+)-[A-Za-z0-9_]+$")


def remove_abandoned_staging(out_dir: Path) -> None:
    """Remove the staging folders in ``out_dir`` left by runs that were killed (their
    process no longer exists); folders of runs still going, and anything else, are kept."""
    try:
        entries = list(os.scandir(out_dir))
    except OSError:
        return
    for entry in entries:
        found = _STAGING.match(entry.name)
        if found and entry.is_dir(follow_symlinks=False) and not _running(int(found[1])):
            shutil.rmtree(entry.path, ignore_errors=True)


def _running(pid: int) -> bool:
    if pid == os.getpid() or os.name == "nt":  # Windows: os.kill would end the process
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError, OverflowError):
        return True  # another user's process, or cannot tell: leave it alone
    return True


class OutputError(Exception):
    """The output folder cannot be written; the message says why."""


def default_output_dir(paths: list[str], target: str) -> Path:
    """The generator's folder beside the first model path (a file's folder, or the folder)."""
    first = Path(paths[0])
    base = first if first.is_dir() else first.parent
    return base / DEFAULT_FOLDERS[target]


def write_all(files: Mapping[str, str | bytes], out_dir: Path) -> list[Path]:
    """Write every file under ``out_dir`` (created if needed) or, on failure, none of them.

    Text is written as UTF-8 with ``\\n`` line ends whatever the platform, so two runs give
    the same bytes. Returns the written paths in the order given.
    """
    for rel in files:
        if Path(rel).is_absolute() or ".." in Path(rel).parts:
            raise OutputError(f"refusing to write {rel!r} outside {out_dir}")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        remove_abandoned_staging(out_dir)
        staging = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-", dir=out_dir))
    except OSError as err:
        raise OutputError(f"cannot create {out_dir}: {err.strerror or err}") from None

    progress.stage(f"writing {len(files)} file{'s' if len(files) != 1 else ''} into {out_dir}")
    try:
        for rel, content in files.items():
            target = staging / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            data = content.encode("utf-8") if isinstance(content, str) else content
            target.write_bytes(data)
        written = []
        for rel in files:
            final = out_dir / rel
            final.parent.mkdir(parents=True, exist_ok=True)
            os.replace(staging / rel, final)
            written.append(final)
        return written
    except OSError as err:
        raise OutputError(f"cannot write into {out_dir}: {err.strerror or err}") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def check_target(path: Path, folder: bool) -> None:
    """Refuse, before any work starts, an output that could not be written at the end: a
    folder where a file is wanted (or the reverse), a read-only file, or a place where
    nothing can be created. A missing parent folder is not an error: it is created when the
    output is written, as ``write_all`` creates its folder. Whether a folder can be written
    is found by creating (and removing) a scratch entry in it: permission bits do not say,
    for root or on a read-only file system."""
    if path.exists():
        if folder and not path.is_dir():
            raise OutputError(f"{path} is a file, not a folder")
        if not folder and path.is_dir():
            raise OutputError(f"{path} is a folder: give a file name")
        if not folder and path.is_file() and not os.access(path, os.W_OK):
            raise OutputError(f"{path} is read-only")
        if not folder and not path.is_file():
            return  # a device or pipe (/dev/null, /dev/stdout): written in place
    holder = path if folder and path.is_dir() else path.parent
    existing = holder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"cannot create {holder}: {existing} is a file, not a folder")
    try:
        if existing == holder:
            fd, probe = tempfile.mkstemp(prefix=STAGING_PREFIX + "probe-", dir=existing)
            os.close(fd)
            os.unlink(probe)
        else:
            os.rmdir(tempfile.mkdtemp(prefix=STAGING_PREFIX + "probe-", dir=existing))
    except OSError as err:
        raise OutputError(f"cannot write into {existing}: {err.strerror or err}") from None


def write_file(path: Path, content: str | bytes) -> Path:
    """Write one file atomically: into a temporary file beside it, then renamed over it, so a
    reader (or a failure half-way) never sees part of it. Its folder is created if needed; a
    device or pipe (``/dev/stdout``) is written in place."""
    data = content.encode("utf-8") if isinstance(content, str) else content
    try:
        if path.exists() and not path.is_file() and not path.is_dir():
            with open(path, "wb") as stream:
                stream.write(data)
            return path
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, staged = tempfile.mkstemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-",
                                      dir=path.parent)
        try:
            with os.fdopen(fd, "wb") as stream:
                stream.write(data)
            os.replace(staged, path)
        except BaseException:
            os.unlink(staged)
            raise
    except OSError as err:
        raise OutputError(f"cannot write {path}: {err.strerror or err}") from None
    return path
