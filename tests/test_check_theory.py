"""``cyphy check-theory``: every session cyphy generates passes it, and mutants that Isabelle
rejects are reported with exit 1 and the line (the issue's list of what Isabelle rejects)."""

from __future__ import annotations

import re
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
        # with SDF's default inertial Evolve also holds the wheels' equations of motion
        out.append(generate([CORPUS / "marXbot"], root / "corpus-marxbot-sdf",
                            default_inertial="sdf"))
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


# ---------------------------------------------------------------- the command on sessions

def run_cli(folder: Path, capsys) -> tuple[int, str]:  # type: ignore[no-untyped-def]
    from cyphy.cli import main

    code = main(["check-theory", str(folder)])
    out = capsys.readouterr()
    return code, out.out + out.err


def test_every_generated_session_passes(sessions: list[Path], capsys) -> None:
    for folder in sessions:
        code, out = run_cli(folder, capsys)
        assert code == 0, out
        assert out.count("\n") == 1 and "no problem found (static check, not Isabelle)" in out


def mutant(folder: Path, name: str, old: str, new: str, count: int = 1) -> tuple[Path, str]:
    """A copy of the session whose main theory has ``old`` replaced by ``new``."""
    target = folder.parent / f"{folder.name}-{name}"
    target.mkdir()
    theory = ""
    for p in folder.iterdir():
        text = p.read_text()
        if p.suffix == ".thy" and "Prelude" not in p.name:
            assert old in text, (old, p)
            text = text.replace(old, new, count)
            theory = text
        (target / p.name).write_text(text)
    return target, theory


def line_of(text: str, fragment: str, nth: int = 1) -> int:
    """The line of the ``nth`` occurrence of ``fragment``."""
    at = -1
    for _ in range(nth):
        at = text.index(fragment, at + 1)
    return text.count("\n", 0, at) + 1


def assert_rejected(folder: Path, capsys, code_id: str, line: int, words: str) -> None:  # type: ignore[no-untyped-def]
    code, out = run_cli(folder, capsys)
    assert code == 1, out
    hits = [ln for ln in out.splitlines() if f".thy:{line}: {code_id}:" in ln and words in ln]
    assert hits, out


def test_duplicate_definition_is_rejected(sessions, capsys) -> None:
    old = 'definition Motor_Kd :: real where "Motor_Kd = 0.0"\n'
    folder, text = mutant(sessions[0], "dup", old, old + old.replace("0.0", "1.0"))
    assert_rejected(folder, capsys, "T-DUPLICATE", line_of(text, "definition Motor_Kd", 2),
                    "Motor_Kd is declared twice")


def test_use_before_definition_is_rejected(sessions, capsys) -> None:
    old = 'definition Motor_R :: real where "Motor_R = 1.0"\n'
    folder, text = mutant(sessions[0], "order", old, "")
    text = text.replace("\nend\n", "\n" + old + "\nend\n")
    (next(folder.glob("*_CyPhyCircus.thy"))).write_text(text)
    assert_rejected(folder, capsys, "T-ORDER", line_of(text, '"Evolve = '),
                    "Motor_R is used before its definition")


def test_reserved_word_as_parameter_is_rejected(sessions, capsys) -> None:
    folder, text = mutant(sessions[0], "reserved", "DriveCall w", "DriveCall on", count=3)
    text = text.replace("\\<guillemotleft>w\\<guillemotright>", "\\<guillemotleft>on"
                        "\\<guillemotright>").replace("?(w)", "?(on)")
    (next(folder.glob("*_CyPhyCircus.thy"))).write_text(text)
    assert_rejected(folder, capsys, "T-RESERVED", line_of(text, '"DriveCall on = '), "'on'")


def test_division_on_nat_is_rejected(sessions, capsys) -> None:
    """``/`` is Fields.thy's inverse_divide: nat is no instance of class inverse."""
    folder, text = mutant(sessions[0], "div", 'globals_3: "(cycle = 1)"',
                          'globals_3: "(cycle = (1 / 2))"')
    assert_rejected(folder, capsys, "T-TYPE", line_of(text, "globals_3"), "inverse")


def test_proof_citing_a_missing_definition_is_rejected(sessions, capsys) -> None:
    folder, text = mutant(sessions[0], "fact", "by (simp add: Init_def closure)",
                          "by (simp add: Inti_def closure)")
    line = line_of(text, "Inti_def")
    assert_rejected(folder, capsys, "T-FACT", line, "no definition of Inti")
    assert_rejected(folder, capsys, "T-CLOSURE", line - 1, "does not cite Init_def")


def test_proof_citing_an_unknown_lemma_is_rejected(sessions, capsys) -> None:
    folder, text = mutant(sessions[0], "lemma", "by (simp add: Init_def closure)",
                          "by (simp add: Init_def closure NCSP_Init)")
    assert_rejected(folder, capsys, "T-FACT", line_of(text, "NCSP_Init"), "cites NCSP_Init")


def test_missing_recall_syntax_is_rejected(sessions, capsys) -> None:
    folder = sessions[0].parent / "recall"
    folder.mkdir()
    for p in sessions[0].iterdir():
        (folder / p.name).write_text(p.read_text().replace("begin recall_syntax", "begin"))
    prelude = (folder / "CyPhyCircus_Prelude.thy").read_text()
    code, out = run_cli(folder, capsys)
    assert code == 1
    assert f"CyPhyCircus_Prelude.thy:{line_of(prelude, 'begin')}: T-RECALL:" in out
    assert "T-AMBIGUOUS: this term parses two ways" in out


