"""docs/equations.md's model of a motor whose shaft is the joint (issue 27): it simulates with
the command the page gives, and settles where a hand derivation says."""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import pytest

from cyphy.cli import main

DOC = Path(__file__).resolve().parent.parent / "docs" / "equations.md"


def test_the_turntable_of_the_docs_settles_at_the_demanded_speed(tmp_path: Path,
                                                                  capsys) -> None:
    text = DOC.read_text()
    (model,) = re.findall(r"```robosim\n(.*?)```", text, re.S)
    (command,) = re.findall(r"^\$ cyphy simulate turntable.rsm (.*?)$", text, re.M)
    (tmp_path / "turntable.rsm").write_text(model)
    args = command.replace("\\\n", " ").split()
    assert main(["simulate", str(tmp_path / "turntable.rsm"), *args, "--samples", "6"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    last = dict(zip(rows[0], map(float, rows[-1])))
    # steady state with das = 2: e = 0, so T = 0 (no acceleration): Kt*i = b*av gives
    # i = 0.01*2/0.5 = 0.04; L*i' = 0 gives V = R*i + Ke*av = 1.04; V = Ki*z gives z = 0.208
    assert last["Spindle_v"] == pytest.approx(2.0, abs=1e-5)
    assert last["Drive_i"] == pytest.approx(0.04, abs=1e-5)
    assert last["Drive_V"] == pytest.approx(1.04, abs=1e-5)
    assert last["Drive_int1"] == pytest.approx(0.208, abs=1e-5)
