"""The axioms of a theory shown satisfiable by values among their own numbers
(``cyphy/backends/isabelle/witness.py``), without Z3; what no such values satisfy is left to
Z3, whose verdicts stay those of ``unsatisfiable_axioms``."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from conftest import EXAMPLES, ROOT
from cyphy import expr as ex
from cyphy.backends.isabelle import axioms
from cyphy.backends.isabelle.witness import satisfied
from cyphy.lang.parser import parse_text
from cyphy.semantics.circus import ast as c


def axdef(*where: str, nat: tuple[str, ...] = ("cycle",), real: tuple[str, ...] = ("tscale",)
          ) -> c.AxDef:
    """The constants ``cycle :: nat`` and ``tscale :: real`` constrained by ``where``."""
    exprs = []
    for text in where:
        parsed = parse_text(f"const w: boolean = {text}", "<axiom>")
        assert parsed.file is not None and not parsed.diagnostics, parsed.diagnostics
        exprs.append(parsed.file.items[0].value)
    constants = tuple(c.Binding(n, c.NAT) for n in nat) + tuple(c.Binding(n, c.REAL)
                                                               for n in real)
    return c.AxDef(constants, tuple(exprs))


@pytest.mark.parametrize("where", [
    ("cycle > 0", "tscale > 0", "cycle == 1"),  # the marXbot's
    ("cycle > 0", "tscale > 0", "cycle == 3", "tscale == 0.025"),
    ("cycle >= 2 /\\ cycle <= 4", "tscale * 2 == 4"),
    ("not (cycle == 0)", "tscale > 0 => cycle > 1"),
])
def test_axioms_satisfied_by_their_own_numbers_need_no_z3(
        where: tuple[str, ...], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "z3", None)  # importing Z3 would fail
    assert satisfied(axdef(*where))
    assert axioms.unsatisfiable_axioms(axdef(*where)) is None


@pytest.mark.parametrize("where, verdict", [
    (("cycle > 0", "tscale > 0", "cycle == 0"), "have no model"),  # unsatisfiable
    (("tscale > 0", "tscale < 0"), "have no model"),
    (("cycle == 0.5",), "have no model"),  # a nat is no half
    (("tscale * tscale == 2",), None),  # satisfiable, by no rational: Z3 finds √2
    (("cycle > 0", "tscale == 1 / (cycle - cycle)"), None),  # Z3's x/0 is uninterpreted
    (("tscale > 0 /\\ tscale < 0.001",), None),  # between the numbers tried
])
def test_what_no_tried_value_satisfies_is_left_to_z3(where: tuple[str, ...],
                                                     verdict: str | None) -> None:
    pytest.importorskip("z3")
    assert not satisfied(axdef(*where))
    found = axioms.unsatisfiable_axioms(axdef(*where))
    assert (found is None) if verdict is None else (verdict in found), found


def test_unsupported_nodes_and_chains_are_left_to_z3() -> None:
    assert not satisfied(axdef("abs(tscale) == 1"))  # a call: Z3's translation decides
    assert not satisfied(axdef("0 < tscale < 1"))  # a chain
    assert not satisfied(c.AxDef((), (ex.Name(("x",)),)))  # a real name is no truth value


def test_a_warm_gen_isabelle_imports_neither_z3_nor_sympy(tmp_path) -> None:
    env = {**os.environ, "CYPHY_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    env.pop("CYPHY_NO_CACHE", None)
    script = ("import sys; from cyphy.cli import main; "
              f"code = main(['gen', {str(EXAMPLES / 'marxbot')!r}, '--isabelle', '-o', "
              f"{str(tmp_path / 'out')!r}, '-q']); "
              "print(code, 'z3' in sys.modules, 'sympy' in sys.modules)")
    runs = [subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env, timeout=300,
                           capture_output=True, text=True) for _ in range(2)]
    assert [r.stdout.splitlines()[-1] for r in runs] == ["0 False True", "0 False False"], runs
