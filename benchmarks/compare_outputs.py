"""Byte-identical outputs across two revisions: check out each in a git worktree, run every
``gen`` target, ``show`` (text and JSON) and ``solve`` on the examples and on the RoboTool
corpus (``../shared/corpus``, when present), and compare the files written, the standard
output, the diagnostics and the exit statuses.

    python3 benchmarks/compare_outputs.py REV_A REV_B [--no-corpus] [--keep DIR]

Each revision runs in one process (imports paid once; the commands run in it one after the
other, as the tests run them); paths of the worktree and of the output folder are replaced by
placeholders before comparing. Exit status 1 when anything differs.
"""

from __future__ import annotations

import argparse
import filecmp
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS = ROOT.parent / "shared" / "corpus" / "pmodel-examples"
TARGETS = ("sdf", "urdf", "mjcf", "isabelle", "cyphycircus", "latex")

#: Runs in the revision's worktree: every command on each model folder (pairs of folder and
#: output folder, one per line on stdin), each command's exit status, stdout and stderr
#: written to ``OUT/<command>.txt`` with paths made neutral.
_RUNNER = r"""
import contextlib, io, sys
from pathlib import Path
from cyphy.cli import main

tree, targets = sys.argv[1], sys.argv[2].split(",")


def run_folder(folder, out):
    commands = {f"gen-{t}": ["gen", folder, f"--{t}", "-o", str(out / f"gen-{t}")]
                for t in targets}
    commands.update({"show": ["show", folder], "show-json": ["show", folder, "--format", "json"],
                     "solve": ["solve", folder]})
    for name, argv in commands.items():
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            try:
                code = main(argv)
            except SystemExit as stop:
                code = stop.code
        text = f"exit {code}\n--- stdout\n{stdout.getvalue()}--- stderr\n{stderr.getvalue()}"
        text = text.replace(str(out), "<OUT>").replace(tree, "<TREE>")
        (out / f"{name}.txt").write_text(text)


for job in sys.stdin.read().splitlines():
    folder, out = job.split("\t")
    run_folder(folder, Path(out))
"""


def folders(tree: Path, corpus: bool) -> dict[str, Path]:
    """The model folders to run, by a stable name: the examples (in the worktree) and the
    corpus's project folders."""
    found = {f"examples/{p.name}": p for p in sorted((tree / "examples").iterdir()) if p.is_dir()}
    if corpus and CORPUS.is_dir():
        for p in sorted({f.parent for f in CORPUS.rglob("*") if f.suffix in (".pm", ".rst")}):
            found[f"corpus/{p.relative_to(CORPUS)}"] = p
    return found


def run_revision(rev: str, work: Path, corpus: bool) -> Path:
    """Check out ``rev`` and run everything; returns the folder of results."""
    tree = work / f"tree-{rev.replace('/', '_')}"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(tree), rev],
                   check=True, capture_output=True)
    results = work / f"out-{rev.replace('/', '_')}"
    try:
        jobs = []
        for name, folder in folders(tree, corpus).items():
            out = results / name
            out.mkdir(parents=True)
            jobs.append(f"{folder}\t{out}")
        subprocess.run([sys.executable, "-c", _RUNNER, str(tree), ",".join(TARGETS)],
                       input="\n".join(jobs), text=True, cwd=tree, check=True,
                       env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"})
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)],
                       check=False, capture_output=True)
    return results


def differences(a: Path, b: Path) -> list[str]:
    """Relative paths that differ, or exist on one side only."""
    out: list[str] = []

    def walk(cmp: filecmp.dircmp[str], prefix: str) -> None:
        out.extend(f"{prefix}{n} (only in A)" for n in cmp.left_only)
        out.extend(f"{prefix}{n} (only in B)" for n in cmp.right_only)
        _, mismatch, errors = filecmp.cmpfiles(cmp.left, cmp.right, cmp.common_files,
                                               shallow=False)
        out.extend(f"{prefix}{n}" for n in mismatch + errors)
        for name, sub in sorted(cmp.subdirs.items()):
            walk(sub, f"{prefix}{name}/")

    walk(filecmp.dircmp(a, b), "")
    return sorted(out)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rev_a")
    parser.add_argument("rev_b")
    parser.add_argument("--no-corpus", action="store_true", help="the examples only")
    parser.add_argument("--keep", metavar="DIR", help="keep the results in DIR")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(args.keep) if args.keep else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        a = run_revision(args.rev_a, work, not args.no_corpus)
        b = run_revision(args.rev_b, work, not args.no_corpus)
        files = sum(1 for p in a.rglob("*") if p.is_file())
        found = differences(a, b)
        for line in found:
            print(f"differs: {line}")
        print(f"{files} files of {args.rev_a} compared with {args.rev_b}: "
              f"{len(found)} differ")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
