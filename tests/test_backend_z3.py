"""The Z3 printer of the shared expression AST: exact literals, real division with its
divisors, chained comparisons, powers, the exact functions and the uninterpreted ones."""

from __future__ import annotations

import pytest
import z3

from cyphy import expr as ex
from cyphy.translate.to_z3 import UnsupportedNode, Z3Printer, value_text
from cyphy.lang.parser import parse_text


def _expr(text: str) -> ex.Expr:
    result = parse_text(f"const c: real = {text}", "<test>")
    assert not result.diagnostics
    return result.file.items[0].value


def _printer() -> Z3Printer:
    return Z3Printer(lambda name, node: z3.Real(name))


def _valid(term: z3.BoolRef) -> bool:
    s = z3.Solver()
    s.add(z3.Not(term))
    return s.check() == z3.unsat


def test_literals_are_exact_rationals() -> None:
    term = _printer().doprint(_expr("0.025025 + 1e-3 + 3cm"))
    assert z3.simplify(term) == z3.Q(25025 + 1000 + 30000, 1000000)


def test_division_is_real_and_its_divisor_listed() -> None:
    x, y = z3.Reals("x y")
    p = _printer()
    guarded = p.defined(_expr("x / (y - 1) == 2"))
    assert _valid(z3.Implies(guarded, y != 1))
    assert len(p.divisors) == 1
    assert not _printer().divisors  # literal divisors need no guard
    ints = Z3Printer(lambda name, node: z3.Int(name)).doprint(_expr("7 / 2 + i / j"))
    assert z3.is_real(ints)  # 7/2 is 3.5, not integer division


def test_chained_comparison_and_connectives() -> None:
    a, b = z3.Reals("a b")
    term = _printer().doprint(_expr("a == b < 4 /\\ not (a > 5)"))
    assert _valid(term == z3.And(z3.And(a == b, b < 4), z3.Not(a > 5)))


def test_powers_exact_functions_and_if() -> None:
    x = z3.Real("x")
    p = _printer()
    assert _valid(p.doprint(_expr("x^3")) == x * x * x)
    assert _valid(p.doprint(_expr("abs(x)")) >= 0)
    assert _valid(p.doprint(_expr("if x > 1 then 1 else 0 end")) <= 1)
    assert not p.uninterpreted


def test_unknown_functions_are_uninterpreted_and_listed() -> None:
    p = _printer()
    term = p.doprint(_expr("sin(x) + ScrewAxis(x, 2)"))
    assert p.uninterpreted == {"sin", "ScrewAxis"} and z3.is_real(term)


def test_vectors_are_unsupported() -> None:
    with pytest.raises(UnsupportedNode):
        _printer().doprint(_expr("(|1, 2|)"))


def test_value_text() -> None:
    assert value_text(z3.RealVal("1/2")) == "0.5"
    assert value_text(z3.RealVal("1/3")) == "1/3 (≈ 0.333333)"
    assert value_text(z3.IntVal(-4)) == "-4"
    assert value_text(z3.BoolVal(True)) == "true"
