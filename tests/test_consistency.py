"""`cyphy check --consistency`: C1-C5 on the marXbot mapping, on faulty mappings of ours
(tests/mappings/), and C1/C2 against NumPy's rank test on random linear mappings.

Witnesses are not compared with fixed strings: each is read back from the diagnostic and
checked against the equations it claims to satisfy or contradict.
"""

from __future__ import annotations

import json
import re
import shutil
import tempfile
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cyphy.api import CheckOptions, check
from cyphy.cli import main
from conftest import CORPUS, EXAMPLES, needs_corpus

MAPPINGS = Path(__file__).parent / "mappings"
WHEEL, AXIS = Fraction("0.025025"), Fraction("0.06")  # the marXbot's mapping constants


def _consistency(path: Path) -> list[dict]:
    result = check([str(path)], CheckOptions(consistency=True))
    return [d.to_json() for d in result.report.diagnostics if d.code.id != "L4"]


def _num(text: str) -> Fraction:
    """A witness value as printed: ``0.5``, ``-2``, ``1001/4800 (≈ 0.208542)``."""
    return Fraction(text.split(" (")[0])


def _values(text: str) -> dict[str, Fraction]:
    """``lv = 0.5, av = 1/3 (≈ 0.333333)`` → {lv: 1/2, av: 1/3}."""
    return {m[1]: _num(m[2]) for m in re.finditer(
        r"([\w:.]+) = (-?[\d./]+(?: \(≈ [-\d.e]+\))?)", text)}


def _codes(diags: list[dict]) -> list[str]:
    return [d["code"] for d in diags]


# ------------------------------------------------------------------------------------ marXbot


def _check_marxbot_c5(diags: list[dict]) -> None:
    conflicts = [d for d in diags if d["code"] == "C5"]
    assert len(conflicts) == 1
    c5 = conflicts[0]
    assert "operation move and the operation stop both write Core::LHinge::LMotor.das and " \
        "Core::RHinge::RMotor.das" in c5["message"]
    assert len(c5["notes"]) == 2
    for note, port in zip(c5["notes"], ("LMotor", "RMotor")):
        match = re.fullmatch(rf"Core::\w+::{port}\.das: move\((.*)\) sets it to (\S+), "
                             r"stop\(\) to (\S+)", note)
        assert match, note
        args, moved, stopped = _values(match[1]), _num(match[2]), _num(match[3])
        # The move solution: dsl = lv/r + a*av/(2r), dsr = lv/r - a*av/(2r).
        sign = 1 if port == "LMotor" else -1
        expected = args["lv"] / WHEEL + sign * AXIS * args["av"] / (2 * WHEEL)
        assert moved == expected and stopped == 0 and moved != stopped


def test_marxbot_move_and_stop_exist_are_unique_and_conflict() -> None:
    diags = _consistency(EXAMPLES / "marxbot" / "Mapping.rsm")
    assert _codes(diags) == ["C5"], diags  # C1-C4 hold, nothing unknown
    _check_marxbot_c5(diags)


def test_marxbot_folder_and_json_output(capsys) -> None:
    assert main(["check", "--consistency", "--format", "json",
                 str(EXAMPLES / "marxbot")]) == 0
    diags = json.loads(capsys.readouterr().out)
    assert _codes(diags) == ["C5"]
    _check_marxbot_c5(diags)


@needs_corpus
def test_corpus_marxbot_mapping() -> None:
    """RoboTool's own marXbot mapping (whose p-model has geometry errors that do not
    concern the mapping)."""
    result = check([str(CORPUS / "marXbot")], CheckOptions(consistency=True))
    diags = [d.to_json() for d in result.report.diagnostics]
    ours = [d for d in diags if d["code"].startswith("C") or d["code"] == "E-CONSISTENCY"]
    assert _codes(ours) == ["C5"]
    _check_marxbot_c5(ours)


# ------------------------------------------------------------------------ faulty mappings


def test_good_mapping_only_conflicts() -> None:
    assert _codes(_consistency(MAPPINGS / "Good.rsm")) == ["C5"]


