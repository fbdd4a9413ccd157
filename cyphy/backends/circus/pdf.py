"""Typesetting a generated LaTeX document with ``pdflatex`` (Debian's TeX Live), in a
temporary folder, so that nothing but the PDF comes back."""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path


class PdfError(Exception):
    def __init__(self, message: str, hint: str) -> None:
        super().__init__(message)
        self.hint = hint


def typeset(document: str, support: dict[str, str], timeout: float = 120.0) -> bytes:
    """The PDF of ``document`` (with ``support`` files such as a style beside it)."""
    exe = shutil.which("pdflatex")
    if exe is None:
        raise PdfError("pdflatex is not installed", "install TeX Live (Debian: apt-get "
                       "install texlive-latex-base) or generate --latex without --pdf")
    with tempfile.TemporaryDirectory(prefix="cyphy-pdf-") as tmp:
        folder = Path(tmp)
        (folder / "document.tex").write_text(document, encoding="utf-8")
        for rel, text in support.items():
            (folder / rel).write_text(text, encoding="utf-8")
        try:
            run = subprocess.run(
                [exe, "-interaction=nonstopmode", "-halt-on-error", "document.tex"],
                cwd=folder, capture_output=True, text=True, timeout=timeout,
                env={"PATH": "/usr/bin:/bin", "SOURCE_DATE_EPOCH": "0",
                     "FORCE_SOURCE_DATE": "1", "HOME": tmp})
        except subprocess.TimeoutExpired:
            raise PdfError(f"pdflatex took longer than {timeout:.0f} s", "") from None
        pdf = folder / "document.pdf"
        if run.returncode != 0 or not pdf.exists():
            errors = [line for line in run.stdout.splitlines() if line.startswith("!")]
            raise PdfError("pdflatex failed: " + ("; ".join(errors[:3]) or "no PDF"),
                           "the .tex file is still written without --pdf; please report "
                           "this as a bug of cyphy")
        return pdf.read_bytes()
