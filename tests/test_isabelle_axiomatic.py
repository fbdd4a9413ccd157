"""``cyphy gen --isabelle --isabelle-dialect axiomatic``: the Ax_CyPhyCircus session checked
statically (Isabelle is not available here): lexing, ASCII, theory name, no closure lemmas,
define-before-use, the expected actions, and Evolve's explicit ODEs against ``cyphy solve``;
a model whose equations cannot be reduced gets E-ISABELLE-ODE and no files."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
import sympy
from hypothesis import HealthCheck, given, settings

from conftest import EXAMPLES

MAPPINGS = Path(__file__).resolve().parent / "mappings"
from cyphy import api
from cyphy.semantics.dynamics.closed_form import inline_definitions
from cyphy.backends.isabelle.names import RESERVED, is_identifier
from cyphy.cli import main
from cyphy.verify.theory.ax_types import check_ax_theory
from theory_check import session_findings
from test_isabelle import MARXBOT, MARXBOT_ACTIONS, lex_errors, mappings, theory_header, \
    write_model

ELEMENTS = ("marXbotBase::Core::LHinge::LMotor", "marXbotBase::Core::RHinge::RMotor",
            "marXbotBase::Core::Proximity::1")
THEORY = "marXbotBase_AxCyPhyCircus.thy"
IMPORT = '"Axiomatic_CyPhyCircus.Ax_CyPhyCircus"'
DEFINITION = re.compile(r'^definition (\w+) :: "([^"]*)" where\n  "([^"]*)"', re.M)
ODE = re.compile(r"(\w+)` = (.*?)(?=,\n\s+\w+` = |\]$)", re.S)


def axiomatic(paths: list[Path], elements: tuple[str, ...] = ELEMENTS, **more) -> api.Generated:
    return api.generate_isabelle(paths, api.SemanticsGenOptions(
        dialect="axiomatic", elements=elements, **more))


@pytest.fixture(scope="module")
def marxbot() -> api.Generated:
    generated = axiomatic([MARXBOT])
    assert not generated.report.has_errors, generated.report.diagnostics
    return generated


def definitions(text: str) -> list[tuple[str, str, str]]:
    return DEFINITION.findall(text)


def odes(text: str, evolve: str) -> dict[str, str]:
    """``variable -> printed right-hand side`` of the evolution ``[\\<Lambda> …]``."""
    [body] = [b for n, _, b in definitions(text) if n == evolve]
    m = re.fullmatch(rf"{evolve} = \[\\<Lambda> (.*)\]", body, re.S)
    assert m is not None, body
    return dict(ODE.findall(m.group(1) + "]"))


def hol_to_sympy(term: str) -> sympy.Expr:
    """A printed HOL arithmetic term (+ - * / ^, names, decimals) as SymPy, names real."""
    names = set(re.findall(r"[A-Za-z]\w*", term))
    return sympy.sympify(term.replace("^", "**"),
                         locals={n: sympy.Symbol(n, real=True) for n in names})


def _split_top(text: str) -> list[str]:
    """The comma-separated items of a printed tuple's inside, split at depth 0."""
    items, depth, start = [], 0, 0
    for k, ch in enumerate(text):
        depth += (ch == "(") - (ch == ")")
        if ch == "," and depth == 0:
            items.append(text[start:k].strip())
            start = k + 1
    return items + [text[start:].strip()]


