"""The documentation runs as written (issue 29): every ``console`` block of the README and of
``docs/`` is run, command by command, and its output compared with what the page shows; the
quick start runs from a fresh clone of the repository and each artefact it shows is checked
by something other than cyphy; the site builds with ``mkdocs build --strict``.

A page's runnable examples are fenced ``console`` blocks: ``$ COMMAND`` lines (``cyphy`` is
this checkout's, and ``# exit N`` at the end gives a status other than 0), each followed by
its output (stdout and stderr as one stream), where ``[...]`` stands for text that varies (times), or alone on a line for lines left
out.
A fenced block just after ``<!-- file: PATH -->`` is a file the page asks the reader to
write: it is written before the page's commands run, in a scratch folder holding a copy of
``examples/``.

Every other block that holds a command (a shell block, or a plain one whose line starts like
one) must be a ``console`` block, or be listed in :data:`NOT_RUN` with the reason it cannot
run here: a command shown is a command tested, unless the test says why not.
"""

from __future__ import annotations

import csv
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from conftest import ROOT, flowstar_binary

FENCE = re.compile(r"(?:<!-- file: (?P<file>\S+) -->\n)?```(?P<lang>\w*)\n(?P<body>.*?)^```",
                   re.S | re.M)
EXIT = re.compile(r"\s+#\s*exit (\d+)$")


@dataclass
class Example:
    command: str
    shown: list[str]
    status: int


@dataclass
class Page:
    path: Path
    files: dict[str, str] = field(default_factory=dict)
    examples: list[Example] = field(default_factory=list)


def read_page(path: Path) -> Page:
    page = Page(path)
    for m in FENCE.finditer(path.read_text(encoding="utf-8")):
        if m["file"]:
            page.files[m["file"]] = m["body"]
        elif m["lang"] == "console":
            for line in m["body"].splitlines():
                if line.startswith("$ "):
                    command = line[2:]
                    status = EXIT.search(command)
                    page.examples.append(Example(EXIT.sub("", command), [],
                                                 int(status[1]) if status else 0))
                else:
                    page.examples[-1].shown.append(line)
    return page


#: Shell-like blocks that hold commands the tests cannot run, by (page, first line), with why.
_SYNOPSIS = "a synopsis: PATH and the [options] are placeholders (a console block runs an instance)"
_SETUP = "installs system packages and builds Flow* (minutes, as root): CI runs it"
_SUITE = "the test suite itself"
NOT_RUN: dict[tuple[str, str], str] = {
    ("README.md", "bash .ci/install"): _SETUP,
    ("docs/install.md", "bash .ci/install"): _SETUP,
    ("README.md", "python3 -m pytest -q"): _SUITE,
    ("docs/development.md", "python3 -m pytest"): _SUITE,
    ("docs/development.md", "python3 benchmarks/bench_startup.py"):
        "the benchmarks: minutes each on purpose, run by hand, not part of the suite",
    ("docs/editors.md", "pip install 'cyphy[lsp]'"):
        "installs a package; `cyphy lsp` then waits for an editor on its standard input",
    ("docs/commands/reach.md", "cyphy simulate ../shared/corpus/pmodel-examples/marXbot"):
        "reads RoboTool's corpus in ../shared, which a clone has not; the reach takes minutes "
        "(benchmarks/bench_marxbot_reach.py runs it)",
    ("docs/commands/gen-cyphycircus.md", "cyphy gen MAPPING --cyphycircus|--latex"): _SYNOPSIS,
    ("docs/commands/gen-sdf.md", "cyphy gen PATH... --sdf"): _SYNOPSIS,
    ("docs/commands/gen-urdf-mjcf.md", "cyphy gen PATH... --urdf"): _SYNOPSIS,
    ("docs/commands/view.md", "cyphy view PATH..."): _SYNOPSIS,
    ("docs/commands/reach.md", "cyphy gen examples/marxbot --flowstar"): _SYNOPSIS,
    ("docs/commands/simulate.md", "$ cyphy simulate tests/data/heldout/ranger"):
        "reads tests/data/heldout, which the scratch copy of examples/ has not: "
        "tests/test_simulate_typed.py runs it from the checkout and compares its output",
}
SHELL_LANGS = ("", "sh", "bash", "shell", "text")
COMMAND = re.compile(r"\s*(\$ |(cyphy|python3?|bash|pip|ls|mkdocs|isabelle|git) )")


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def matches(shown: list[str], actual: list[str]) -> bool:
    """``[...]`` alone on a line stands for any lines (none too), within a line for any
    text."""
    pattern = "\n".join(r"(?:[^\n]*\n)*?[^\n]*" if s == "[...]" else
                        "[^\n]*".join(map(re.escape, s.split("[...]"))) for s in shown)
    return re.fullmatch(pattern, "\n".join(actual)) is not None


def run_page(page: Page, cwd: Path, checkout: Path) -> list[str]:
    """Run the page's commands in ``cwd``; the differences from what it shows."""
    for name, text in page.files.items():
        (cwd / name).parent.mkdir(parents=True, exist_ok=True)
        (cwd / name).write_text(text)
    env = {**os.environ, "PYTHONPATH": str(checkout), "CYPHY_PROGRESS": "0"}
    found = flowstar_binary()
    if found is not None:
        env["CYPHY_FLOWSTAR"] = str(found)
    problems = []
    for ex in page.examples:
        if re.search(r"\bcyphy reach\b", ex.command) and found is None:
            continue  # (the Flow* tests skip likewise)
        script = f'cyphy() {{ "{sys.executable}" -m cyphy "$@"; }}\n{ex.command}\n'
        done = subprocess.run(["bash", "-c", script], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, cwd=cwd, env=env,
                              timeout=900, stdin=subprocess.DEVNULL)
        actual = done.stdout.splitlines()  # one stream, in the order a terminal shows
        if done.returncode != ex.status or not matches(ex.shown, actual):
            problems.append(f"{page.path.name}: $ {ex.command}\n"
                            f"  exit {done.returncode} (shown: {ex.status})\n  shown:\n    "
                            + "\n    ".join(ex.shown) + "\n  actual:\n    "
                            + "\n    ".join(actual))
    return problems


