"""Parts: P1-P3.

A part ``part p = P { instantiation C = e … }`` gives values to the constants of P, the p-model
it instantiates (only P's own, p-model-level constants: the constants of P's blocks are set by
``instantiation`` in their reference blocks). The values are written in the scope of the
containing p-model.
"""

from __future__ import annotations

from collections.abc import Iterator

from cyphy.diagnostics import Severity, did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import type_to_notation
from cyphy.wellformed.indexing import lookup_in, part_names, type_problem
from cyphy.wellformed.registry import WFContext, rule


def _parts(ctx: WFContext) -> Iterator[tuple[ast.SourceFile, ast.PModel, ast.Part, ast.PModel]]:
    """Every part of the user's p-models whose p-model resolves (else S1 reports it)."""
    for file, pm in ctx.pmodels():
        for part in pm.parts:
            target = ctx.target(part)
            if isinstance(target, ast.PModel):
                yield file, pm, part, target


def _constants(pm: ast.PModel) -> dict[str, ast.VarDecl]:
    return {d.name: d for d in pm.declarations if d.kind is ast.DeclKind.CONST}


def _given(ctx: WFContext, part: ast.Part, sub: ast.PModel, name: str) -> bool:
    """Whether ``--const`` gives the constant a value (its bare name, ``P::C`` or ``p::C``)."""
    return any(key in (name, f"{sub.name}::{name}", f"{part.name}::{name}")
               or key.endswith(f"::{part.name}::{name}") for key in ctx.consts)


@rule("P1", "a part instantiates every constant of its p-model that has no value",
      Severity.WARNING)
def check_P1_instantiates_missing(ctx: WFContext) -> None:
    """A part instantiates every constant of its p-model that has no value: ``part p = P {
    instantiation C = … }`` for each ``const C: T`` of P without ``= value``, unless
    ``--const`` gives it one.

    A warning, not an error: cyphy treats a constant left without a value as a parameter of the
    whole model (as RoboTool prompts for it), which ``--const`` can supply when a generator
    runs; the generators refuse to run while one is still missing (``E-CONST``)."""
    for _, _, part, sub in _parts(ctx):
        given = {i.name for i in part.instantiations}
        missing = [d.name for d in _constants(sub).values()
                   if d.value is None and d.name not in given
                   and not _given(ctx, part, sub, d.name)]
        if missing:
            listed = ", ".join(missing)
            plural = "s" if len(missing) > 1 else ""
            ctx.error("P1", part, f"part {part.name} does not instantiate the constant{plural} "
                      f"{listed} of p-model {sub.name}, which ha{'ve' if plural else 's'} no "
                      "value", f"add 'instantiation {missing[0]} = …' to part {part.name}")


@rule("P2", "a part does not instantiate a constant that already has a value")
def check_P2_no_override(ctx: WFContext) -> None:
    """A part does not instantiate a constant of its p-model that already has a value
    (``const C: real = 1`` in P and ``instantiation C = 2`` in a part of P)."""
    for _, _, part, sub in _parts(ctx):
        constants = _constants(sub)
        for inst in part.instantiations:
            decl = constants.get(inst.name)
            if decl is not None and decl.value is not None:
                ctx.error("P2", inst, f"part {part.name} instantiates constant {inst.name} of "
                          f"p-model {sub.name}, which already has a value (line "
                          f"{decl.span.line})", f"remove the instantiation, or remove the "
                          f"value of {inst.name} in {sub.name} to make it a parameter")


@rule("P3", "a part instantiates only declared constants, with values of their type")
def check_P3_declared_and_typed(ctx: WFContext) -> None:
    """A part only instantiates constants that its p-model declares (not its variables, not
    names it does not declare), with values of the constant's type."""
    for file, pm, part, sub in _parts(ctx):
        constants = _constants(sub)
        variables = {d.name: d for d in sub.declarations}
        lookup = lookup_in(ctx, file, part_names(pm, part))
        for inst in part.instantiations:
            decl = constants.get(inst.name)
            if decl is None:
                other = variables.get(inst.name)
                if other is not None:
                    ctx.error("P3", inst, f"part {part.name} instantiates '{inst.name}', "
                              f"{other.kind.value} of p-model {sub.name}, not a constant",
                              "only constants can be instantiated")
                else:
                    ctx.error("P3", inst, f"part {part.name} instantiates '{inst.name}', but "
                              f"p-model {sub.name} declares no constant of that name",
                              did_you_mean(inst.name, constants) or
                              f"its constants are: {', '.join(constants) or '(none)'}")
                continue
            problem = type_problem(inst.value, decl.type, lookup)
            if problem is not None:
                ctx.error("P3", inst.value, f"part {part.name} instantiates constant "
                          f"{inst.name} of p-model {sub.name} with {problem}",
                          f"{inst.name} is declared {type_to_notation(decl.type)}")
