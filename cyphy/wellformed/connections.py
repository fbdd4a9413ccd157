"""Fixed and flexible connections: Fix1-Fix4, Flex1-Flex3.

Name resolution (S1) already reports a connection whose target or source names nothing in the
right place; these rules check what is left: the target is not the connected element's own
link, the source named by a part is a link or joint of the part's p-model itself (not one
buried in another block) and is not ambiguous, and targets that S1 could not check (a part
declared after the connection) are checked here, once every part is resolved. A diagnostic S1
already gave for the same connection is never repeated.
"""

from __future__ import annotations

from collections.abc import Iterator
from graphlib import CycleError, TopologicalSorter

from cyphy.diagnostics import did_you_mean
from cyphy.lang import ast
from cyphy.wellformed.indexing import reported
from cyphy.wellformed.registry import per_node, WFContext, rule

K = ast.BlockKind


@per_node
def _links(pm: ast.PModel) -> dict[str, ast.Block]:
    """The links the p-model contains (directly: a connection can only name these)."""
    return {b.name: b for b in pm.blocks if b.kind is K.LINK}


def _part_pmodel(ctx: WFContext, pm: ast.PModel, name: str) -> tuple[bool, ast.PModel | None]:
    """(whether ``pm`` has a part ``name``, the p-model that part instantiates if resolved)."""
    for part in pm.parts:
        if part.name == name:
            target = ctx.target(part)
            return True, target if isinstance(target, ast.PModel) else None
    return False, None


def _target_problem(ctx: WFContext, pm: ast.PModel, link: str, part: str | None
                    ) -> tuple[str, str] | None:
    """(message, hint) when ``link [in part]``, written in ``pm``, is not a link contained in
    ``pm`` or in the p-model of one of its parts; None when it is or cannot be told."""
    if part is None:
        links = _links(pm)
        if link in links:
            return None
        elsewhere = [p.name for p in pm.parts
                     if isinstance(ctx.target(p), ast.PModel)
                     and link in _links(ctx.target(p))]
        hint = (f"'{link}' is a link of part {elsewhere[0]}: write '{link} in {elsewhere[0]}'"
                if elsewhere else did_you_mean(link, links)
                or "name a link of this p-model, or 'L in P' for link L of part P")
        return f"p-model {pm.name} contains no link '{link}'", hint
    found, sub = _part_pmodel(ctx, pm, part)
    if not found:
        return (f"p-model {pm.name} has no part '{part}'",
                did_you_mean(part, [p.name for p in pm.parts]) or "name a part of this p-model")
    if sub is None:
        return None  # the part's p-model does not resolve: S1
    links = _links(sub)
    if link in links:
        return None
    return (f"part {part} (p-model {sub.name}) contains no link '{link}'",
            did_you_mean(link, links) or f"name a link of p-model {sub.name}: "
            f"{', '.join(links) or '(it has none)'}")


def _report_target(ctx: WFContext, rule_id: str, pm: ast.PModel, link: str, part: str | None,
                   node: ast.Node, what: str) -> None:
    problem = _target_problem(ctx, pm, link, part)
    if problem is not None and not reported(ctx, "S1", node.span):
        message, hint = problem
        ctx.error(rule_id, node, f"{what} goes to '{_written(link, part)}', but {message}", hint)


def _written(link: str, part: str | None) -> str:
    return f"{link} in {part}" if part is not None else link


def _blocks(node: ast.PModel | ast.Block, ancestors: tuple[ast.Block, ...] = ()
            ) -> Iterator[tuple[ast.Block, tuple[ast.Block, ...]]]:
    for b in node.blocks:
        yield b, ancestors
        yield from _blocks(b, ancestors + (b,))


def _own_link(ancestors: tuple[ast.Block, ...]) -> ast.Block | None:
    for a in reversed(ancestors):
        if a.kind is K.LINK:
            return a
    return None


