"""The newcomer's path (issue 20): version, quiet and strict modes, diagnostics on stderr,
JSON from `gen`, options that would be silently ignored, progress on long runs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import pytest

import cyphy
from conftest import EXAMPLES, ROOT
from cyphy.cli import main

ENV = {**os.environ, "PYTHONPATH": str(ROOT)}
# A model whose only diagnostic is a warning (L4: a link without inertial information).
WARNED = "package w\npmodel W {\n\tlocal link L { def { } }\n}\n"


def cyphy_run(*args: str, env: dict[str, str] | None = None
              ) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "cyphy", *args], capture_output=True,
                          text=True, cwd=ROOT, env=env or ENV, timeout=300)


def test_version_from_the_package_metadata() -> None:
    assert cyphy.__version__ == version("cyphy")
    done = cyphy_run("--version")
    assert done.returncode == 0 and done.stdout.strip() == f"cyphy {version('cyphy')}"


def test_quiet_prints_errors_only(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    model = tmp_path / "w.rsm"
    model.write_text(WARNED)
    assert main(["check", str(model)]) == 0
    assert "WARNING L4" in capsys.readouterr().err
    for argv in (["-q", "check", str(model)], ["check", "-q", str(model)],
                 ["--quiet", "gen", "--sdf", "-o", str(tmp_path / "o"), str(model)]):
        assert main(argv) == 0
        out, err = capsys.readouterr()
        assert (out, err) == ("", ""), argv
    assert (tmp_path / "o" / "W.sdf").is_file()
    model.write_text(WARNED.replace("local link L", "local lnk L"))
    assert main(["-q", "check", str(model)]) == 1
    assert "ERROR E-SYNTAX" in capsys.readouterr().err


def test_warnings_as_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    model = tmp_path / "w.rsm"
    model.write_text(WARNED)
    assert main(["check", "--warnings-as-errors", str(model)]) == 1
    assert "(--warnings-as-errors)" in capsys.readouterr().err
    out = tmp_path / "o"
    assert main(["--warnings-as-errors", "gen", "--sdf", "-o", str(out), str(model)]) == 1
    assert "nothing written" in capsys.readouterr().err and not out.exists()
    assert main(["check", "--warnings-as-errors", str(EXAMPLES / "marxbot")]) == 0


@pytest.mark.parametrize("argv", [
    ["check", "EXAMPLES/faulty"],
    ["show", "EXAMPLES/faulty"],
    ["solve", "EXAMPLES/faulty"],
    ["gen", "--sdf", "EXAMPLES/faulty"],
    ["gen", "--cyphycircus", "EXAMPLES/faulty"],
])
def test_diagnostics_go_to_stderr(argv: list[str], tmp_path: Path,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    argv = [a.replace("EXAMPLES", str(EXAMPLES)) for a in argv]
    if argv[0] == "gen":
        argv += ["-o", str(tmp_path / "o")]
    assert main(argv) == 1
    out, err = capsys.readouterr()
    assert "ERROR S1" in err and "ERROR" not in out


def test_gen_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "o"
    assert main(["gen", "--sdf", "--format", "json", "-o", str(out),
                 str(EXAMPLES / "marxbot")]) == 0
    stdout, err = capsys.readouterr()
    document = json.loads(stdout)
    assert document["written"] == [str(out / "marXbotBase.sdf"),
                                   str(out / "marXbotBase.names.json")]
    assert document["error"] is None and err == ""
    assert {d["code"] for d in document["diagnostics"]} == {"W-SDF-SENSOR"}
    assert main(["gen", "--sdf", "--format", "json", "-o", str(tmp_path / "bad"),
                 str(EXAMPLES / "faulty")]) == 1
    document = json.loads(capsys.readouterr().out)
    assert document["written"] == [] and "nothing written" in document["error"]
    assert [d["code"] for d in document["diagnostics"]] == ["S1", "E-MEMBER"]


def test_solve_element_that_names_nothing_is_a_usage_error(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["solve", str(EXAMPLES / "marxbot"), "--model", "marXbotBase",
                 "--element", "Nope::X"]) == 2
    assert "--element 'Nope::X' names no element of marXbotBase" in capsys.readouterr().err
    assert main(["solve", str(EXAMPLES / "marxbot"), "--model", "marXbotBase", "--element",
                 "marXbotBase::Core::LHinge::LMotor"]) == 0


def test_isabelle_element_without_the_axiomatic_dialect_is_a_usage_error(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit:
        main(["gen", "--isabelle", "--isabelle-element", "marXbotBase::Core", "-o",
              str(tmp_path / "o"), str(EXAMPLES / "marxbot" / "Mapping.rsm")])
    assert exit.value.code == 2
    assert "--isabelle-element needs --isabelle-dialect axiomatic" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_progress_on_runs_over_a_second(tmp_path: Path) -> None:
    """A run that lasts over a second says what it is doing (forced on: not a terminal)."""
    model = tmp_path / "big.rsm"
    model.write_text("package b\nimport physmod::math::*\npmodel B {\n" + "".join(
        f"\tlocal link L{i} {{ def {{ inertial information {{ mass 1 }} }} "
        f"pose {{ x = {i} y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }} }}\n"
        for i in range(12000)) + "}\n")  # over a second even on a fast processor
    env = {**ENV, "CYPHY_PROGRESS": "1", "CYPHY_NO_CACHE": "1"}
    done = cyphy_run("check", str(model), env=env)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = [line for line in done.stderr.splitlines() if line.startswith("cyphy: ")]
    assert lines and all(line.endswith(" s)") for line in lines), done.stderr[-2000:]
    assert not cyphy_run("-q", "check", str(model), env=env).stderr
