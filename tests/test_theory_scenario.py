"""``gen --isabelle/--cyphycircus/--latex --scenario FILE``: the scenario that ``simulate`` and
``reach`` read starts ``Init`` (issue 26). Values are read back from the generated text (the
assignment's tuples, the specification's bounds), not from cyphy's program."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from cyphy.cli import main
from conftest import EXAMPLES

DCMOTOR = EXAMPLES / "dcmotor"

SCENARIO = """\
model = "DCMotorBase"
horizon = 1.0
tscale = 0.05
[init]
Motor_av = 2.5
Motor_e_int = 0.75
Motor_int1 = 0.5
Shaft_v = 0.25
Range_distance = [3, 3.1]
"""


def _generate(tmp_path: Path, capsys, *target: str) -> tuple[str, str]:
    """The generated theory (or text) and the command's stderr."""
    scenario = tmp_path / "start.toml"
    scenario.write_text(SCENARIO)
    out = tmp_path / "out"
    assert main(["gen", *target, str(DCMOTOR), "--scenario", str(scenario), "-o", str(out)]) == 0
    text = "".join(p.read_text() for p in sorted(out.iterdir())
                   if p.suffix in (".thy", ".cpc", ".tex") and "Prelude" not in p.name)
    return text, capsys.readouterr().err


def _split(tuple_text: str) -> list[str]:
    """The items of a printed tuple, a HOL literal's «» (the utp dialect's) taken off."""
    plain = tuple_text.replace("\\<guillemotleft>", "").replace("\\<guillemotright>", "")
    return [t.strip() for t in plain.split(",")]


def _init_assignment(text: str, assign: str) -> dict[str, str]:
    """The ``(x, y) := (a, b)`` of the theory's Init, as {name: value text}."""
    m = re.search(r'"Init = \(\(\(([^)]*)\) ' + re.escape(assign) + r' \(([^)]*)\)\)', text)
    assert m is not None, "no Init assignment"
    names, values = _split(m.group(1)), _split(m.group(2))
    assert len(names) == len(values)
    return dict(zip(names, values))


def test_utp_init_starts_at_the_scenario(tmp_path: Path, capsys) -> None:
    text, err = _generate(tmp_path, capsys, "--isabelle")
    start = _init_assignment(text, ":=\\<^sub>C")
    assert (start["Motor_av"], start["Shaft_v"], start["Motor_e_int"]) == ("2.5", "0.25", "0.75")
    assert start["Motor_i"] == start["Shaft_theta"] == start["timer"] == "0"  # 0 otherwise
    assert "Range_distance" not in start  # an interval: the specification after it
    assert ("{Range_distance}\\<^sub>v:[true, ((3 \\<le>\\<^sub>u &Range_distance) \\<and> "
            "(&Range_distance \\<le>\\<^sub>u \\<guillemotleft>3.1\\<guillemotright>))]") in text
    assert '"(tscale = 0.05)"' in text  # the scenario's tscale
    # a world input started by the scenario is not held: it stays free in Evolve
    assert "$Range_distance\\<acute> =\\<^sub>u 0" not in text
    # the reduction's name is no state of this dialect: said, with the scenario's line
    assert re.search(r"start\.toml:7:1: WARNING W-SCENARIO-INIT: .*'Motor_int1'", err)
    assert "'Motor_e_int'" not in err


def test_axiomatic_init_starts_at_the_scenario(tmp_path: Path, capsys) -> None:
    text, err = _generate(tmp_path, capsys, "--isabelle", "--isabelle-dialect", "axiomatic")
    start = _init_assignment(text, ":=")
    assert (start["Motor_av"], start["Shaft_v"], start["Motor_int1"]) == ("2.5", "0.25", "0.5")
    assert start["Motor_i"] == start["Motor_theta"] == "0"
    assert ("(cSpec Range_distance (True)\\<^sub>e (((3 \\<le> Range_distance) \\<and> "
            "(Range_distance \\<le> 3.1)))\\<^sub>e)") in text
    assert re.search(r"WARNING W-SCENARIO-INIT: .*'Motor_e_int'", err)


