"""Check SDF files with libsdformat 12 (our ``sdfcheck``) and load them in PyBullet.

See ``../shared/spec/sdf-validation.md``. ``check_sdf`` is the validity gate of
``sdf.md`` decision 2: ``sdf::Root::Load`` plus the checks of ``ign sdf -k``
and, by default, strict parsing (unknown elements are errors) and the tree lints
(movable joints need ``<axis>`` with ``<limit>``; one tree per model).
``pybullet_load`` checks that Bullet loads and steps a file; it always runs in a
child process, because Bullet's SDF importer segfaults on non-tree models.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

SOURCE = Path(__file__).with_name("sdfcheck.cc")
PKG = "sdformat12"
INSTALL_HINT = (
    "install it with `apt-get install -y libsdformat-dev sdformat-sdf g++ pkg-config` "
    "(Debian 12; .ci/run does this)"
)


class SdfToolsMissing(RuntimeError):
    """libsdformat 12, a compiler or PyBullet is not installed."""


def _run(cmd: list[str], **kw) -> subprocess.CompletedProcess[str]:
    return subprocess.run(cmd, check=False, capture_output=True, text=True, **kw)


@functools.cache
def build_checker() -> Path:
    """Compile ``sdfcheck.cc`` (once per session; cached on disk by source hash)."""
    for tool in ("pkg-config", "g++"):
        if shutil.which(tool) is None:
            raise SdfToolsMissing(f"`{tool}` is not on PATH; {INSTALL_HINT}")
    flags = _run(["pkg-config", "--cflags", "--libs", PKG])
    if flags.returncode != 0:
        raise SdfToolsMissing(
            f"libsdformat 12 not found (`pkg-config {PKG}` failed: {flags.stderr.strip()}); "
            + INSTALL_HINT
        )
    key = hashlib.sha256(SOURCE.read_bytes() + flags.stdout.encode()).hexdigest()[:16]
    folder = Path(tempfile.gettempdir()) / "cyphy-sdfcheck" / key
    exe = folder / "sdfcheck"
    if exe.is_file() and os.access(exe, os.X_OK):
        return exe
    folder.mkdir(parents=True, exist_ok=True)
    partial = folder / f"sdfcheck.{os.getpid()}.tmp"
    cmd = ["g++", "-O1", "-o", str(partial), str(SOURCE), *flags.stdout.split()]
    built = _run(cmd)
    if built.returncode != 0:
        raise RuntimeError(f"compiling sdfcheck failed:\n{' '.join(cmd)}\n{built.stderr}")
    os.replace(partial, exe)  # atomic: parallel sessions never see half a binary
    return exe


def _check(exe: Path, paths: list[Path], flags: list[str]) -> dict[Path, list[str]]:
    """Run sdfcheck once over ``paths``; on a crash, retry file by file."""
    proc = _run([str(exe), *flags, *map(str, paths)], timeout=600)
    found: dict[Path, list[str]] = {}
    names = sorted(((str(p), p) for p in paths), key=lambda sp: -len(sp[0]))
    for line in proc.stdout.splitlines():
        if line.startswith("OK "):
            found.setdefault(Path(line[3:]), [])
        elif line.startswith("ERROR "):
            rest = line[6:]
            for name, path in names:  # longest first: a path may contain ": "
                if rest.startswith(name + ": "):
                    found.setdefault(path, []).append(rest[len(name) + 2 :])
                    break
            else:
                raise RuntimeError(f"sdfcheck printed an unexpected line: {line!r}")
    missing = [p for p in paths if p not in found]
    if missing and len(paths) > 1:
        for p in missing:
            found.update(_check(exe, [p], flags))
    elif missing:
        what = f"signal {-proc.returncode}" if proc.returncode < 0 else f"exit {proc.returncode}"
        found[paths[0]] = [f"sdfcheck crashed ({what}): {proc.stderr.strip()[-500:]}"]
    if proc.returncode not in (0, 1) and not missing:
        raise RuntimeError(f"sdfcheck exited with {proc.returncode}: {proc.stderr}")
    return found


def check_sdf(
    paths: Iterable[str | os.PathLike[str]], *, strict: bool = True, lints: bool = True
) -> dict[Path, list[str]]:
    """Errors per file (an empty list means the file passes).

    With ``strict=False, lints=False`` this is exactly the verdict of ``ign sdf -k``.
    """
    exe = build_checker()
    flags = ["--strict"] * strict + ["--lints"] * lints
    files = [Path(p) for p in paths]
    result: dict[Path, list[str]] = {}
    for start in range(0, len(files), 256):  # stay far below the argv limit
        chunk = list(dict.fromkeys(files[start : start + 256]))
        result.update(_check(exe, chunk, flags))
    return result


# The child process: load, step, then check that the state stayed finite.
_BULLET_CHILD = r"""
import math, sys
import pybullet as p
path, steps, joints = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
p.connect(p.DIRECT)
p.setGravity(0, 0, -9.81)
bodies = p.loadSDF(path)
if not bodies:
    sys.exit("loadSDF returned no bodies")
