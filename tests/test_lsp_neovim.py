"""``cyphy lsp`` driven by a real editor's client: Neovim's built-in LSP client, headless
(``tests/editors/neovim_probe.lua``), on the faulty example. Its diagnostics must be what
``cyphy check --format json`` reports, and go to definition must reach the library."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pygls")
NVIM = shutil.which("nvim")
pytestmark = pytest.mark.skipif(NVIM is None, reason="Neovim (apt: neovim) is not installed")

ROOT = Path(__file__).resolve().parent.parent
PROBE = ROOT / "tests" / "editors" / "neovim_probe.lua"


def test_neovim_gets_cyphy_checks_diagnostics_and_definitions(tmp_path: Path) -> None:
    folder = tmp_path / "faulty"
    shutil.copytree(ROOT / "examples" / "faulty", folder)
    arm = folder / "arm.rsm"
    lines = arm.read_text(encoding="utf-8").splitlines()
    line = next(n for n, ln in enumerate(lines) if "jref Shoulder" in ln)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "CYPHY_FILE": str(arm),
           "CYPHY_PYTHON": sys.executable, "CYPHY_OUT": str(tmp_path / "out.tsv"),
           "CYPHY_LINE": str(line + 1), "CYPHY_COL": str(lines[line + 1].index("flexibly")
                                                         + len("flexibly connected to "))}
    subprocess.run([NVIM, "--headless", "-u", "NONE", "-i", "NONE", "-c",
                    f"luafile {PROBE}"], env=env, timeout=180, check=True,
                   stdin=subprocess.DEVNULL, capture_output=True)
    rows = [r.split("\t") for r in (tmp_path / "out.tsv").read_text().splitlines()]

    got = sorted((r[1], tuple(int(x) for x in r[2:6]), r[6].replace("\\n", "\n"))
                 for r in rows if r[0] == "diagnostic")
    check = subprocess.run([sys.executable, "-m", "cyphy", "check", "--format", "json",
                            str(arm)], capture_output=True, text=True, timeout=120,
                           env={**os.environ, "PYTHONPATH": str(ROOT)})
    expected = sorted((d["code"], (d["span"]["line"] - 1, d["span"]["column"] - 1,
                                   d["span"]["end_line"] - 1, d["span"]["end_column"] - 1),
                       d["message"] + (f"\nhint: {d['hint']}" if d["hint"] else ""))
                      for d in json.loads(check.stdout))
    assert [g[0] for g in got] == ["E-MEMBER", "S1"]
    assert got == expected

    (definition,) = [r for r in rows if r[0] == "definition"]  # 'UpperArm', the next link
    assert Path(definition[1]) == arm
    assert re.match(r"\s*local link UpperArm\b", lines[int(definition[2])])
