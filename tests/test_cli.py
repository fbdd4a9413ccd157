"""The command line: exit statuses, text and JSON output, and start-up imports."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from cyphy.cli import main
from conftest import EXAMPLES

BROKEN = "pmodel P {\n  local link L {\n    def { }\n    jref J = Revolte { }\n  }\n}\n"


def test_check_clean_example_exits_0(capsys) -> None:
    assert main(["check", str(EXAMPLES / "marxbot")]) == 0
    out, err = capsys.readouterr()
    assert "5 files checked: 0 errors, 0 warnings" in err and out == ""  # diagnostics: stderr


def test_check_errors_exit_1_with_caret_and_hint(tmp_path: Path, capsys) -> None:
    model = tmp_path / "broken.rsm"
    model.write_text(BROKEN)
    assert main(["check", str(model)]) == 1
    out = capsys.readouterr().err
    assert f"{model}:4:5: ERROR S1: unknown joint definition 'Revolte'" in out
    assert "    4 |     jref J = Revolte { }\n" in out
    assert "hint: did you mean 'Revolute'? (import physmod::joints::Revolute)" in out


def test_json_format(tmp_path: Path, capsys) -> None:
    model = tmp_path / "broken.rsm"
    model.write_text(BROKEN.replace("}\n}\n", ""))
    assert main(["check", "--format", "json", str(model)]) == 1
    diags = json.loads(capsys.readouterr().out)
    assert [d["code"] for d in diags] == ["E-SYNTAX"]
    assert diags[0]["span"]["line"] == 2 and diags[0]["span"]["column"] == 16
    assert "'}'" in diags[0]["hint"]


def test_syntax_only_skips_resolution(tmp_path: Path, capsys) -> None:
    model = tmp_path / "broken.rsm"
    model.write_text(BROKEN)
    assert main(["check", "--syntax-only", str(model)]) == 0


def test_search_path(tmp_path: Path, capsys) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "app").mkdir()
    (tmp_path / "lib" / "defs.rsm").write_text("package mine\njoint Hinge { input tau: real }\n")
    model = tmp_path / "app" / "robot.rsm"
    model.write_text("import mine::*\n" + BROKEN.replace("Revolte", "Hinge"))
    assert main(["check", str(model)]) == 1
    capsys.readouterr()
    assert main(["check", "--path", str(tmp_path / "lib"), str(model)]) == 0


def test_missing_path_is_an_error(tmp_path: Path, capsys) -> None:
    assert main(["check", str(tmp_path / "nope.rsm")]) == 1
    assert "E-IO" in capsys.readouterr().err


def test_usage_error_exits_2() -> None:
    proc = subprocess.run([sys.executable, "-m", "cyphy", "check"], capture_output=True)
    assert proc.returncode == 2
    proc = subprocess.run([sys.executable, "-m", "cyphy", "frobnicate"], capture_output=True)
    assert proc.returncode == 2


def test_help_does_not_import_heavy_libraries() -> None:
    code = (
        "import sys\n"
        "from cyphy.cli import main\n"
        "for argv in (['--help'], ['check', '--help'], ['show', '--help']):\n"
        "    try:\n        main(argv)\n    except SystemExit:\n        pass\n"
        "heavy = sorted(m for m in ('sympy', 'z3', 'numpy', 'scipy') if m in sys.modules)\n"
        "print('HEAVY', heavy)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert "HEAVY []" in proc.stdout, proc.stdout + proc.stderr


def test_check_does_not_import_sympy_or_z3() -> None:
    code = (
        "import sys\n"
        "from cyphy.cli import main\n"
        f"main(['check', {str(EXAMPLES / 'marxbot')!r}])\n"
        "print('HEAVY', sorted(m for m in ('sympy', 'z3') if m in sys.modules))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert "HEAVY []" in proc.stdout, proc.stdout + proc.stderr


def test_only_consistency_imports_z3() -> None:
    """Z3 is imported by ``check --consistency`` alone (and SymPy not even then)."""
    mapping = str(EXAMPLES / "marxbot" / "Mapping.rsm")
    for argv, expected in ((["check", mapping], "[]"),
                           (["check", "--consistency", mapping], "['z3']")):
        code = (
            "import sys\n"
            "from cyphy.cli import main\n"
            f"main({argv!r})\n"
            "print('HEAVY', sorted(m for m in ('sympy', 'z3') if m in sys.modules))\n"
        )
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert f"HEAVY {expected}" in proc.stdout, proc.stdout + proc.stderr


def test_faulty_example_reports_each_mistake(capsys) -> None:
    assert main(["check", "--format", "json", str(EXAMPLES / "faulty")]) == 1
    diags = json.loads(capsys.readouterr().out)
    assert [(d["code"], d["span"]["line"], d["span"]["column"]) for d in diags] == [
        ("S1", 9, 3), ("E-MEMBER", 17, 4)]
    assert "import physmod::joints::Revolute" in diags[0]["hint"]
    assert "body" in diags[1]["hint"]


def test_show_text_and_json(capsys) -> None:
    assert main(["show", str(EXAMPLES / "marxbot"), "--model", "marXbotBase"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("p-model marXbotBase\n")
    assert "  link marXbotBase::Core  pose 0 0 0.0575 0 0 0\n" in out
    assert main(["show", str(EXAMPLES / "marxbot"), "--model", "marXbotBase",
                 "--format", "json", "--const", "Kp=2", "--const", "IR::a=1e-3"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"model", "links", "joints", "unconnected", "fixed", "devices",
                         "relations", "constants", "missing", "motion"}
    assert "SpeedControlMotor::Kp" not in data["missing"] and "IR::b" in data["missing"]
    motor = next(d for d in data["devices"] if d["prefix"] == "LMotor")
    assert {"name": "Kp", "kind": "const", "mangled": "LMotor_Kp", "value": 2} in motor["ports"]


def test_show_bad_const_is_a_usage_error(capsys) -> None:
    try:
        main(["show", str(EXAMPLES / "marxbot"), "--const", "Kp"])
    except SystemExit as exit:
        assert exit.code == 2
    assert "NAME=VALUE" in capsys.readouterr().err


def test_show_with_errors_exits_1(tmp_path: Path, capsys) -> None:
    model = tmp_path / "broken.rsm"
    model.write_text(BROKEN)
    assert main(["show", str(model)]) == 1
    assert capsys.readouterr().out == ""


@pytest.mark.parametrize("name, text", [
    ("c.toml", 'Kp = 2\n"IR::a" = 0.001\nAXIS = [0, 0, 1]\n'),
    ("c.json", '{"Kp": 2, "IR::a": 0.001, "AXIS": [0, 0, 1]}'),
])
def test_consts_file(tmp_path: Path, capsys, name: str, text: str) -> None:
    (tmp_path / name).write_text(text)
    assert main(["show", str(EXAMPLES / "marxbot"), "--model", "marXbotBase", "--format",
                 "json", "--consts", str(tmp_path / name), "--const", "Kp=3"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert "SpeedControlMotor::Kp" not in data["missing"] and "IR::a" not in data["missing"]
    motor = next(d for d in data["devices"] if d["prefix"] == "LMotor")
    assert {"name": "Kp", "kind": "const", "mangled": "LMotor_Kp", "value": 3} in motor["ports"]


@pytest.mark.parametrize("target, option, owner", [
    ("--cyphycircus", ["--split-trees"], "--sdf"),
    ("--sdf", ["--pdf"], "--latex"),
    ("--sdf", ["--isabelle-dialect", "axiomatic"], "--isabelle"),
])
def test_an_option_of_another_target_is_a_usage_error(tmp_path: Path, capsys, target: str,
                                                      option: list[str], owner: str) -> None:
    out = tmp_path / "out"
    code = main(["gen", str(EXAMPLES / "marxbot" / "Mapping.rsm"), target, *option,
                 "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and f"{option[0]} is an option of {owner}" in err and target in err
    assert not out.exists()


def test_options_shared_by_semantic_targets_are_accepted(tmp_path: Path, capsys) -> None:
    for target in ("--cyphycircus", "--isabelle"):
        assert main(["gen", str(EXAMPLES / "marxbot" / "Mapping.rsm"), target, "--tscale",
                     "0.01", "-o", str(tmp_path / target.strip("-"))]) == 0


def test_the_command_flushes_its_output_before_its_quick_exit(tmp_path: Path) -> None:
    # `cyphy` (cli.run) leaves with os._exit, skipping the interpreter's teardown.
    out = tmp_path / "sdf"
    ok = subprocess.run([sys.executable, "-m", "cyphy", "gen", str(EXAMPLES / "manipulator"),
                         "--sdf", "-o", str(out)], capture_output=True, text=True)
    assert ok.returncode == 0 and "wrote" in ok.stdout and any(out.glob("*.sdf"))
    bad = subprocess.run([sys.executable, "-m", "cyphy", "check", str(EXAMPLES / "faulty")],
                         capture_output=True, text=True)
    assert bad.returncode == 1 and "ERROR S1" in bad.stderr + bad.stdout
    assert "2 errors" in bad.stdout + bad.stderr
