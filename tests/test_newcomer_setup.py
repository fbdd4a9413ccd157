"""The newcomer's path (issue 29): what a fresh set-up gives works without extra flags.
`reach` finds the Flow* that `.ci/install` built, by the search the tests use, and says where
it looked when there is none."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT, flowstar_binary, needs_flowstar
from cyphy.verify.flowstar.locate import find_flowstar
from cyphy.verify.flowstar.verdict import FlowstarMissing


def _bare_env(tmp_path: Path, **extra: str) -> dict[str, str]:
    """An environment whose PATH holds Python only (no flowstar) and whose tools folder is
    ``extra``'s, as after `.ci/install` on a machine where Flow* is not on PATH."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("CYPHY_FLOWSTAR", "CYPHY_TOOLS_DIR", "XDG_CACHE_HOME")}
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir(exist_ok=True)
    (bin_dir / "python3").symlink_to(sys.executable)
    env.update(PATH=str(bin_dir), HOME=str(tmp_path / "home"), PYTHONPATH=str(ROOT), **extra)
    return env


def test_the_tools_folder_is_searched(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    tools = tmp_path / "tools"
    tools.mkdir()
    fake = tools / "flowstar"
    fake.write_text("#!/bin/sh\n")
    fake.chmod(0o755)
    for k, v in _bare_env(tmp_path).items():
        monkeypatch.setenv(k, v)
    monkeypatch.delenv("CYPHY_FLOWSTAR", raising=False)
    monkeypatch.setenv("CYPHY_TOOLS_DIR", str(tools))
    assert find_flowstar() == str(fake.resolve())
    # XDG_CACHE_HOME/cyphy-tools, as .ci/install computes it
    monkeypatch.delenv("CYPHY_TOOLS_DIR")
    cache = tmp_path / "cache"
    (cache / "cyphy-tools").mkdir(parents=True)
    fake.rename(cache / "cyphy-tools" / "flowstar")
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    assert find_flowstar() == str((cache / "cyphy-tools" / "flowstar").resolve())


def test_missing_flowstar_says_where_it_looked(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    for k, v in _bare_env(tmp_path).items():
        monkeypatch.setenv(k, v)
    monkeypatch.delenv("CYPHY_FLOWSTAR", raising=False)
    monkeypatch.setenv("CYPHY_TOOLS_DIR", str(tmp_path / "nothing"))
    with pytest.raises(FlowstarMissing) as err:
        find_flowstar()
    message = str(err.value)
    assert str(tmp_path / "nothing" / "flowstar") in message
    assert "flowstar on PATH" in message and ".ci/install" in message
    with pytest.raises(FlowstarMissing, match="--flowstar-bin /no/such/flowstar"):
        find_flowstar("/no/such/flowstar")


@needs_flowstar
def test_reach_finds_the_flowstar_setup_built(tmp_path: Path) -> None:
    """The README's `reach` example with no --flowstar-bin and no flowstar on PATH: only
    the tools folder .ci/install fills."""
    built = flowstar_binary()
    env = _bare_env(tmp_path, CYPHY_TOOLS_DIR=str(built.parent) if built.name == "flowstar"
                    else "")
    if built.name != "flowstar":
        env["CYPHY_FLOWSTAR"] = str(built)
    done = subprocess.run(
        [sys.executable, "-m", "cyphy", "reach", str(EXAMPLES / "dcmotor"), "--scenario",
         str(EXAMPLES / "dcmotor" / "sampled_stop.toml"), "-o", str(tmp_path / "out")],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("SAFE: ")
