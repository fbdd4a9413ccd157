"""The newcomer's path (issue 29): hints that are right, the examples clean, the repository
ignoring what cyphy writes, and a test run that ends with its summary line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from cyphy.cli import main
from cyphy.outputs import DEFAULT_FOLDERS


def _check(tmp_path: Path, text: str, capsys: pytest.CaptureFixture[str]) -> str:
    (tmp_path / "m.rsm").write_text(text)
    assert main(["check", str(tmp_path / "m.rsm")]) == 1
    return capsys.readouterr().err


def test_a_missing_import_is_named_not_misspelt(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    err = _check(tmp_path, "package t\npmodel T {\n\tlocal link L {\n\t\tdef { }\n\t\t"
                 "jref J = Revolute { }\n\t}\n\tlocal link M { def { } }\n}\n", capsys)
    assert "unknown joint definition 'Revolute'" in err
    assert "did you mean 'Revolute'" not in err
    assert "'Revolute' is declared in physmod::joints, which this file does not import: " \
        "add `import physmod::joints::*`" in err
    # a real misspelling still gets the close name and its import
    err = _check(tmp_path, "package t\npmodel T {\n\tlocal link L {\n\t\tdef { }\n\t\t"
                 "jref J = Revolut { }\n\t}\n\tlocal link M { def { } }\n}\n", capsys)
    assert "did you mean 'Revolute'? (import physmod::joints::Revolute)" in err


@pytest.mark.parametrize("name", ["nan", "inf", "NaN"])
def test_no_tan_for_nan(name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    err = _check(tmp_path, f"package t\npmodel T {{\n\tconst c: real = {name}\n\t"
                 "local link L { def { } }\n}\n", capsys)
    assert f"unknown name '{name}'" in err and "did you mean" not in err
    assert f"RoboSim has no '{name}': every value is a finite number" in err


@pytest.mark.parametrize("written, word, symbol", [
    ("true and false", "and", "/\\"), ("1 < 2 or 2 < 3", "or", "\\/"),
    ("(true) and (false)", "and", "/\\")])
def test_and_as_conjunction(written: str, word: str, symbol: str, tmp_path: Path,
                            capsys: pytest.CaptureFixture[str]) -> None:
    err = _check(tmp_path, f"package t\npmodel T {{\n\tconst c: boolean = {written}\n\t"
                 "local link L { def { } }\n}\n", capsys)
    assert "E-SYNTAX" in err
    assert f"RoboSim writes '{word}' as '{symbol}'" in err


@pytest.mark.parametrize("example", sorted(p.name for p in EXAMPLES.iterdir()
                                           if p.is_dir() and p.name != "faulty"))
def test_the_examples_are_clean_under_warnings_as_errors(example: str) -> None:
    assert main(["check", "--warnings-as-errors", str(EXAMPLES / example)]) == 0


def test_gitignore_covers_every_default_output_folder() -> None:
    ignored = set((ROOT / ".gitignore").read_text().split())
    assert {f"{folder}/" for folder in DEFAULT_FOLDERS.values()} <= ignored


def test_pytest_prints_its_summary_line(tmp_path: Path) -> None:
    """`python3 -m pytest -q` (the README's and CI's command) with the project's settings
    ends with "N passed": a second -q from addopts would hide it."""
    (tmp_path / "test_one.py").write_text("def test_one():\n    assert True\n")
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
                           str(tmp_path / "test_one.py")], capture_output=True, text=True,
                          cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT)},
                          timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().splitlines()[-1].startswith("1 passed")


_SKO_MODEL = ("package t\nimport physmod::SKO::joints::Revolute_y\npmodel T {\n\tlocal link L {\n"
              "\t\tdef { }\n\t\tjref J = Revolute_y { flexibly connected to M }\n\t}\n"
              "\tlocal link M { def { } }\n}\n")


def test_the_newer_library_is_named_not_misspelt(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """RoboTool's newer library (physmod::SKO, physmod::trivial, …) is not built in: the hint
    says where it comes from and how to give it, not 'did you mean physmod::joints' (whose
    Revolute has other ports); with its folder given by --path the model checks."""
    err = _check(tmp_path, _SKO_MODEL, capsys)
    assert "import from unknown package 'physmod::SKO::joints'" in err
    assert "did you mean" not in err
    # the joint it names is unknown for that reason, not for its spelling
    assert "unknown joint definition 'Revolute_y'" in err
    assert "it is imported from physmod::SKO::joints (line 2), which is not found" in err
    assert "physmod::SKO is part of RoboTool's newer library, which cyphy does not build in: " \
        "give its folder, `--path <physmod-libs>/lib/physmod/SKO`" in err
    err = _check(tmp_path, _SKO_MODEL.replace("import physmod::SKO::joints::Revolute_y",
                                              "import physmod::trivial::sensors::*"), capsys)
    assert "import of unknown package 'physmod::trivial::sensors'" in err
    assert "physmod::trivial is part of RoboTool's newer library" in err
    # a user's own folder declaring the package, as the newer library's files do
    library = tmp_path / "lib"
    library.mkdir()
    (library / "joints.pm").write_text(
        "package physmod::SKO::joints\njoint Revolute_y {\n\tInOut theta: real\n}\n")
    (tmp_path / "m.rsm").write_text(_SKO_MODEL)
    assert main(["check", str(tmp_path / "m.rsm"), "--path", str(library)]) == 0
