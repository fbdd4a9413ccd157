"""The newcomer's path (issue 29): a folder that cannot be read is a diagnostic, not a
silent gap in the model."""

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