def check_static(files: dict[str, str], theory: str) -> str:
    """The static properties of an axiomatic session; returns the theory text."""
    assert set(files) == {"ROOT", "README", "names.tsv", theory}
    for text in files.values():
        text.encode("ascii")
        assert "sorry" not in text and "oops" not in text
    text = files[theory]
    assert lex_errors(text) == []
    name, imports = theory_header(text)
    assert name == Path(theory).stem and is_identifier(name)
    assert imports == [IMPORT]
    assert "\nlemma" not in text and "[closure]" not in text and "NCSP" not in text
    assert '= "Axiomatic_CyPhyCircus" +' in files["ROOT"] and f"    {name}\n" in files["ROOT"]
    assert "\nconsts\n  cycle :: nat\n  tscale :: real\n" in text
    assert session_findings(files) == []  # cyphy check-theory accepts the session
    # define before use: every action a body mentions is defined above it (or is WaitT)
    defined = {"WaitT"} if "\nprimrec WaitT ::" in text else set()
    actions = {n for n, typ, _ in definitions(text) if typ.endswith(") cyphyaction")}
    for n, typ, body in definitions(text):
        assert typ.endswith(") cyphyaction") or typ.endswith("_chan set"), typ
        used = set(re.findall(r"(?<![\w`])[A-Za-z]\w*", re.sub(r"\\<[^>]*>", " ", body)))
        assert (used & actions) - {n} <= defined, (n, (used & actions) - defined)
        defined.add(n)
        for ident in used:
            assert ident not in RESERVED or ident in {"True", "False", "Skip", "Stop", "real",
                                                       "nat", "bool", "UNIV", "set", "sin",
                                                       "cos", "sqrt", "exp", "abs"}, ident
    return text


# ---------------------------------------------------------------- marXbot


def test_marxbot_passes_the_static_checks(marxbot) -> None:
    text = check_static(marxbot.files, THEORY)
    names = dict(line.split("\t")[1:3] for line in marxbot.files["names.tsv"].splitlines()[1:]
                 if line.count("\t") == 3)
    expected = [{"Evolve": "Evolve_v"}.get(a, a) for a in MARXBOT_ACTIONS]
    # then the d-model process D (from the machine SMovement) and the composition N, all
    # over the system's one state (Ax_CyPhyCircus hides no state)
    expected += [f"marXbotSoftware{a}" for a in ("Init", "Read", "Step", "Write", "Main")]
    expected += ["M_channels", "M_v"]  # M is a word of the grammar
    assert [n for n, _, _ in definitions(text)] == expected
    assert "alphabet MState = marXbotBaseState +\n  marXbotSoftware_mode :: nat\n" in text
    assert {t for _, t, _ in definitions(text)} == {
        "(marXbotBase_chan, MState) cyphyaction", "marXbotBase_chan set",
        "real \\<Rightarrow> real \\<Rightarrow> (marXbotBase_chan, MState) cyphyaction"}
    assert "chantype marXbotBase_chan =\n  tock :: unit\n  registerRead_obstacle :: bool\n" \
        "  registerWrite_move :: \"real \\<times> real\"\n  registerWrite_stop :: unit\n" in text
    assert names.get("LMotor_das") == "LMotor_das"


def test_marxbot_theory_type_checks(marxbot) -> None:
    assert check_ax_theory(marxbot.files[THEORY]) == []


