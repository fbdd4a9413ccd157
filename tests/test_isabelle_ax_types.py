"""The axiomatic dialect's type checker (cyphy/verify/theory/ax_types.py): it accepts the theories
cyphy generates (the examples' whole models, the marXbot restricted to its motors, the corpus
marXbot), and rejects seeded faults: ``real list * real``, a keyword as a parameter name, an
undefined constant, a state variable where a value is needed outside a lifted position, a
Boolean rate, name sets the parallel's syntax does not read, a name shadowing the parents."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import api
from cyphy.backends.isabelle.ax_terms import AX_RESERVED
from cyphy.backends.isabelle.names import IsabelleNames
from cyphy.verify.theory.ax_signatures import (AX_CONSTANTS, AX_KEYWORDS, AX_SIGNATURES,
                                               UNCHECKED)
from cyphy.verify.theory.ax_types import check_ax_theory, parse_type, parser

THEORY = "DCMotorBase_AxCyPhyCircus.thy"
MOTORS = ("marXbotBase::Core::LHinge::LMotor", "marXbotBase::Core::RHinge::RMotor")


def axiomatic(paths, elements: tuple[str, ...] = (),  # type: ignore[no-untyped-def]
              default_inertial: str | None = None) -> str:
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions(
        dialect="axiomatic", elements=elements, default_inertial=default_inertial))
    assert not generated.report.has_errors, generated.report.diagnostics
    [text] = [t for p, t in generated.files.items() if p.endswith("_AxCyPhyCircus.thy")]
    return text


@pytest.fixture(scope="module")
def dcmotor() -> str:
    return axiomatic([EXAMPLES / "dcmotor"])


def test_every_signature_reads_and_cites_its_source() -> None:
    for name, (typ, source) in AX_SIGNATURES.items():
        parse_type(typ.replace("\\<Longrightarrow>\\<^sub>\\<triangle>", "prism"))
        assert re.search(r"\.thy(:\d+| \w)", source), (name, source)
        if "use site" in source:
            assert "Ranger_CyPhyCircus.thy:" in source, (name, source)
    assert {"Evolve", "InterruptCond"} <= {w for line in UNCHECKED for w in re.findall(r"\w+",
                                                                                          line)}


def test_dcmotor_theory_type_checks(dcmotor: str) -> None:
    assert "[\\<Lambda> " in dcmotor and "cSpec Motor_das" in dcmotor
    assert check_ax_theory(dcmotor) == []


def test_marxbot_motors_theory_type_checks() -> None:
    assert check_ax_theory(axiomatic([EXAMPLES / "marxbot"], MOTORS)) == []


@needs_corpus
def test_corpus_marxbot_theory_type_checks() -> None:
    """The corpus marXbot's links have no mass (E-DYNAMICS on the whole model): its motors;
    and the whole model once its links get SDF's default inertial (--default-inertial sdf),
    with the wheels' equations of motion in Evolve."""
    assert check_ax_theory(axiomatic([CORPUS / "marXbot"], MOTORS)) == []
    whole = axiomatic([CORPUS / "marXbot"], default_inertial="sdf")
    assert "LHinge_v" in whole and "RHinge_theta" in whole
    assert check_ax_theory(whole) == []


def seeded(text: str, old: str, new: str) -> list[str]:
    assert old in text, old
    return check_ax_theory(text.replace(old, new))


def test_real_list_times_real_is_rejected(dcmotor: str) -> None:
    """A1 in this dialect: a vector constant times a real in an ODE."""
    errors = seeded(dcmotor, "Shaft_theta` = Shaft_v", "Shaft_theta` = (Shaft_A * Shaft_v)")
    assert len(errors) == 1 and errors[0].startswith("definition Evolve_v:")
    assert "list" in errors[0]


def test_keyword_parameter_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, '"DriveCall w = (cSpec Motor_das (True)\\<^sub>e '
                    '(((Motor_das = w)))\\<^sub>e)"',
                    '"DriveCall until = (cSpec Motor_das (True)\\<^sub>e '
                    '(((Motor_das = until)))\\<^sub>e)"')
    assert errors == ["definition DriveCall: the bound name 'until' is a keyword of the "
                      "imported syntax"]
    assert "until" in AX_KEYWORDS


def test_undefined_constant_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "(Range_range \\<le> 1.0)", "(Range_range \\<le> Range_max)")
    assert errors == ["definition NearToDModel: 'Range_max' is not declared"]


def test_transpose_v_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "Shaft_theta` = Shaft_v", "Shaft_theta` = (transpose_v Shaft_F_3)")
    assert errors == ["definition Evolve_v: 'transpose_v' is not declared"]


def test_state_variable_outside_a_lifted_position_is_rejected(dcmotor: str) -> None:
    """An action's argument is not lifted over the state: a variable there is its lens."""
    errors = seeded(dcmotor, "(DriveCall w)", "(DriveCall Motor_das)")
    assert len(errors) == 1 and errors[0].startswith("definition DriveFromDModel: cannot unify")
    assert "lens" in errors[0]


def test_boolean_rate_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "Range_range` = Range_distance_rate", "Range_range` = True")
    assert len(errors) == 1 and errors[0].startswith("definition Evolve_v: cannot unify")


def test_nat_where_real_is_needed_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "((real cycle) * tscale)", "(cycle * tscale)")
    assert errors and errors[0].startswith("definition MainAction: cannot unify")


def test_utp_dialect_operator_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "(tock \\<rightarrow> Skip)", "(tock \\<^bold>\\<rightarrow> Skip)")
    assert len(errors) == 1 and errors[0].startswith("definition ReceiveFromDModel: No terminal")