def _scratch(tmp_path: Path) -> Path:
    cwd = tmp_path / "work"
    shutil.copytree(ROOT / "examples", cwd / "examples")
    return cwd


RUNNABLE = [p for p in pages() if read_page(p).examples]


def test_the_docs_have_runnable_examples() -> None:
    names = {p.relative_to(ROOT).as_posix() for p in RUNNABLE}
    assert {"README.md", "docs/quickstart.md", "docs/guide/index.md"} <= names


@pytest.mark.parametrize("path", RUNNABLE, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_shown_command_prints_what_is_shown(path: Path, tmp_path: Path) -> None:
    problems = run_page(read_page(path), _scratch(tmp_path), ROOT)
    assert not problems, "\n".join(problems)


def test_every_command_shown_is_run_or_says_why_not() -> None:
    """A block that shows a command is a ``console`` block (run above), or :data:`NOT_RUN`
    says why it cannot run here; an entry of :data:`NOT_RUN` that matches no block is stale."""
    unexplained, matched = [], set()
    for path in pages():
        name = path.relative_to(ROOT).as_posix()
        for m in FENCE.finditer(path.read_text(encoding="utf-8")):
            lines = m["body"].splitlines()
            if m["file"] or m["lang"] not in SHELL_LANGS or \
                    not any(COMMAND.match(line) for line in lines):
                continue
            keys = [k for k in NOT_RUN if k[0] == name and lines[0].startswith(k[1])]
            matched.update(keys)
            if not keys:
                unexplained.append(f"{name}: {lines[0]}")
    assert not unexplained, "make these console blocks, or say in NOT_RUN why they cannot " \
        "run:\n" + "\n".join(unexplained)
    assert set(NOT_RUN) <= matched, sorted(set(NOT_RUN) - matched)


def test_the_site_quick_start_is_the_readme_s() -> None:
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## Quick start\n") + len("## Quick start\n"):
                     readme.index("\n## ", readme.index("## Quick start\n") + 1)]
    page = (ROOT / "docs" / "quickstart.md").read_text()
    assert page.startswith("# Quick start\n")
    assert page.split("\n", 1)[1].strip() == section.replace("](docs/", "](").strip()


def test_the_readme_is_short() -> None:
    assert len((ROOT / "README.md").read_text().splitlines()) <= 300


def test_the_site_builds_strictly(tmp_path: Path) -> None:
    pytest.importorskip("mkdocs")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d",
                           str(tmp_path / "site")], capture_output=True, text=True, cwd=ROOT,
                          timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert (tmp_path / "site" / "guide" / "index.html").is_file()
    assert (tmp_path / "site" / "commands" / "reach" / "index.html").is_file()


def test_the_quick_start_from_a_fresh_clone(tmp_path: Path) -> None:
    """A newcomer's first five minutes: clone, then the README's quick start as written, in
    the clone; each artefact it shows is then read by something other than cyphy."""
    if not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    clone = tmp_path / "cyphy"
    done = subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    problems = run_page(read_page(clone / "README.md"), clone, clone)
    assert not problems, "\n".join(problems)
    out = clone / "out"
    # SDF: XML whose root is <sdf version="1.6"> with the model's links; libsdformat accepts it
    root = ET.parse(out / "sdf" / "Manipulator.sdf").getroot()
    assert root.tag == "sdf" and root.get("version") == "1.6"
    assert sorted(link.get("name") for link in root.findall("./model/link")) == \
        ["Arm", "Forearm", "Gripper", "Stand"]  # the four links of Manipulator.rsm
    sys.path.insert(0, str(ROOT / "tests"))
    from sdf_tools.validate import SdfToolsMissing, check_sdf

    try:
        assert check_sdf([out / "sdf" / "Manipulator.sdf"]) == \
            {out / "sdf" / "Manipulator.sdf": []}
    except SdfToolsMissing:
        if os.environ.get("CI"):
            raise
    # PNGs: the signature and the size (IHDR) of a real picture
    for png in (out / "manipulator.png", out / "dc.png"):
        data = png.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
        assert int.from_bytes(data[16:20], "big") >= 200
    # the CSV: PI speed control has no steady-state error, so the speed ends at the demand
    # (10), after the overshoot the text describes
    with open(out / "dc.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    speeds = [float(r["Motor_av"]) for r in rows]
    assert float(rows[-1]["t"]) == 3.0 and abs(speeds[-1] - 10) < 0.05
    assert 12.5 < max(speeds) < 13.5
    # the Isabelle session: ROOT names the theory that is written
    session = (out / "isabelle" / "ROOT").read_text()
    assert "DCMotorBase_CyPhyCircus" in session
    assert "theory DCMotorBase_CyPhyCircus" in \
        (out / "isabelle" / "DCMotorBase_CyPhyCircus.thy").read_text()
    # nothing written beside the examples (reach keeps no model there)
    assert not subprocess.run(["git", "status", "--porcelain", "examples"], cwd=clone,
                              capture_output=True, text=True).stdout
