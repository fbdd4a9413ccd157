"""What a generator returns: files by name, or none and the diagnostics that say why."""

from __future__ import annotations

from dataclasses import field

from cyphy.diagnostics import Report
from cyphy.records import record


@record(frozen=False, slots=False)
class Generated:
    """What a generator produced: files by relative path, in writing order. ``files`` is
    empty when the model has errors (the report says which), so nothing gets written."""

    report: Report
    sources: dict[str, str] = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)