def test_marxbot_terms_use_the_axiomatic_notation(marxbot) -> None:
    text = marxbot.files[THEORY]
    bodies = {n: b for n, _, b in definitions(text)}
    # Init also starts every state of the reduction (cyphy solve's, below) at 0 (Rule 2)
    states = ["LMotor_av", "LMotor_i", "LMotor_int1", "LMotor_theta", "RMotor_av", "RMotor_i",
              "RMotor_int2", "RMotor_theta"]
    assert bodies["Init"] == (f"Init = ((timer, LMotor_das, RMotor_das, {', '.join(states)}) "
                              f":= ({', '.join(['0'] * 11)}))")
    assert bodies["ObstacleToDModel"] == (
        "ObstacleToDModel = ((registerRead_obstacle\\<^bold>!(True) \\<rightarrow> Skip) \\<lhd> "
        "(Proximity1_voltage \\<ge> 3.0) \\<rhd> (registerRead_obstacle\\<^bold>!(False) "
        "\\<rightarrow> Skip))")
    assert bodies["MoveFromDModel"] == \
        "MoveFromDModel = (registerWrite_move\\<^bold>?(lv, av) \\<rightarrow> (MoveCall lv av))"
    assert bodies["MoveCall"].startswith(
        "MoveCall lv av = (cSpec ((LMotor_das, RMotor_das))\\<^sub>v (True)\\<^sub>e "
        "((\\<exists> move_dsl::real. \\<exists> move_dsr::real. (LMotor_das = move_dsl)")
    assert bodies["MoveCall"].endswith(")\\<^sub>e)")
    assert ":[" not in text  # the generic Spec notation is not bound to cSpec (B6)
    # ours, not the paper's \<interleave>: the calls' updates persist until the first tock
    assert bodies["ReceiveFromDModel"] == (
        "ReceiveFromDModel = (\\<mu> Y. ((MoveFromDModel ;; Y) \\<box> ((StopFromDModel ;; Y) "
        "\\<box> (tock \\<rightarrow> Skip))))")
    # the timer's reset also puts the outputs on their definitions (values: the test below),
    # after the world's input chooses its rate for the evolution
    main = re.fullmatch(
        r"MainAction = \(Init ;; \(\\<mu> X\. \(SendToDModel ;; \(ReceiveFromDModel ;; "
        r"\(\(WaitT \(cycle - 1\)\) ;; \(\(\(cSpec Proximity1_distance_rate \(True\)\\<\^sub>e "
        r"\(True\)\\<\^sub>e\) ;; \(\(timer, LMotor_T, Proximity1_voltage, RMotor_T\) := "
        r"\(0, .*\)\)\) ;; \(\(Evolve_v \\<triangle>\\<\^sub>p \(timer \\<ge> \(\(real cycle\) \* "
        r"tscale\)\)\) ;; X\)\)\)\)\)\)\)", bodies["MainAction"])
    assert main is not None, bodies["MainAction"]
    assert '"WaitT 0 = Skip" |\n  "WaitT (Suc n) = (tock \\<rightarrow> WaitT n)"' in text
    assert "axiomatization where\n  globals_1: \"(cycle > 0)\" and" in text


def test_marxbot_evolve_is_the_reduction_of_cyphy_solve(marxbot) -> None:
    printed = odes(marxbot.files[THEORY], "Evolve_v")
    solved = api.solve([EXAMPLES / "marxbot"], api.SolveOptions(
        model="marXbotBase", elements=ELEMENTS, closed_form=False))
    reduced = solved.reduced
    assert reduced is not None and not reduced.obstacles
    zero = {s: 0 for n, s in reduced.symbols.items() if n.startswith("der_")}
    for state in reduced.states:  # one ODE per state, the same right-hand side
        assert sympy.simplify(hol_to_sympy(printed[state])
                              - reduced.rhs[state].xreplace(zero)) == 0, state
    assert set(reduced.states) == {"LMotor_av", "LMotor_i", "LMotor_int1", "LMotor_theta",
                                   "RMotor_av", "RMotor_i", "RMotor_int2", "RMotor_theta"}
    # the outputs that are state fields follow the states and the world's input, the
    # distance, which moves at its rate (chain rule), timer' = 1
    sym = {s: sympy.Symbol(s, real=True) for s in reduced.states}
    distance = sympy.Symbol("Proximity1_distance", real=True)
    rate = sympy.Symbol("Proximity1_distance_rate", real=True)
    for output in ("LMotor_T", "RMotor_T", "Proximity1_voltage"):
        g = reduced.outputs[output]
        expected = sum(sympy.diff(g, sym[s]) * reduced.rhs[s].xreplace(zero)
                       for s in reduced.states) + sympy.diff(g, distance) * rate
        assert sympy.simplify(hol_to_sympy(printed[output]) - expected) == 0, output
    assert printed["Proximity1_distance"] == "Proximity1_distance_rate"  # not frozen
    assert hol_to_sympy(printed["Proximity1_voltage"]).has(rate)
    # before each evolution the rate is chosen afresh, then the outputs are set to their
    # values over the states and inputs (the reduction's solutions): the IR law ties the
    # voltage to the distance again
    main = re.search(r'"MainAction = .*?\(cSpec Proximity1_distance_rate \(True\)\\<\^sub>e '
                     r'\(True\)\\<\^sub>e\) ;; '
                     r'\(\(timer, ([\w, ]+)\) := \(0, (.*)\)\)\) ;; '
                     r'\(\(Evolve_v', marxbot.files[THEORY])
    assert main is not None
    tied = main.group(1).split(", ")
    assert tied == ["LMotor_T", "Proximity1_voltage", "RMotor_T"]
    values = _split_top(main.group(2))
    for output, value in zip(tied, values):
        expected = reduced.outputs[output].xreplace(zero)
        assert sympy.simplify(hol_to_sympy(value) - expected) == 0, output
    assert printed["timer"] == "1"
    assert set(printed) == set(reduced.states) | {"LMotor_T", "RMotor_T", "Proximity1_voltage",
                                                  "Proximity1_distance", "timer"}
    # the locals and integrals that evolve are state fields now
    text = marxbot.files[THEORY]
    private = text[text.index("alphabet marXbotBaseState"):text.index("section \\<open>Actions")]
    for state in reduced.states:
        assert f"\n  {state} :: real\n" in private


