"""Numeric evaluation of constant expressions (cyphy.model.evaluate, sdf.md decision 5)."""

from __future__ import annotations

import math
import re
from typing import Mapping

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy.expr import Expr, Num, Quantity
from cyphy.lang.parser import grammar, parse_text
from cyphy.model.array import Array
from cyphy.model.evaluate import (
    MATH_FUNCTIONS,
    UNIT_FACTORS,
    EvalError,
    UnboundName,
    Value,
    coerce,
    evaluate,
    free_names,
)

PREFIX = "const c: real = "


def parse(src: str) -> Expr:
    """The expression ``src``, parsed as a constant's value so tests read like models."""
    result = parse_text(PREFIX + src, "t.rsm")
    assert result.file is not None, result.diagnostics
    return result.file.items[0].value


def ev(src: str, env: Mapping[str, object] | None = None, **kwargs: object) -> Value:
    return evaluate(parse(src), env or {}, **kwargs)  # type: ignore[arg-type]


def fails(src: str, env: Mapping[str, object] | None = None) -> EvalError:
    with pytest.raises(EvalError) as info:
        ev(src, env)
    return info.value


def column(src_offset: int) -> int:
    """The 1-based column of character ``src_offset`` of the expression in the parsed line."""
    return len(PREFIX) + src_offset + 1


# --------------------------------------------------------------------------- int and real


@pytest.mark.parametrize(
    ("src", "expected", "kind"),
    [
        ("7/2", 3.5, float),
        ("6/2", 3.0, float),
        ("2*3", 6, int),
        ("2+3-10", -5, int),
        ("7 % 3", 1, int),
        ("-7 % 3", 2, int),
        ("7.5 % 2", 1.5, float),
        ("2^10", 1024, int),
        ("2^-1", 0.5, float),
        ("2.0*3", 6.0, float),
        ("0.05", 0.05, float),
        ("1e+16", 1e16, float),
        ("- 0.5", -0.5, float),
        ("-2^2", -4, int),
        ("2 cat 3", 8, int),
        ("x^{2}", 9, int),
    ],
)
def test_integer_and_real_arithmetic(src: str, expected: Value, kind: type) -> None:
    value = ev(src, {"x": 3})
    assert value == expected
    assert type(value) is kind


def test_coerce_real_makes_a_float() -> None:
    value = coerce(7, "real")
    assert value == 7.0 and type(value) is float


@pytest.mark.parametrize(
    ("value", "declared", "expected"),
    [(4.0, "int", 4), (3, "nat", 3), (0, "nat", 0), (True, "boolean", True), ("a", "string", "a")],
)
def test_coerce_accepts(value: Value, declared: str, expected: Value) -> None:
    result = coerce(value, declared)
    assert result == expected and type(result) is type(expected)


@pytest.mark.parametrize(
    ("value", "declared"),
    [(2.5, "int"), (2.5, "nat"), (-1, "nat"), (1, "boolean"), (True, "real"), (True, "int"),
     ("1", "real"), (1, "string"), (np.zeros(3), "real")],
)
def test_coerce_rejects(value: Value, declared: str) -> None:
    with pytest.raises(EvalError):
        coerce(value, declared)


def test_coerce_int_set_to_a_fraction_says_why() -> None:
    ref = parse("2.5")
    with pytest.raises(EvalError) as info:
        coerce(ev("2.5"), "int", ref.span)  # type: ignore[attr-defined]
    assert "whole number" in info.value.message and "2.5" in info.value.message
    assert info.value.span == ref.span  # type: ignore[attr-defined]
    assert info.value.hint


# --------------------------------------------------------------------------- units


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("0.03m", 0.03),
        ("3cm", 0.03),
        ("5mm", 0.005),
        ("2km", 2000.0),
        ("0.01kg", 0.01),
        ("500g", 0.5),
        ("20ms", 0.02),
        ("2s", 2.0),
        ("1rad", 1.0),
        ("90deg", math.pi / 2),
        ("3N", 3.0),
        ("1.0 metre", 1.0),
        ("2 meters", 2.0),
        ("2.0 second", 2.0),
        ("1 kilogram", 1.0),
        ("4 newtons", 4.0),
        ("180 degrees", math.pi),
        ("1 radian", 1.0),
    ],
)
def test_units_convert_to_si(src: str, expected: float) -> None:
    value = ev(src)
    assert value == pytest.approx(expected, rel=1e-15)
    assert type(value) is float


