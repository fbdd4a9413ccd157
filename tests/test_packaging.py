"""The wheel a user installs holds everything cyphy reads at run time (issue 20: the built-in
physmod library was left out, so `cyphy check` failed outside an editable install).

The wheel is built with pip, installed without its dependencies into a fresh virtual
environment that sees the system's packages (numpy, Lark, … are already installed there, and
fetching them would make the test slow), and run from a temporary folder, so neither the source
tree nor the editable install can be what answers."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT

pytestmark = pytest.mark.packaging


def _data_files() -> set[str]:
    """The files below cyphy/ that are not Python sources: grammars, library, templates."""
    return {p.relative_to(ROOT).as_posix() for p in (ROOT / "cyphy").rglob("*")
            if p.is_file() and p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "-w",
                    str(out), str(ROOT)], check=True, cwd=out, timeout=600)
    (built,) = out.glob("cyphy-*.whl")
    return built


def test_wheel_holds_every_data_file(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "cyphy/lang/library/physmod/joints.rsm" in names
    assert _data_files() <= names, sorted(_data_files() - names)


def test_installed_wheel_checks_the_example(wheel: Path, tmp_path: Path) -> None:
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
                   check=True, timeout=300)
    python = venv / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps",
                    "--force-reinstall", str(wheel)], check=True, cwd=tmp_path, timeout=300)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["CYPHY_NO_CACHE"] = "1"
    work = tmp_path / "cwd"
    work.mkdir()
    where = subprocess.run([str(python), "-c", "import cyphy; print(cyphy.__file__)"],
                           capture_output=True, text=True, cwd=work, env=env, timeout=60)
    assert Path(where.stdout.strip()).is_relative_to(venv), where.stdout + where.stderr
    done = subprocess.run([str(venv / "bin" / "cyphy"), "check", str(EXAMPLES / "marxbot")],
                          capture_output=True, text=True, cwd=work, env=env, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "0 errors, 0 warnings" in done.stdout + done.stderr
