"""Platform mappings: IX5, an index into an indexed element names one of its copies.

``Core::Proximity[1].voltage`` reads copy 1 of the ring of 24 sensors ``index j : [0,24)``.
An index outside the range (``Proximity[24]``), or as many indices as the element does not
have, names no sensor: the semantics would read a variable that does not exist, and the
mapping's event would never (or always) occur. Indices and bounds are evaluated as IX1
evaluates bounds (constants included: ``index j : [0, N)`` with ``const N: nat = 24``, or
``--const N=24``, or a scenario's ``[consts]``, which ``simulate`` and ``reach`` pass to the
checks). One that needs a constant without a value is not compared: a warning (IX5 too)
says so, and the commands given the value decide.
"""

from __future__ import annotations

from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Code, Severity
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.lang.resolution.names import steps_of
from cyphy.lang.scopes import is_constant
from cyphy.model.evaluate import EvalError, UnboundName, evaluate
from cyphy.wellformed.indexing import ConstantEnv, Names, indices
from cyphy.wellformed.mapping_names import walk_path
from cyphy.wellformed.platform_services import MemberMapping, Site, label_of, members_of, sites
from cyphy.wellformed.registry import WFContext, rule


_IX5_OPEN = Code("IX5", Severity.WARNING, "an index or range that needs a constant without "
                 "a value is not compared")


def _integer(ctx: WFContext, file: ast.SourceFile, names: Names, e: ex.Expr
             ) -> tuple[int | None, str | None]:
    """The integer value of ``e`` where it is written, or None (no value here, or not an
    integer: IX1 and S3 report those), with the constant without a value it needs, if
    that is why (not a parameter of the mapping: ``Proximity[k]`` is read at run time)."""
    try:
        value = evaluate(e, ConstantEnv(ctx, file, names))
    except UnboundName as err:
        known = (names.get(err.name) if "::" not in err.name else None) or next(
            iter(ctx.scopes.lookup(file, tuple(err.name.split("::")), is_constant)), None)
        constant = isinstance(known, ast.VarDecl) and known.kind is ast.DeclKind.CONST
        return None, err.name if constant else None
    except EvalError:
        return None, None
    return (value if isinstance(value, int) and not isinstance(value, bool) else None), None


def _ranges(ctx: WFContext) -> dict[int, tuple[ast.SourceFile, Names]]:
    """For each index declaration (by id), the file and names where its range is written."""
    found: dict[int, tuple[ast.SourceFile, Names]] | None = ctx.cache.get("index-ranges")
    if found is None:
        found = {id(index): (file, outer) for file, _, _, index, outer in indices(ctx)}
        ctx.cache["index-ranges"] = found
    return found


def _indexed_elements(ctx: WFContext, site: Site, member: MemberMapping
                      ) -> Iterator[tuple[ex.Index, ast.Block | ast.Part]]:
    """Each ``E[…]`` of the member's paths with the element ``E`` (a sensor, a joint, a
    part…) it indexes, wherever ``E`` is on the path (``Chassis::Axle[1].Motor.das``)."""
    if site.pmodel is None or site.pmodel_file is None:
        return
    for m in member.members:
        for e in ast.expressions_in(m):
            for node in e.walk():
                steps = steps_of(node.base) if isinstance(node, ex.Index) else None
                if not steps:
                    continue
                names = [s[0] for s in steps]
                if names[0] == site.pmodel.name:
                    names = names[1:]
                walked = list(walk_path(ctx, site.pmodel, site.pmodel_file, names))
                if walked and len(walked) == len(names):
                    yield node, walked[-1][0]  # type: ignore[misc]


@rule("IX5", "an index into an indexed element names one of its copies")
def check_IX5_mapping_indices(ctx: WFContext) -> None:
    """In a platform mapping, ``E[i]`` names copy ``i`` of an element declared with
    ``index v : [a, b)`` (or ``[a, b]``): as many indices as the element has index
    declarations, each within its range."""
    for site in sites(ctx):
        for member in members_of(site.mapping):
            for node, block in _indexed_elements(ctx, site, member):
                where = f"the mapping of {label_of(member)}"
                if len(node.args) != len(block.indices):
                    ctx.error("IX5", node, f"{where} gives {block.name} {len(node.args)} "
                              f"ind{'ex' if len(node.args) == 1 else 'ices'}; it has "
                              f"{len(block.indices)}", f"write one index per 'index' of "
                              f"{block.name}")
                    continue
                for arg, decl in zip(node.args, block.indices):
                    file, outer = _ranges(ctx).get(id(decl), (site.file, {}))
                    (value, a), (low, b), (high, c) = (
                        _integer(ctx, site.file, {}, arg), _integer(ctx, file, outer, decl.lower),
                        _integer(ctx, file, outer, decl.upper))
                    open_ = sorted({n for n in (a, b, c) if n is not None})
                    if open_:
                        _undecided(ctx, arg, where, block, decl, open_)
                    if value is None or low is None or high is None:
                        continue
                    last = high if decl.closed else high - 1
                    if not low <= value <= last:
                        ctx.error("IX5", arg, f"{where} reads copy {value} of {block.name}, "
                                  f"whose index {decl.var} ranges over {low}..{last}",
                                  f"use an index from {low} to {last}")


def _undecided(ctx: WFContext, arg: ex.Expr, where: str, block: ast.Block | ast.Part,
               decl: ast.IndexDecl, names: list[str]) -> None:
    """A warning, not silence: ``check`` cannot tell whether the copy exists, the commands
    given the constants (``gen``/``simulate``/``reach`` with ``--const`` or ``[consts]``)
    can, and refuse it then."""
    which = ", ".join(names)
    ctx.report.report(_IX5_OPEN, f"{where}: whether {block.name}[{to_notation(arg)}] is a copy of "
                      f"{block.name} (index {decl.var}) is not decided: {which} "
                      f"ha{'s' if len(names) == 1 else 've'} no value", arg.span,
                      f"give {' and '.join(f'--const {n}=…' for n in names)} (or set it in "
                      "the scenario's [consts]) to check the index; gen, simulate and reach "
                      "check it with the values they are given")
