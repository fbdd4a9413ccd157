"""Where a mesh file named by a model lies, judged from its text alone.

A model is shared and translated on other machines: a mesh named by an absolute path, by a
relative path that climbs out of the model's folder (``../../etc/passwd``) or by a URL
(``http://``, ``file://``) is not part of the model, and a generated file that refers to it
would also disclose a path of this machine. Such a mesh is reported (a warning), and nothing
is done that depends on whether it exists, so that no diagnostic reveals which files exist
outside the model's folder. Every printer that writes mesh references (SDF, URDF) asks here.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import PurePosixPath

#: URI schemes that simulators resolve against their own model paths: not files of this
#: machine, so neither inside nor outside the model's folder.
SIMULATOR_SCHEMES = ("model", "package")

_SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.-]*):")


def outside_model_folder(uri: str) -> str | None:
    """Why the mesh ``uri`` (as written in the model) lies outside the model's folder — "an
    absolute path", "a path that leaves the model's folder", "a URL" — or None when it is a
    path inside it, or a ``model://`` / ``package://`` URI that the simulator resolves. Pure
    text: the file system is never consulted."""
    scheme = _SCHEME.match(uri)
    if scheme and len(scheme.group(1)) > 1:  # "C:" is a Windows drive, not a scheme
        if scheme.group(1).lower() in SIMULATOR_SCHEMES and uri[len(scheme.group(0)):
                                                               ].startswith("//"):
            return None
        return "a URL"
    text = uri.replace("\\", "/")
    if text.startswith("/") or re.match(r"^[A-Za-z]:", text) or text.startswith("~"):
        return "an absolute path"
    normal = posixpath.normpath(text)
    if normal == ".." or normal.startswith("../") or PurePosixPath(normal).is_absolute():
        return "a path that leaves the model's folder"
    return None
