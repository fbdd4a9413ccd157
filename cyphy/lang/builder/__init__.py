"""Lark's tree → the syntax tree (:mod:`cyphy.lang.ast`): one method per grammar rule, in
one module per part of the notation, composed into :class:`Builder`."""

from __future__ import annotations

from cyphy.lang.builder.declarations import DeclarationRules
from cyphy.lang.builder.dmodel import DModelRules
from cyphy.lang.builder.expressions import ExpressionRules
from cyphy.lang.builder.physical import PModelRules


class Builder(DeclarationRules, PModelRules, DModelRules, ExpressionRules):
    """Builds one file's syntax tree bottom-up (see :class:`~cyphy.lang.builder.base.BuilderBase`)."""
