"""The newcomer's path (issue 29), at scale and at the edges: a folder that cannot be read is a
diagnostic, not a silent gap in the model; a model nested too deeply says where."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from conftest import EXAMPLES
from cyphy.cli import main


def test_an_unreadable_sub_folder_is_reported(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    project = tmp_path / "project"
    shutil.copytree(EXAMPLES / "dcmotor", project)
    hidden = project / "more"
    hidden.mkdir()
    (hidden / "Extra.rsm").write_text("package extra\n")
    # listing the folder fails as for a user without read permission (root, who runs CI,
    # reads any folder whatever its bits: the failure is made where os.walk lists it)
    real = os.scandir

    def scandir(path: object = ".") -> object:
        if Path(os.fsdecode(path)) == hidden:
            raise PermissionError(13, "Permission denied", os.fsdecode(path))
        return real(path)

    monkeypatch.setattr(os, "scandir", scandir)
    assert main(["check", str(project)]) == 1
    err = capsys.readouterr().err
    assert f"ERROR E-IO: cannot read the folder {hidden}: Permission denied" in err
    monkeypatch.undo()
    assert main(["check", str(project)]) == 0


def test_nests_too_deeply_says_where(tmp_path: Path) -> None:
    """A flat sum of 30,000 terms: too deep for the walks over it, and the message points at
    the sum (line 3, column 18), not at nothing."""
    import subprocess
    import sys

    from conftest import ROOT

    model = tmp_path / "deep.rsm"
    model.write_text("package d\npmodel D {\n\tconst c: real = " + " + ".join(["1"] * 30000)
                     + "\n\tlocal link L { def { } }\n}\n")
    done = subprocess.run([sys.executable, "-m", "cyphy", "check", str(model)],
                          capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 1
    assert f"cyphy: error: {model}:3:18: the model nests too deeply" in done.stderr
