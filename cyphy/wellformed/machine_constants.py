"""A machine's constants without a value (STM15, a warning).

The paper allows a constant without a value: it is a parameter of the whole model, which is
then a family of models (spec ``semantics.md``, Rule 2; ``notation.md``: "an implicit model
parameter"). So ``check`` accepts it. But running the machine needs its value: ``simulate``,
``reach`` and ``gen --flowstar`` refuse the model until it has one (``--const``, the
scenario's ``[consts]``); ``gen --isabelle`` keeps it open, a constant of the theory that
``D`` reads (:mod:`cyphy.semantics.circus.dmodel_cycle`). Before,
``check`` said nothing, and the user learnt it only from those commands. The warning names
the constant where it is declared: a machine's own (``const k: real``) or one outside it
that the machine reads (a package's), unless ``check --const`` gives it.
"""

from __future__ import annotations

from cyphy.diagnostics import Severity
from cyphy.lang import ast
from cyphy.model.machines import Machine, open_constants
from cyphy.wellformed.machines import checked_machines, machine_kind
from cyphy.wellformed.registry import WFContext, rule


@rule("STM15", "a machine's constants have values (warning: simulate and reach need them)",
      Severity.WARNING)
def check_STM15_constant_values(ctx: WFContext) -> None:
    """A constant a machine (or an operation definition) declares, or reads from outside
    it, has a value, or ``--const`` gives one; otherwise it is open (a family of models)
    and the commands that run the machine refuse the model."""
    given = {key.split("::")[-1] for key in ctx.consts}
    warned: set[int] = set()
    for m in checked_machines(ctx):
        for name, decl in open_constants(m, ctx.scopes, given).items():
            _warn(ctx, m, name, decl, warned)


def _warn(ctx: WFContext, m: Machine, name: str, decl: ast.VarDecl, warned: set[int]) -> None:
    """One warning per declaration, at it."""
    if id(decl) in warned:
        return
    warned.add(id(decl))
    ctx.error("STM15", decl, f"the constant {name} read by {machine_kind(m)} has no value: the "
              "model is a family (the paper's open constant), and simulate, reach and "
              "gen --flowstar refuse it until it has one (gen --isabelle keeps it open, a "
              "constant of the theory)",
              f"give it a value (const {name}: … = …), or give it to those commands: "
              f"--const {name}=…, or {name} = … in the scenario's [consts]")
