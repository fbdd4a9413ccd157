"""Interrupted runs (issue 20): a `gen` killed by SIGTERM while writing leaves its staging
folder, which the next run removes; Ctrl-C ends with status 130 and no traceback."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from conftest import EXAMPLES, ROOT, sigint_as_at_a_terminal
from cyphy.outputs import STAGING_PREFIX, remove_abandoned_staging, write_all

ENV = {**os.environ, "PYTHONPATH": str(ROOT)}

#: A writer that stops after its first file, as a run killed in the middle of writing.
SLOW_WRITER = """
import sys, time
from pathlib import Path
from cyphy import outputs
real = Path.write_bytes
def slow(self, data):
    real(self, data)
    print("STAGED", flush=True)
    time.sleep(60)
Path.write_bytes = slow
outputs.write_all({"a.sdf": "<sdf/>", "b.json": "{}"}, Path(sys.argv[1]))
"""


def test_a_killed_gen_leaves_nothing_after_the_next_run(tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-c", SLOW_WRITER, str(out)],
                            stdout=subprocess.PIPE, text=True, env=ENV)
    assert proc.stdout is not None and proc.stdout.readline().strip() == "STAGED"
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=30)
    left = [p.name for p in out.iterdir()]
    assert len(left) == 1 and left[0].startswith(STAGING_PREFIX)  # what SIGTERM leaves
    (out / ".cyphy-notes").mkdir()  # not a staging folder: someone's
    done = subprocess.run([sys.executable, "-m", "cyphy", "gen", "--sdf", "-o", str(out),
                           str(EXAMPLES / "marxbot")], capture_output=True, text=True,
                          env=ENV, timeout=300)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in out.iterdir()) == [
        ".cyphy-notes", "marXbotBase.names.json", "marXbotBase.sdf"]


def test_staging_of_a_running_writer_is_kept(tmp_path: Path) -> None:
    mine = tmp_path / f"{STAGING_PREFIX}{os.getpid()}-abc"
    mine.mkdir()
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        theirs = tmp_path / f"{STAGING_PREFIX}{sleeper.pid}-xyz"
        theirs.mkdir()
        remove_abandoned_staging(tmp_path)
        assert mine.is_dir() and theirs.is_dir()
    finally:
        sleeper.kill()
        sleeper.wait()
    remove_abandoned_staging(tmp_path)
    assert mine.is_dir() and not theirs.exists()
    assert write_all({"x.txt": "x"}, tmp_path) == [tmp_path / "x.txt"]


def test_ctrl_c_ends_with_130_and_no_traceback(tmp_path: Path) -> None:
    """SIGINT while a command runs (here: while it waits in its worker thread)."""
    code = ("import sys, time\nfrom cyphy import cli\nfrom cyphy.cli import check\n"
            "def slow(args):\n    print('RUNNING', flush=True)\n    time.sleep(60)\n"
            "    return 0\ncheck.run = slow\nsys.argv = ['cyphy', 'check', 'x.rsm']\ncli.run()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=ENV, cwd=tmp_path,
                            preexec_fn=sigint_as_at_a_terminal)
    assert proc.stdout is not None and proc.stdout.readline().strip() == "RUNNING"
    time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130 and "Traceback" not in err, err


def test_ctrl_c_during_the_final_flush_ends_with_130(tmp_path: Path) -> None:
    code = ("import sys, time\nfrom cyphy import cli\ncli.main = lambda argv=None: 0\n"
            "class Slow:\n    def write(self, s):\n        return len(s)\n"
            "    def flush(self):\n        sys.stderr.write('FLUSHING\\n'); "
            "sys.stderr.flush(); time.sleep(60)\n"
            "sys.stdout = Slow()\ncli.run()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stderr=subprocess.PIPE, text=True,
                            env=ENV, cwd=tmp_path, preexec_fn=sigint_as_at_a_terminal)
    assert proc.stderr is not None and proc.stderr.readline().strip() == "FLUSHING"
    time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130 and "Traceback" not in err, err
