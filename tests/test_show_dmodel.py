"""``cyphy show --dmodel``: modules, controllers and machines as text and JSON."""

from __future__ import annotations

import json

from conftest import CORPUS, EXAMPLES, needs_corpus
from cyphy.cli import main


def show(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["show", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@needs_corpus
def test_corpus_marxbot_lists_smovement(capsys):
    # The folder also holds p-models with errors of their own: they do not stop the d-model.
    code, out, _ = show(capsys, str(CORPUS / "marXbot"), "--dmodel", "--format", "json")
    assert code == 0
    data = json.loads(out)
    (m,) = [m for m in data["machines"] if m["name"] == "SMovement"]
    assert [s["name"] for s in m["states"]] == ["SMoving", "DMoving", "Waiting", "STurning",
                                                "DTurning"]
    assert len(m["transitions"]) == 10
    t5 = next(t for t in m["transitions"] if t["name"] == "t5")
    assert t5 == {"name": "t5", "from": "J1", "to": "Waiting", "trigger": None,
                  "condition": "$obstacle", "action": "#MBC; $stop()", "exec": False}
    assert [t["exec"] for t in m["transitions"]].count(True) == 3
    assert m["junctions"] == [{"name": "i1", "kind": "initial"},
                              {"name": "J1", "kind": "junction"},
                              {"name": "J2", "kind": "junction"}]
    assert data["modules"][0]["platform"]["provides"] == ["MovementI"]
    assert data["controllers"][0]["machines"] == [{"name": "sm", "target": "SMovement"}]


def test_example_machine_as_text(capsys):
    code, out, _ = show(capsys, str(EXAMPLES / "dcmotor" / "DCMotorSoftware.rsm"), "--dmodel")
    assert code == 0
    lines = out.splitlines()
    assert "machine SSpeed (cycle 1)" in lines
    assert "  constant wref: real = 10.0" in lines
    assert "    Cruise  [entry $drive(wref)]" in lines
    assert "    t3: Check -> Stopped [$near] / $stop()" in lines
    assert "    t1: Cruise -> Check exec" in lines


def test_json_of_actions_and_composite_states(tmp_path, capsys):
    f = tmp_path / "m.rst"
    f.write_text("interface I { event e: real go(x: real) }\n"
                 "stm M { var v: real = 0 clock C input context { uses I } "
                 "output context { requires I }\n"
                 " initial i0 state S { initial k state In { during v = v + 1 } "
                 "transition u { from k to In } }\n"
                 " transition t0 { from i0 to S action #C; $go(v); wait(2) }\n"
                 " transition t1 { from S to S exec condition $e?v /\\ since(C) > 2 } }\n")
    code, out, _ = show(capsys, str(f), "--dmodel", "--format", "json")
    assert code == 0
    (m,) = json.loads(out)["machines"]
    assert m["states"] == [
        {"name": "S", "parent": None, "entry": None, "during": None, "exit": None},
        {"name": "S::In", "parent": "S", "entry": None, "during": "v = v + 1", "exit": None}]
    assert [t["from"] + ">" + t["to"] for t in m["transitions"]] == ["S::k>S::In", "i0>S",
                                                                     "S>S"]
    assert m["transitions"][1]["action"] == "#C; $go(v); wait(2)"
    assert m["transitions"][2]["condition"] == "$e?v /\\ since(C) > 2"
    assert m["inputs"] == ["e"] and m["operations"] == ["go"] and m["clocks"] == ["C"]


def test_bad_machine_exits_1(tmp_path, capsys):
    f = tmp_path / "m.rst"
    f.write_text("stm M { state S { } transition t { from S to T } }\n")
    code, out, err = show(capsys, str(f), "--dmodel")
    assert code == 1 and out == ""
    assert "m.rst:1:1: ERROR STM2" in err and "m.rst:1:46: ERROR STM1" in err


def test_no_dmodel_exits_1(tmp_path, capsys):
    f = tmp_path / "p.rsm"
    f.write_text("const c: real = 1\n")
    code, out, err = show(capsys, str(f), "--dmodel")
    assert code == 1 and out == "" and "no module, controller or state machine" in err
