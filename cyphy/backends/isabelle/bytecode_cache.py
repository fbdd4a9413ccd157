"""Jinja2's compiled templates kept between runs: a theory's three templates are compiled
from their text once (0.1-0.2 s), then loaded as bytecode.

This is Jinja2's own :class:`~jinja2.FileSystemBytecodeCache` (which checks each entry
against the template's source and Jinja2's bytecode format before using it), in a folder
of cyphy's cache (:mod:`cyphy.disk_cache`: ``jinja-<fingerprint>``, the fingerprint naming
the Jinja2 version and the module that sets the environment's options, which change the
compiled code), with cyphy's policy added: an entry is loaded only when this user owns it
and nobody else may write it (it is code), and a cache that cannot be written is ignored.
Imported only when a template is rendered (it imports Jinja2).
"""

from __future__ import annotations

from pathlib import Path

import jinja2
from jinja2.bccache import Bucket, FileSystemBytecodeCache

from cyphy import disk_cache

_PACKAGE = Path(__file__).resolve().parent.parent.parent


class TrustedBytecodeCache(FileSystemBytecodeCache):
    """Jinja2's file-system cache that reads only trusted entries and never fails a render."""

    def load_bytecode(self, bucket: Bucket) -> None:
        try:
            with open(self._get_cache_filename(bucket), "rb") as f:
                if disk_cache.trusted(f):
                    bucket.load_bytecode(f)  # checks Jinja2's magic and the source checksum
        except OSError:
            pass  # none yet, or unreadable: compiled from the template

    def dump_bytecode(self, bucket: Bucket) -> None:
        try:
            super().dump_bytecode(bucket)
        except OSError:
            pass  # compiled again next time


def bytecode_cache(configured_in: str) -> TrustedBytecodeCache | None:
    """The cache for an environment whose options are set in the module ``configured_in``
    (a path under the package), or None when caching is off or its folder cannot be made."""
    root = disk_cache.cache_root()
    fingerprint = None if root is None else disk_cache.fingerprint(
        _PACKAGE, (configured_in, "backends/isabelle/bytecode_cache.py"),
        jinja2.__version__.encode())
    if root is None or fingerprint is None:
        return None
    folder = disk_cache.folder(root, "jinja", fingerprint)
    try:
        disk_cache.make_folder(folder)
    except OSError:
        return None
    return TrustedBytecodeCache(str(folder), "%s.jinja")
