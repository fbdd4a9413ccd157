"""Which p-model a command that elaborates one is about, when the files given declare none.

A user hands ``cyphy gen --sdf`` a platform mapping (``examples/marxbot/Mapping.rsm``) or a
d-model as readily as the p-model: RoboTool resolves names across the project folder, and so
does cyphy (the folder's files are read as neighbours). Without this the elaborating commands
would see no p-model among the files the user named and stop (``E-MODEL``), while the
semantics' generators, which follow the mapping to its p-model, work on the same file.
"""

from __future__ import annotations

from cyphy.lang import ast
from cyphy.lang.workspace import Workspace


def _pmodels(f: ast.SourceFile) -> list[ast.PModel]:
    return [i for i in f.items if isinstance(i, ast.PModel) and not i.fragment]


def declares_pmodel(ws: Workspace) -> bool:
    """Whether a file the user named declares a (non-fragment) p-model."""
    return any(_pmodels(f) for f in ws.user_files())


def folder_pmodel_files(ws: Workspace) -> list[str]:
    """The other user files (neighbours in the folders, ``--path``) that declare the p-model
    the named files are about: the p-model a named mapping maps to, else every p-model there
    (elaboration then picks the only top-level one, or asks for ``--model``). Library files
    are never candidates. Sorted, so that the choice never depends on reading order."""
    library = {f.path for pkg in ws.packages.values() if pkg.builtin for f in pkg.files}
    named = set(ws.targets)
    others = [f for path, f in ws.files.items()
              if path not in named and path not in library and _pmodels(f)]
    mapped = {m.pmodel[-1] for f in ws.user_files() for m in f.items
              if isinstance(m, ast.PlatformMapping)}
    if mapped:
        others = [f for f in others if any(pm.name in mapped for pm in _pmodels(f))]
    return sorted(f.path for f in others)