def test_name_shadowing_a_parent_constant_is_rejected(dcmotor: str) -> None:
    errors = seeded(dcmotor, "registerWrite_stop", "Hide")
    assert errors == ["'Hide' shadows a constant of the imported sessions"]


def test_name_sets_only_as_svids_in_the_parallel_notation() -> None:
    """A6: ``((x, y))\\<^sub>v`` and ``0\\<^sub>L`` are terms, not svids
    (Shallow-Expressions Variables.thy:212-230): the notation cannot read them."""
    for text in ("(Skip \\<lbrakk>((x, y))\\<^sub>v | {} | z\\<rbrakk> Stop)",
                 "(Skip \\<lbrakk>x | {} | 0\\<^sub>L\\<rbrakk> Stop)"):
        with pytest.raises(Exception, match="Unexpected"):
            parser().parse(text, start="action")
    for text in ("(Skip \\<lbrakk>(x, y) | {} | z\\<rbrakk> Stop)",
                 "(cParallelAct ((x, y))\\<^sub>v 0\\<^sub>L {} Skip Stop)"):
        parser().parse(text, start="action")


def test_parallel_with_name_sets_type_checks(tmp_path: Path) -> None:
    """ReceiveFromDModel is a loop, so nothing generated has name sets; the checker still reads the partitioned interleaving in both forms the printer
    writes for an Interleave node with name sets (seeded in place of the loop)."""
    from test_isabelle import SOFTWARE, write_model

    software = SOFTWARE.format(ops="move(lv: real)", events="", outputs=" event lamp: boolean")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { equation Base::J::M.das == lv }\n"
               "  output event lamp ? on { action Base::Lamp.on = on }\n}\n")
    paths = write_model(tmp_path, software, mapping)
    generated = api.generate_isabelle(paths, api.SemanticsGenOptions(
        dialect="axiomatic", elements=("Robot::Base::J::M",)))
    loop = generated.files["Robot_AxCyPhyCircus.thy"]
    assert "\\<lbrakk>" not in loop and check_ax_theory(loop) == []
    body = re.search(r'"ReceiveFromDModel = (.*)"', loop)
    assert body is not None
    text = loop.replace(body.group(1), "(MoveFromDModel \\<lbrakk>M_das | {} | Lamp_on\\<rbrakk> "
                                       "LampFromDModel)")
    assert check_ax_theory(text) == []
    one_sided = text.replace("\\<lbrakk>M_das | {} | Lamp_on\\<rbrakk> LampFromDModel",
                             "cParallelAct_ LampFromDModel")
    one_sided = one_sided.replace("(MoveFromDModel cParallelAct_ ",
                                  "(cParallelAct M_das 0\\<^sub>L {} MoveFromDModel ")
    assert check_ax_theory(one_sided) == []
    wrong = text.replace("M_das | {} | Lamp_on", "M_das | {} | registerWrite_move")
    assert check_ax_theory(wrong) == ["definition ReceiveFromDModel: 'registerWrite_move' is "
                                      "no variable of the state"]


WORDS = sorted(w for w in AX_KEYWORDS | AX_CONSTANTS if w.isidentifier())


@pytest.mark.parametrize("word", WORDS)
def test_every_word_the_checker_rejects_is_renamed_by_the_printer(word: str) -> None:
    """The axiomatic names table (the common reserved words and AX_RESERVED) never hands out
    a keyword of the parents or the name of a constant the notation denotes."""
    assert IsabelleNames(AX_RESERVED).add(word) != word


@pytest.mark.parametrize("word", ["until", "elseif", "update", "src"])
def test_keyword_parameters_are_renamed_and_type_check(tmp_path: Path, word: str) -> None:
    from test_isabelle import SOFTWARE, write_model

    software = SOFTWARE.format(ops=f"move({word}: real)", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               f"  operation move {{ equation Base::J::M.das == {word} }}\n}}\n")
    text = axiomatic(write_model(tmp_path, software, mapping), ("Robot::Base::J::M",))
    assert f'"MoveCall {word}_b = ' in text
    assert check_ax_theory(text) == []


def test_channel_instantiation_is_not_lifted(dcmotor: str) -> None:
    """``c\\<^bold>.v`` (Channels_Events.thy:89) takes a plain term: a number fits the
    channel's type, a state variable there is its lens."""
    plain = "(registerWrite_stop \\<rightarrow> StopCall)"
    assert seeded(dcmotor, plain, "(registerWrite_drive\\<^bold>.(1.0) \\<rightarrow> "
                  "StopCall)") == []
    errors = seeded(dcmotor, plain, "(registerWrite_drive\\<^bold>.(Motor_das) \\<rightarrow> "
                    "StopCall)")
    assert len(errors) == 1 and errors[0].startswith("definition StopFromDModel: cannot unify")


def test_indexed_choice_binds_its_variable(dcmotor: str) -> None:
    ok = seeded(dcmotor, "StopFromDModel = (registerWrite_stop \\<rightarrow> StopCall)",
                "StopFromDModel = (\\<box> i\\<in>(UNIV :: bool set). ((i = True) \\<^bold>& "
                "(registerWrite_stop \\<rightarrow> StopCall)))")
    assert ok == []
    errors = seeded(dcmotor, "StopFromDModel = (registerWrite_stop \\<rightarrow> StopCall)",
                    "StopFromDModel = (\\<box> i\\<in>(UNIV :: bool set). ((i = 1.0) \\<^bold>& "
                    "(registerWrite_stop \\<rightarrow> StopCall)))")
    assert len(errors) == 1 and "bool" in errors[0]
