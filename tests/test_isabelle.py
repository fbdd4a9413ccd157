"""``cyphy gen --isabelle``: the session's files checked statically (Isabelle is not available
here): lexing, theory name, ASCII, define-before-use, one closure lemma after each action
definition, identifiers, and every definition body read back into the action AST that was
printed (round trip), for the marXbot and for Hypothesis-generated mappings."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES
from cyphy import api, codes
from cyphy.backends.isabelle.names import RESERVED, IsabelleNames, is_identifier
from cyphy.backends.isabelle.theory import calls, generate_session
from cyphy.cli import main
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.build import build_semantics
from isabelle_reader import parser, read_action, read_definitions
from cyphy.verify.theory.utp_types import check_theory
from robot_model import ROBOT
from theory_check import session_findings

MARXBOT = EXAMPLES / "marxbot" / "Mapping.rsm"
MARXBOT_ACTIONS = ["Init", "ObstacleToDModel", "SendToDModel", "MoveCall", "MoveFromDModel",
                   "StopCall", "StopFromDModel", "ReceiveFromDModel", "Evolve", "MainAction"]


def semantics(paths: list[Path]):  # type: ignore[no-untyped-def]
    checked = api.check(paths, api.CheckOptions(neighbours_as_targets=True))
    assert not checked.report.has_errors, checked.report.diagnostics
    sem = build_semantics(checked.workspace, checked.resolution, checked.report)
    assert sem is not None, checked.report.diagnostics
    return sem


@pytest.fixture(scope="module")
def marxbot():  # type: ignore[no-untyped-def]
    return semantics([MARXBOT])


@pytest.fixture(scope="module")
def marxbot_session(marxbot):  # type: ignore[no-untyped-def]
    return generate_session(marxbot.program, marxbot.names)


# ---------------------------------------------------------------- the static checks


def lex_errors(text: str) -> list[str]:
    """Error tokens of Pygments' Isabelle lexer and of isar-tools' outer-syntax lexer."""
    from pygments.lexers import IsabelleLexer
    from pygments.token import Error

    from isar_tools.source.lexer import Kind, tokenize  # pinned test dependency

    errors = [v for t, v in IsabelleLexer().get_tokens(text) if t in Error]
    return errors + [t.text for t in tokenize(text) if t.kind is Kind.ERROR]


def theory_header(text: str) -> tuple[str, list[str]]:
    m = re.search(r"^theory (\S+)\n  imports ([^\n]+)\nbegin\b", text, re.M)
    assert m is not None
    assert text.rstrip().endswith("\nend")
    return m.group(1), m.group(2).split()


def term_identifiers(term: str) -> set[str]:
    """The identifiers of a printed term (not the symbols' names inside ``\\<…>``)."""
    without_symbols = re.sub(r"\\<[^>]*>", " ", term)
    return set(re.findall(r"(?<![\w.])[A-Za-z][A-Za-z0-9_]*", without_symbols))


KEYWORDS_OF_TERMS = {"Skip", "Stop", "MuC", "InterruptCondC", "WaitC", "EvolveC", "true", "false", "True", "False", "UNIV", "set", "list",
                     "real", "nat", "int", "bool", "uop", "bop", "trop", "fmod", "powr", "Cons",
                     "sin", "cos", "tan", "sqrt", "exp", "ln", "abs", "arctan"}


def check_session(session, program: c.Program) -> None:  # type: ignore[no-untyped-def]
    """Every static property the issue asks of a generated session."""
    theories = {p: t for p, t in session.files.items() if p.endswith(".thy")}
    assert set(session.files) >= {"ROOT", "README", "names.tsv"}
    for path, text in session.files.items():
        text.encode("ascii")  # pure ASCII
        assert "sorry" not in text and "oops" not in text
    for path, text in theories.items():
        assert lex_errors(text) == [], path
        name, _ = theory_header(text)
        assert name == Path(path).stem and is_identifier(name)
    assert len({p.lower() for p in theories}) == len(theories)
    text = theories[f"{session.theory_name}.thy"]
    assert theory_header(text)[1] == ["CyPhyCircus_Prelude"]
    assert f"theories\n    CyPhyCircus_Prelude\n    {session.theory_name}\n" in session.files["ROOT"]

    # D, when the files have a machine, and the composition N (with its channel set) last
    composed = isinstance(program.dmodel, c.BasicProcess)
    system = session.names[program.system.name] if composed else None
    definitions = [d for d in read_definitions(text) if d[0] != system]
    # Exactly one [closure] lemma right after each action definition, same parameters.
    assert len(definitions) == text.count("\ndefinition") - len(
        [k for k in program.pmodel.constants if k.value is not None]) - 2 * composed
    assert text.count("[closure]") == len(definitions) + composed
    names = [d[0] for d in definitions]
    assert names == [session.names[a] for a in session.actions]
    for name, params, _, lemma, stated in definitions:
        assert lemma == f"{name}_NCSP"
        assert stated.split() == [name, *params]

    # Define before use, on the AST: every call is to an action defined earlier (or to the
    # recursion variable of an enclosing MuC).
    defined: set[str] = set()
    for name, action in session.actions.items():
        mu_vars = {n.var for n in c.walk(action.body) if isinstance(n, c.Mu)}
        params = {p.name for p in action.params}
        for callee in calls(action.body):
            assert callee in defined or callee in mu_vars or callee in params, (name, callee)
        defined.add(name)

    # Identifiers: the restricted form, no keyword, globals pairwise distinct, binders
    # distinct from every global.
    idents = session.names.identifiers()
    assert len(idents) == len(session.names.items())
    for ident in idents:
        assert is_identifier(ident) and ident not in RESERVED, ident
    from isar_tools.source.keywords import BUILTIN_COMMANDS

    for name, params, body, _, _ in definitions:
        for ident in term_identifiers(body) | set(params):
            if ident in KEYWORDS_OF_TERMS:
                continue
            assert is_identifier(ident) and ident not in RESERVED, ident
            assert ident not in BUILTIN_COMMANDS, ident
    for ident in idents:
        assert ident not in BUILTIN_COMMANDS, ident

    # The type checker of cyphy/verify/theory/utp_types.py: every definition, constant and axiom
    # type-checks against the library's signatures; no transpose, vector constants only
    # read by component.
    assert check_theory(text) == []
    assert session_findings(session.files) == []  # cyphy check-theory accepts the session
    assert "transpose" not in text
    for k in program.pmodel.constants:
        if isinstance(k.type, c.TSeq):
            for name, _, body, _, _ in definitions:
                uses = re.findall(rf"(?<!\w){session.names[k.name]}(?!\w)( !)?", body)
                assert all(uses), (name, k.name)

    # Round trip: each definition body reads back into the action it was printed from.
    pm = program.pmodel
    local = pm.local.name if pm.local.fields else None
    for name, params, body, _, _ in definitions:
        original = session.actions[session.names.inverse()[name]]
        assert read_action(body, params, session.symbols, pm.state.name, local) == \
            original.body, name
    if composed:  # N composes D's main action and P's, after both
        assert f'"{system} = HideCSP ((state {session.names[program.dmodel.state.name]} ' \
            f'\\<bullet> {definitions[-1][0]})' in text
        assert f"lemma {system}_NCSP [closure]" in text.split(f'"{system} = ')[1]


# ---------------------------------------------------------------- marXbot


def test_marxbot_session_passes_every_static_check(marxbot, marxbot_session) -> None:
    check_session(marxbot_session, marxbot.program)


def test_marxbot_theory_order(marxbot_session) -> None:
    text = marxbot_session.files["marXbotBase_CyPhyCircus.thy"]
    landmarks = ["axiomatization\n  cycle :: nat and\n  tscale :: real\nwhere",
                 "definition LHinge_AXIS :: \"real list\"", "consts LMotor_b :: real",
                 "datatype marXbotBase_chan =", "alphabet marXbotBaseVisible =",
                 "alphabet marXbotBaseState = marXbotBaseVisible +",
                 "type_synonym marXbotBase_action"]
    landmarks += [f"definition {a} ::" for a in MARXBOT_ACTIONS]
    positions = [text.index(m) for m in landmarks]
    assert positions == sorted(positions)
    # then D (the machine SMovement: init, read, step, write, main) and the composition named
    # after the mapping M, renamed M_v: utp-main's grammar has the word M
    # (utp/utp_concurrency.thy:392), so `definition M` would not parse
    d_actions = [f"marXbotSoftware{a}" for a in ("Init", "Read", "Step", "Write", "Main")]
    assert [d[0] for d in read_definitions(text)] == MARXBOT_ACTIONS + d_actions + ["M_v"]
    assert text.index("alphabet marXbotSoftwareState =") < text.index("definition Init ::")


def test_marxbot_terms_match_the_spec_form(marxbot_session) -> None:
    text = marxbot_session.files["marXbotBase_CyPhyCircus.thy"]
    # Init starts every ODE state at 0 (Rule 2): each variable whose rate Evolve gives,
    # but the PI error e, whose rate is only read (Kd * e'): its equation gives its value
    init = re.search(r'"Init = \(\(([^)]*)\) :=\\<\^sub>C \(([^)]*)\)\)"', text)
    assert init is not None
    targets, values = init.group(1).split(", "), init.group(2).split(", ")
    assert targets[:3] == ["timer", "LMotor_das", "RMotor_das"] and set(values) == {"0"}
    evolve = text.split('"Evolve = ')[1].split("lemma")[0]
    rated = set(re.findall(r"\$(\w+)\\<acute>", evolve))
    assert set(targets) == rated - {"LMotor_e", "RMotor_e"}
    assert {"LHinge_theta", "LHinge_v", "LMotor_av", "LMotor_i", "LMotor_e_int"} <= set(targets)
    assert ("registerRead_obstacle!(true) \\<^bold>\\<rightarrow> Skip) \\<triangleleft> "
            "(&Proximity1_voltage \\<ge>\\<^sub>u \\<guillemotleft>3.0\\<guillemotright>)") in text
    assert ('"MoveCall lv av = ({LMotor_das, RMotor_das}\\<^sub>v:[true, (\\<^bold>\\<exists> '
            'move_dsl::real \\<bullet> \\<^bold>\\<exists> move_dsr::real') in text
    assert "(registerWrite_move?(lv)?(av) \\<^bold>\\<rightarrow> (MoveCall lv av))" in text
    assert "by (simp add: MoveFromDModel_def closure prod.case_eq_if)" in text
    # ours, not the paper's |||: the calls' updates persist until the cycle's first tock
    assert ('"ReceiveFromDModel = (MuC (\\<lambda> Y. ((MoveFromDModel ;; Y) \\<box> '
            '((StopFromDModel ;; Y) \\<box> (tock \\<^bold>\\<rightarrow> Skip)))))"') in text
    assert "($timer\\<acute> =\\<^sub>u 1)" in text
    assert ("(InterruptCondC Evolve (&timer \\<ge>\\<^sub>u \\<guillemotleft>((real cycle) * "
            "tscale)\\<guillemotright>))") in text
    assert "(ReceiveFromDModel ;; ((WaitC tock (cycle - 1)) ;;" in text
    assert "| registerWrite_move \"real \\<times> real\"" in text
    assert 'globals_3: "(cycle = 1)"' in text
    # vectors are written per component (no transpose, no list arithmetic), evolving locals
    # are state (rates $x\<acute>), set-points are held
    assert "transpose" not in text and "DerC" not in text.split("section")[-1]
    assert "  LHinge_fA_3 :: real\n" in text and "  LHinge_theta :: real\n" in text
    # fA = pA + ad(fV)*A*v + A*a, component 3: ad's third row is (-fV_2, fV_1, 0, 0, 0, 0)
    assert ("($LHinge_fA_3 =\\<^sub>u (($LHinge_pA_3 + ((((- $LHinge_fV_2) * "
            "\\<guillemotleft>(LHinge_A ! 0)\\<guillemotright>) + ($LHinge_fV_1 * "
            "\\<guillemotleft>(LHinge_A ! 1)\\<guillemotright>)) * $LHinge_v)) + "
            "\\<guillemotleft>((LHinge_A ! 2) * LHinge_a)\\<guillemotright>))") in text
    # the hinges' equations of motion (tests/test_semantics_motion.py checks their values)
    assert "($LHinge_tau =\\<^sub>u \\<guillemotleft>(0.000006262506249999999 * " \
        "LHinge_a)\\<guillemotright>)" in text
    assert "($LHinge_theta\\<acute> =\\<^sub>u $LHinge_v)" in text
    assert "($LMotor_das\\<acute> =\\<^sub>u 0)" in text
    assert "are held: LMotor_das, RMotor_das' = 0 in Evolve" in " ".join(text.split())


def test_marxbot_calls_persist_without_a_caveat() -> None:
    """ReceiveFromDModel is a loop of sequential receptions, not the paper's lossy |||: the
    theory's header states the deviation (with the utp-main lines that make the interleaving
    lossy), and W-INTERLEAVE, which warned about it, is gone with --isabelle-namesets."""
    generated = api.generate_isabelle([MARXBOT])
    assert "W-INTERLEAVE" not in codes.REGISTRY
    assert not generated.report.has_errors
    text = generated.files["marXbotBase_CyPhyCircus.thy"]
    assert "|||" not in text.split("begin", 1)[1] and "Caveat" not in text
    header = " ".join(text.split("*)")[0].split())
    assert "Deviation from the paper: ReceiveFromDModel receives the d-model's calls" in header
    assert "utp_circus_parallel.thy:846-847" in header


def test_marxbot_generation_is_deterministic() -> None:
    first = api.generate_isabelle([MARXBOT]).files
    assert api.generate_isabelle([MARXBOT]).files == first


def test_names_table(marxbot_session) -> None:
    rows = [r.split("\t") for r in marxbot_session.files["names.tsv"].splitlines()]
    assert rows[0] == ["qualified", "cyphycircus", "isabelle", "definition"]
    table = {r[0]: (r[1], r[2]) for r in rows[1:]}
    assert table["marXbotBase::Core::LHinge::LMotor.das"] == ("LMotor_das", "LMotor_das")
    assert table["M::move::dsl"] == ("move_dsl", "move_dsl")
    definition = {r[0]: r[3] for r in rows[1:]}  # a device constant's block-qualified name
    assert definition["marXbotBase::Core::LHinge::LMotor::R"] == "SpeedControlMotor::R"
    assert definition["marXbotBase::Core::LHinge::LMotor.das"] == ""


def test_names_table_lists_every_state_field_of_the_theory(marxbot_session) -> None:
    """Each field of the theory's alphabets (read by check-theory's reader, not from the
    printer's tables) is a row: the vector ports by component (LHinge_F_1..6, not LHinge_F),
    the integrator states (LMotor_e_int) as integrals of their operand."""
    from cyphy.verify.theory.scope import declarations
    from cyphy.verify.theory.lexer import commands, tokenize

    text = marxbot_session.files[f"{marxbot_session.theory_name}.thy"]
    fields = {tok.text for cmd in commands(tokenize(text)) if cmd.keyword == "alphabet"
              for kind, tok in declarations(cmd) if kind == "constant"}
    rows = [r.split("\t") for r in marxbot_session.files["names.tsv"].splitlines()[1:]]
    listed = {r[2]: r[0] for r in rows}
    assert fields and fields <= set(listed), sorted(fields - set(listed))
    assert [listed[f"LHinge_F_{k}"] for k in range(1, 7)] == [
        f"marXbotBase::Core::LHinge.F[{k}]" for k in range(1, 7)]
    assert "LHinge_F" not in listed
    assert listed["LMotor_e_int"] == "integral of marXbotBase::Core::LHinge::LMotor.e"


def test_cli_writes_the_session(tmp_path: Path, capsys) -> None:
    out = tmp_path / "isa"
    assert main(["gen", "--isabelle", str(MARXBOT), "-o", str(out), "--tscale", "0.01"]) == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "CyPhyCircus_Prelude.thy", "README", "ROOT", "marXbotBase_CyPhyCircus.thy",
        "names.tsv"]
    assert '"(tscale = 0.01)"' in (out / "marXbotBase_CyPhyCircus.thy").read_text()
    assert "WARNING" not in capsys.readouterr().err
    readme = (out / "README").read_text()
    assert "isabelle build -o document=false -d <utp-main> -D <session>" in readme


