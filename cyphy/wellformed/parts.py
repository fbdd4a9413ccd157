"""Parts: P1-P3."""

from __future__ import annotations