def test_text_starts_only_its_state(tmp_path: Path, capsys) -> None:
    """The text keeps the paper's ∃ PLocal: the ODEs' states are no state to start, each
    named in a warning; the world input is started in its interval."""
    text, err = _generate(tmp_path, capsys, "--cyphycircus")
    assert ("Init ≙ timer, Motor_das := 0, 0 ; Range_distance : [true, 3 ≤ Range_distance' "
            "∧ Range_distance' ≤ 3.1]") in text
    unassigned = re.findall(r"W-SCENARIO-INIT: the scenario's initial value of '(\w+)'", err)
    assert unassigned == ["Motor_av", "Motor_e_int", "Motor_int1", "Shaft_v"]


def test_scenario_constants_and_machine_apply(tmp_path: Path, capsys) -> None:
    """The marXbot's motor constants are open in the model: the scenario's [consts] give
    them (--const wins), its machine is D's."""
    scenario = tmp_path / "m.toml"
    scenario.write_text('horizon = 1.0\ntscale = 0.1\nmachine = "SStop"\n[consts]\n'
                        '"SpeedControlMotor::R" = 1.25\n"SpeedControlMotor::L" = 0.5\n')
    out = tmp_path / "out"
    assert main(["gen", "--isabelle", str(EXAMPLES / "marxbot"), "--scenario", str(scenario),
                 "--const", "SpeedControlMotor::L=0.125", "-o", str(out)]) == 0
    text = (out / "marXbotBase_CyPhyCircus.thy").read_text()
    assert 'definition LMotor_R :: real where "LMotor_R = 1.25"' in text
    assert 'definition RMotor_L :: real where "RMotor_L = 0.125"' in text
    # D is SStop's two modes (Cruising, Stopped), not the module's SMovement (64 modes)
    modes = set(re.findall(r"&marXbotSoftware_mode =\\<\^sub>u (\d+)\)", text))
    assert modes == {"0", "1"}
    assert "WARNING" not in capsys.readouterr().err


@pytest.mark.parametrize("content, expected", [
    (None, "cannot read the scenario"),
    ("horizon = 1.0\n", "the scenario needs 'tscale'"),
    ("horizon = 1.0\ntscale = 0.1\n[init]\nMotor_av = nan\n", "Motor_av"),
])
def test_bad_scenario_is_a_diagnostic_and_writes_nothing(tmp_path: Path, capsys, content,
                                                         expected) -> None:
    scenario = tmp_path / "bad.toml"
    if content is not None:
        scenario.write_text(content)
    out = tmp_path / "out"
    code = main(["gen", "--isabelle", str(DCMOTOR), "--scenario", str(scenario), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 1 and "E-SCENARIO" in err and expected in err
    assert "Traceback" not in err and not out.exists()


def test_started_theories_pass_the_tests_checks_and_check_theory() -> None:
    """The utp theory with a scenario's Init reads back into its program (the round trip),
    and passes the type checker and check-theory; the axiomatic one its static checks."""
    from cyphy import api
    from cyphy.api.semantics import semantics
    from cyphy.backends.isabelle.theory import generate_session
    from test_isabelle import check_session
    from test_isabelle_axiomatic import check_static

    scenario = str(DCMOTOR / "whole_bench.toml")
    _, built = semantics([DCMOTOR], api.SemanticsGenOptions(scenario=scenario))
    check_session(generate_session(built.program, built.names), built.program)
    generated = api.generate_isabelle([DCMOTOR], api.SemanticsGenOptions(
        scenario=scenario, dialect="axiomatic"))
    text = check_static(generated.files, "DCMotorBase_AxCyPhyCircus.thy")
    assert "(cSpec Range_distance (True)" in text


def test_latex_with_a_started_init_typesets(tmp_path: Path, capsys) -> None:
    """pdflatex (a real tool) typesets the LaTeX whose Init has the scenario's interval."""
    import shutil

    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed")
    scenario = tmp_path / "start.toml"
    scenario.write_text(SCENARIO)
    out = tmp_path / "out"
    assert main(["gen", "--latex", "--pdf", str(DCMOTOR), "--scenario", str(scenario),
                 "-o", str(out)]) == 0
    tex = (out / "BenchMapping.tex").read_text()
    init = tex[tex.index("Init \\circdef timer"):]
    init = " ".join(init[:init.index("\\end{circusaction}")].replace("\\\\", " ").split())
    assert init == ("Init \\circdef timer, Motor\\_das := 0, 0 \\circseq 1 Range\\_distance "
                    "\\prefixcolon [true, 1 3 \\leq Range\\_distance' 1 \\land "
                    "Range\\_distance' \\leq 3\\decimalpoint 1]")
    assert (out / "BenchMapping.pdf").read_bytes().startswith(b"%PDF")
