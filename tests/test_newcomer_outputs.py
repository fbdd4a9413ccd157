"""The newcomer's path (issue 29): every output path is checked before the work starts (exit
2, a clear message), results are written atomically, and a missing parent folder is created
for a file as `gen` creates its output folder."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from cyphy import outputs
from cyphy.cli import main
from cyphy.outputs import OutputError, write_file

ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def _read_only_folder(tmp_path: Path) -> Path:
    """A folder nothing can be created in: 0555 for a user, /sys (sysfs refuses new files)
    for root, whom permission bits do not stop."""
    if os.geteuid() == 0:
        try:
            os.close(tempfile.mkstemp(dir="/sys")[0])
        except OSError:
            return Path("/sys")
        pytest.skip("no read-only folder for root here")
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    return folder


def _cyphy(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "cyphy", *args], capture_output=True,
                          text=True, cwd=cwd, env=ENV, timeout=300)


def test_simulate_creates_the_missing_folder_and_writes_both_results(tmp_path: Path) -> None:
    done = _cyphy("simulate", str(EXAMPLES / "dcmotor"), "--t-end", "0.5", "--input",
                  "Motor_das=10", "-o", "results/run.csv", "--plot", "plots/run.png",
                  cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "results" / "run.csv").read_text().startswith("t,")
    assert (tmp_path / "plots" / "run.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in tmp_path.rglob(".cyphy-staging-*")]


@pytest.mark.parametrize("option", ["-o", "--plot"])
def test_simulate_refuses_a_folder_before_integrating(option: str, tmp_path: Path) -> None:
    (tmp_path / "out").mkdir()
    started = time.perf_counter()
    # --t-end 1e4 with a stiff-free model takes minutes: a refusal must come first
    done = _cyphy("simulate", str(EXAMPLES / "dcmotor"), "--t-end", "10000", "--samples",
                  "100000", "--input", "Motor_das=10*sin(t)", option, "out", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert f"cyphy simulate: error: {option} out: out is a folder: give a file name" \
        in done.stderr
    assert time.perf_counter() - started < 60


def test_read_only_targets_are_refused(tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    ro = _read_only_folder(tmp_path)
    model = str(EXAMPLES / "dcmotor")
    for argv in (["simulate", model, "-o", str(ro / "run.csv")],
                 ["simulate", model, "--plot", str(ro / "sub" / "run.png")],
                 ["view", str(EXAMPLES / "manipulator"), "-o", str(ro / "m.png")],
                 ["gen", "--sdf", model, "-o", str(ro / "sdf")],
                 ["reach", model, "--scenario", "x.toml", "-o", str(ro / "f")]):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert f"cyphy {argv[0]}: error: " in err and f"cannot write into {ro}" in err, err
    if os.geteuid() != 0:  # a read-only file (root may write any)
        target = tmp_path / "old.csv"
        target.write_text("old\n")
        target.chmod(0o444)
        assert main(["simulate", model, "-o", str(target)]) == 2
        assert "is read-only" in capsys.readouterr().err


def test_a_file_where_a_folder_is_wanted(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    plain = tmp_path / "plain"
    plain.write_text("x")
    assert main(["gen", "--sdf", str(EXAMPLES / "dcmotor"), "-o", str(plain)]) == 2
    assert f"-o {plain}: {plain} is a file, not a folder" in capsys.readouterr().err
    assert main(["view", str(EXAMPLES / "manipulator"), "-o", str(plain / "m.png")]) == 2
    assert f"{plain} is a file, not a folder" in capsys.readouterr().err
    assert plain.read_text() == "x"


def test_write_file_is_atomic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "run.csv"
    target.write_text("old\n")

    def refuse(src: str, dst: str) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(outputs.os, "replace", refuse)
    with pytest.raises(OutputError, match="No space left on device"):
        write_file(target, "new\n")
    assert target.read_text() == "old\n"  # the old file whole, no partial new one
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv"]
    monkeypatch.undo()
    write_file(target, "new\n")
    assert target.read_text() == "new\n"
