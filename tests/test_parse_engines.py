"""The parse engines give the same results (cyphy/lang/grammar.py): lark-cython's C LALR loop fed
by cyphy's one-pass lexer (cyphy/lang/lexer.py), used for every parse when lark-cython is
installed, and fed by lark-cython's own contextual lexer, against Lark's own pure-Python lexer
and loop, on every model file of the examples, the tests' data, the library and the corpus
(when ``../shared`` is there), each whole and cut short at several points (syntax errors).
Compared are the syntax trees with every field, spans included (the AST's equality skips
spans), and the diagnostics; the tokens the one-pass lexer cuts from texts made to trip it
(keywords where names go, units, comments, strings across lines) against Lark's contextual
lexer's; and cyphy parses the same without lark-cython at all."""

from __future__ import annotations

import dataclasses
import enum
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from conftest import CORPUS, EXAMPLES, ROOT
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy.lang import lexer, parser
from cyphy.lang.grammar import Engine, compiled, pure
from lark.exceptions import UnexpectedInput

pytestmark = pytest.mark.skipif(compiled() is None, reason="lark-cython is not installed")

SUFFIXES = (".pm", ".rst", ".rsm")
#: Where each file is cut short: fractions of its length (mid-token, mid-block, mid-line).
CUTS = (0.13, 0.37, 0.5, 0.71, 0.93)


def _files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*") if p.suffix in SUFFIXES and p.is_file())


def _ours() -> list[Path]:
    return (_files(EXAMPLES) + _files(ROOT / "tests" / "data")
            + _files(ROOT / "cyphy" / "lang" / "library"))


def _corpus() -> list[Path]:
    shared = CORPUS.parent
    return _files(shared) if shared.is_dir() else []


def canonical(node: Any) -> Any:
    """Every field of every node, spans included, as nested tuples (so that two trees equal
    here agree on everything the later stages and the diagnostics read)."""
    if dataclasses.is_dataclass(node) and not isinstance(node, type):
        return (type(node).__name__,
                tuple((f.name, canonical(getattr(node, f.name)))
                      for f in dataclasses.fields(node)))
    if isinstance(node, (tuple, list)):
        return (type(node).__name__, tuple(canonical(x) for x in node))
    if isinstance(node, enum.Enum):
        return (type(node).__name__, node.value)
    assert node is None or type(node) in (str, int, float, bool), (type(node), node)
    return node


def _texts(path: Path) -> list[tuple[str, str]]:
    text = path.read_text(encoding="utf-8", errors="replace")
    return [(f"{path.name} whole", text)] + [
        (f"{path.name} cut at {cut}", text[:int(len(text) * cut)]) for cut in CUTS]


def _outcome(engine: Any, text: str) -> Any:
    try:
        return canonical(parser.parse_with(engine, text, "m.pm"))
    except UnexpectedInput as err:  # only whether both fail matters: pure Lark describes it
        return ("syntax error", type(err).__name__)


def _lark_cythons_lexer() -> Engine:
    """lark-cython's loop fed by its own contextual lexer (what runs if the one-pass lexer
    cannot be built for the grammar)."""
    fast = compiled()
    assert fast is not None and fast.lexer is not None
    return dataclasses.replace(fast, lexer=None)


def _compare(paths: list[Path], monkeypatch: pytest.MonkeyPatch | None) -> tuple[int, int]:
    """The engines on every text; with ``monkeypatch``, ``parse_text`` too, with and without
    lark-cython. (Parses, syntax errors) counted."""
    fast, slow, contextual = compiled(), pure(), _lark_cythons_lexer()
    assert fast is not None
    parses = failures = 0
    for path in paths:
        for label, text in _texts(path):
            got, expected = _outcome(fast, text), _outcome(slow, text)
            assert got == expected, label
            assert _outcome(contextual, text) == expected, label
            parses += 1
            failures += got[0] == "syntax error"
            if monkeypatch is None:
                continue
            # What a user gets: parse_text, with lark-cython and with pure Lark alone.
            with_fast = canonical(parser.parse_text(text, "m.pm"))
            with monkeypatch.context() as m:
                m.setattr(parser, "compiled", lambda: None)
                assert canonical(parser.parse_text(text, "m.pm")) == with_fast, label
    return parses, failures