def test_unit_on_a_parenthesised_expression() -> None:
    value = ev("(0.085*cos(2*j*PI/24))m", {"j": 1, "PI": math.pi})
    assert value == pytest.approx(0.085 * math.cos(math.pi / 12))


def test_every_unit_the_grammar_accepts_has_a_factor() -> None:
    pattern = grammar().get_terminal("UNIT").pattern.value
    units = set(re.findall(r"(?<=[:|])[A-Za-z]+(?=[|)])", pattern))
    assert "metre" in units and "deg" in units
    assert units <= set(UNIT_FACTORS)


def test_unknown_unit_is_an_error() -> None:
    with pytest.raises(EvalError, match="unknown unit 'furlong'"):
        evaluate(Quantity(Num("1"), "furlong"), {})


# --------------------------------------------------------------------------- functions and PI


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("sin(PI/2)", 1.0),
        ("cos(0)", 1.0),
        ("tan(PI/4)", 1.0),
        ("asin(1)", math.pi / 2),
        ("acos(1)", 0.0),
        ("atan(1)", math.pi / 4),
        ("atan2(1, 0)", math.pi / 2),
        ("sqrt(16)", 4.0),
        ("exp(0)", 1.0),
        ("log(exp(2))", 2.0),
        ("abs(-3)", 3),
        ("sgn(-2.5)", -1.0),
        ("sgn(0)", 0),
        ("det([|1,2;3,4|])", -2.0),
        ("dot((|1,2,3|), (|4,5,6|))", 32.0),
        ("norm((|3,4|))", 5.0),
    ],
)
def test_scalar_math_functions(src: str, expected: float) -> None:
    assert ev(src, {"PI": math.pi}) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("transpose([|1,2;3,4|])", [[1, 3], [2, 4]]),
        ("adj([|1,2;3,4|])", [[1, 3], [2, 4]]),
        ("inverse([|2,0;0,4|])", [[0.5, 0], [0, 0.25]]),
        ("identity(2)", [[1, 0], [0, 1]]),
        ("zeroes(2)", [[0, 0], [0, 0]]),
        ("zeroes(1, 3)", [[0, 0, 0]]),
        ("skew((|1,2,3|))", [[0, -3, 2], [3, 0, -1], [-2, 1, 0]]),
        ("cross((|1,0,0|), (|0,1,0|))", [0, 0, 1]),
        ("submatrix([|1,2,3;4,5,6;7,8,9|])(1, 1, 2, 2)", [[5, 6], [8, 9]]),
        ("Rot((|0,0,1|), PI/2)", [[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
        ("ScrewAxis((|0,0,1|), (|0,0,0|))", [0, 0, 1, 0, 0, 0]),
    ],
)
def test_matrix_math_functions(src: str, expected: list[object]) -> None:
    value = ev(src, {"PI": math.pi})
    assert isinstance(value, Array)
    np.testing.assert_allclose(value, np.array(expected, dtype=float), atol=1e-12)


def test_skew_is_the_cross_product_matrix() -> None:
    env = {"u": np.array([1.0, -2.0, 0.5]), "v": np.array([0.3, 4.0, -1.0])}
    np.testing.assert_allclose(ev("skew(u) * v", env), ev("cross(u, v)", env))


def test_adjoint_and_ad_have_the_block_layout() -> None:
    env = {"T": np.array([[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]], dtype=float)}
    adjoint = ev("Adjoint(T)", env)
    assert isinstance(adjoint, Array) and adjoint.shape == (6, 6)
    np.testing.assert_allclose(adjoint[3:, :3], ev("skew((|1,2,3|))"))
    ad = ev("ad((|1,2,3,4,5,6|))")
    assert isinstance(ad, Array)
    np.testing.assert_allclose(ad[3:, :3], ev("skew((|4,5,6|))"))
    np.testing.assert_allclose(ad[:3, 3:], np.zeros((3, 3)))


def test_a_models_own_pi_wins_over_the_library() -> None:
    own = ev("2*i*PI", {"i": 1, "PI": 3.1415})
    assert own == pytest.approx(6.283) and own != pytest.approx(2 * math.pi)
    assert ev("cos(PI)", {"PI": 3.1415}) == pytest.approx(math.cos(3.1415))
    assert ev("cos(PI)", {"PI": math.pi}) == -1.0


def test_functions_given_by_the_caller_are_merged_over_the_library() -> None:
    functions = {"twice": lambda x: 2 * x, "sin": lambda x: 42}
    assert ev("twice(3) + sin(0)", functions=functions) == 48
    assert ev("cos(0)", functions=functions) == 1.0
    assert "sin" in MATH_FUNCTIONS and "PI" not in MATH_FUNCTIONS


# --------------------------------------------------------------------------- vectors, matrices


def test_vector_literals_are_1d() -> None:
    for src in ("(|1,0,0|)", "[|1,0,0|]"):
        value = ev(src)
        assert isinstance(value, Array) and value.shape == (3,)
        np.testing.assert_array_equal(value, [1.0, 0.0, 0.0])


def test_matrix_literals_are_2d_and_read_only() -> None:
    value = ev("[|1,2;3,4|]")
    assert isinstance(value, Array) and value.shape == (2, 2)
    assert ev("(|1,0;0,1|)").shape == (2, 2)  # type: ignore[union-attr]
    assert ev("[|1;2;3|]").shape == (3, 1)  # type: ignore[union-attr]
    with pytest.raises(TypeError):
        value[0, 0] = 9  # type: ignore[index]
    with pytest.raises(AttributeError):
        value.flat = (9.0,)  # type: ignore[misc]


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("[|1,0;0,1|] * (|2,3|)", [2, 3]),
        ("[|1,2;3,4|] * [|0,1;1,0|]", [[2, 1], [4, 3]]),
        ("(|1,2|) * [|1,2;3,4|]", [7, 10]),
        ("2 * (|1,2,3|)", [2, 4, 6]),
        ("(|1,2,3|) * 0.5", [0.5, 1, 1.5]),
        ("(|1,2,3|) / 2", [0.5, 1, 1.5]),
        ("(|1,2|) + (|3,4|)", [4, 6]),
        ("(|1,2|) - (|3,4|)", [-2, -2]),
        ("- (|1,2|)", [-1, -2]),
        ("[|1,1;0,1|] ^ 3", [[1, 3], [0, 1]]),
        ("[|2,0;0,2|] cat -1", [[0.5, 0], [0, 0.5]]),
        ("((|1,2|))m", [1, 2]),
        ("((|1,2|))cm", [0.01, 0.02]),
    ],
)
def test_vector_and_matrix_arithmetic(src: str, expected: list[object]) -> None:
    value = ev(src)
    assert isinstance(value, Array)
    np.testing.assert_allclose(value, np.array(expected, dtype=float))


