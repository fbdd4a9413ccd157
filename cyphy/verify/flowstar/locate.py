"""Where the Flow* executable is: the one search that ``cyphy reach``, the tests and the
benchmarks share, so that the Flow* ``.ci/install`` builds (outside the project, in the tools
folder) is found without ``--flowstar-bin`` and without touching ``PATH``.

The places, in order: ``--flowstar-bin`` when given (and then only it), ``$CYPHY_FLOWSTAR``,
``flowstar`` in the tools folder (``$CYPHY_TOOLS_DIR``, else ``$XDG_CACHE_HOME/cyphy-tools``,
else ``~/.cache/cyphy-tools``: the folder ``.ci/install`` builds into), then ``flowstar`` on
``PATH``. When none holds an executable the error lists every place looked at.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from cyphy.verify.flowstar.verdict import FlowstarMissing


def tools_dir() -> Path:
    """The folder ``.ci/install`` builds the external tools into (its ``flowstar_dir``)."""
    if os.environ.get("CYPHY_TOOLS_DIR"):
        return Path(os.environ["CYPHY_TOOLS_DIR"])
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "cyphy-tools"


def _executable(candidate: str) -> str | None:
    """``candidate`` as an absolute path when it is an executable file (a path) or names one
    on ``PATH`` (a bare name). Flow* runs in a scratch folder of its own, where a relative
    path would name nothing."""
    found = shutil.which(candidate)
    return str(Path(found).resolve()) if found else None


def find_flowstar(given: str | None = None) -> str:
    """The Flow* executable as an absolute path, or :class:`FlowstarMissing` saying where it
    was looked for and how to get one."""
    if given:
        places = [(f"--flowstar-bin {given}", given)]
    else:
        places = []
        if os.environ.get("CYPHY_FLOWSTAR"):
            places.append((f"$CYPHY_FLOWSTAR ({os.environ['CYPHY_FLOWSTAR']})",
                           os.environ["CYPHY_FLOWSTAR"]))
        built = tools_dir() / "flowstar"
        places.append((f"{built} (where .ci/install builds it)", str(built)))
        places.append(("flowstar on PATH", "flowstar"))
    for _, candidate in places:
        found = _executable(candidate)
        if found is not None:
            return found
    looked = "; ".join(label for label, _ in places)
    raise FlowstarMissing(
        f"Flow* not found (looked at: {looked}): run `bash .ci/install` (it builds Flow* "
        "2.1.0 from ../shared/tools/flowstar), or install Flow* 2.1.0 (https://flowstar.org) "
        "and give --flowstar-bin PATH, set CYPHY_FLOWSTAR, or put it on PATH as flowstar")
