"""The library entry points behind the CLI: values in, results with diagnostics out.

Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from cyphy.diagnostics import Report
from cyphy.lang.placement import check_placement
from cyphy.lang.resolve import Resolution, check_scopes
from cyphy.lang.workspace import Workspace, load_workspace


@dataclass(frozen=True)
class CheckOptions:
    syntax_only: bool = False
    search_paths: tuple[str, ...] = ()


@dataclass
class CheckResult:
    workspace: Workspace
    report: Report
    resolution: Resolution | None = None
    sources: dict[str, str] = field(default_factory=dict)


def check(paths: Sequence[str | Path], options: CheckOptions = CheckOptions()) -> CheckResult:
    """Parse the files (or folders) and, unless ``syntax_only``, resolve names and check the
    scope conditions. Diagnostics of library files are never reported."""
    ws, report = load_workspace(paths, options.search_paths)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    check_placement(ws.user_files(), report)
    result.resolution = check_scopes(ws, report)
    return result
