"""Value checks the paper leaves as future work: V1-V5 (on the elaborated model)."""

from __future__ import annotations
