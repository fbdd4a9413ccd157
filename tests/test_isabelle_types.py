"""The Hindley–Milner checker of cyphy/verify/theory/utp_types.py: it accepts the theories cyphy
generates (examples and the corpus marXbot), and rejects seeded faults: the ``real list *
real`` of the old Evolve, list arithmetic, a keyword as a parameter name, an undefined
constant, a state variable of the wrong kind in EvolveC's relation."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.verify.theory.utp_types import SIGNATURES, TypeError_, check_theory, instance, parse_type, unify


def theory(paths: list[Path], default_inertial: str | None = None) -> str:
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions(
        default_inertial=default_inertial))
    assert not generated.report.has_errors, generated.report.diagnostics
    [text] = [t for p, t in generated.files.items() if p.endswith("_CyPhyCircus.thy")]
    return text


@pytest.fixture(scope="module")
def dcmotor() -> str:
    return theory([EXAMPLES / "dcmotor"])


def test_every_signature_reads_and_cites_its_source() -> None:
    for name, (typ, source) in SIGNATURES.items():
        parse_type(typ)
        # every library entry (HOL's too) cites file:line; the prelude's are cyphy's own
        assert re.search(r"\.thy:\d+", source) or source.startswith("prelude"), (name, source)


def test_dcmotor_theory_type_checks(dcmotor: str) -> None:
    assert check_theory(dcmotor) == []


@needs_corpus
def test_corpus_marxbot_theory_type_checks() -> None:
    assert check_theory(theory([CORPUS / "marXbot"])) == []
    # with SDF's default inertial, Evolve carries the wheels' equations of motion too
    whole = theory([CORPUS / "marXbot"], default_inertial="sdf")
    assert "$RHinge_tau =\\<^sub>u" in whole and check_theory(whole) == []


def seeded(text: str, old: str, new: str) -> list[str]:
    assert old in text
    return check_theory(text.replace(old, new, 1))


def test_real_list_times_real_is_rejected(dcmotor: str) -> None:
    """A1: the old Evolve lifted a list constant times a real."""
    errors = seeded(dcmotor, "\\<guillemotleft>((Shaft_A ! 2) * Shaft_a)\\<guillemotright>",
                    "\\<guillemotleft>(Shaft_A * Shaft_a)\\<guillemotright>")
    assert len(errors) == 1 and errors[0].startswith("definition Evolve:")
    assert "list" in errors[0]  # list has no times (first), and is not real


def test_list_times_list_is_rejected(dcmotor: str) -> None:
    """B1's cousin: HOL has no multiplication on lists (and + on lists is not addition)."""
    errors = seeded(dcmotor, "\\<guillemotleft>((Shaft_A ! 2) * Shaft_a)\\<guillemotright>",
                    "\\<guillemotleft>(Shaft_A * Shaft_A)\\<guillemotright>")
    assert errors and "no instance list :: times" in errors[0]


def test_keyword_parameter_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, '"DriveCall w = ({Motor_das}\\<^sub>v:[true, ((&Motor_das '
                    '=\\<^sub>u \\<guillemotleft>w\\<guillemotright>))]\\<^sub>C)"',
                    '"DriveCall on = ({Motor_das}\\<^sub>v:[true, ((&Motor_das '
                    '=\\<^sub>u \\<guillemotleft>on\\<guillemotright>))]\\<^sub>C)"')
    assert errors == ["definition DriveCall: the bound name 'on' is a keyword of the "
                      "imported syntax"]


def test_undefined_constant_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "\\<guillemotleft>Motor_Kp\\<guillemotright>",
                    "\\<guillemotleft>Motor_Kq\\<guillemotright>")
    assert errors == ["definition Evolve: 'Motor_Kq' is not declared"]


def test_transpose_v_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "($Shaft_F_1 * ", "((uop transpose_v $Shaft_F_1) * ")
    assert errors == ["definition Evolve: 'transpose_v' is not declared"]


def test_program_variable_in_evolution_relation_is_rejected(dcmotor: str) -> None:
    """EvolveC takes a relation: &x (a predicate on one state) does not fit in it."""
    errors = seeded(dcmotor, "($Range_range =\\<^sub>u $Range_distance)",
                    "($Range_range =\\<^sub>u &Range_distance)")
    assert errors and errors[0].startswith("definition Evolve: cannot unify")


def test_nat_where_real_is_needed_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "\\<guillemotleft>((real cycle) * tscale)\\<guillemotright>",
                    "\\<guillemotleft>(cycle * tscale)\\<guillemotright>")
    assert errors and "cannot unify" in errors[0]


def test_old_parallel_name_sets_do_not_parse() -> None:
    """A3: {x}\\<^sub>v in the parallel's salpha position is not accepted."""
    text = ('definition P :: "S_action" where\n  "P = (Skip \\<lbrakk>{x}\\<^sub>v\\<parallel>'
            '0\\<^sub>L\\<rbrakk> Skip)"\nlemma')
    errors = check_theory('alphabet S =\n  x :: real\n\ntype_synonym S_action = '
                          '"(S, C) action"\n\n' + text)
    assert errors and errors[0].startswith("definition P: Unexpected")


def test_sorted_unification() -> None:
    with pytest.raises(TypeError_, match="no instance bool :: plus"):
        unify(instance("+"), parse_type("bool \\<Rightarrow> bool \\<Rightarrow> bool"))
    unify(instance("+"), parse_type("(real, 's) uexpr \\<Rightarrow> (real, 's) uexpr "
                                    "\\<Rightarrow> (real, 's) uexpr"))
