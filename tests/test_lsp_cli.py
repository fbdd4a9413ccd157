"""``cyphy lsp`` as a command: it costs nothing to the other commands, and without its optional
packages it says what to install instead of failing."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def test_help_does_not_import_the_language_server_libraries() -> None:
    code = ("import sys\nfrom cyphy.cli import main\n"
            "for argv in (['--help'], ['lsp', '--help']):\n"
            "    try:\n        main(argv)\n    except SystemExit:\n        pass\n"
            "print('LOADED', sorted(m for m in ('pygls', 'lsprotocol', 'cattrs', 'numpy')"
            " if m in sys.modules))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=ENV, timeout=120)
    assert "LOADED []" in proc.stdout, proc.stdout + proc.stderr
    assert "language server" in proc.stdout


def test_without_pygls_it_says_what_to_install() -> None:
    code = ("import sys\nsys.modules['pygls'] = None\nsys.modules['lsprotocol'] = None\n"
            "from cyphy.cli import main\nsys.exit(main(['lsp']))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=ENV, timeout=120, stdin=subprocess.DEVNULL)
    assert proc.returncode == 1
    assert "pip install 'cyphy[lsp]'" in proc.stderr and "Traceback" not in proc.stderr