def test_removed_namesets_option_is_a_usage_error(capsys) -> None:
    """--isabelle-namesets is gone (no generated interleaving updates state): argparse's exit
    2, nothing written."""
    with pytest.raises(SystemExit) as stop:
        main(["gen", "--isabelle", str(MARXBOT), "--isabelle-namesets"])
    assert stop.value.code == 2
    assert "unrecognized arguments: --isabelle-namesets" in capsys.readouterr().err


def test_cli_writes_nothing_for_a_broken_model(tmp_path: Path) -> None:
    for name in ("Treel.rsm", "marXbotBase.rsm", "marXbotSoftware.rsm"):
        (tmp_path / name).write_text((EXAMPLES / "marxbot" / name).read_text())
    (tmp_path / "Mapping.rsm").write_text(
        MARXBOT.read_text().replace("Core::LHinge::LMotor.das == dsl", "Core::Nope.das == dsl"))
    out = tmp_path / "isa"
    assert main(["gen", "--isabelle", str(tmp_path / "Mapping.rsm"), "-o", str(out)]) == 1
    assert not out.exists()


def test_prelude_is_the_shipped_text(marxbot_session) -> None:
    prelude = marxbot_session.files["CyPhyCircus_Prelude.thy"]
    for fact in ("EvolveC_NCSP [closure]", "InterruptC_NCSP [closure]",
                 "InterruptCondC_NCSP [closure]", "MuC_NCSP [closure]", "WaitC_NCSP [closure]"):
        assert fact in prelude
    assert lex_errors(prelude) == []
    assert theory_header(prelude) == ("CyPhyCircus_Prelude",
                                      ['"UTP-Circus.utp_circus"', '"HOL.Transcendental"'])
    assert 'definition fmod :: "real \\<Rightarrow> real \\<Rightarrow> real"' in prelude