def test_marxbot_with_constants_prints_numbers(tmp_path: Path) -> None:
    generated = axiomatic([MARXBOT], consts={"SpeedControlMotor::Kd": 0.0,
                                             "SpeedControlMotor::J": 0.01})
    printed = odes(generated.files[THEORY], "Evolve_v")
    assert "LMotor_Kd" not in printed["LMotor_i"] and "LMotor_J" not in printed["LMotor_av"]
    assert sympy.simplify(hol_to_sympy(printed["LMotor_av"]) - hol_to_sympy(
        "100 * LMotor_Kt * LMotor_i - 100 * LMotor_av * LMotor_b")) == 0
    assert check_ax_theory(generated.files[THEORY]) == []


def test_generation_is_deterministic(marxbot) -> None:
    assert axiomatic([MARXBOT]).files == marxbot.files


def test_the_default_dialect_is_unchanged() -> None:
    default = api.generate_isabelle([MARXBOT])
    utp = api.generate_isabelle([MARXBOT], api.SemanticsGenOptions(dialect="utp",
                                                                   elements=ELEMENTS))
    assert default.files == utp.files and "CyPhyCircus_Prelude.thy" in default.files


# ---------------------------------------------------------------- refusals


def _massless_wheel_robot(folder: Path) -> list[Path]:
    """The mapping tests' two-wheeled robot with its left wheel massless: no inertial
    information (L4 warns; a mass of 0 is V1's error, which gen refuses first), so its
    kinematic tree has no equations of motion and nothing relates the hinge's effort to its
    motion."""
    for name in ("Robot.rsm", "RobotSoftware.rsm", "Good.rsm"):
        text = (MAPPINGS / name).read_text()
        if name == "Robot.rsm":
            start, end = text.index("local link LWheel"), text.index("local link RWheel")
            wheel = re.sub(r"def \{.*?\n\t\t\}\n", "def { }\n", text[start:end], flags=re.S)
            assert "inertial" not in wheel
            text = text[:start] + wheel + text[end:]
        (folder / name).write_text(text)
    return sorted(folder.glob("*.rsm"))


def test_equations_that_cannot_be_reduced_are_refused(tmp_path: Path) -> None:
    # a chosen hinge whose tree gives no equation of motion: its effort determines nothing
    files = _massless_wheel_robot(tmp_path)
    generated = axiomatic(files, elements=("Robot::Base::LHinge",))
    # (issue 27: the structural analysis finds it, and says so in the user's file)
    errors = [d for d in generated.report.diagnostics if d.code.id == "E-UNDERDETERMINED"]
    assert errors and generated.files == {}
    assert any("how LHinge_theta, LHinge_v evolve" in d.message for d in errors)
    assert all(d.span.file.endswith("Robot.rsm") for d in errors)  # the hinge, not physmod


def test_a_whole_model_without_equations_of_motion_is_a_located_error(tmp_path: Path) -> None:
    generated = axiomatic(_massless_wheel_robot(tmp_path), elements=())
    (error,) = [d for d in generated.report.diagnostics if d.severity.value == "ERROR"]
    assert error.code.id == "E-DYNAMICS" and "LHinge" in error.message
    assert error.span.file.endswith("Robot.rsm") and generated.files == {}


# ---------------------------------------------------------------- whole models (issue 16)


