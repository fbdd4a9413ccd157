"""Progress that moves (issue 29): a long ``cyphy check`` says how far it has gone within each
phase, not only which phase it is in. Counted, not timed: every :func:`progress.stage` and
:func:`progress.step` call is recorded while a 300-link model is parsed (really: no parse
cache), resolved, elaborated and checked, and each phase must report many steps that advance
(what :func:`progress.tick` shows is the latest of them, whenever it looks)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from cyphy import api, progress
from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
from synthetic import tree_model, write_model  # noqa: E402

LINKS = 300


@pytest.fixture
def updates(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, str]]:
    """(stage, step) of every update, in order; a stage's own update has step ''."""
    seen: list[tuple[str, str]] = []
    current = [""]

    def stage(text: str) -> None:
        current[0] = text
        seen.append((text, ""))

    def step(detail: str) -> None:
        seen.append((current[0], detail))

    monkeypatch.setattr(progress, "stage", stage)
    monkeypatch.setattr(progress, "step", step)
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    return seen


def _numbers(steps: list[str], pattern: str) -> list[int]:
    return [int(m[1]) for s in steps if (m := re.fullmatch(pattern, s))]


def test_every_phase_of_a_long_check_reports_steps_that_advance(
        tmp_path: Path, updates: list[tuple[str, str]]) -> None:
    from cyphy.wellformed import RULES

    result = api.check([write_model(tmp_path, tree_model(LINKS, 3))])
    assert not [d for d in result.report.diagnostics if d.severity.value == "ERROR"]

    def steps(prefix: str) -> list[str]:
        return [s for stage, s in updates if stage.startswith(prefix) and s]

    # parsing: a step per block opened, at its line, lines going forward through the model
    # (the library's files, parsed next, start again at their first lines)
    lines = _numbers(steps("reading synthetic.pm"), r"line (\d+)")
    back = next((i for i in range(1, len(lines)) if lines[i] < lines[i - 1]), len(lines))
    model = lines[:back]
    assert len(model) >= 4 * LINKS  # a link, its def, body, sensor, poses
    assert model[-1] > 20 * LINKS
    # name resolution: one step per element of the p-model, counting up to all of them
    resolved = _numbers(steps("resolving names"), rf"Tree{LINKS}: (\d+) of {LINKS} elements")
    assert resolved == list(range(1, LINKS + 1))
    # elaboration: one step per link, then the joints and the devices
    elaborated = steps(f"elaborating Tree{LINKS}")
    assert _numbers(elaborated, r"(\d+) links") == list(range(1, LINKS + 1))
    assert f"{LINKS} links: connecting the joints" in elaborated
    # the well-formedness conditions: a stage each, every one of them
    checked = {stage.split(":")[0][len("checking "):] for stage, _ in updates
               if stage.startswith("checking ")}
    assert checked == set(RULES)


def test_steps_within_a_stage_are_shown_and_a_new_stage_clears_them(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """What a log shows (``CYPHY_PROGRESS=1``): the stage with its latest step; a step of the
    same stage again only after :data:`progress.LOG_EVERY_S`; a new stage at once, without
    the old stage's step."""
    clock = [100.0]
    monkeypatch.setattr(progress.time, "monotonic", lambda: clock[0])
    monkeypatch.setenv("CYPHY_PROGRESS", "1")
    progress.start()
    clock[0] += progress.AFTER_S
    progress.stage("reading big.rsm (1/1)")
    progress.step("line 10")
    progress.tick()
    progress.step("line 20")
    clock[0] += progress.LOG_EVERY_S / 2
    progress.tick()  # too soon after the last line of this stage
    clock[0] += progress.LOG_EVERY_S / 2
    progress.tick()
    progress.stage("resolving names")
    progress.tick()  # a new stage: shown at once, and its own, with no step
    lines = capsys.readouterr().err.splitlines()
    assert [re.sub(r" \([\d.]+ s\)$", "", line) for line in lines] == [
        "cyphy: reading big.rsm (1/1): line 10",
        "cyphy: reading big.rsm (1/1): line 20",
        "cyphy: resolving names",
    ]
