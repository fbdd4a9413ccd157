"""isar-tools' own project, proof and syntax checks (``isar check``) on a generated session."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

#: Commands that Isabelle/UTP and Ax_CyPhyCircus declare: isar-tools knows only Isabelle's
#: own keywords without the sessions that define them, and says so with this finding.
FOREIGN_COMMANDS = ("alphabet", "chantype")


def isar_findings(files: dict[str, str], folder: Path) -> list[dict[str, object]]:
    """Write the session to ``folder`` and return what ``isar check`` (its default groups:
    project, proofs, syntax) finds, minus the findings about the UTP commands."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (folder / name).write_text(text)
    proc = subprocess.run([sys.executable, "-m", "isar_tools", "check", "--format", "json",
                           str(folder)], capture_output=True, text=True)
    findings = json.loads(proc.stdout)["findings"]
    return [f for f in findings if not (
        f["code"] == "document-argument"
        and any(f"unexpected '{c}'" in str(f["message"]) for c in FOREIGN_COMMANDS))]