def test_the_engines_agree_on_our_files_whole_and_cut_short(monkeypatch):
    paths = _ours()
    assert len(paths) >= 40, paths
    parses, failures = _compare(paths, monkeypatch)
    # Most cut-short texts are syntax errors, every whole file parses: both paths exercised.
    assert failures >= len(paths) * 3, (parses, failures)
    assert parses - failures >= len(paths), (parses, failures)


@pytest.mark.skipif(not CORPUS.parent.is_dir(), reason="../shared/corpus is absent")
def test_the_engines_agree_on_the_corpus_whole_and_cut_short():
    paths = _corpus()
    assert len(paths) >= 100, len(paths)
    parses, failures = _compare(paths, None)
    assert failures >= len(paths) * 3 and parses - failures >= len(paths), (parses, failures)


def test_a_compiled_parse_leaves_no_token_in_the_tree():
    text = (EXAMPLES / "dcmotor" / "DCMotorBase.rsm").read_text()
    fast = compiled()
    assert fast is not None
    result = parser.parse_with(fast, text, "m.pm")
    assert result.file is not None and not parser.contains_lark_objects(result)


def test_the_diagnostics_of_a_syntax_error_are_pure_larks():
    """lark-cython's errors carry no interactive parser: the file is parsed again by Lark."""
    text = "pmodel P {\n  local link L {\n    pose { x = 1 y = }\n  }\n}\n"
    with pytest.raises(UnexpectedInput):
        parser.parse_with(compiled(), text, "m.pm")
    result = parser.parse_text(text, "m.pm")
    assert result.file is None
    (diag,) = result.diagnostics
    assert (diag.span.line, diag.span.column, diag.code.id) == (3, 22, "E-SYNTAX"), diag
    assert diag.message == "unexpected '}'", diag


def test_cyphy_parses_without_lark_cython():
    """A machine without lark-cython (it is imported only if present) parses with pure Lark
    and gets the same tree: the child process cannot import it."""
    path = EXAMPLES / "dcmotor" / "DCMotorBase.rsm"
    code = (
        "import sys; sys.modules['lark_cython'] = None; sys.path.insert(0, 'tests')\n"
        "from cyphy.lang import grammar, parser\n"
        "assert grammar.compiled() is None and grammar.lark_cython is None\n"
        f"r = parser.parse_text(open({str(path)!r}).read(), 'm.pm')\n"
        "from test_parse_engines import canonical\n"
        "print(repr(canonical(r)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)},
                         timeout=120)
    assert out.returncode == 0, out.stderr
    here = parser.parse_text(path.read_text(), "m.pm")
    assert here.file is not None
    assert out.stdout.strip() == repr(canonical(here))


# ----- the one-pass lexer against Lark's contextual lexer, token by token

def _shifted(engine: Engine, text: str) -> tuple[str, list[tuple[Any, ...]]]:
    """Whether ``engine`` parses ``text``, and every token its parser shifted (up to the
    error), with its type, text and positions."""
    tokens: list[tuple[Any, ...]] = []

    def shift(tok: Any) -> Any:
        tokens.append((tok.type, str(tok.value), tok.start_pos, tok.line, tok.column,
                       tok.end_pos, tok.end_line, tok.end_column))
        return tok

    callbacks: dict[Any, Any] = {rule: _nothing for rule in engine.lark.rules}
    callbacks.update({term.name: shift for term in engine.lark.terminals})
    try:
        engine.parse(text, callbacks)
    except UnexpectedInput:
        return "syntax error", tokens
    return "parsed", tokens


def _nothing(symbols: list[Any]) -> None:
    return None


