"""``D`` for a machine the automaton cannot hold: its first cycle reads the inputs (no
``exec`` before the first read), so the mode it starts in depends on the events at t = 0.
The theory then writes the cycle out (:mod:`cyphy.semantics.circus.dmodel_cycle`: ``Read``
before ``Start``), as ``simulate`` runs the machine on its interpreter; before, ``D`` was
left opaque (``W-SEMANTICS-DMODEL``) and ``animate`` refused the session.

The model is the held-out rover with one ``exec`` taken out (``from Ahead to Turn condition
$near``): in the first cycle the drive machine enters ``Ahead`` and, if something is already
near, turns at once. The oracle for the theory is ``simulate`` (the model's equations and
the machine's interpreter, never the theory): ``animate`` runs the generated text."""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from cyphy import api
from cyphy.cli import main

ROVER = Path(__file__).parent / "data" / "heldout" / "rover"
DIALECTS = ("utp", "axiomatic")


def _rover(folder: Path, distance: float) -> tuple[Path, Path]:
    """The rover whose drive machine reads ``near`` in its first cycle, and its bump
    scenario with the obstacle starting ``distance`` metres away."""
    shutil.copytree(ROVER, folder)
    software = folder / "RoverSoftware.rsm"
    text = software.read_text()
    assert "from Ahead to Turn exec condition $near" in text
    software.write_text(text.replace("from Ahead to Turn exec condition $near",
                                     "from Ahead to Turn condition $near"))
    scenario = folder / "bump.toml"
    text = scenario.read_text()
    assert "\nRange_distance = 1.55\n" in text
    scenario.write_text(text.replace("\nRange_distance = 1.55\n",
                                     f"\nRange_distance = {distance}\n"))
    return folder, scenario


def _run(command: str, target: Path, scenario: Path) -> str:
    """``cyphy simulate`` (the model) or ``cyphy animate`` (the theory) over 2 s, 21
    samples, under the scenario (its [init] and the obstacle's approach), JSON."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main([command, str(target), "--scenario", str(scenario), "--t-end", "2",
                     "--samples", "21", "--format", "json", "-q"]) == 0
    return out.getvalue()


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("distance", [0.3, 1.55])  # near from the start; near from t = 1.05 s
def test_d_is_written_and_animates_as_simulate_runs_it(tmp_path: Path, dialect: str,
                                                       distance: float) -> None:
    folder, scenario = _rover(tmp_path / "rover", distance)
    generated = api.generate_isabelle([folder], api.SemanticsGenOptions(
        dialect=dialect, scenario=str(scenario)))
    codes = [d.code.id for d in generated.report.diagnostics]
    assert not generated.report.has_errors and "W-SEMANTICS-DMODEL" not in codes, codes
    session = tmp_path / "thy"
    session.mkdir()
    for name, text in generated.files.items():
        (session / name).write_text(text)
    theory = next(t for n, t in generated.files.items() if n.endswith(".thy")
                  and "Prelude" not in n)
    # the events are read before the first cycle, which may already turn
    assert "RoverSoftwareInit ;; (RoverSoftwareRead ;; (RoverSoftwareStart" in theory
    assert main(["check-theory", str(session)]) == 0

    anim = json.loads(_run("animate", session, scenario))
    columns, rows = anim["columns"], np.array(anim["rows"])
    sim = json.loads(_run("simulate", folder, scenario))
    assert np.allclose(rows[:, 0], sim["t"])
    common = [c for c in columns[1:] if c in sim["columns"]]
    assert {"LMotor_av", "RMotor_av", "Pan_av", "LAxle_v"} <= set(common)
    for col in common:
        assert np.max(np.abs(rows[:, columns.index(col)] - sim["columns"][col])) < 1e-5, col
    # independent of both: the right wheel's demand is +cruise (8) or -spin (-4); near from
    # the start turns the rover in the first cycle, so that wheel runs backwards at once
    right = rows[:, columns.index("RMotor_av")]
    if distance < 0.5:
        assert right[1] < 0 and np.all(right[1:] < 0)
    else:
        assert right[1] > 0 and right[10] > 5
