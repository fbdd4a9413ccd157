"""Conformance with RoboTool's public examples (../shared/corpus, skipped when absent).

Every .pm and .rst file parses, and every project folder of the corpus resolves with no
scope or typing error (the well-formedness conditions have their own conformance test). Where a corpus model really is wrong, it is listed in KNOWN_WRONG with the
reason: the SimpleArm model equates 3x4 matrices with 4x3 literals (S3).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cyphy import api
from cyphy.lang.parser import contains_lark_objects, parse_text
from conftest import CORPUS, corpus_model_files, corpus_project_folders, needs_corpus

_X_4X3 = ("S3", "Revolute_x/Revolute_z/Prismatic_x declare X_CF/X_FM: matrix(real,3,4) but "
          "equate them to 4-row, 3-column literals [|…;…;…;…|]: a real dimension mismatch")
KNOWN_WRONG: dict[str, list[tuple[str, str]]] = {
    "SimpleArm": [_X_4X3] * 3,
}
"""folder (relative to the corpus) → [(code, reason)], one per diagnostic, for models that
really are wrong."""


def _rel(p: Path) -> str:
    return str(p.relative_to(CORPUS))


@needs_corpus
@pytest.mark.parametrize("path", corpus_model_files(), ids=_rel)
def test_every_corpus_file_parses(path: Path) -> None:
    result = parse_text(path.read_text(encoding="utf-8"), str(path))
    assert result.diagnostics == ()
    assert result.file is not None and result.file.items
    assert not contains_lark_objects(result.file)


@needs_corpus
def test_corpus_file_count() -> None:
    files = corpus_model_files()
    assert len([f for f in files if f.suffix == ".pm"]) == 158
    assert len([f for f in files if f.suffix == ".rst"]) == 2


@needs_corpus
def test_syntax_only_check_passes_on_the_whole_corpus() -> None:
    result = api.check([CORPUS], api.CheckOptions(syntax_only=True))
    assert result.report.diagnostics == []
    assert len(result.workspace.targets) == 160


@needs_corpus
@pytest.mark.parametrize("folder", corpus_project_folders(), ids=_rel)
def test_every_corpus_project_resolves(folder: Path) -> None:
    files = sorted(p for p in folder.iterdir() if p.suffix in (".pm", ".rst"))
    result = api.check(files, api.CheckOptions(wellformedness=False))
    found = sorted((d.code.id, d.message) for d in result.report.diagnostics)
    expected_codes = [code for code, _ in KNOWN_WRONG.get(_rel(folder), [])]
    assert [code for code, _ in found] == expected_codes, found


@needs_corpus
def test_marxbot_mapping_resolves_into_the_pmodel_and_dmodel() -> None:
    folder = CORPUS / "marXbot"
    result = api.check([folder / "Mapping.pm"])
    mapping_file = result.workspace.files[str(folder / "Mapping.pm")]
    mapping = mapping_file.items[-1]
    module = result.resolution.get(mapping)
    assert module is not None and module.name == "marXbotSoftware"
    assert result.report.diagnostics == []