#: Text that the one-pass lexer must cut as the contextual lexer does: keywords and unit
#: words where a name may go, exponents and unit suffixes against names, the operators that
#: share a first character, comments, strings with line breaks, characters no terminal takes.
TRICKY = ("link", "mass", "pose", "const", "local", "def", "kg", "m", "s", "metres", "rad",
          "^", "^x", "x^2", "5kg", "(1)m", "2 metres", "3.5e-2", "7", "(|", "|)", "|", "==",
          "=", "=>", "<=", "/\\", "\\/", "//c\n", "/*\nc*/", "/", "::", ":", "\"a\nb\"",
          "\"", "@", "\t", "\n", " ", "{", "}", "(", ")", ",", "-", "not", "true")


def _tokens_at(text: str) -> list[int]:
    return [i for i in range(1, len(text)) if text[i - 1].isspace() != text[i].isspace()]


@settings(max_examples=300, deadline=None)
@given(st.data())
def test_the_one_pass_lexer_cuts_the_tokens_larks_contextual_lexer_does(data):
    """Lark's pure engine is the oracle: the same tokens are shifted, with the same
    positions, up to the same outcome, on example files with tricky text put in or taken
    out at token boundaries."""
    fast = compiled()
    assert fast is not None and fast.lexer is not None
    path = data.draw(st.sampled_from(_ours()), label="file")
    text = path.read_text(encoding="utf-8")
    for _ in range(data.draw(st.integers(1, 3), label="edits")):
        at = data.draw(st.sampled_from(_tokens_at(text) or [0]), label="at")
        cut = data.draw(st.integers(0, 12), label="cut")
        text = text[:at] + data.draw(st.sampled_from(TRICKY), label="put") + text[at + cut:]
    assert _shifted(fast, text) == _shifted(pure(), text)


def test_a_keyword_where_a_name_goes_is_cut_by_the_states_own_lexer(monkeypatch):
    """``link``, ``mass`` and ``pose`` are keywords that the one pass reads as such; where
    the parser takes a name only, the state's own lexer cuts the text again (a name), and
    the tree is Lark's."""
    text = ("pmodel P {\n const mass: real = 1.0\n local link link {\n"
            "  def { inertial information { mass mass } }\n  pose { x = 5m y = 2^mass }\n"
            " }\n}\n")
    fast = compiled()
    assert fast is not None
    calls: list[int] = []
    again = lexer._contextual_token

    def counted(*args: Any) -> Any:
        calls.append(1)
        return again(*args)

    monkeypatch.setattr(lexer, "_contextual_token", counted)
    assert _outcome(fast, text) == _outcome(pure(), text)
    assert _outcome(fast, text)[0] == "ParseResult", _outcome(fast, text)
    assert len(calls) >= 6, calls  # mass, link, mass (twice), … read again as names
    assert _shifted(fast, text) == _shifted(pure(), text)


def test_a_character_no_terminal_takes_is_a_syntax_error_at_its_place():
    text = "pmodel P {\n local link L { pose { x = 1 @ } }\n}\n"
    fast = compiled()
    assert fast is not None
    with pytest.raises(UnexpectedInput):
        parser.parse_with(fast, text, "m.pm")
    (diag,) = parser.parse_text(text, "m.pm").diagnostics
    assert (diag.span.line, diag.span.column, diag.code.id) == (2, 30, "E-LEX"), diag


def test_the_lines_and_columns_after_a_string_across_lines_and_a_comment_are_larks():
    text = ('pmodel P {\n local link L {\n  pose { x = "a\nb\n c" y = 1 /* d\n e */ z = 2 }\n'
            ' }\n}\n')
    fast = compiled()
    assert fast is not None
    outcome, tokens = _shifted(fast, text)
    assert (outcome, tokens) == _shifted(pure(), text)
    assert outcome == "parsed" and ("NUMBER", "2", 70, 6, 11, 71, 6, 12) in tokens, tokens


@pytest.mark.parametrize("text", ["", "  \n", "// only a comment\n", "/* x */", "package p",
                                  "package p\n// end", '"', "/*", "package p\n@"])
def test_texts_with_few_tokens_or_none_parse_as_larks(text):
    """The end token's place when no token or one came before it, and an unfinished string
    or comment at the end."""
    fast = compiled()
    assert fast is not None
    assert _outcome(fast, text) == _outcome(pure(), text)
    assert _shifted(fast, text) == _shifted(pure(), text)
