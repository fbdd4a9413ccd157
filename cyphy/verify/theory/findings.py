"""What ``cyphy check-theory`` reports: a file, a line, a code and a message."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, order=True)
class Finding:
    path: Path
    line: int  # 0: the file as a whole
    code: str
    message: str

    def render(self, base: Path | None = None) -> str:
        path = self.path
        if base is not None:
            try:
                path = self.path.relative_to(base)
            except ValueError:
                pass
        where = f"{path}:{self.line}" if self.line else f"{path}"
        return f"{where}: {self.code}: {self.message}"
