"""Files in, checked: parsed, names resolved, the well-formedness conditions (and, asked for,
the mappings' consistency with Z3) reported. The first stage of every command."""

from __future__ import annotations

from dataclasses import field
from pathlib import Path
from typing import Mapping, Sequence

from cyphy import collector, progress
from cyphy.deep import deep
from cyphy.diagnostics import Report
from cyphy.lang.placement import check_placement
from cyphy.lang.resolve import Resolution, check_scopes
from cyphy.lang.targets import folder_files
from cyphy.lang.workspace import Workspace, load_workspace
from cyphy.records import record
from cyphy.wellformed import RULES, WFContext, check_wellformed


@record(slots=False)
class CheckOptions:
    syntax_only: bool = False
    search_paths: tuple[str, ...] = ()
    wellformedness: bool = True
    consts: dict[str, object] = field(default_factory=dict)
    neighbours_as_targets: bool = False  # check the files the given ones use, too
    value_checks: bool = True  # V1-V5 (geometry, inertia, meshes): what simulators need
    consistency: bool = False  # also C1-C5 on the platform mappings (imports Z3)
    z3_timeout_ms: int | None = None  # per Z3 query; None: the checks' default
    find_in_folder: str = ""  # "pmodel", "mapping": the folder's when the files have none
    overrides: Mapping[str, str] = field(default_factory=dict)  # path → unsaved text (editors)


@record(frozen=False, slots=False)
class CheckResult:
    workspace: Workspace
    report: Report
    resolution: Resolution | None = None
    sources: dict[str, str] = field(default_factory=dict)


@deep
def check(paths: Sequence[str | Path], options: CheckOptions = CheckOptions()) -> CheckResult:
    """Parse the files (or folders) and, unless ``syntax_only``, resolve names and check the
    scope conditions. Diagnostics of library files are never reported."""
    with collector.paused():  # the syntax tree and the resolution tables all stay alive
        result = _front_end(paths, options)
    if options.consistency and result.resolution is not None:
        _check_consistency(result.workspace, result.resolution, result.report, options)
    return result


def _front_end(paths: Sequence[str | Path], options: CheckOptions) -> CheckResult:
    ws, report = load_workspace(paths, options.search_paths, overrides=options.overrides)
    result = CheckResult(ws, report, sources=ws.texts)
    if options.syntax_only:
        return result
    found = folder_files(ws, options.find_in_folder) if options.find_in_folder else []
    ws.targets = ws.targets + found  # cyphy/lang/targets.py
    if options.neighbours_as_targets or found:
        ws.targets = _with_dependencies(ws)
    check_placement(ws.user_files(), report)
    progress.stage("resolving names")
    result.resolution = check_scopes(ws, report)
    if options.wellformedness:
        only = None if options.value_checks else {i for i in RULES if not i.startswith("V")}
        check_wellformed(WFContext(ws, result.resolution, report, dict(options.consts),
                                   z3=options.consistency), only)
    return result


def _check_consistency(ws: Workspace, resolution: Resolution, report: Report,
                       options: CheckOptions) -> None:
    # lazy: Z3 and the encoding: only `--consistency` pays for them
    from cyphy.semantics.consistency import DEFAULT_TIMEOUT_MS, check_consistency

    check_consistency(ws, resolution, report, options.consts,
                      options.z3_timeout_ms or DEFAULT_TIMEOUT_MS)


def _with_dependencies(ws: Workspace) -> list[str]:
    """The given files and every (non-library) file they use, transitively: what a
    generator translates with them, so what must be resolved and checked with them. Files
    that merely sit in the same folder (another robot's p-model) are left out."""
    item_file = {id(item): f.path for f in ws.files.values() for item in f.items}
    library = {f.path for pkg in ws.packages.values() if pkg.builtin for f in pkg.files}
    targets = list(ws.targets)
    while True:
        ws.targets = targets
        resolution = check_scopes(ws, Report())
        used = {item_file[id(d)] for d in resolution.targets.values() if id(d) in item_file}
        new = sorted(used - set(targets) - library)
        if not new:
            return targets
        targets = targets + new