def test_indexing_counts_from_one() -> None:
    env = {"Axis": np.array([1.0, 0.0, 0.0]), "M": np.array([[1.0, 2.0], [3.0, 4.0]])}
    assert ev("Axis[1]", env) == 1.0
    assert ev("(|4,5,6|)[3]") == 6.0
    assert ev("M[1,2]", env) == 2.0
    assert ev("M[2,1]", env) == 3.0
    np.testing.assert_array_equal(ev("M[2]", env), [3.0, 4.0])


def test_cross_product_matrix_from_an_axis_as_models_write_it() -> None:
    env = {"Axis": ev("(|1,0,0|)")}
    src = "[|0, -Axis[3],Axis[2];Axis[3],0,-Axis[1];-Axis[2],Axis[1],0|]"
    np.testing.assert_array_equal(ev(src, env), ev("skew(Axis)", env))


@pytest.mark.parametrize(
    ("src", "fragment"),
    [
        ("(|1,2,3|)[0]", "out of range 1..3"),
        ("(|1,2,3|)[4]", "out of range 1..3"),
        ("(|1,2,3|)[1.0]", "must be an integer"),
        ("M[1,1,1]", "at most 2"),
        ("x[1]", "only vectors and matrices"),
    ],
)
def test_bad_indexing(src: str, fragment: str) -> None:
    assert fragment in fails(src, {"M": np.eye(2), "x": 3}).message


