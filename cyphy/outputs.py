"""Writing generated files: all of them or none, byte-identical from run to run.

A generator returns its files as an ordered mapping of relative paths to text. They are
written into a fresh temporary folder beside the destination first and moved into place
only when every one of them has been written, so a failure (a full disk, a bad path) never
leaves a half-written output behind.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Mapping

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
        staging = Path(tempfile.mkdtemp(prefix=".cyphy-", dir=out_dir))
    except OSError as err:
        raise OutputError(f"cannot create {out_dir}: {err.strerror or err}") from None
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
