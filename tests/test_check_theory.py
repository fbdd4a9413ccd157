"""``cyphy check-theory``: every session cyphy generates passes it, and mutants that Isabelle
rejects are reported with exit 1 and the line (the issue's list of what Isabelle rejects)."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.verify.theory.grammar import grammars
from cyphy.verify.theory.session import read_session


def generate(paths: list[Path], folder: Path, **options: object) -> Path:
    """Write the Isabelle session of a mapping to ``folder``."""
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions(**options))
    assert not generated.report.has_errors, generated.report.diagnostics
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in generated.files.items():
        (folder / name).write_text(text)
    return folder


EXAMPLE_MAPPINGS = [EXAMPLES / "dcmotor", EXAMPLES / "marxbot" / "Mapping.rsm"]


@pytest.fixture(scope="module")
def sessions(tmp_path_factory) -> list[Path]:  # type: ignore[no-untyped-def]
    """Both dialects of both examples (and the corpus marXbot when ../shared is there)."""
    root = tmp_path_factory.mktemp("sessions")
    out = []
    for path in EXAMPLE_MAPPINGS:
        for dialect in ("utp", "axiomatic"):
            out.append(generate([path], root / f"{path.stem}-{dialect}", dialect=dialect))
    if CORPUS.is_dir():
        out.append(generate([CORPUS / "marXbot"], root / "corpus-marxbot"))
    return out


def test_no_generated_theory_merges_plain_hol_without_recall(sessions: list[Path]) -> None:
    """Each theory's imports read: a UTP grammar merged with plain HOL's needs recall_syntax
    right after begin (the prelude imports HOL.Transcendental beside UTP-Circus)."""
    merges = 0
    for folder in sessions:
        session, problems = read_session(folder)
        assert problems == []
        kinds, findings = grammars(session)
        assert findings == [], folder
        assert "merged" not in kinds.values()
        for th in session.theories:
            merges += any(i.startswith("HOL.") for i in th.imports) and any(
                i.startswith("UTP") for i in th.imports)
    assert merges >= 2  # the prelude of each utp session does merge them


def test_prelude_without_recall_is_a_merge_and_its_terms_are_ambiguous(sessions) -> None:
    from cyphy.verify.theory.grammar import ambiguous_terms

    folder = sessions[0]
    prelude = folder / "CyPhyCircus_Prelude.thy"
    text = prelude.read_text()
    mutant = folder.parent / "no-recall"
    mutant.mkdir()
    for p in folder.iterdir():
        (mutant / p.name).write_text(p.read_text())
    (mutant / prelude.name).write_text(text.replace("begin recall_syntax", "begin", 1))
    session, _ = read_session(mutant)
    kinds, findings = grammars(session)
    [finding] = findings
    assert finding.code == "T-RECALL" and finding.path.name == prelude.name
    assert finding.line == text.splitlines().index("begin recall_syntax") + 1
    ambiguous = ambiguous_terms(session, kinds)
    # the prelude writes no purged symbol; the theory importing it inherits the merge
    assert {f.path.name for f in ambiguous} == {next(
        p.name for p in mutant.glob("*_CyPhyCircus.thy"))}
    assert all(f.code == "T-AMBIGUOUS" and f.line > 0 for f in ambiguous)
