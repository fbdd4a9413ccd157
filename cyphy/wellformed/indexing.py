"""Indices and poses: IX1, IX2, PO1."""

from __future__ import annotations
