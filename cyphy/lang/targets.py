"""What a command is about when the files given do not declare it: the p-model (for the
commands that elaborate one) or the platform mapping (for the semantics' generators).

A user hands ``cyphy gen --sdf`` a platform mapping (``examples/marxbot/Mapping.rsm``), or
``cyphy gen --isabelle`` the p-model, as readily as the file the command is about: RoboTool
resolves names across the project folder, and so does cyphy (the folder's files are read as
neighbours). Without this the command would find nothing among the files the user named and
stop (``E-MODEL``, ``E-MAPPING``) although its folder holds the answer.
"""

from __future__ import annotations

from cyphy.lang import ast
from cyphy.lang.workspace import Workspace

PMODEL, MAPPING = "pmodel", "mapping"


def _pmodels(f: ast.SourceFile) -> list[ast.PModel]:
    return [i for i in f.items if isinstance(i, ast.PModel) and not i.fragment]


def _mappings(f: ast.SourceFile) -> list[ast.PlatformMapping]:
    return [i for i in f.items if isinstance(i, ast.PlatformMapping)]


def _modules(f: ast.SourceFile) -> list[ast.Module]:
    return [i for i in f.items if isinstance(i, ast.Module)]


def folder_files(ws: Workspace, what: str) -> list[str]:
    """The other user files (neighbours in the folders, ``--path``) that declare ``what``
    (:data:`PMODEL` or :data:`MAPPING`) for the files named, when none of those declares one:

    * a p-model: the one a named mapping maps to, else every p-model there (elaboration then
      picks the only top-level one, or asks for ``--model``);
    * a mapping: those of a named p-model or d-model module, else every mapping there (the
      generators then pick the only one, or ask for ``--model``).

    Library files are never candidates. Sorted, so that the choice never depends on the
    order the files were read in."""
    named = list(ws.user_files())
    declares = _pmodels if what == PMODEL else _mappings
    if any(declares(f) for f in named):
        return []
    library = {f.path for pkg in ws.packages.values() if pkg.builtin for f in pkg.files}
    others = [f for path, f in ws.files.items()
              if path not in set(ws.targets) and path not in library and declares(f)]
    if what == PMODEL:
        mapped = {m.pmodel[-1] for f in named for m in _mappings(f)}
        chosen = [f for f in others if any(pm.name in mapped for pm in _pmodels(f))]
    else:
        pmodels = {pm.name for f in named for pm in _pmodels(f)}
        modules = {m.name for f in named for m in _modules(f)}
        chosen = [f for f in others if any(m.pmodel[-1] in pmodels or m.dmodel[-1] in modules
                                           for m in _mappings(f))]
    return sorted(f.path for f in chosen or others)