def test_c1_contradicting_equation() -> None:
    diags = _consistency(MAPPINGS / "Contradiction.rsm")
    (c1,) = [d for d in diags if d["code"] == "C1"]
    assert c1["severity"] == "ERROR" and c1["span"]["line"] == 6
    args = _values(re.search(r"move\((.*?)\)", c1["message"])[1])
    # lv = 0.025*(dsl + dsr)/2 and dsl + dsr = 1 agree only for lv = 0.0125.
    assert set(args) == {"lv", "av"} and args["lv"] != Fraction("0.0125")
    core = [n for n in c1["notes"] if "Contradiction.rsm" in n]
    assert any(n.endswith("dsl + dsr == 1") for n in core)
    assert any("lv == 0.025 * (dsl + dsr) / 2" in n for n in core)
    assert "C2" not in _codes(diags)


def test_c2_free_local() -> None:
    diags = _consistency(MAPPINGS / "Free.rsm")
    c2 = [d for d in diags if d["code"] == "C2"]
    assert [re.search(r"determine (\S+):", d["message"])[1] for d in c2] == [
        "Base::LHinge::LMotor.das", "Base::RHinge::RMotor.das"]
    for d in c2:
        args = _values(re.search(r"move\((.*?)\)", d["message"])[1])
        one, other = (_values(n.split(": ", 1)[1]) for n in d["notes"])
        for sol in (one, other):  # both satisfy move's equations for the same arguments
            assert sol["Base::LHinge::LMotor.das"] == sol["dsl"]
            assert sol["Base::RHinge::RMotor.das"] == sol["dsr"]
            assert args["lv"] == Fraction("0.025") * (sol["dsl"] + sol["dsr"]) / 2
        port = re.search(r"determine (\S+):", d["message"])[1]
        assert one[port] != other[port]


def test_c3_typed_event_without_value() -> None:
    diags = _consistency(MAPPINGS / "NoValue.rsm")
    (c3,) = [d for d in diags if d["code"] == "C3"]
    assert c3["severity"] == "ERROR"
    voltage = _values(c3["message"])["Base::Front.voltage"]
    # The predicate holds (> 0.6) but d*d == voltage - 1 has no real solution.
    assert Fraction("0.6") < voltage < 1
    assert any(n.endswith("d * d == Base::Front.voltage - 1") for n in c3["notes"])


def test_c3_unique_two_values() -> None:
    diags = _consistency(MAPPINGS / "TwoValues.rsm")
    (w,) = [d for d in diags if d["code"] == "C3-UNIQUE"]
    assert w["severity"] == "WARNING"
    found = re.search(r"when Base::Front\.voltage = (\S+): d = (\S+) or d = (\S+)", w["message"])
    voltage, d1, d2 = (_num(found[i]) for i in (1, 2, 3))
    assert voltage > 2 and d1 != d2 and d1 * d1 == voltage - 1 == d2 * d2


def test_c4_never_and_always() -> None:
    diags = _consistency(MAPPINGS / "Predicates.rsm")
    c4 = {d["span"]["line"]: d for d in diags if d["code"] == "C4"}
    assert sorted(c4) == [18, 19]
    never, always = c4[18], c4[19]
    assert "obstacle can never hold" in never["message"]
    assert [n.split(": ", 1)[1] for n in never["notes"] if "Predicates.rsm" in n] == [
        "Base::Front.voltage >= 3", "Base::Front.voltage < 2"]
    assert "bump always holds" in always["message"]
    # bump is judged over the bumper's range {0, 1}: its equation is what makes it valid.
    assert any("Bump_pressed == if Bump_force > 1 then 1 else 0 end" in n
               for n in always["notes"])


def test_uninterpreted_function_is_unknown_never_a_pass() -> None:
    diags = _consistency(MAPPINGS / "Uninterpreted.rsm")
    unknown = [d for d in diags if d["code"] == "C-UNKNOWN"]
    assert {re.search(r"decide (C\d)", d["message"])[1] for d in unknown} >= {"C1", "C2"}
    assert all("sin" in d["message"] for d in unknown)
    assert not {"C1", "C2"} & set(_codes(diags))


def test_z3_timeout_option_and_usage_errors() -> None:
    good = str(MAPPINGS / "Good.rsm")
    assert main(["check", "--consistency", "--z3-timeout", "2000", good]) == 0
    with pytest.raises(SystemExit) as exit_:
        main(["check", "--consistency", "--z3-timeout", "0", good])
    assert exit_.value.code == 2
    assert main(["check", "--consistency", "--syntax-only", good]) == 2