for _ in range(steps):
    p.stepSimulation()
count = 0
for b in bodies:
    pos, orn = p.getBasePositionAndOrientation(b)
    values = list(pos) + list(orn)
    for j in range(p.getNumJoints(b)):
        values += p.getJointState(b, j)[:2]
    count += p.getNumJoints(b)
    if not all(math.isfinite(v) for v in values):
        sys.exit(f"non-finite state in body {b} after {steps} steps")
if joints >= 0 and count != joints:
    sys.exit(f"expected {joints} joints, Bullet made {count}")
print("CYPHY-BULLET-OK")
"""


def _bullet_output(text: str) -> str:
    """Bullet's messages, one per line (``Error: Joint is of type REVOLUTE but ...``)."""
    text = re.sub(r"b3(Warning|Error)\[[^\]]*\]:\s*", r"\n\1: ", text)
    noise = ("pybullet build time", "CYPHY-BULLET-OK")
    lines = (ln.strip() for ln in text.splitlines())
    return "\n".join(ln for ln in lines if ln and not ln.startswith(noise))


def pybullet_load(
    path: str | os.PathLike[str],
    steps: int = 240,
    *,
    expect_joints: int | None = None,
    timeout: float = 60,
) -> str | None:
    """Load ``path`` with ``pybullet.loadSDF`` (DIRECT) and step it in a child process.

    Returns None on success, else the error text (an exception, a crash, a timeout,
    non-finite state, or a joint count other than ``expect_joints``), followed by
    whatever Bullet printed.
    """
    if importlib.util.find_spec("pybullet") is None:
        raise SdfToolsMissing("pybullet is not installed; `pip install -e '.[test]'`")
    joints = -1 if expect_joints is None else expect_joints
    cmd = [sys.executable, "-c", _BULLET_CHILD, str(path), str(steps), str(joints)]
    try:
        proc = _run(cmd, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else e.stdout
        return f"timed out after {timeout:g} s\n{_bullet_output(out or '')}".strip()
    said = _bullet_output(proc.stdout)
    if proc.returncode == 0 and "CYPHY-BULLET-OK" in proc.stdout:
        return None
    if proc.returncode < 0:
        name = signal.Signals(-proc.returncode).name
        head = f"crashed with {name}"
    else:
        lines = [ln for ln in proc.stderr.strip().splitlines() if ln.strip()]
        head = lines[-1] if lines else f"exit status {proc.returncode}"
    return f"{head}\n{said}".strip()


def pybullet_load_many(
    paths: Iterable[str | os.PathLike[str]], steps: int = 240, *, workers: int | None = None
) -> dict[Path, str | None]:
    """``pybullet_load`` for many files, one child process each, run in parallel."""
    files = [Path(p) for p in paths]
    with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
        return dict(zip(files, pool.map(lambda f: pybullet_load(f, steps), files)))