# --------------------------------------------------------------------------- conditions, logic


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("if x > 0 then 1 else 2 end", 1),
        ("if x < 0 then 1 else 2 end", 2),
        ("if x < 0 then sqrt(x) else 0 end", 0),
        ("if x > 0 then 1 else if x < 0 then -1 else 0 end end", 1),
        ("1 < 2", True),
        ("2 <= 2", True),
        ("3 > 4", False),
        ("3 >= 4.5", False),
        ("2 == 2.0", True),
        ("1 != 2", True),
        ("(|1,2|) == [|1,2|]", True),
        ("(|1,2|) == (|1,2,3|)", False),
        ('"box" == "box"', True),
        ("true /\\ false", False),
        ("true \\/ false", True),
        ("false => true", True),
        ("true => false", False),
        ("true <=> true", True),
        ("not (1 < 2)", False),
        ("x == 0 /\\ 1/x > 2", False),
        ("x != 0 \\/ 1/x > 2", True),
        ("x == 0 => 1/x > 2", True),
    ],
)
def test_conditions_comparisons_and_connectives(src: str, expected: Value) -> None:
    value = ev(src, {"x": 3})
    assert value == expected and type(value) is type(expected)


# --------------------------------------------------------------------------- errors


def test_unknown_name_is_named_and_located() -> None:
    src = "2 * HEIGHT + 1"
    error = fails(src)
    assert isinstance(error, UnboundName)
    assert error.name == "HEIGHT" and "HEIGHT" in error.message
    assert (error.span.line, error.span.column) == (1, column(src.index("HEIGHT")))
    assert (error.span.end_line, error.span.end_column) == (1, column(src.index("HEIGHT") + 6))


def test_unknown_qualified_name_uses_its_full_text_and_suggests() -> None:
    error = fails("Treel::HEIGHT", {"Treel::HIGHT": 1.0})
    assert isinstance(error, UnboundName) and error.name == "Treel::HEIGHT"
    assert "Treel::HIGHT" in error.hint


def test_qualified_names_and_paths_are_looked_up_by_text() -> None:
    env = {"Treel::HEIGHT": 0.05, "LMotor::T": 2}
    assert ev("Treel::HEIGHT * 2", env) == 0.1
    assert ev("LMotor.T + 1", env) == 3


@pytest.mark.parametrize(
    ("src", "fragment"),
    [
        ("1/0", "division by zero"),
        ("1.5/0.0", "division by zero"),
        ("5 % 0", "division by zero"),
        ("0^-1", "division by zero"),
        ("(|1,2|)/0", "division by zero"),
        ("sqrt(-1)", "sqrt"),
        ("log(0)", "log"),
        ("asin(2)", "asin"),
        ("sin(1, 2)", "sin takes 1 argument, got 2"),
        ("atan2(1)", "atan2 takes 2 arguments, got 1"),
        ("zeroes(1, 2, 3)", "zeroes takes 1 to 2 arguments, got 3"),
        ("sin((|1,2|))", "sin expects a number"),
        ("identity(-1)", "natural number"),
        ("inverse([|1,2;2,4|])", "singular"),
        ("det([|1,2,3|])", "matrix"),
        ("submatrix(identity(2))(1, 1, 2, 2)", "does not fit"),
        ("frobnicate(1)", "unknown function 'frobnicate'"),
        ("x(1)", "constant, not a function"),
        ("if 1 then 2 else 3 end", "condition of 'if' must be a boolean"),
        ("not 1", "boolean"),
        ("1 /\\ true", "boolean"),
        ("true + 1", "boolean"),
        ('"a" + 1', "string"),
        ('1 < "a"', "string"),
        ("1 == true", "cannot compare"),
        ("(|1,2|) + 1", "cannot combine"),
        ("(|1,2|) + (|1,2,3|)", "cannot combine"),
        ("(|1,2|) * (|1,2|)", "two vectors"),
        ("[|1,2;3,4|] * (|1,2,3|)", "cannot multiply"),
        ("[|1,2;3|]", "different lengths"),
        ("[|1,2,3|] ^ 2", "square matrix"),
        ("(-8)^0.5", "no real power"),
        ("10^10^10", "too large"),
        ("1e308 * 10", "finite"),
        ("exp(1000)", "overflow"),
        ("1 < 2 < 3", "cannot order"),
        ("derivative(x)", "derivative"),
        ("integral(x, 0, 1)", "integral"),
        ("<1, 2>", "sequence"),
        ('Geom (| geomType = "box" |)', "record"),
        ("3(4)", "named function"),
        ("f(1).y", "field"),
    ],
)
def test_errors_are_eval_errors_with_a_clear_message(src: str, fragment: str) -> None:
    error = fails(src, {"x": 3})
    assert fragment in error.message
    assert error.span.line == 1 and error.span.column >= column(0)