# ---------------------------------------------------------------- names


def test_reserved_words_get_a_suffix() -> None:
    names = IsabelleNames()
    assert names.add("end") == "end_v"
    assert names.add("transpose") == "transpose_v"
    assert names.add("end_v") == "end_v_v"
    assert names.add("Skip") == "Skip_v"
    assert names.add("LMotor_das") == "LMotor_das"
    assert names.add("a__b_") == "a_b"
    assert names.add("1x") == "n1x"
    assert len(set(names.inverse())) == 7


def test_round_trip_grammar_is_conflict_free() -> None:
    assert parser() is not None  # built with strict=True: no LALR or terminal conflicts


# ---------------------------------------------------------------- generated mappings

SOFTWARE = """\
package soft
interface MovesI {{ {ops} }}
interface SeesI {{ {events} }}
module Soft {{
  cycleDef cycle == 1
  robotic platform Platform {{ provides MovesI uses SeesI{outputs} }}
}}
"""

# Names that are Isabelle or UTP words but fine in RoboSim: they must be mangled.
PARAM_NAMES = ["lv", "av", "x", "fst", "card", "theory", "lemma", "wait", "ok", "hd", "on", "sp",
               "wp", "wlp", "frz", "at", "within"]
OP_NAMES = ["move", "stop", "turn", "card", "halt"]
EVENT_NAMES = ["obstacle", "distance", "bump", "fst", "light"]