def test_no_mapping_is_reported() -> None:
    diags = _consistency(EXAMPLES / "marxbot" / "marXbotBase.rsm")
    assert _codes(diags) == ["E-CONSISTENCY"]


def test_errors_stop_the_checks(tmp_path: Path) -> None:
    for name in ("Robot.rsm", "RobotSoftware.rsm"):
        shutil.copy(MAPPINGS / name, tmp_path / name)
    text = (MAPPINGS / "Good.rsm").read_text().replace("LMotor.das == dsl", "LMotor.dsa == dsl")
    (tmp_path / "Bad.rsm").write_text(text)
    codes = _codes(_consistency(tmp_path / "Bad.rsm"))
    assert "E-CONSISTENCY" in codes and not any(c.startswith("C") for c in codes)


# ------------------------------------------------------------- random linear mappings


REST = """	operation stop {
		equation Base::LHinge::LMotor.das == 0
		equation Base::RHinge::RMotor.das == 0
	}
	input event obstacle { predicate Base::Front.voltage >= 3.0 }
	input event bump { predicate Base::Bump.pressed > 0.5 }
	input event distance ? d {
		equation Base::Front.voltage == 0.2/(d + 0.01) + 0.5
		predicate Base::Front.voltage > 0.5
	}
"""
UNKNOWNS = ("x1", "x2", "Base::LHinge::LMotor.das", "Base::RHinge::RMotor.das")
ARGS = ("lv", "av")


def _side(coefficients: list[int], names: tuple[str, ...]) -> str:
    terms = [f"{c}*{n}" for c, n in zip(coefficients, names) if c]
    return " + ".join(terms) or "0"


rows = st.lists(st.tuples(st.lists(st.integers(-2, 2), min_size=4, max_size=4),
                          st.lists(st.integers(-2, 2), min_size=2, max_size=2),
                          st.integers(-2, 2)), min_size=1, max_size=4)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rows)
def test_c1_c2_agree_with_rank_test(equations) -> None:
    """Equations M·u == D·args + e over u = (x1, x2, LMotor.das, RMotor.das). An input u_k
    is determined iff e_k lies in M's row space; C2 fails for it iff it is not determined
    and some arguments make the system solvable (rank [M D] == rank [M D e]). C1 fails iff
    some arguments make it unsolvable (rank M < rank [M D e])."""
    m = np.array([u for u, _, _ in equations], dtype=float)
    d = np.array([a for _, a, _ in equations], dtype=float)
    e = np.array([[c] for _, _, c in equations], dtype=float)
    rank = np.linalg.matrix_rank
    mentioned = [k for k in (2, 3) if m[:, k].any()]
    solvable_somewhere = rank(np.hstack([m, d])) == rank(np.hstack([m, d, e]))
    expected_c2 = [UNKNOWNS[k] for k in mentioned if solvable_somewhere and
                   rank(np.vstack([m, np.eye(4)[k]])) > rank(m)]
    expected_c1 = rank(m) < rank(np.hstack([m, d, e]))

    lines = [f"\t\tequation {_side(u, UNKNOWNS)} == {_side(a, ARGS)} + {c}"
             for u, a, c in equations]
    text = ("import consistencyRobot::*\nimport robotSoftware::*\n"
            "map Random dmodel RobotSoftware to pmodel Robot {\n\toperation move {\n"
            "\t\tvar x1: real, x2: real\n" + "\n".join(lines) + "\n\t}\n" + REST + "}\n")
    with tempfile.TemporaryDirectory() as folder:
        for name in ("Robot.rsm", "RobotSoftware.rsm"):
            shutil.copy(MAPPINGS / name, Path(folder) / name)
        (Path(folder) / "Random.rsm").write_text(text)
        diags = _consistency(Path(folder) / "Random.rsm")
    assert "C-UNKNOWN" not in _codes(diags), diags
    move = [d for d in diags if d["span"]["line"] == 4]
    got_c2 = [re.search(r"determine (\S+):", d["message"])[1] for d in move
              if d["code"] == "C2"]
    assert got_c2 == expected_c2, text
    assert ("C1" in _codes(move)) == expected_c1, text
