"""Broken models give the right diagnostic (code, position, hint), and nothing makes the parser
raise: every input comes back as a file, diagnostics, or both."""

from __future__ import annotations

import pytest

from cyphy.diagnostics import Diagnostic
from cyphy.lang.parser import ParseResult, parse_text

PATH = "broken.pm"
FATAL = {"E-SYNTAX", "E-LEX"}

# ----------------------------------------------------------------------------- helpers


def fatal(text: str) -> Diagnostic:
    """The single diagnostic of a text the parser must reject (no file comes back)."""
    result = parse_text(text, PATH)
    assert result.file is None
    assert len(result.diagnostics) == 1, result.diagnostics
    (d,) = result.diagnostics
    assert d.span.file == PATH
    return d


def where(d: Diagnostic) -> tuple[str, int, int]:
    return (d.code.id, d.span.line, d.span.column)


def check_invariants(result: ParseResult) -> None:
    """The contract of parse_text: a file, or diagnostics, and ``file is None`` exactly when
    there is a fatal (syntax or lexical) diagnostic."""
    assert isinstance(result, ParseResult)
    assert result.file is not None or result.diagnostics
    has_fatal = any(d.code.id in FATAL for d in result.diagnostics)
    assert (result.file is None) == has_fatal
    for d in result.diagnostics:
        assert d.span.line >= 1 and d.span.column >= 1
        assert d.message


# ----------------------------------------------------------------------------- unclosed blocks


def test_missing_closing_brace_points_at_the_innermost_unclosed_block():
    d = fatal(
        "pmodel P {\n"
        "  local link L {\n"   # this `{` (line 2, column 16) is never closed
        "    def { }\n"
    )
    assert where(d) == ("E-SYNTAX", 2, 16)
    assert (d.span.end_line, d.span.end_column) == (2, 17)
    assert "not closed" in d.message
    assert "'}'" in d.hint


def test_missing_closing_brace_of_a_pmodel():
    d = fatal("// header\npmodel P {\n  local link L { def { } }\n")
    assert where(d) == ("E-SYNTAX", 2, 10)
    assert "'}'" in d.hint


def test_missing_closing_brace_ignores_braces_in_comments_and_strings():
    d = fatal(
        "pmodel P {\n"
        "  // a closing brace in a comment }\n"
        '  local link L { def { mesh { shape "}" } } }\n'
        "  /* and { one } more */\n"
    )
    assert where(d) == ("E-SYNTAX", 1, 10)


def test_extra_closing_brace():
    d = fatal("pmodel P { local link L { } }\n}\n")
    assert where(d) == ("E-SYNTAX", 2, 1)
    assert d.message == "unexpected '}'"


def test_unexpected_end_of_file_outside_blocks():
    d = fatal("const c: real =\n")
    assert where(d) == ("E-SYNTAX", 2, 1)
    assert d.message == "unexpected end of file"
    assert "a number" in d.hint and "a name" in d.hint


# ----------------------------------------------------------------------------- unexpected tokens


def test_unexpected_token_in_a_pose():
    d = fatal("pmodel P {\n  local link L {\n    pose { x = }\n  }\n}\n")
    assert where(d) == ("E-SYNTAX", 3, 16)
    assert d.message == "unexpected '}'"
    assert "a number" in d.hint and "a name" in d.hint


def test_unexpected_token_with_crlf_and_tabs():
    d = fatal("pmodel P {\r\n\tlocal link L {\r\n\t\tpose { x = }\r\n\t}\r\n}\r\n")
    assert where(d) == ("E-SYNTAX", 3, 14)


def test_index_without_closing_bracket():
    d = fatal("pmodel P { local link L { index i : [0, 8 } }")
    assert where(d) == ("E-SYNTAX", 1, 43)
    assert "')'" in d.hint and "']'" in d.hint


def test_misspelt_keyword_is_a_syntax_error_at_the_misspelling():
    d = fatal("pmodel P { local link L { def { inertial informaton { mass 1 } } } }")
    assert where(d) == ("E-SYNTAX", 1, 42)
    assert "informaton" in d.message
    assert "'information'" in d.hint


def test_misspelt_local_is_read_as_a_bare_relation_and_fails_at_the_next_word():
    # `lcoal` is a name, and a name may start a bare relation (`x == 1`), so the error is
    # found at `link`, where a comparison operator was expected.
    d = fatal("pmodel P { lcoal link L {} }")
    assert where(d) == ("E-SYNTAX", 1, 18)
    assert d.message == "unexpected 'link'"
    assert "'=='" in d.hint


