"""Platform mappings: PMap1-PMap12."""

from __future__ import annotations