@pytest.fixture(scope="module", params=["dcmotor", "marxbot"])
def whole(request) -> tuple[str, api.Generated]:
    generated = axiomatic([EXAMPLES / request.param], elements=())
    assert not generated.report.has_errors, generated.report.diagnostics
    return request.param, generated


WHOLE = {"dcmotor": ("DCMotorBase", {"Shaft_theta", "Shaft_v"}),
         "marxbot": ("marXbotBase", {"LHinge_theta", "LHinge_v", "RHinge_theta", "RHinge_v"})}


def test_whole_model_evolve_is_the_reduction_of_cyphy_solve(whole) -> None:
    """Without --isabelle-element: the equations of motion determine the joints, vectors are
    components on both sides, and every ODE is cyphy solve's (states) or its chain rule
    (state fields the reduction solves)."""
    example, generated = whole
    pmodel, joints = WHOLE[example]
    theory = f"{pmodel}_AxCyPhyCircus.thy"
    text = check_static(generated.files, theory)
    printed = odes(text, "Evolve_v")
    solved = api.solve([EXAMPLES / example], api.SolveOptions(model=pmodel,
                                                               closed_form=False))
    reduced = solved.reduced
    assert reduced is not None and not reduced.obstacles
    assert joints <= set(reduced.states)
    # solve keeps the equations of motion as the articulated-body algorithm's definitions;
    # written out, they must be the joint-space equations the theory holds
    assert reduced.definitions
    inline_definitions(reduced, solved.system)
    zero = {s: 0 for n, s in reduced.symbols.items() if n.startswith("der_")}
    for state in reduced.states:
        assert sympy.simplify(hol_to_sympy(printed[state])
                              - reduced.rhs[state].xreplace(zero)) == 0, state
    # the joints' twists are state fields per component; those the equations give as
    # functions of the states follow them by the chain rule
    sym = {s: sympy.Symbol(s, real=True) for s in reduced.states}
    prefix = sorted(joints)[0].split("_")[0]
    twist = [f"{prefix}_fV_{k}" for k in range(1, 7)]
    assert set(twist) <= set(printed)
    for name in twist:
        if name in reduced.outputs:
            g = reduced.outputs[name].xreplace(zero)
            expected = sum(sympy.diff(g, sym[s]) * reduced.rhs[s].xreplace(zero)
                           for s in reduced.states)
            assert sympy.simplify(hol_to_sympy(printed[name]) - expected) == 0, name
    # the rotating axis's component of the child twist is the joint speed's rate
    assert any(sympy.simplify(hol_to_sympy(printed[n])
                              - reduced.rhs[f"{prefix}_v"].xreplace(zero)) == 0
               for n in twist)
    assert f"  {prefix}_fA_3 :: real\n" in text and f"{prefix}_fA ::" not in text
    assert "transpose" not in text and "ad(" not in text
    assert printed["timer"] == "1"


def test_whole_model_theory_type_checks(whole) -> None:
    name, generated = whole
    assert check_ax_theory(generated.files[f"{WHOLE[name][0]}_AxCyPhyCircus.thy"]) == []


def test_whole_model_states_the_composition(whole) -> None:
    """N = ((DMain ⟦dvars | cs | pvars⟧ MainAction) \\<Zhide> cs) over the one alphabet that
    extends P's with D's: the name sets, read against the alphabets the theory declares,
    partition the state (D's variables to D, every other to P), cs is every register
    channel and tock; the checker rejects a name set with a name that is no variable."""
    _, generated = whole
    [theory] = [n for n in generated.files if n.endswith(".thy")]
    text = generated.files[theory]
    alphabets = {m.group(1): (m.group(2), re.findall(r"  (\w+) :: ", m.group(3)))
                 for m in re.finditer(r"^alphabet (\w+) =(?: (\w+) \+)?\n((?:  .*\n)*)",
                                      text, re.M)}
    [(system, (parent, d_fields))] = [(k, v) for k, v in alphabets.items()
                                      if k.endswith("State") and v[0] and v[0].endswith("State")
                                      and v[0] in alphabets]
    p_fields = []
    while parent is not None:
        parent, fields = alphabets[parent]
        p_fields = fields + p_fields
    chan, declared = re.search(r"^chantype (\w+) =\n((?:  .*\n)*)", text, re.M).groups()
    m = re.search(r'"(\w+) = \(\((\w+)Main \\<lbrakk>\(([^)]*)\) \| (\w+) \| \(([^)]*)\)'
                  r'\\<rbrakk> MainAction\) \\<Zhide> (\w+)\)"', text)
    assert m is not None
    n, _, d_set, cs, p_set, hidden = m.groups()
    assert cs == hidden and f'definition {n} :: "({chan}, {system}) cyphyaction"' in text
    assert d_set.split(", ") == d_fields and sorted(p_set.split(", ")) == sorted(p_fields)
    chans = re.search(rf'"{cs} = \\<lbrace>(.*)\\<rbrace>"', text).group(1).split(", ")
    assert sorted(chans) == sorted(re.findall(r"  (\w+) :: ", declared))
    assert check_ax_theory(text) == []
    assert check_ax_theory(text.replace(f"| {cs} | (timer, ", f"| {cs} | (timer_x, ", 1))


