"""Hostile values (issue 20): what `gen` and `show` reject, `cyphy check` rejects too, with the
same code; numbers beyond a double, deep nesting and huge index ranges end in diagnostics, not
in an internal error (exit 70) or minutes of computing."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT
from cyphy import api
from cyphy.cli import main

HEAD = "package h\nimport physmod::math::*\n"


def box_model(const: str = "", size: str = "length = 0.1, width = 0.1, height = 0.1",
              mass: str = "1.0", index: str = "") -> str:
    return HEAD + f"""pmodel M {{
{const}
	local link L {{
		{index}
		def {{ }}
		local body B {{
			def {{
				box({size})
				inertial information {{ mass {mass} }}
			}}
		}}
	}}
}}
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "m.rsm"
    path.write_text(text, encoding="utf-8")
    return path


def codes_of(path: Path) -> list[str]:
    return [d.code.id for d in api.check([path]).report.errors]


@pytest.mark.parametrize("value", ["1/0", "0/0", "sqrt(-1)", "log(0)", "1e309", "K + 1",
                                   "1e308*10", "2^100000"])
def test_check_rejects_what_gen_rejects(tmp_path: Path, value: str) -> None:
    path = write(tmp_path, box_model(f"\tconst K : real = {value}",
                                     "length = K, width = 0.1, height = 0.1"))
    assert codes_of(path) == ["E-EVAL"]
    generated = api.generate_sdf([path])
    assert not generated.files and "E-EVAL" in {d.code.id for d in generated.report.errors}


@pytest.mark.parametrize("const, size, mass", [
    ("", "length = 1e155, width = 1e155, height = 1e155", "1.0"),  # OverflowError
    ("", "length = 0.1, width = 0.1, height = 0.1", "1e309"),  # LinAlgError on inf
    ("", "length = 0.1, width = 0.1, height = 0.1", "1" + "0" * 400),  # int beyond a double
    ("\tconst K : real = 1e308", "length = K, width = K, height = K", "1.0"),
], ids=["box-1e155", "mass-1e309", "mass-400-digits", "box-1e308"])
def test_overflow_is_a_diagnostic_not_an_internal_error(tmp_path: Path, capsys: pytest.
                                                         CaptureFixture[str], const: str,
                                                         size: str, mass: str) -> None:
    path = write(tmp_path, box_model(const, size, mass))
    for command in (["check"], ["show"], ["gen", "--sdf", "-o", str(tmp_path / "out")]):
        assert main([*command, str(path)]) == 1, command
        err = capsys.readouterr().err
        assert "E-EVAL" in err and "internal error" not in err
    assert not (tmp_path / "out").exists()


def test_show_prints_the_model_and_its_value_errors(tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    path = write(tmp_path, box_model("\tconst K : real = 1/0",
                                     "length = K, width = 0.1, height = 0.1"))
    assert main(["show", str(path)]) == 1
    out, err = capsys.readouterr()
    assert "p-model M" in out and "body M::L::B" in out
    assert "E-EVAL: division by zero" in err


def cyphy(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """The installed command's way in (``run``: the deep stack of cyphy/deep.py)."""
    return subprocess.run([sys.executable, "-m", "cyphy", *args], capture_output=True,
                          text=True, cwd=ROOT, timeout=timeout,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})


def nested_parts(depth: int) -> str:
    text = HEAD
    for i in range(depth - 1):
        text += f"pmodel M{i} {{\n\tpart P = M{i + 1}\n}}\n"
    return text + f"pmodel M{depth - 1} {{\n\tlocal link L {{ def {{ }} }}\n}}\n"


@pytest.mark.parametrize("what, text", [
    ("500-term sum", box_model("\tconst K : real = " + "+".join(["0.001"] * 500),
                               "length = K, width = 0.1, height = 0.1")),
    ("500-deep parentheses", box_model("\tconst K : real = " + "(0.001+" * 500 + "0" +
                                       ")" * 500, "length = K, width = 0.1, height = 0.1")),
    ("parts nested 500 deep", nested_parts(500)),
], ids=["sum", "parentheses", "parts"])
def test_deep_nesting_is_handled(tmp_path: Path, what: str, text: str) -> None:
    path = write(tmp_path, text)
    for _ in range(2):  # the second run reads the parse cache
        done = cyphy("check", str(path))
        assert done.returncode == 0, (what, done.stderr[-2000:])
    done = cyphy("gen", "--sdf", "-o", str(tmp_path / "out"), str(path))
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr[-2000:]


def test_deep_nesting_through_the_api(tmp_path: Path) -> None:
    """A script calling the API gets the command's deep stack: 500-deep parts elaborate and
    give SDF (Python's default stack ends this in a RecursionError)."""
    from cyphy import api

    path = write(tmp_path, nested_parts(500))
    assert not api.check([path]).report.has_errors
    sdf = api.generate_sdf([path], api.SdfGenOptions(model="M0"))
    assert not sdf.report.has_errors and sdf.files


def test_nesting_beyond_any_stack_is_an_error_not_a_crash(tmp_path: Path) -> None:
    path = write(tmp_path, box_model("\tconst K : real = " + "+".join(["1"] * 60000),
                                     "length = K, width = 0.1, height = 0.1"))
    done = cyphy("check", str(path))
    assert done.returncode == 1 and "nests too deeply" in done.stderr, done.stderr[-2000:]
    assert "Traceback" not in done.stderr and "internal error" not in done.stderr


def test_an_index_range_over_the_limit_is_an_error_at_once(tmp_path: Path) -> None:
    path = write(tmp_path, box_model(index="index i : [0, 1000000000)"))
    done = cyphy("check", str(path), timeout=60)
    assert done.returncode == 1
    assert "IX1" in done.stderr + done.stdout and "more than the limit of 100000" in \
        done.stderr + done.stdout


def test_nested_ranges_over_the_limit_stop_elaboration(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYPHY_MAX_COPIES", "50")
    text = box_model(index="index i : [0, 10)").replace(
        "local body B {", "local body B {\n\t\t\tindex j : [0, 10)")
    path = write(tmp_path, text)
    errors = api.check([path]).report.errors
    assert [d.code.id for d in errors] == ["E-INDEX"]
    assert "more than the limit of 50" in errors[0].message
    monkeypatch.setenv("CYPHY_MAX_COPIES", "110")  # 10 links, 100 bodies
    assert api.check([path]).report.errors == []


def test_max_copies_option_raises_the_limit(tmp_path: Path) -> None:
    path = write(tmp_path, box_model(index="index i : [0, 20)"))
    assert cyphy("check", "--max-copies", "10", str(path)).returncode == 1
    assert cyphy("check", "--max-copies", "20", str(path)).returncode == 0