def expressions(leaves: list[str]) -> st.SearchStrategy[str]:
    atoms = st.sampled_from(leaves) | st.sampled_from(["0", "2", "0.5", "3.25"])
    return st.recursive(
        atoms,
        lambda sub: st.builds(lambda a, op, b: f"({a} {op} {b})", sub,
                              st.sampled_from(["+", "-", "*", "/"]), sub)
        | st.builds(lambda a: f"-{a}", sub),
        max_leaves=5)


@st.composite
def mappings(draw) -> tuple[str, str]:  # type: ignore[no-untyped-def]
    """A d-model (platform with operations and input events) and its mapping as text."""
    op_names = draw(st.lists(st.sampled_from(OP_NAMES), min_size=0, max_size=3, unique=True))
    ev_names = draw(st.lists(st.sampled_from(EVENT_NAMES), min_size=0, max_size=3,
                             unique=True))
    ev_names = [e for e in ev_names if e not in op_names]
    ops, events, members = [], [], []
    for op in op_names:
        params = draw(st.lists(st.sampled_from(PARAM_NAMES), max_size=2, unique=True))
        ops.append(f"{op}({', '.join(f'{p}: real' for p in params)})")
        local = draw(st.booleans())
        const = draw(st.booleans())
        leaves = [*params, *(["w"] if local else []), *(["k"] if const else [])] or ["1"]
        decls = (" var w: real" if local else "") + (" const k: real = 0.25" if const else "")
        eqs = [f"equation Base::J::M.das == {draw(expressions(leaves))}"]
        if local:
            eqs.append(f"equation w == {draw(expressions([*params, '1']))}")
        members.append(f"  operation {op} {{{decls} {' '.join(eqs)} }}\n")
    for ev in ev_names:
        typed = draw(st.booleans())
        index = draw(st.integers(0, 3))
        events.append(f"event {ev}" + (": real" if typed else ""))
        pred = f"Arm::S[{index}].voltage {draw(st.sampled_from(['>=', '<', '>']))} " \
               f"{draw(st.sampled_from(['3.0', '1', '0.5']))}"
        if typed:
            value = draw(expressions([f"Arm::S[{index}].voltage", "2"]))
            members.append(f"  input event {ev} ? d {{ predicate {pred} "
                           f"equation d == {value} }}\n")
        else:
            members.append(f"  input event {ev} {{ predicate {pred} }}\n")
    lamp = draw(st.booleans())
    outputs = " event lamp: boolean" if lamp else ""
    if lamp:
        members.append("  output event lamp ? on { action Base::Lamp.on = on }\n")
    software = SOFTWARE.format(ops=" ".join(ops), events=" ".join(events), outputs=outputs)
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               + "".join(members) + "}\n")
    return software, mapping


