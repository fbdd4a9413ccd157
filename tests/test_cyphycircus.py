"""The paper's semantic rules on the marXbot mapping, the text round trip, LaTeX and PDF."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy import expr as ex
from cyphy.api import SemanticsGenOptions, generate_cyphycircus, semantics
from cyphy.backends.circus.reader import read_program
from cyphy.backends.circus.text import program_to_text
from cyphy.semantics.circus import ast as c

MAPPING = EXAMPLES / "marxbot" / "Mapping.rsm"


def _program(path: Path, **kw: object) -> c.Program:
    checked, built = semantics([path], SemanticsGenOptions(**kw))  # type: ignore[arg-type]
    assert built is not None, [str(d) for d in checked.report.diagnostics]
    return built.program


@pytest.fixture(scope="module")
def marxbot() -> c.Program:
    return _program(MAPPING)


def _actions(p: c.Program) -> dict[str, c.ActionDef]:
    return {a.name: a for a in p.pmodel.actions}


def _name(n: str) -> ex.Name:
    return ex.Name((n,))


def test_rule1_globals_channels_and_system(marxbot: c.Program) -> None:
    g = marxbot.globals
    assert [b.name for b in g.constants] == ["cycle", "tscale"]
    assert ex.BinOp("==", _name("cycle"), ex.Num("1")) in g.where  # cycleDef cycle == 1
    assert ex.BinOp(">", _name("tscale"), ex.Num("0")) in g.where
    chans = {ch.name: ch for ch in marxbot.channels}
    assert chans["registerRead"].variants == (c.ChannelVariant("obstacle", (c.BOOL,)),)
    assert chans["registerWrite"].variants == (c.ChannelVariant("move", (c.REAL, c.REAL)),
                                               c.ChannelVariant("stop", ()))
    cs = ("registerRead", "registerWrite", "tock")
    assert marxbot.system == c.ProcessDef("M", c.PHide(c.PParallel(
        c.PRef("marXbotSoftware"), cs, c.PRef("marXbotBase")), cs))


def test_tscale_option_fixes_tscale() -> None:
    p = _program(MAPPING, tscale=0.001)
    assert ex.BinOp("==", _name("tscale"), ex.Num("0.001")) in p.globals.where


def test_state_schema_private_and_visible(marxbot: c.Program) -> None:
    fields = {f.name: f.visible for f in marxbot.pmodel.state.fields}
    assert marxbot.pmodel.state.name == "marXbotBaseState"
    for private in ("timer", "LHinge_tau", "LHinge_pV", "LHinge_pA", "LMotor_das",
                    "Proximity1_voltage"):
        assert fields[private] is False, private
    for visible in ("LMotor_T", "Proximity0_distance", "LHinge_F"):
        assert fields[visible] is True, visible
    local = {f.name for f in marxbot.pmodel.local.fields}
    assert marxbot.pmodel.local.name == "marXbotBaseLocal"
    assert {"LHinge_theta", "move_dsl", "move_dsr"} <= local
    assert not local & set(fields)


def test_constants_with_values_and_open(marxbot: c.Program) -> None:
    consts = {k.name: k for k in marxbot.pmodel.constants}
    assert consts["move_axisLength"].value == ex.Num("0.06")  # 0.06m in SI
    assert consts["LMotor_J"].value is None  # open: a parameter of the model
    assert consts["LHinge_AXIS"].value == ex.Seq((ex.Num("0.0"), ex.Num("1.0"), ex.Num("0.0")))


def test_init_and_input_event(marxbot: c.Program) -> None:
    acts = _actions(marxbot)
    assert acts["Init"].body == c.Assign(("timer", "LMotor_das", "RMotor_das"),
                                         (ex.Num("0"),) * 3)
    obstacle = acts["ObstacleToDModel"].body
    assert isinstance(obstacle, c.Cond)
    assert obstacle.cond == ex.BinOp(">=", _name("Proximity1_voltage"), ex.Num("3.0"))
    assert obstacle.then == c.Prefix(c.Comm("registerRead", "obstacle", (c.Out(ex.Bool(True)),)),
                                     c.Skip())
    assert obstacle.orelse == c.Prefix(
        c.Comm("registerRead", "obstacle", (c.Out(ex.Bool(False)),)), c.Skip())
    assert acts["SendToDModel"].body == c.Call("ObstacleToDModel")  # one mapping: no |||


def test_operations_and_receive(marxbot: c.Program) -> None:
    acts = _actions(marxbot)
    move = acts["MoveCall"]
    assert [p.name for p in move.params] == ["lv", "av"]
    spec = move.body
    assert isinstance(spec, c.Spec) and spec.frame == ("LMotor_das", "RMotor_das")
    assert spec.pre == ex.Bool(True)
    assert isinstance(spec.post, c.Exists)
    assert [b.name for b in spec.post.bound] == ["move_dsl", "move_dsr"]
    assert len(spec.post.body) == 4
    assert spec.post.body[0] == ex.BinOp("==", _name("LMotor_das"), _name("move_dsl"))
    assert acts["MoveFromDModel"].body == c.Prefix(
        c.Comm("registerWrite", "move", (c.In("lv"), c.In("av"))),
        c.Call("MoveCall", (_name("lv"), _name("av"))))
    assert acts["StopFromDModel"].body == c.Prefix(c.Comm("registerWrite", "stop", ()),
                                                   c.Call("StopCall"))
    # ours, not the paper's |||: every call's update persists until the cycle's first tock
    loop = c.Call("Y")
    assert acts["ReceiveFromDModel"].body == c.Mu("Y", c.ExtChoice((
        c.Seq((c.Call("MoveFromDModel"), loop)), c.Seq((c.Call("StopFromDModel"), loop)),
        c.Prefix(c.Comm("tock", None, ()), c.Skip()))))


def test_evolve_has_every_equation_once_and_timer(marxbot: c.Program) -> None:
    from cyphy.api import ElaborateOptions, elaborate

    model = elaborate([EXAMPLES / "marxbot"], ElaborateOptions("marXbotBase")).model
    assert model is not None
    from cyphy.semantics.dynamics.equations import motion
    from cyphy.semantics.circus.values import si_units

    # the two hinges' equations of motion (their values: tests/test_semantics_motion.py)
    motion_equations = [si_units(e.expr) for e in motion(model)]
    assert [e.left.text for e in motion_equations] == ["LHinge_tau", "RHinge_tau"]
    # the hinges hang from the root link Core, fixed to the world: their parent twists are 0
    zero = ex.Seq(tuple(ex.Num("0") for _ in range(6)))
    twists = [ex.BinOp("==", _name(f"{h}Hinge_{p}"), zero) for h in "LR" for p in ("pV", "pA")]
    expected = [e for d in model.devices for e in d.equations] + list(model.relations) + \
        twists + motion_equations
    evolution = _actions(marxbot)["Evolve"].body
    assert isinstance(evolution, c.Evolution)
    assert evolution.state == "marXbotBaseState" and evolution.locals == "marXbotBaseLocal"
    eqs = list(evolution.equations)
    assert eqs[-1] == ex.BinOp("==", ex.Derivative(_name("timer")), ex.Num("1"))
    assert sorted(map(repr, eqs[:-1])) == sorted(map(repr, expected))
    declared = {f.name for f in marxbot.pmodel.state.fields} | \
        {f.name for f in marxbot.pmodel.local.fields} | \
        {k.name for k in marxbot.pmodel.constants}
    assert c.names_in(evolution) <= declared


def test_main_action(marxbot: c.Program) -> None:
    timer, cycle = _name("timer"), _name("cycle")
    assert marxbot.pmodel.main == c.Seq((c.Call("Init"), c.Mu("X", c.Seq((
        c.Call("SendToDModel"), c.Call("ReceiveFromDModel"),
        c.Wait(ex.BinOp("-", cycle, ex.Num("1"))),
        c.Assign(("timer",), (ex.Num("0"),)),
        c.InterruptCond(c.Call("Evolve"), ex.BinOp(">=", timer, ex.BinOp(
            "*", cycle, _name("tscale")))),
        c.Call("X"))))))


def test_names_unique_and_defined_before_use(marxbot: c.Program) -> None:
    names = [a.name for a in marxbot.pmodel.actions]
    assert len(names) == len(set(names))
    seen: set[str] = set()
    for a in marxbot.pmodel.actions:
        calls = {n.name for n in c.walk(a.body) if isinstance(n, c.Call)}
        calls -= {n.var for n in c.walk(a.body) if isinstance(n, c.Mu)}
        assert calls <= seen, (a.name, calls - seen)
        seen.add(a.name)
    globals_ = [f.name for f in marxbot.pmodel.state.fields + marxbot.pmodel.local.fields] + \
        [k.name for k in marxbot.pmodel.constants]
    assert len(globals_) == len(set(globals_))


def test_text_round_trip(marxbot: c.Program) -> None:
    text = program_to_text(marxbot)
    assert "Evolve ≙ [Λ marXbotBaseState | ∃ marXbotBaseLocal •" in text
    assert "timer' = 1" in text
    # the deviation from the paper is stated as comments, which the reader skips
    assert text.startswith("// Deviation from the paper: ReceiveFromDModel receives")
    assert read_program(text) == marxbot


@needs_corpus
def test_corpus_marxbot_mapping() -> None:
    p = _program(CORPUS / "marXbot" / "Mapping.pm")
    acts = _actions(p)
    assert list(acts) == ["Init", "ObstacleToDModel", "SendToDModel", "MoveCall",
                          "MoveFromDModel", "StopCall", "StopFromDModel",
                          "ReceiveFromDModel", "Evolve"]
    assert read_program(program_to_text(p)) == p


@needs_corpus
def test_corpus_marxbot_isabelle_shares_the_semantics_checks() -> None:
    """The corpus p-model has a zero-height box (V2): irrelevant to the semantics, so the
    Isabelle generator, like --cyphycircus, does not refuse it."""
    from cyphy.api import generate_isabelle

    generated = generate_isabelle([CORPUS / "marXbot" / "Mapping.pm"])
    assert not generated.report.has_errors
    theory = generated.files["marXbotBase_CyPhyCircus.thy"]
    assert "definition MoveCall" in theory


# --------------------------------------------------------------------------- generated mappings

SOFTWARE = """package gen
interface OpsI {{
{ops}
}}
interface EvI {{
{events}
}}
module Soft {{
  cycleDef cycle == 1
  robotic platform Plat {{
    provides OpsI
    uses EvI
  }}
}}
"""

MAPPING_TEXT = """package genmap
import marXbotBase::*
import gen::*
map G dmodel Soft to pmodel marXbotBase {{
{body}
}}
"""

_PORTS = ["Core::LHinge::LMotor.das", "Core::RHinge::RMotor.das"]


@st.composite
def mappings(draw: st.DrawFn) -> tuple[str, str, int, int]:
    n_ops = draw(st.integers(0, 3))
    n_events = draw(st.integers(0, 3))
    ops, events, body = [], [], []
    for i in range(n_ops):
        params = [f"p{i}_{k}" for k in range(draw(st.integers(0, 2)))]
        ops.append(f"  op{i}({', '.join(p + ': real' for p in params)})")
        lines = [f"  operation op{i} {{", "    var w: real"]
        for port in draw(st.lists(st.sampled_from(_PORTS), min_size=1, max_size=2,
                                  unique=True)):
            coeff = draw(st.integers(1, 5))
            rhs = " + ".join([f"{coeff}*w", *params]) if params else f"{coeff}*w"
            lines.append(f"    equation {port} == {rhs}")
        lines.append(f"    equation w == {draw(st.integers(0, 9))}")
        body += lines + ["  }"]
    for i in range(n_events):
        typed = draw(st.booleans())
        events.append(f"  event ev{i}" + (": real" if typed else ""))
        sensor = draw(st.integers(0, 23))
        threshold = draw(st.integers(1, 5))
        lines = [f"  input event ev{i}" + (" ? v" if typed else "") + " {",
                 f"    predicate Core::Proximity[{sensor}].voltage >= {threshold}.0"]
        if typed:
            lines.append(f"    equation v == 2*Core::Proximity[{sensor}].voltage")
        body += lines + ["  }"]
    return (SOFTWARE.format(ops="\n".join(ops), events="\n".join(events)),
            MAPPING_TEXT.format(body="\n".join(body)), n_ops, n_events)


@settings(max_examples=15, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(mappings())
def test_rules_on_generated_mappings(tmp_path_factory: pytest.TempPathFactory,
                                     case: tuple[str, str, int, int]) -> None:
    software, mapping, n_ops, n_events = case
    folder = tmp_path_factory.mktemp("gen")
    for f in ("Treel.rsm", "marXbotBase.rsm"):
        shutil.copy(EXAMPLES / "marxbot" / f, folder / f)
    (folder / "Soft.rsm").write_text(software)
    (folder / "Map.rsm").write_text(mapping)
    p = _program(folder / "Map.rsm")
    acts = _actions(p)
    send = acts["SendToDModel"].body
    branches = [a for a in acts if a.endswith("ToDModel") and a != "SendToDModel"]
    assert len(branches) == n_events
    if n_events == 0:
        assert send == c.Skip()
    elif n_events == 1:
        assert send == c.Call(branches[0])
    else:
        assert send == c.Interleave(tuple(c.Call(b) for b in branches))
    for i, b in enumerate(branches):
        cond = acts[b].body
        assert b == f"Ev{i}ToDModel" and isinstance(cond, c.Cond)
        typed = f"event ev{i}: real" in software
        assert isinstance(cond.then, c.IndexedExtChoice) == typed  # Rule 5
        if typed:
            assert cond.then.body.comm.fields[-1] == c.Out(_name(cond.then.var.name))
            assert isinstance(cond.then.where, c.Exists) and len(cond.then.where.body) == 1
            # Rule 4's else-branch of a typed event leaves the value open (ours).
            assert isinstance(cond.orelse, c.IndexedExtChoice)
            assert cond.orelse.where == c.Exists((), ())
            assert cond.orelse.body.comm.fields == (c.Out(ex.Bool(False)),
                                                    c.Out(_name(cond.orelse.var.name)))
        else:
            assert cond.orelse == c.Prefix(c.Comm("registerRead", f"ev{i}",
                                                  (c.Out(ex.Bool(False)),)), c.Skip())
    # Every communication carries as many values as its channel variant has types.
    arity = {(ch.name, v.tag): len(v.types) for ch in p.channels for v in ch.variants}
    arity.update({(ch.name, None): 0 for ch in p.channels if not ch.variants})
    for a in p.pmodel.actions:
        for n in c.walk(a.body):
            if isinstance(n, c.Comm):
                assert len(n.fields) == arity[(n.channel, n.tag)], (a.name, n)
    receive = acts["ReceiveFromDModel"].body
    tock = c.Prefix(c.Comm("tock", None, ()), c.Skip())
    assert (receive == tock) == (n_ops == 0)
    declared = {f.name for f in p.pmodel.state.fields} | \
        {f.name for f in p.pmodel.local.fields} | {k.name for k in p.pmodel.constants} | \
        {"cycle", "tscale"}
    for a in p.pmodel.actions:
        bound = {b.name for b in a.params} | {n.name for n in c.walk(a.body) if isinstance(n, c.In)}
        bound |= {b.name for n in c.walk(a.body) if isinstance(n, c.Exists) for b in n.bound}
        bound |= {n.var.name for n in c.walk(a.body) if isinstance(n, c.IndexedExtChoice)}
        assert c.names_in(a.body) <= declared | bound, a.name
    names = [x.name for x in p.pmodel.actions]
    assert len(names) == len(set(names))
    assert read_program(program_to_text(p)) == p


# --------------------------------------------------------------------------- files

def _gen(tmp_path: Path, *flags: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "cyphy", "gen", str(MAPPING), *flags,
                           "-o", str(tmp_path)], capture_output=True, text=True)


def test_gen_cyphycircus_files_deterministic(tmp_path: Path) -> None:
    first = generate_cyphycircus([MAPPING], "text")
    second = generate_cyphycircus([MAPPING], "text")
    assert set(first.files) == {"M.cpc", "M.names.json"}
    assert first.files == second.files
    run = _gen(tmp_path, "--cyphycircus")
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "M.cpc").read_text(encoding="utf-8") == first.files["M.cpc"]
    import json

    table = json.loads((tmp_path / "M.names.json").read_text())
    assert table["marXbotBase::Core::LHinge::LMotor.das"] == "LMotor_das"
    assert table["M::move::dsl"] == "move_dsl"


def test_gen_refuses_model_with_errors(tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(EXAMPLES / "marxbot", bad)
    text = (bad / "Mapping.rsm").read_text().replace("Core::LHinge::LMotor.das == dsl",
                                                       "Core::LHinge::LMotr.das == dsl")
    (bad / "Mapping.rsm").write_text(text)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "cyphy", "gen", str(bad / "Mapping.rsm"),
                          "--cyphycircus", "-o", str(out)], capture_output=True, text=True)
    assert run.returncode == 1
    assert "LMotr" in run.stderr and "Traceback" not in run.stderr
    assert not out.exists()


def test_latex_uses_czt_macros() -> None:
    tex = generate_cyphycircus([MAPPING], "latex").files["M.tex"]
    for macro in ("\\circprocess marXbotBase \\circdef \\circbegin", "\\circstate",
                  "\\begin{schema}{marXbotBaseState}", "\\mathbf{visible}\\; LMotor\\_T",
                  "\\Lambda marXbotBaseState", "\\derivative{timer} = 1", "\\circmu X",
                  "\\circinterrupt", "\\extchoice", "\\prefixcolon", "\\circend",
                  "registerRead\\_obstacle!\\true \\then \\Skip"):
        assert macro in tex, macro
    assert tex.count("\\circtoolsoff") == tex.count("\\circtoolson")
    assert "\n% Deviation from the paper: ReceiveFromDModel receives" in tex
    body = tex.replace("\\_", "")
    assert "_" not in body.split("\\begin{document}")[1].replace("%%Z", "")


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex is not installed")
def test_latex_pdf(tmp_path: Path) -> None:
    run = _gen(tmp_path, "--latex", "--pdf")
    assert run.returncode == 0, run.stderr
    pdf = (tmp_path / "M.pdf").read_bytes()
    assert pdf.startswith(b"%PDF")
    import re

    pages = re.findall(rb"/Type\s*/Page\b", pdf)
    assert len(pages) >= 2  # the semantics of the marXbot takes more than one page
    second = _gen(tmp_path / "again", "--latex", "--pdf")
    assert second.returncode == 0
    assert (tmp_path / "again" / "M.pdf").read_bytes() == pdf  # reproducible


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex is not installed")
def test_latex_string_constants_are_escaped(tmp_path: Path) -> None:
    """Issue 20: `$ % # & ^ _ ~ }` were written raw, and the document did not typeset."""
    from cyphy import expr as ex
    from cyphy.backends.circus.latex import STYLE, LatexExpression

    hostile = 'cost $5 100% #1 a&b x^2 my_var ~ {x} \\end{document} <a|b> "q"\x1b[31m'
    printed = LatexExpression().print(ex.Str(hostile))
    (tmp_path / "cyphycircus.sty").write_text(STYLE, encoding="utf-8")
    (tmp_path / "s.tex").write_text(
        "\\documentclass{article}\n\\usepackage{cyphycircus}\n\\begin{document}\n"
        f"\\begin{{zed}} s == {printed} \\end{{zed}}\n\\end{{document}}\n", encoding="utf-8")
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "s.tex"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-3000:]
    assert "\x1b" not in printed and "end{document}" not in printed.replace(
        "\\textbackslash{}end\\{document\\}", "")
