"""The parser reads RoboSim behaviour (controllers, state machines, operation definitions)
into syntax trees with spans: every construct of the d-model notation, and the corpus's
d-models with no body skipped. The model texts are written for the test."""

from __future__ import annotations

import pytest

from conftest import CORPUS, needs_corpus
from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.parser import contains_lark_objects, parse_text

PATH = "m.rst"
N = lambda *parts: ex.Name(parts)  # noqa: E731
num = ex.Num


def parse(text: str) -> ast.SourceFile:
    result = parse_text(text, PATH)
    assert result.diagnostics == (), [f"{d.span}: {d.message} ({d.hint})"
                                      for d in result.diagnostics]
    assert result.file is not None and not contains_lark_objects(result.file)
    return result.file


def machine(body: str) -> ast.StateMachine:
    (stm,) = parse("stm M {\n" + body + "\n}").items
    assert isinstance(stm, ast.StateMachine)
    return stm


def test_machine_declarations_contexts_and_cycle():
    stm = machine("cycleDef cycle == 1\n const PI: real, lv: real = 0.1\n var x: int = 0\n"
                  " clock C\n input context { uses ObstacleI }\n"
                  " output context { requires MovementI }\n requires Extra")
    assert stm.cycle_defs == (ast.CycleDef(ex.BinOp("==", N("cycle"), num("1"))),)
    assert [(v.name, v.kind.value if hasattr(v.kind, "value") else v.kind, v.value)
            for v in stm.variables] == [("PI", "const", None), ("lv", "const", num("0.1")),
                                       ("x", "var", num("0"))]
    assert stm.clocks == (ast.ClockDecl("C"),)
    assert stm.contexts == (
        ast.Context("input", (ast.InterfaceUse("uses", ("ObstacleI",)),)),
        ast.Context("output", (ast.InterfaceUse("requires", ("MovementI",)),)))
    assert [u.interface for u in stm.interface_uses] == [("Extra",), ("ObstacleI",),
                                                         ("MovementI",)]


def test_nodes_states_and_actions():
    stm = machine("initial i0\n junction J\n final F\n"
                  " state S { entry $move(lv, 0); #C during x = x + 1 exit $stop() }")
    assert stm.nodes == (ast.MachineNode("initial", "i0"), ast.MachineNode("junction", "J"),
                         ast.MachineNode("final", "F"))
    (s,) = stm.states
    move = ex.Call(ex.PlatformRef(("move",)), (N("lv"), num("0")))
    assert s.actions("entry") == (ast.CallStatement(move), ast.ClockReset("C"))
    assert s.actions("during") == (ast.Assign(N("x"), ex.BinOp("+", N("x"), num("1"))),)
    assert s.actions("exit") == (ast.CallStatement(ex.Call(ex.PlatformRef(("stop",)), ())),)


def test_transition_parts_and_spans():
    stm = machine("transition t5 {\n  from J1 to Waiting exec\n"
                  "  condition $obstacle /\\ since(MBC) >= PI/av\n"
                  "  action #MBC; $stop(); $done!3; wait(2); exec\n}")
    (t,) = stm.transitions
    assert (t.name, t.source, t.target, t.exec, t.trigger) == ("t5", "J1", "Waiting", True,
                                                               None)
    assert t.condition == ex.BinOp("/\\", ex.PlatformRef(("obstacle",)), ex.BinOp(
        ">=", ex.Call(N("since"), (N("MBC"),)), ex.BinOp("/", N("PI"), N("av"))))
    assert t.action == (ast.ClockReset("MBC"),
                        ast.CallStatement(ex.Call(ex.PlatformRef(("stop",)), ())),
                        ast.SendStatement(ex.PlatformRef(("done",)), num("3")),
                        ast.WaitStatement(num("2")), ast.ExecStatement())
    assert (t.source_span.line, t.source_span.column) == (3, 8)
    assert (t.target_span.line, t.target_span.column) == (3, 14)
    assert (t.span.line, t.span.end_line) == (2, 6)


def test_event_value_binding_and_trigger():
    stm = machine("transition t { from A to B trigger $go condition $ dist ? d /\\ d < 1 }")
    (t,) = stm.transitions
    assert t.trigger == ex.PlatformRef(("go",))
    assert t.condition.left == ex.PlatformRef(("dist",), "d")
    assert not t.exec and t.action is None


def test_composite_states_nest_nodes_and_transitions():
    stm = machine("state Outer { initial i junction j state Inner { } "
                  "transition t { from i to Inner } }")
    (outer,) = stm.states
    assert outer.nodes == (ast.MachineNode("initial", "i"), ast.MachineNode("junction", "j"))
    assert [s.name for s in outer.states] == ["Inner"]
    assert [t.name for t in outer.transitions] == ["t"]


def test_controller_and_operation_definition():
    f = parse("controller C { cycleDef cycle == 1 uses I requires J sref sm = P::S\n"
              " connection C on e to sm on e\n stm Inline { initial i } }\n"
              "operation scale(a: real) { terminates initial i0 state S { } }")
    ctrl, op = f.items
    assert isinstance(ctrl, ast.Controller)
    assert ctrl.machine_refs == (ast.MachineRef("sref", "sm", ("P", "S")),)
    assert [m.name for m in ctrl.machines] == ["Inline"]
    assert ast.Connection("C", "e", "sm", "e", None) in ctrl.members
    assert op.kind == "operation" and [p.name for p in op.params] == ["a"]
    assert ast.Terminates() in op.members and [s.name for s in op.states] == ["S"]


def test_duplicate_transition_part_is_reported():
    result = parse_text("stm M { transition t { from A to B to C } }", PATH)
    (d,) = result.diagnostics
    assert d.message == "'to' is given twice in transition t"
    assert (d.span.line, d.span.column) == (1, 39)


def test_sending_to_a_non_event_is_reported():
    result = parse_text("stm M { state S { entry x!1 } }", PATH)
    assert [d.code.id for d in result.diagnostics] == ["E-SYNTAX"]
    assert result.diagnostics[0].hint == "write $event!value"


@pytest.mark.parametrize("text,line,col,hint", [
    ("stm M { state S { entry } }", 1, 25, "a name"),
    ("stm M { transition t { from A goes B } }", 1, 31, "'to'"),
    ("stm M {\n  state S {\n", 2, 11, "add the missing '}'"),
])
def test_machine_syntax_errors_have_spans_and_hints(text, line, col, hint):
    result = parse_text(text, PATH)
    assert result.file is None
    (d,) = result.diagnostics
    assert (d.span.line, d.span.column) == (line, col)
    assert hint in d.hint


@needs_corpus
def test_corpus_d_models_parse_with_no_body_skipped():
    files = sorted(CORPUS.rglob("*.rst"))
    assert files
    machines = []
    for f in files:
        result = parse_text(f.read_text(encoding="utf-8"), str(f))
        assert result.diagnostics == () and result.file is not None, f
        machines += [i for i in result.file.items if isinstance(i, ast.StateMachine)]
    smovement = next(m for m in machines if m.name == "SMovement")
    assert len(smovement.states) == 5 and len(smovement.transitions) == 10