def write_model(folder: Path, software: str, mapping: str) -> list[Path]:
    files = {"sw.rsm": software, "robot.rsm": ROBOT, "map.rsm": mapping}
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return [folder / name for name in files]


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(model=mappings())
def test_generated_mappings_pass_every_static_check(tmp_path_factory, model) -> None:
    folder = tmp_path_factory.mktemp("mapping")
    sem = semantics(write_model(folder, *model))
    session = generate_session(sem.program, sem.names)
    check_session(session, sem.program)


def test_disjoint_updates_persist(tmp_path: Path) -> None:
    """An operation and an output event that write different variables: the receiving loop
    keeps both updates without a name-set partition (which the paper's ||| needed: the
    option that wrote one, --isabelle-namesets, is gone)."""
    software = SOFTWARE.format(ops="move(lv: real)", events="event bump",
                               outputs=" event lamp: boolean")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { equation Base::J::M.das == lv }\n"
               "  input event bump { predicate Arm::S[0].voltage > 1 }\n"
               "  output event lamp ? on { action Base::Lamp.on = on }\n}\n")
    paths = write_model(tmp_path, software, mapping)
    paper = api.generate_isabelle(paths)
    assert paper.report.diagnostics == []
    text = paper.files["Robot_CyPhyCircus.thy"]
    assert ('"ReceiveFromDModel = (MuC (\\<lambda> Y. ((MoveFromDModel ;; Y) \\<box> '
            '((LampFromDModel ;; Y) \\<box> (tock \\<^bold>\\<rightarrow> Skip)))))"') in text
    sem = semantics(paths)
    check_session(generate_session(sem.program, sem.names), sem.program)


