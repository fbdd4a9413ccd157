"""Which p-model a command elaborates (the one named, else the only top-level one), and
whether an elaborated model has every constant a generator needs."""

from __future__ import annotations

from cyphy import codes
from cyphy.diagnostics import Report, Span
from cyphy.lang import ast
from cyphy.lang.workspace import Workspace
from cyphy.model.elements import ElaboratedModel

MODEL = codes.code("E-MODEL", codes.E, "the p-model to elaborate cannot be chosen")
MISSING = codes.code("E-CONST", codes.E, "constants without values that a generator needs")


def require_constants(model: ElaboratedModel, report: Report, what: str,
                      owners: set[str] | None = None) -> bool:
    """For a generator: report every constant without a value at once (``E-CONST``) and
    say whether the model can be generated; with ``owners``, only the constants declared
    by those (p-models, devices), by name."""
    missing = {n: spans for n, spans in model.missing.items()
               if owners is None or n.rpartition("::")[0] in owners}
    if not missing:
        return True
    names = ", ".join(missing)
    first = next(iter(missing.values()))[0]
    report.report(MISSING, f"{what} needs values for {len(missing)} constant"
                  f"{'s' if len(missing) != 1 else ''} without one: {names}", first,
                  "give them with --const NAME=VALUE (repeatable) or --consts FILE",
                  [f"{n} is declared at {spans[0]}" for n, spans in missing.items()])
    return False


def _pmodels(ws: Workspace) -> list[tuple[ast.PModel, ast.SourceFile]]:
    return [(item, f) for f in ws.user_files() for item in f.items
            if isinstance(item, ast.PModel) and not item.fragment]


def top_level_pmodels(ws: Workspace) -> list[tuple[ast.PModel, ast.SourceFile]]:
    """The p-models of the user's files that no other of them uses as a part."""
    candidates = _pmodels(ws)
    used = {p.pmodel[-1] for pm, _ in candidates for p in pm.parts}
    return [c for c in candidates if c[0].name not in used]


def choose_pmodel(ws: Workspace, name: str | None, report: Report
                  ) -> tuple[ast.PModel, ast.SourceFile] | None:
    """The p-model to elaborate: the one named, else the only one of the user's files that
    no other p-model uses as a part."""
    candidates = _pmodels(ws)
    if name is not None:
        chosen = [c for c in candidates if c[0].name == name or
                  "::".join(c[1].package + (c[0].name,)) == name]
        if not chosen:
            names = ", ".join(sorted(c[0].name for c in candidates)) or "(none)"
            report.report(MODEL, f"no p-model named '{name}'", _files_span(ws),
                          f"the p-models are: {names}")
            return None
        return chosen[0]
    top = top_level_pmodels(ws)
    if len(top) == 1:
        return top[0]
    if not candidates:
        report.report(MODEL, "no p-model in the given files", _files_span(ws),
                      "name a file or folder that declares a pmodel")
        return None
    meant = sorted(top or candidates, key=lambda c: (c[0].span.file, c[0].span.line))
    names = ", ".join(sorted(c[0].name for c in meant))
    report.report(MODEL, "several p-models could be meant", meant[0][0].span,
                  f"choose one with --model: {names}",
                  [f"p-model {pm.name} is declared at {pm.span}" for pm, _ in meant[1:]])
    return None


def _files_span(ws: Workspace) -> Span:
    """Where a problem with the whole selection of files is reported: the first file given
    (no line), or nowhere when there is none."""
    return Span.unknown(str(ws.targets[0])) if ws.targets else Span.unknown()