def _parts(ctx: WFContext) -> Iterator[tuple[ast.PModel, ast.Part, ast.PModel | None]]:
    for _, pm in ctx.pmodels():
        for part in pm.parts:
            target = ctx.target(part)
            yield pm, part, target if isinstance(target, ast.PModel) else None


# --------------------------------------------------------------------------- fixed


@rule("Fix1", "a link's fixed connection goes to another link of its p-model or of a part")
def check_Fix1_link_fixed_target(ctx: WFContext) -> None:
    """A fixed connection ``fixed to L`` (or ``fixed to L in P``) of a link l goes to a link L
    other than l, contained in the p-model that contains l or in the p-model of a part P
    contained there. (A link fixed to itself is L6.)"""
    for site in ctx.blocks():
        block = site.block
        if block.kind is not K.LINK:
            continue
        for c in block.fixed:
            if c.part is None and c.target == block.name:
                continue  # L6
            _report_target(ctx, "Fix1", site.pmodel, c.target, c.part, c,
                           f"the fixed connection of link {block.name}")


@rule("Fix2", "a part's fixed connection starts from a link of the part's p-model")
def check_Fix2_part_fixed_source(ctx: WFContext) -> None:
    """In ``part p = P { link L fixed to … }``, L is a link contained in P, the p-model that
    defines p: a link of P itself, not one nested inside another block of P."""
    for _, part, sub in _parts(ctx):
        if sub is None:
            continue
        links = _links(sub)
        for c in part.fixed:
            if c.link in links or reported(ctx, "S1", c.span):
                continue
            nested = [(b, a) for b, a in _blocks(sub) if b.kind is K.LINK and b.name == c.link]
            where = (f", only inside {nested[0][1][-1].kind.value} {nested[0][1][-1].name}"
                     if nested and nested[0][1] else "")
            ctx.error("Fix2", c, f"part {part.name} fixes link '{c.link}', but p-model "
                      f"{sub.name} does not contain a link '{c.link}'{where}",
                      did_you_mean(c.link, links) or
                      f"name one of the links of {sub.name}: {', '.join(links) or '(none)'}")


@rule("Fix3", "a part's fixed connection goes to a link of its p-model or of a part")
def check_Fix3_part_fixed_target(ctx: WFContext) -> None:
    """In ``part p = P { link L fixed to T in Q }``, T is a link contained in the p-model that
    contains p, or in the p-model of a part Q contained there; never link L of p itself."""
    for pm, part, _ in _parts(ctx):
        for c in part.fixed:
            if c.part == part.name and c.target == c.link:
                ctx.error("Fix3", c, f"part {part.name} fixes its link {c.link} to itself",
                          "fix the link to a link of another part or of the p-model")
                continue
            _report_target(ctx, "Fix3", pm, c.target, c.part, c,
                           f"the fixed connection of link {c.link} of part {part.name}")


@rule("Fix4", "the fixed connections between a p-model's links form no cycle")
def check_Fix4_no_fixed_cycle(ctx: WFContext) -> None:
    """Links fixed to one another in a cycle (``A fixed to B``, ``B fixed to A``) weld a link
    to itself through the others: a closed chain, which each command meets differently (the
    SDF gets a loop of joints, ``simulate`` refuses it, the semantics drops the motion). The
    connection that closes the cycle is reported, once per cycle."""
    for _, pm in ctx.items(ast.PModel):
        links = _links(pm)
        edges: dict[tuple[str, str], ast.FixedConnection] = {}
        for name, link in links.items():
            for c in link.fixed:
                if c.part is None and c.target in links and c.target != name:
                    edges.setdefault((name, c.target), c)
        while edges:
            graph: dict[str, set[str]] = {}
            for source, target in edges:
                graph.setdefault(source, set()).add(target)
            try:
                TopologicalSorter(graph).prepare()
                break
            except CycleError as err:
                cycle = list(reversed(err.args[1]))  # graphlib lists it against the edges
                closing = edges.pop((cycle[-2], cycle[-1]))
                ctx.error("Fix4", closing, f"link {cycle[-2]} fixed to {cycle[-1]} closes a cycle "
                          f"of fixed connections ({' → '.join(cycle)}) in p-model {pm.name}",
                          "remove one fixed connection of the cycle: fixed links are one rigid "
                          "body, joined once")