def test_isar_tools_finds_nothing_in_the_marxbot_session(marxbot_session, tmp_path) -> None:
    from isar_check import isar_findings

    assert isar_findings(marxbot_session.files, tmp_path / "session") == []


# ---------------------------------------------------------------- words of the library

#: Words that utp-main's syntax makes keywords (mixfix delimiters, read from its sources by
#: cyphy.backends.isabelle.library_words) or HOL's (at, within), plus library constants.
LIBRARY_WORDS = ["on", "sp", "wp", "wlp", "frz", "at", "within", "state", "var", "mods",
                 "nmods", "mdf", "ns", "nuses", "vrt", "invr", "con", "alpha", "tt", "do",
                 "od", "II", "U", "NCSP", "Skip", "uop", "cond", "spec", "useq"]


def _syntax_words() -> list[str]:
    from cyphy.backends.isabelle.library_words import SYNTAX_WORDS

    return sorted(SYNTAX_WORDS)


@pytest.mark.parametrize("word", sorted(set(LIBRARY_WORDS) | set(_syntax_words())))
def test_library_word_is_renamed_as_global_and_as_bound_name(word: str) -> None:
    from cyphy.backends.isabelle.terms import bound_identifier

    assert word in RESERVED
    assert IsabelleNames().add(word) == f"{word}_v"
    assert bound_identifier(word, set()) == f"{word}_b"


