"""A workspace: the model files that resolve against each other, grouped into packages.

RoboTool resolves names across a project folder, so a workspace holds the files the user named,
every model file in the same folders, the ``--path`` folders and the built-in ``physmod``
library (``cyphy/lang/library``). A user package with the same name as a library package
replaces it whole.
"""

from __future__ import annotations

import os

from dataclasses import field
from functools import lru_cache
from pathlib import Path
from typing import Iterable, Iterator, Mapping

from cyphy import codes, progress
from cyphy.diagnostics import Report, Span
from cyphy.lang import ast
from cyphy.lang import parse_cache
from cyphy.records import record

MODEL_SUFFIXES = (".pm", ".rst", ".rsm")
LIBRARY_ROOT = Path(__file__).parent / "library"

Declaration = ast.TopLevel


@record(frozen=False, slots=False)
class Package:
    """All declarations of one package, over all files that declare it."""

    name: ast.QName
    members: dict[str, list[Declaration]] = field(default_factory=dict)
    files: list[ast.SourceFile] = field(default_factory=list)
    builtin: bool = False

    def add(self, decl: Declaration, name: str) -> None:
        self.members.setdefault(name, []).append(decl)


@record(frozen=False, slots=False)
class Workspace:
    files: dict[str, ast.SourceFile] = field(default_factory=dict)
    texts: dict[str, str] = field(default_factory=dict)
    packages: dict[ast.QName, Package] = field(default_factory=dict)
    targets: list[str] = field(default_factory=list)
    """Paths of the files the user asked about (their diagnostics are reported)."""
    file_package: dict[str, ast.QName] = field(default_factory=dict)
    named: list[str] = field(default_factory=list)
    """Paths of the files (or the files of the folders) given on the command line."""

    def package_of(self, file: ast.SourceFile) -> Package:
        return self.packages[self.file_package[file.path]]

    def user_files(self) -> Iterator[ast.SourceFile]:
        for path in self.targets:
            f = self.files.get(path)
            if f is not None:
                yield f

    def all_declarations(self) -> Iterator[tuple[Package, str, Declaration]]:
        for package in self.packages.values():
            for name, decls in package.members.items():
                for d in decls:
                    yield package, name, d


def declared_name(decl: Declaration) -> str | None:
    """The name a top-level item declares in its package (None for unnamed items)."""
    if isinstance(decl, (ast.PackageDecl, ast.EndPackage, ast.Import, ast.Solution)):
        return None
    return getattr(decl, "name", None)


def model_files_in(folder: Path, recursive: bool,
                   unreadable: list[tuple[Path, str]] | None = None) -> list[Path]:
    """The model files in ``folder`` (and below it when ``recursive``). A folder that cannot
    be listed is added to ``unreadable`` with the reason (``Path.glob`` skips it silently,
    and its models would be missing without a word)."""
    found: list[Path] = []

    def refused(err: OSError) -> None:
        if unreadable is not None:
            unreadable.append((Path(err.filename or folder), err.strerror or str(err)))

    for root, dirs, files in os.walk(folder, onerror=refused):
        dirs.sort()
        found.extend(Path(root, f) for f in files if Path(f).suffix in MODEL_SUFFIXES)
        if not recursive:
            break
    return sorted(p for p in found if p.is_file())


def library_files() -> list[Path]:
    return model_files_in(LIBRARY_ROOT, recursive=True)


def _read(path: Path, report: Report) -> str | None:
    try:
        data = path.read_bytes()
    except OSError as err:
        report.report(codes.IO, f"cannot read {path}: {err.strerror}", Span.unknown(str(path)),
                      "check the path and its permissions")
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data[: err.start].count(b"\n") + 1
        col = err.start - (data.rfind(b"\n", 0, err.start) + 1) + 1
        report.report(codes.ENCODING, f"byte {data[err.start]:#04x} is not valid UTF-8",
                      Span(str(path), line, col, line, col + 1), "save the file as UTF-8")
        return None


