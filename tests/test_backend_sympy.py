"""The expression AST as SymPy: exact literals, units, functions, derivatives, errors."""

from __future__ import annotations

import pytest
import sympy

from cyphy import expr as ex
from cyphy.translate.to_sympy import T, UnsupportedNode, to_sympy
from cyphy.lang.parser import parse_text


def expr(text: str) -> ex.Expr:
    value = parse_text(f"const c: real = {text}", "t.rsm").file.items[0].value
    assert value is not None
    return value


def test_exact_rationals_and_units() -> None:
    assert to_sympy(expr("0.025025*(dsl + dsr)/2")) == sympy.Rational(25025, 2000000) * (
        sympy.Symbol("dsl", real=True) + sympy.Symbol("dsr", real=True))
    assert to_sympy(expr("3cm")) == sympy.Rational(3, 100)
    assert to_sympy(expr("90deg")) == sympy.pi / 2


def test_equation_and_derivative_over_time() -> None:
    e = to_sympy(expr("L*derivative(i) == V - R*i"), time_dependent=frozenset({"i"}))
    i = sympy.Function("i", real=True)(T)
    L, V, R = (sympy.Symbol(n, real=True) for n in ("L", "V", "R"))
    assert e == sympy.Eq(L * sympy.Derivative(i, T), V - R * i)
    assert sympy.solve(e, sympy.Derivative(i, T)) == [(V - R * i) / L]


def test_functions_connectives_and_matrices() -> None:
    assert to_sympy(expr("sqrt(4) + sin(0)")) == 2
    x = sympy.Symbol("x", real=True)
    assert to_sympy(expr("x > 0 /\\ not (x > 1)")) == sympy.And(x > 0, sympy.Not(x > 1))
    assert to_sympy(expr("[|1, 2; 3, 4|] * (|1, 1|)")) == sympy.Matrix([3, 7])
    assert to_sympy(expr("(|4, 5, 6|)[2]")) == 5
    assert to_sympy(expr("ScrewAxis(x, 1)")) == sympy.Function("ScrewAxis")(x, 1)


def test_unsupported_nodes_are_loud() -> None:
    with pytest.raises(UnsupportedNode):
        to_sympy(expr("<1, 2>"))
    with pytest.raises(TypeError):
        to_sympy(expr("1"), colour="red")