@pytest.mark.parametrize("word", ["on", "sp", "wp", "wlp", "frz", "at", "within"])
def test_keyword_parameter_is_renamed_in_the_theory(tmp_path: Path, word: str) -> None:
    software = SOFTWARE.format(ops=f"move({word}: real)", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               f"  operation move {{ equation Base::J::M.das == {word} }}\n}}\n")
    sem = semantics(write_model(tmp_path, software, mapping))
    session = generate_session(sem.program, sem.names)
    text = session.files["Robot_CyPhyCircus.thy"]
    assert f'"MoveCall {word}_b = ({{M_das}}\\<^sub>v:[true, ((&M_das =\\<^sub>u ' \
           f'\\<guillemotleft>{word}_b\\<guillemotright>))]\\<^sub>C)"' in text
    assert not re.search(rf"(?<![\w\\<]){word}(?![\w>])", text.split("section \\<open>Actions")[1]
                         .replace(f"{word}_b", ""))
    check_session(session, sem.program)


# ---------------------------------------------------------------- values that reach a theory


@pytest.mark.parametrize("option", [["--tscale", "-1"], ["--tscale", "0"], ["--tscale", "nan"],
                                    ["--tscale", "inf"], ["--tscale", "x"], ["--name", "a*)b"],
                                    ["--name", "1x"], ["--name", "x_"], ["--name", "a b"]])
def test_bad_tscale_or_name_is_a_usage_error(tmp_path: Path, capsys, option) -> None:
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as exit_:
        main(["gen", "--isabelle", str(MARXBOT), "-o", str(out), *option])
    assert exit_.value.code == 2
    assert option[0] in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("tscale", [-1.0, 0.0, float("nan")])
def test_inconsistent_tscale_axioms_are_refused(tscale: float) -> None:
    for dialect in ("utp", "axiomatic"):
        generated = api.generate_isabelle(
            [MARXBOT], api.SemanticsGenOptions(tscale=tscale, dialect=dialect))
        assert generated.files == {}
        assert [d.code.id for d in generated.report.diagnostics] == ["E-ISABELLE-AXIOMS"]


def test_cycle_restriction_contradicting_cycle_positive_is_refused(tmp_path: Path) -> None:
    software = SOFTWARE.format(ops="move(lv: real)", events="", outputs="").replace(
        "cycleDef cycle == 1", "cycleDef cycle == 0")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { equation Base::J::M.das == lv }\n}\n")
    paths = write_model(tmp_path, software, mapping)
    generated = api.generate_isabelle(paths)
    assert generated.files == {}
    # STM9 refuses the literal period at the cycleDef, before the axioms are written (the
    # axioms' own check, E-ISABELLE-AXIOMS, is the backstop: test_inconsistent_tscale_…)
    (found,) = [d for d in generated.report.diagnostics if d.severity.value == "ERROR"]
    assert found.code.id == "STM9" and "is 0" in found.message
    assert found.span.file.endswith("sw.rsm") and "cycleDef cycle == 0" in \
        Path(found.span.file).read_text().splitlines()[found.span.line - 1]