def test_error_points_at_the_offending_node() -> None:
    src = "1 + sqrt(0 - 4)"
    error = fails(src)
    assert error.span.column == column(src.index("sqrt"))
    src = "2 * (3 + 1/0)"
    assert fails(src).span.column == column(src.index("1/0"))


def test_a_function_raising_value_error_becomes_an_eval_error() -> None:
    def picky(x: Value) -> Value:
        raise ValueError("wants something else")

    with pytest.raises(EvalError, match="picky wants something else"):
        ev("picky(1)", functions={"picky": picky})


def test_bad_env_values_are_eval_errors() -> None:
    fails("x + 1", {"x": [1, 2]})
    assert ev("x + 1", {"x": np.int64(2)}) == 3
    assert ev("x[2]", {"x": np.array([1, 2])}) == 2.0


def test_nesting_beyond_the_recursion_limit_is_an_eval_error() -> None:
    assert ev("+".join(["1"] * 200)) == 200
    with pytest.raises(EvalError, match="deeply nested"):
        ev("+".join(["1"] * 5000))


# --------------------------------------------------------------------------- free_names


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("1 + 2", set()),
        ("(0.085*cos(2*j*PI/24))m", {"j", "PI"}),
        ("Treel::HEIGHT / 2 + LMotor.T", {"Treel::HEIGHT", "LMotor::T"}),
        ("submatrix(M)(0, k, 3, 3)", {"M", "k"}),
        ("if a then b[i] else sin(c) end", {"a", "b", "i", "c"}),
        ("[| 0, -Axis[3]; Axis[2], 0 |]", {"Axis"}),
        ("sin(sin)", {"sin"}),
    ],
)
def test_free_names(src: str, expected: set[str]) -> None:
    assert free_names(parse(src)) == expected


def test_free_names_are_exactly_what_evaluation_needs() -> None:
    expr = parse("(0.085*cos(2*j*PI/24))m + Treel::HEIGHT")
    env = {name: 1 for name in free_names(expr)}
    evaluate(expr, env)
    for missing in env:
        with pytest.raises(UnboundName):
            evaluate(expr, {k: v for k, v in env.items() if k != missing})


# --------------------------------------------------------------------------- property


def _arithmetic() -> st.SearchStrategy[str]:
    """Arithmetic text over small ints. Powers take a parenthesised base and a literal exponent
    in -2..3, so values stay small; otherwise the text relies on the shared precedence
    (``+ -`` < ``* / %`` < unary ``-`` < ``^``, left-associative except ``^``)."""
    leaves = st.integers(0, 9).map(str)

    def extend(children: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        return st.one_of(
            st.tuples(children, st.sampled_from("+-*/%"), children).map(" ".join),
            st.tuples(children, st.integers(-2, 3)).map(lambda t: f"( {t[0]} ) ^ {t[1]}"),
            children.map(lambda c: f"( {c} )"),
            children.map(lambda c: f"- {c}"),
        )

    return st.recursive(leaves, extend, max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(_arithmetic())
def test_evaluate_agrees_with_python(src: str) -> None:
    try:
        expected = eval(src.replace("^", "**"))  # noqa: S307 - digits and operators only
    except (ZeroDivisionError, OverflowError):
        expected = None
    if expected is None or isinstance(expected, complex) or not math.isfinite(expected):
        with pytest.raises(EvalError):
            ev(src)
        return
    value = ev(src)
    assert value == expected
    assert type(value) is type(expected)


@settings(max_examples=300, deadline=None)
@given(_arithmetic(), st.integers(-3, 3))
def test_compiled_evaluation_equals_the_interpreter(src: str, j: int) -> None:
    """``evaluate_fast`` (closures, cached per expression) gives the interpreter's value, or
    the interpreter's very error."""
    from cyphy.model.evaluate import evaluate_fast

    expr = parse_text(f"const c: real = (({src}) + j)m * cos(j)", "t.rsm").file.items[0].value
    env = {"j": j}
    try:
        expected: object = evaluate(expr, env)
    except EvalError as err:
        with pytest.raises(EvalError) as info:
            evaluate_fast(expr, env)
        assert info.value.message == err.message
        return
    for _ in range(2):  # compiled on the first call, cached on the second
        value = evaluate_fast(expr, env)
        assert value == expected and type(value) is type(expected)
