"""Rendering diagnostics safely (issue 20): what comes from the model is escaped and cut, and
a diagnostic without a place says so instead of ``<unknown>:0:0``."""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import EXAMPLES
from cyphy import codes
from cyphy.cli import main
from cyphy.diagnostics import EXCERPT_WIDTH, Diagnostic, Span, render_text


def test_control_characters_of_the_model_are_escaped() -> None:
    source = "const s: string = \"\x1b[2J\x1b]0;pwned\x07\"\x00 \u202e x"
    d = Diagnostic(codes.SYNTAX, "unexpected '\x1b[31m'", Span("m.rsm", 1, 19, 1, 30), "")
    out = render_text([d], {"m.rsm": source})
    assert not any(ord(ch) < 32 and ch != "\n" for ch in out) and "\u202e" not in out
    assert "\\x1b[2J" in out and "\\x07" in out and "\\x00" in out and "\\u202e" in out
    excerpt, caret = out.splitlines()[1:3]
    start = caret.index("^")
    assert excerpt[start:].startswith('"\\x1b[2J')  # the caret still points at the token


def test_a_long_line_is_cut_around_the_error(tmp_path: Path) -> None:
    line = "a" * 5_000_000 + "BAD" + "b" * 1000
    d = Diagnostic(codes.SYNTAX, "unexpected 'BAD'", Span("m.rsm", 1, 5_000_001, 1, 5_000_004))
    out = render_text([d], {"m.rsm": line})
    assert len(out) < 3 * EXCERPT_WIDTH + 200
    excerpt, caret = out.splitlines()[1:3]
    start = caret.index("^")
    assert excerpt[start:start + 3] == "BAD" and caret.count("^") == 3
    assert excerpt.startswith("    1 | …") and excerpt.endswith("…")


def test_a_long_message_is_cut() -> None:
    d = Diagnostic(codes.SYNTAX, "x" * 100_000, Span("m.rsm", 0, 0, 0, 0), "y" * 100_000)
    assert len(render_text([d])) < 2500


def test_no_unknown_zero_zero_location(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                       ) -> None:
    assert main(["show", str(EXAMPLES / "marxbot"), "--model", "Nope"]) == 1
    err = capsys.readouterr().err
    assert ":0:0" not in err and "<unknown>" not in err
    assert "Mapping.rsm: ERROR E-MODEL: no p-model named 'Nope'" in err
    assert main(["check", str(tmp_path / "missing.rsm")]) == 1
    err = capsys.readouterr().err
    assert ":0:0" not in err and f"{tmp_path / 'missing.rsm'}: ERROR E-IO" in err
    two = tmp_path / "two.rsm"
    two.write_text("package t\npmodel A { local link L { def { } } }\n"
                   "pmodel B { local link L { def { } } }\n")
    assert main(["show", str(two)]) == 1
    err = capsys.readouterr().err
    assert f"{two}:2:1: ERROR E-MODEL: several p-models could be meant" in err
    assert f"p-model B is declared at {two}:3:1" in err