def test_operators_the_library_lacks_are_printed_with_the_preludes() -> None:
    """A5: a real exponent is powr (also over the state: through bop), a remainder fmod, a
    sequence over the state a chain of bop Cons (no list display for UTP expressions)."""
    from cyphy import expr as ex
    from cyphy.backends.isabelle.terms import IsabellePrinter, Symbols

    names = IsabelleNames()
    for n in ("x", "k"):
        names.add(n)
    printer = IsabellePrinter(Symbols(names, state=frozenset({"x"}), constants=frozenset({"k"})))
    x, k = ex.Name(("x",)), ex.Name(("k",))
    half, two = ex.Num("0.5"), ex.Num("2")
    assert printer.doprint(ex.BinOp("^", x, half), "uexpr") == \
        "(bop (powr) &x \\<guillemotleft>0.5\\<guillemotright>)"
    assert printer.doprint(ex.BinOp("^", x, two), "uexpr") == "(&x ^ 2)"
    assert printer.doprint(ex.BinOp("^", k, k), "hol") == "(k powr k)"
    assert printer.doprint(ex.BinOp("%", x, k), "uexpr") == \
        "(bop fmod &x \\<guillemotleft>k\\<guillemotright>)"
    assert printer.doprint(ex.BinOp("%", k, two), "hol") == "(fmod k 2)"
    assert printer.doprint(ex.Seq((x, k)), "uexpr") == (
        "(bop Cons &x (bop Cons \\<guillemotleft>k\\<guillemotright> "
        "\\<guillemotleft>[]\\<guillemotright>))")
    assert "\\<langle>" not in printer.doprint(ex.Seq((x,)), "uexpr")


def test_system_name_that_is_no_identifier_is_refused_by_the_api() -> None:
    elements = ("marXbotBase::Core::LHinge::LMotor", "marXbotBase::Core::RHinge::RMotor")
    for dialect in ("utp", "axiomatic"):
        generated = api.generate_isabelle([MARXBOT], api.SemanticsGenOptions(
            system_name="N *) theory", dialect=dialect, elements=elements))
        assert generated.files == {}
        assert [d.code.id for d in generated.report.diagnostics] == ["E-ISABELLE"]


def test_vector_local_of_a_mapping_is_bound_per_component(tmp_path: Path) -> None:
    software = SOFTWARE.format(ops="move(lv: real)", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { var w: vector(real, 3) equation w == (|lv, 0, 0|)\n"
               "    equation Base::J::M.das == w[1] }\n}\n")
    sem = semantics(write_model(tmp_path, software, mapping))
    session = generate_session(sem.program, sem.names)
    text = session.files["Robot_CyPhyCircus.thy"]
    assert "\\<^bold>\\<exists> move_w_3::real \\<bullet>" in text
    assert "\\<guillemotleft>(move_w_2 = 0)\\<guillemotright>" in text
    assert "(&M_das =\\<^sub>u \\<guillemotleft>move_w_1\\<guillemotright>)" in text
    check_session(session, session_program(sem.program, session))


def session_program(program: c.Program, session) -> c.Program:  # type: ignore[no-untyped-def]
    """The program as the session printed it (scalar state): what the round trip reads."""
    from dataclasses import replace

    from cyphy.backends.isabelle.theory import scalar_program

    return replace(program, pmodel=scalar_program(program).program.pmodel)


def test_relation_between_a_scalar_and_a_vector_is_s3_at_its_span(tmp_path: Path) -> None:
    """Ports reached through '.' have no kind for the checker's S3; the scalarisation finds
    the sizes and refuses the relation there, writing nothing."""
    from robot_model import ROBOT

    software = SOFTWARE.format(ops="move(lv: real)", events="", outputs="")
    mapping = ("import robot::*\nmap M dmodel soft::Soft to pmodel Robot {\n"
               "  operation move { equation Base::J::M.das == lv }\n}\n")
    paths = write_model(tmp_path, software, mapping)
    robot = ROBOT.replace("relation M.T == J.tau", "relation M.T == J.F")
    paths[1].write_text(robot, encoding="utf-8")
    out = tmp_path / "out"
    generated = api.generate_isabelle(paths)
    assert generated.files == {}
    [s3] = [d for d in generated.report.diagnostics if d.code.id == "S3"]
    assert "an equation between a scalar and a 6-vector" in s3.message
    line = next(i for i, t in enumerate(robot.splitlines(), 1) if "relation M.T == J.F" in t)
    assert (s3.span.file.endswith("robot.rsm"), s3.span.line) == (True, line)
    assert main(["gen", "--isabelle", *map(str, paths), "-o", str(out)]) == 1
    assert not out.exists()