@pytest.mark.parametrize(
    "text, keyword",
    [
        pytest.param(
            "pmodel P { lcoal link L {} }", "local",
            marks=pytest.mark.xfail(
                strict=True,
                reason="known limitation: inside a block `lcoal` is read as the start of a bare "
                "relation, so the error lands on `link` with no keyword suggestion"),
        ),
        ("pmodel P { local link L { def { inertial informaton { mass 1 } } } }", "information"),
        ("pmodle P { }", "pmodel"),
    ],
)
def test_misspelt_keyword_hint_suggests_the_keyword(text, keyword):
    d = fatal(text)
    assert d.code.id == "E-SYNTAX"
    assert f"did you mean '{keyword}'" in d.hint


def test_misspelt_pose_field_is_a_member_error_with_a_suggestion():
    result = parse_text("pmodel P { local link L { pose { x = 1 yw = 2 } } }", PATH)
    assert result.file is not None
    (d,) = result.diagnostics
    assert where(d) == ("E-MEMBER", 1, 40)
    assert "did you mean 'yaw'" in d.hint


# ----------------------------------------------------------------------------- lexical errors


def test_unterminated_block_comment():
    d = fatal("pmodel P {\n  local link L { def { } }\n  /* forgot to close\n}\n")
    assert where(d) == ("E-LEX", 3, 3)
    assert d.message == "unterminated block comment"
    assert "'*/'" in d.hint


def test_unterminated_string():
    d = fatal('pmodel P {\n  local body B { def { mesh { shape "arm.dae } } }\n}\n')
    assert where(d) == ("E-LEX", 2, 37)
    assert d.message == "unterminated string"
    assert "'\"'" in d.hint


@pytest.mark.xfail(
    strict=True,
    reason="parser bug (minor): STRING may span lines although the E-LEX hint says strings close "
    "'on the same line', so an unterminated string runs to the next quote in the file and the "
    "error is reported there (here E-SYNTAX at 2:20, unexpected name 'x')",
)
def test_unterminated_string_followed_by_another_string():
    d = fatal('const s: string = "abc\nconst t: string = "x"\n')
    assert where(d) == ("E-LEX", 1, 19)


def test_unterminated_string_in_a_state_action():
    d = fatal('stm S { state A { entry x = "oops } }\n')
    assert where(d) == ("E-LEX", 1, 29)
    assert d.message == "unterminated string"


@pytest.mark.parametrize("char", ["@", "#", "$", "~", "§"])
def test_stray_character_is_rejected_at_its_position(char):
    d = fatal(f"pmodel P {{\n  local link L {{ def {{ }} }}\n  {char}\n}}\n")
    assert (d.span.line, d.span.column) == (3, 3)
    assert repr(char) in d.message or f"'{char}'" in d.message


def test_stray_character_is_a_lexical_error():
    d = fatal("pmodel P { local link L { def { } } @ }")
    assert where(d) == ("E-LEX", 1, 37)


def test_clock_reset_outside_an_action_is_a_syntax_error():
    # `#` is a token of actions (`#C`); elsewhere it is out of place, not an unknown character.
    d = fatal("pmodel P { local link L { def { } } # }")
    assert where(d) == ("E-SYNTAX", 1, 37)


def test_stray_characters_inside_machines_are_errors_with_hints():
    d = fatal("stm S { state A { entry $op(1) ; #C ; @x } }")
    assert where(d) == ("E-LEX", 1, 39)
    assert "a name" in d.hint


# ----------------------------------------------------------------------------- units


def test_unit_separated_from_a_name_is_not_a_unit():
    # Short unit symbols are suffixes only when glued to a number or `)`: `a m` is two names.
    d = fatal("const c: real = a m\n")
    assert where(d) == ("E-SYNTAX", 1, 19)
    assert d.message == "unexpected name 'm'"


def test_unit_separated_from_a_number_is_not_a_unit():
    d = fatal("const c: real = 2 m\n")
    assert where(d) == ("E-SYNTAX", 1, 19)
    assert d.message == "unexpected name 'm'"


def test_unit_after_a_name_in_a_pose_starts_a_new_field():
    # In a pose, `m` after a value is read as the next field's name, which then lacks `= e`.
    d = fatal("pmodel P { local link L { pose { x = a m } } }")
    assert where(d) == ("E-SYNTAX", 1, 42)
    assert d.message == "unexpected '}'"
    assert "'='" in d.hint
    # …and with a value, `m` is a field that poses do not have.
    result = parse_text("pmodel P { local link L { pose { x = a m = 1 } } }", PATH)
    assert result.file is not None
    (member,) = result.diagnostics
    assert where(member) == ("E-MEMBER", 1, 40)
    assert "'m'" in member.message