def test_whole_model_generation_is_deterministic(whole) -> None:
    example, generated = whole
    again = axiomatic([EXAMPLES / example], elements=())
    assert again.files == generated.files


def test_an_unknown_element_is_refused() -> None:
    generated = axiomatic([MARXBOT], elements=("marXbotBase::Core::LHinge::LMotr",))
    [error] = [d for d in generated.report.diagnostics if d.code.id == "E-ISABELLE-ODE"]
    assert "names no element" in error.message and "LMotor" in error.hint
    assert generated.files == {}


def test_cli_writes_the_session_beside_the_model(tmp_path: Path, capsys) -> None:
    for path in (EXAMPLES / "marxbot").glob("*.rsm"):
        shutil.copy(path, tmp_path / path.name)
    args = ["gen", "--isabelle", "--isabelle-dialect", "axiomatic", str(tmp_path / "Mapping.rsm")]
    for e in ELEMENTS:
        args += ["--isabelle-element", e]
    assert main(args) == 0
    out = tmp_path / "isabelle-ax-gen"
    assert sorted(p.name for p in out.iterdir()) == sorted(["README", "ROOT", "names.tsv", THEORY])
    assert not (tmp_path / "isabelle-gen").exists()
    readme = (out / "README").read_text()
    assert "CyPhyCircus_Toolkit" in readme and "not in any public repository" in readme
    # the whole model, without --isabelle-element (issue 16)
    whole = tmp_path / "whole"
    assert main(args[:5] + ["-o", str(whole)]) == 0
    assert check_ax_theory((whole / THEORY).read_text()) == []
    # not reducible (the robot's wheel is massless): the error, and nothing written
    other = tmp_path / "other"
    (tmp_path / "robot").mkdir()
    robot = _massless_wheel_robot(tmp_path / "robot")
    assert main(args[:4] + [str(p) for p in robot] + ["--isabelle-element",
                                                      "Robot::Base::LHinge", "-o",
                                                      str(other)]) == 1
    assert "E-UNDERDETERMINED" in capsys.readouterr().err  # issue 27: structural
    assert not other.exists()


# ---------------------------------------------------------------- generated mappings

ROBOT_ELEMENTS = ("Robot::Base::J::M", "Robot::Arm::S")


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(model=mappings())
def test_generated_mappings_lex_and_type_check(tmp_path_factory, model) -> None:
    folder = tmp_path_factory.mktemp("mapping")
    paths = write_model(folder, *model)
    generated = axiomatic(paths, elements=ROBOT_ELEMENTS)
    assert not generated.report.has_errors, generated.report.diagnostics
    text = check_static(generated.files, "Robot_AxCyPhyCircus.thy")
    assert check_ax_theory(text) == []
    printed = odes(text, "Evolve_v")
    assert {"M_av", "M_i", "M_int1", "M_theta", "M_T", "timer"} <= set(printed)
    assert printed["M_theta"] == "M_av"