# --------------------------------------------------------------------------- flexible


@rule("Flex1", "a joint's flexible connection goes to a link of its p-model or of a part")
def check_Flex1_joint_flexible_target(ctx: WFContext) -> None:
    """A flexible connection ``flexibly connected to L`` (or ``… to L in P``) of a joint j goes
    to a link contained in the p-model that contains j's link, or in the p-model of a part P
    contained there; never to j's own link."""
    for site in ctx.blocks():
        block = site.block
        if block.kind is not K.JOINT:
            continue
        own = _own_link(site.ancestors)
        for c in block.flexible:
            if own is not None and c.part is None and c.target == own.name:
                ctx.error("Flex1", c, f"joint {block.name} is flexibly connected to its own "
                          f"link {own.name}",
                          "connect the joint to the link it moves (another link, or 'L in P')")
                continue
            _report_target(ctx, "Flex1", site.pmodel, c.target, c.part, c,
                           f"the flexible connection of joint {block.name}")


@per_node
def _joints(pm: ast.PModel, name: str) -> list[tuple[ast.Block, ast.Block | None]]:
    """The joints called ``name`` in ``pm``, with their links."""
    return [(b, _own_link(a)) for b, a in _blocks(pm) if b.kind is K.JOINT and b.name == name]


@rule("Flex2", "a part's flexible connection names one joint of the part's p-model")
def check_Flex2_part_flexible_source(ctx: WFContext) -> None:
    """In ``part p = P { joint J flexibly connected to … }``, J names a joint contained in P,
    the p-model that defines p, and only one: when links of P have joints of the same name,
    the connection cannot tell which joint it connects."""
    for _, part, sub in _parts(ctx):
        if sub is None:
            continue
        for c in part.flexible:
            joints = _joints(sub, c.joint)
            if len(joints) > 1:
                links = ", ".join(link.name if link else sub.name for _, link in joints)
                ctx.error("Flex2", c, f"part {part.name} connects joint '{c.joint}', but "
                          f"p-model {sub.name} has {len(joints)} joints of that name (in "
                          f"{links})", f"rename the joints of {sub.name} so that each name "
                          "is used once")
            elif not joints and not reported(ctx, "S1", c.span):
                names = sorted({b.name for b, _ in _blocks(sub) if b.kind is K.JOINT})
                ctx.error("Flex2", c, f"part {part.name} connects joint '{c.joint}', but "
                          f"p-model {sub.name} contains no joint of that name",
                          did_you_mean(c.joint, names) or
                          f"its joints are: {', '.join(names) or '(none)'}")


@rule("Flex3", "a part's flexible connection goes to a link of its p-model or of a part")
def check_Flex3_part_flexible_target(ctx: WFContext) -> None:
    """In ``part p = P { joint J flexibly connected to T in Q }``, T is a link contained in the
    p-model that contains p, or in the p-model of a part Q contained there; never the link of
    p that holds J."""
    for pm, part, sub in _parts(ctx):
        for c in part.flexible:
            if sub is not None and c.part == part.name:
                own = {link.name for _, link in _joints(sub, c.joint) if link is not None}
                if c.target in own:
                    ctx.error("Flex3", c, f"part {part.name} connects its joint {c.joint} to "
                              f"{c.target}, the joint's own link",
                              "connect the joint to a link of another part or of the p-model")
                    continue
            _report_target(ctx, "Flex3", pm, c.target, c.part, c,
                           f"the flexible connection of joint {c.joint} of part {part.name}")

