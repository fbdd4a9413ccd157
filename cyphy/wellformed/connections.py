"""Fixed and flexible connections: Fix1-Fix3, Flex1-Flex3."""

from __future__ import annotations