def test_sympy_results_convert_back_to_expressions() -> None:
    from cyphy.translate.to_sympy import to_expr, to_sympy

    a, b, x = (sympy.Symbol(n, real=True) for n in "abx")
    f = sympy.Function("ScrewAxis")
    for value in (a * b / x - sympy.Rational(3, 2) * a / x + b / 10, -a, sympy.Float(0.5) * a,
                  sympy.sqrt(a) + sympy.sin(b) ** 2 - 1 / a ** 2, a ** sympy.Rational(3, 2),
                  sympy.exp(-a) * sympy.cos(x), f(a, b) - 2, sympy.Integer(-3)):
        assert sympy.simplify(to_sympy(to_expr(value)) - value) == 0, value


def test_isar_tools_finds_nothing_in_the_axiomatic_session(marxbot, tmp_path) -> None:
    from isar_check import isar_findings

    assert isar_findings(marxbot.files, tmp_path / "session") == []


def test_namesets_are_svids_or_lenses_where_the_syntax_reads_them(tmp_path: Path) -> None:
    """A6: in ``\\<lbrakk>ns1 | A | ns2\\<rbrakk>`` a name set is an svid (a variable or a
    tuple ``(x, y)``); a side with no names goes through ``cParallelAct``, whose name sets
    are lens terms (a tuple ``((x, y))\\<^sub>v``, empty the zero lens)."""
    from cyphy.backends.isabelle.terms import Symbols
    from cyphy.backends.isabelle.ax_terms import AxiomaticPrinter
    from cyphy.backends.isabelle.names import IsabelleNames
    from cyphy.semantics.circus import ast as c

    names = IsabelleNames()
    for n in ("x", "y", "z"):
        names.add(n)
    printer = AxiomaticPrinter(Symbols(names, state=frozenset({"x", "y", "z"})))
    par = c.Parallel(c.Skip(), ("x", "y"), (), (), c.Stop())
    assert printer.action(par) == "(cParallelAct ((x, y))\\<^sub>v 0\\<^sub>L {} Skip Stop)"
    both = c.Parallel(c.Skip(), ("x", "y"), (), ("z",), c.Stop())
    assert printer.action(both) == "(Skip \\<lbrakk>(x, y) | {} | z\\<rbrakk> Stop)"
    single = c.Parallel(c.Skip(), ("z",), (), ("x",), c.Stop())
    assert printer.action(single) == "(Skip \\<lbrakk>z | {} | x\\<rbrakk> Stop)"
    assert "+\\<^sub>L" not in printer.action(par) and "\\<^bold>0" not in printer.action(par)


def test_marxbot_state_is_scalar_and_lists_are_only_constants(marxbot) -> None:
    """The axiomatic theory shares the scalarisation: vector fields are components, and the
    only real lists are the constants' definitions (no list arithmetic, no transpose)."""
    text = marxbot.files[THEORY]
    assert "  LHinge_fA_3 :: real\n" in text and "LHinge_fA ::" not in text
    assert "transpose" not in text
    lists = [line for line in text.splitlines() if "real list" in line]
    assert lists and all(line.startswith("definition ") for line in lists)
    for name in re.findall(r'^definition (\w+) :: "real list"', text, re.M):
        uses = re.findall(rf"(?<!\w){name}(?!\w)( !)?", text.split("section \\<open>Actions")[1])
        assert all(uses), name


def test_remainder_is_fmod_defined_in_the_theory(tmp_path: Path) -> None:
    """The axiomatic theory has no prelude: fmod is defined in it, before any use."""
    from test_isabelle import SOFTWARE

    software = SOFTWARE.format(ops="move(lv: real)", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { equation Base::J::M.das == lv % 2 }\n}\n")
    paths = write_model(tmp_path, software, mapping)
    text = axiomatic(paths, elements=("Robot::Base::J::M",)).files["Robot_AxCyPhyCircus.thy"]
    definition = text.index('definition fmod :: "real \\<Rightarrow> real \\<Rightarrow> real"')
    assert definition < text.index("(fmod lv 2)")
    assert check_ax_theory(text) == []
    utp = api.generate_isabelle(paths).files["Robot_CyPhyCircus.thy"]
    assert "\\<guillemotleft>(fmod lv 2)\\<guillemotright>" in utp and "definition fmod" not in utp
