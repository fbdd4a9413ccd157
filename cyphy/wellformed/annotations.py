"""Annotations and templates: AN1-AN4."""

from __future__ import annotations