def test_unit_word_after_a_name_is_not_a_unit():
    d = fatal("const c: real = a metre\n")
    assert where(d) == ("E-SYNTAX", 1, 19)


# ----------------------------------------------------------------------------- non-fatal


def test_duplicate_members_are_reported_but_the_file_is_kept():
    result = parse_text(
        "pmodel P { local body B { def {\n"
        '  mesh { shape "a" shape "b" }\n'
        "  inertial information { mass 1 mass 2 }\n"
        "} } }\n",
        PATH,
    )
    assert result.file is not None
    assert [where(d) for d in result.diagnostics] == [
        ("E-DUPLICATE", 2, 20),
        ("E-DUPLICATE", 3, 33),
    ]
    assert "'shape'" in result.diagnostics[0].message
    assert "'mass'" in result.diagnostics[1].message


# ----------------------------------------------------------------------------- robustness

DEPTH = 200

NASTY = {
    "only opening braces": "{{{{{{",
    "only closing braces": "}}}}}}",
    "balanced braces": "{ { } { { } } }",
    "only operators": "+-*/^<=>==!=/\\\\/ cat % . :: ;",
    "only punctuation": "(|[|<>|]|)),;:?",
    "lone caret": "^",
    "caret escapes": "pmodel ^ { ^^x }",
    "unicode": "pmodel Ω { local link λ { def { } } } ≈ × ∀",
    "emoji": "pmodel P { equation 🤖 == 1 }",
    "nul bytes": "pmodel\x00P { \x00 }",
    "nul only": "\x00\x00\x00",
    "control characters": "\x01\x02\x1b[31m pmodel P {}",
    "byte order mark in the middle": "pmodel P {}\ufeffpmodel Q {}",
    "lone surrogate": "pmodel \ud800 {}",
    "form feed and vertical tab": "pmodel\fP\v{ }",
    "deep parentheses": "const c: real = " + "(" * DEPTH + "1" + ")" * DEPTH,
    "deep unclosed parentheses": "const c: real = " + "(" * DEPTH,
    "deep braces": "pmodel P " + "{" * DEPTH + "}" * DEPTH,
    "deep nested states": "stm S {" + " state A {" * DEPTH + "}" * DEPTH + "}",
    "deep nested calls": "const c: real = " + "f(" * DEPTH + "x" + ")" * DEPTH,
    "deep vectors": "const c: real = " + "(|" * 100 + "1" + "|)" * 100,
    "huge integer": "const c: int = " + "9" * 5000,
    "huge exponent": "const c: real = 1e+99999999999999999999",
    "huge index": "pmodel P { local link L { index i : [0, " + "9" * 400 + ") } }",
    "number glued to letters": "const c: real = 12abc",
    "only keywords": "pmodel link joint body sensor actuator local def pose",
    "keyword soup in braces": "pmodel P { def def pose pose local local }",
    "unterminated string at end": 'const s: string = "',
    "unterminated comment at end": "/*",
    "comment markers in a string": 'const s: string = "/* // */"',
    "stray end of comment": "*/",
    "whitespace only": " \t\r\n\r\n  \t",
    "very long line": "pmodel P { " + "local link L { def { } } " * 300 + "}",
    "long sum": "const c: real = " + " + ".join(["1"] * 100),
    "repeated garbage": "}{" * 500,
    "crlf in string": 'const s: string = "a\r\nb"',
    "mapping with junk": "map M dmodel to pmodel { operation { } }",
}


@pytest.mark.parametrize("text", NASTY.values(), ids=NASTY.keys())
def test_parsing_never_raises_and_file_is_none_iff_fatal(text):
    result = parse_text(text, PATH)
    check_invariants(result)


def test_some_nasty_inputs_are_accepted():
    for key in ("balanced braces", "deep parentheses", "deep nested calls", "deep vectors",
                "whitespace only", "very long line", "long sum", "crlf in string",
                "comment markers in a string", "huge integer", "deep nested states"):
        result = parse_text(NASTY[key], PATH)
        if key == "balanced braces":
            assert result.file is None, key
        else:
            assert result.file is not None and result.diagnostics == (), key


@pytest.mark.parametrize(
    "text",
    [
        "const c: real = " + " + ".join(["1"] * 1000),
        "pmodel P { equation " + " /\\ ".join(["a == 1"] * 1000) + " }",
        "const c: real = " + "-" * 1000 + "1",
        "const c: real = " + "f(" * 1000 + "x" + ")" * 1000,
        "const c: real = " + "(|" * 400 + "1" + "|)" * 400,
    ],
    ids=["sum", "conjunction", "unary minus", "calls", "vectors"],
)
def test_parsing_long_expressions_never_raises(text):
    result = parse_text(text, PATH)
    check_invariants(result)