def test_axiomatic_mutants_are_rejected(sessions, capsys) -> None:
    ax = sessions[1]
    text = next(ax.glob("*.thy")).read_text()
    first = next(ln for ln in text.splitlines() if ln.startswith("definition Motor_Kd"))
    folder, text = mutant(ax, "dup", first + "\n", first + "\n" + first + "\n")
    assert_rejected(folder, capsys, "T-DUPLICATE", line_of(text, first, 2), "declared twice")


# ---------------------------------------------------------------- bad input

def test_bad_input_is_a_clear_error(tmp_path: Path, capsys) -> None:
    code, out = run_cli(tmp_path / "missing", capsys)
    assert code == 2 and "no such folder" in out and "Traceback" not in out
    code, out = run_cli(tmp_path, capsys)
    assert code == 2 and "no ROOT" in out
    (tmp_path / "ROOT").write_text('session "S" = "UTP-Circus" +\n  theories\n    A\n')
    cases = {
        b"hello, not a theory\n": ("T-NOT-THEORY", 1),
        b"theory A imports Main begin\n\xff\xfe\nend\n": ("T-ENCODING", 2),
        b"theory A imports Main begin\n(* open\ncomment\nend\n": ("T-LEX", 2),
        b"theory A imports Main begin\ntext \\<open>unterminated\nend\n": ("T-LEX", 2),
        b'theory A imports Main begin\ndefinition x :: nat where "x = 1\nend\n': ("T-LEX", 2),
    }
    for data, (code_id, line) in cases.items():
        (tmp_path / "A.thy").write_bytes(data)
        code, out = run_cli(tmp_path, capsys)
        assert code == 1 and f"A.thy:{line}: {code_id}:" in out and "Traceback" not in out, out
    (tmp_path / "A.thy").unlink()
    code, out = run_cli(tmp_path, capsys)
    assert code == 1 and "T-MISSING" in out


# ---------------------------------------------------------------- reserved words by family

#: One family of words per library whose syntax reserves them (reserved_words.tsv, derived
#: from the sources by tools/derive_isabelle_words.py); each is a d-model parameter below.
WORD_FAMILIES = {
    "HOL binders": ["LEAST", "GREATEST", "INF", "SUP", "UN", "INT", "SIGMA", "MOST", "INFM",
                    "SOME", "THE", "ALL", "EX"],
    "HOL infix words": ["choose", "sums", "differentiable", "Int", "Un", "mod", "div", "dvd",
                        "o", "O", "powr", "at", "within"],
    # (if, then, else are RoboSim keywords too: no d-model can use them)
    "HOL control words": ["let", "case", "of", "SOME", "THE"],
    "Pure words": ["CONST", "TYPE", "PROP", "XCONST"],
    "utp-main words": ["on", "sp", "wp", "frz", "mods", "var", "state", "while", "od", "fi"],
}


def test_the_word_families_come_from_the_derived_table() -> None:
    from cyphy.backends.isabelle.library_words import HOL_SYNTAX_WORDS, SYNTAX_WORDS
    from cyphy.backends.isabelle.names import RESERVED

    for family, words in WORD_FAMILIES.items():
        table = SYNTAX_WORDS if family.startswith("utp") else HOL_SYNTAX_WORDS
        for word in words:
            assert re.fullmatch(r"[\w/.-]+\.(thy|ML):\d+", table[word]), (word, table[word])
            assert word in RESERVED


@pytest.mark.parametrize("dialect", ["utp", "axiomatic"])
@pytest.mark.parametrize("family", sorted(WORD_FAMILIES))
def test_parameters_named_after_reserved_words_are_renamed(tmp_path: Path, family: str,
                                                           dialect: str) -> None:
    """``move(choose: real, sums: real, …)``: every parameter is renamed in the theory, and
    check-theory accepts the session."""
    from test_isabelle import SOFTWARE, write_model

    words = WORD_FAMILIES[family]
    params = ", ".join(f"{w}: real" for w in words)
    software = SOFTWARE.format(ops=f"move({params})", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               f"  operation move {{ equation Base::J::M.das == {' + '.join(words)} }}\n}}\n")
    (tmp_path / "model").mkdir()
    paths = write_model(tmp_path / "model", software, mapping)
    options: dict[str, object] = {"dialect": dialect}
    if dialect == "axiomatic":
        options["elements"] = ("Robot::Base::J::M", "Robot::Arm::S")
    folder = generate(paths, tmp_path / "session", **options)
    [theory] = [p for p in folder.glob("*.thy") if "Prelude" not in p.name]
    actions = theory.read_text().split("definition MoveCall")[1].split("\ndefinition")[0]
    for word in words:
        assert not re.search(rf"(?<![\w\\<]){word}(?![\w>])", actions), (word, actions)
    code, out = run_cli_plain(folder)
    assert code == 0, out


def run_cli_plain(folder: Path) -> tuple[int, str]:
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "cyphy", "check-theory", str(folder)],
                          capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def test_the_api_gives_the_same_findings(sessions) -> None:
    from cyphy.api import check_theory

    result = check_theory(sessions[0])
    assert result.exit_code == 0 and result.findings == [] and result.theories == 2