def load_workspace(
    paths: Iterable[str | Path], search_paths: Iterable[str | Path] = (),
    report: Report | None = None, overrides: Mapping[str, str] | None = None,
) -> tuple[Workspace, Report]:
    """Read and parse the given files or folders (and their neighbours) into a workspace.
    ``overrides`` maps a path (as the file is named) to the text to use instead of what is on
    disk: an editor's unsaved buffers, which may even name files not yet saved."""
    report = report if report is not None else Report()
    overrides = overrides or {}
    ws = Workspace()
    targets: list[Path] = []
    neighbours: list[Path] = []
    unreadable: list[tuple[Path, str]] = []
    for raw in paths:
        p = Path(raw)
        if p.is_dir():
            found = model_files_in(p, recursive=True, unreadable=unreadable)
            if not found:
                report.report(codes.NO_FILES, f"no model files (.pm, .rst, .rsm) in {p}",
                              Span.unknown(str(p)), "name a model file or a folder holding some")
            targets.extend(found)
        elif p.is_file() or str(p) in overrides:
            targets.append(p)
            neighbours.extend(model_files_in(p.parent, recursive=False))
        else:
            report.report(codes.IO, f"no such file or folder: {p}", Span.unknown(str(p)),
                          "check the path")
    for raw in search_paths:
        p = Path(raw)
        if p.is_dir():
            neighbours.extend(model_files_in(p, recursive=True, unreadable=unreadable))
        else:
            report.report(codes.IO, f"--path {p} is not a folder", Span.unknown(str(p)),
                          "give a folder of model files")

    for folder, why in unreadable:
        report.report(codes.IO, f"cannot read the folder {folder}: {why}",
                      Span.unknown(str(folder)), "give yourself read and search permission on "
                      "it, or leave it out: its model files are not read")
    seen: set[Path] = set()
    every = targets + neighbours
    for i, p in enumerate(every):
        key = p.resolve()
        if key in seen:
            continue
        seen.add(key)
        progress.stage(f"reading {p.name} ({i + 1}/{len(every)})")
        text = overrides.get(str(p))
        unsaved = text is not None
        if text is None:
            text = _read(p, report)
        if text is None:
            continue
        parsed = parse_cache.parse(text, str(p), store=not unsaved)
        report.extend(parsed.diagnostics)
        ws.texts[str(p)] = text
        if parsed.file is not None:
            ws.files[str(p)] = parsed.file
    ws.named = [str(p) for p in dict.fromkeys(targets)]
    ws.targets = [str(p) for p in dict.fromkeys(targets)]

    user_packages = {f.package for f in ws.files.values()}
    for path, text, file in _library():
        if file.package in user_packages:
            continue  # the user's own package of that name shadows the library's
        ws.texts[path] = text
        ws.files[path] = file
        _index(ws, file, builtin=True)
    for f in list(ws.files.values()):
        if f.path not in ws.file_package:
            _index(ws, f, builtin=False)
    return ws, report


@lru_cache(maxsize=1)
def _library() -> tuple[tuple[str, str, ast.SourceFile], ...]:
    """The parsed library files, once per process (the syntax tree is immutable)."""
    out = []
    for p in library_files():
        text = p.read_text(encoding="utf-8")
        file = parse_cache.parse(text, str(p)).file
        if file is not None:  # the shipped library always parses (a test checks)
            out.append((str(p), text, file))
    return tuple(out)


def _index(ws: Workspace, file: ast.SourceFile, builtin: bool) -> None:
    name = file.package
    package = ws.packages.get(name)
    if package is None:
        package = ws.packages[name] = Package(name, builtin=builtin)
    package.files.append(file)
    ws.file_package[file.path] = name
    for decl in file.declarations():
        n = declared_name(decl)
        if n is not None:
            package.add(decl, n)
    # Parent packages exist implicitly (``physmod`` for ``physmod::joints``).
    for i in range(1, len(name)):
        ws.packages.setdefault(name[:i], Package(name[:i], builtin=builtin))
