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
from typing import Union

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


#: A link of an instance: the path of parts that leads to it (``("Fingers",)``), and its name.
Node = tuple[str, ...]
#: A fixed connection: from a link, to a link, the connection, and whether the p-model being
#: checked writes it (a link of its own, or a part of its own) rather than a part's p-model.
Edge = tuple[Node, Node, Union[ast.FixedConnection, ast.PartFixed], bool]


def _link_node(ctx: WFContext, pm: ast.PModel, path: Node, target: str,
               part: str | None) -> Node | None:
    """The node of ``target`` (``in part``) seen from ``pm`` at ``path``; None when it names
    no link there (Fix1/Fix3 and S1 report that)."""
    if part is None:
        return path + (target,) if target in _links(pm) else None
    found, sub = _part_pmodel(ctx, pm, part)
    return path + (part, target) if found and sub is not None and target in _links(sub) \
        else None


def _fixed_edges(ctx: WFContext, pm: ast.PModel, path: Node = (),
                 within: tuple[int, ...] = ()) -> Iterator[Edge]:
    """Every fixed connection of ``pm`` with its parts expanded, each part once (the copies
    of an indexed part are fixed alike: a connection names a part, never one copy, so a
    cycle through one copy is a cycle through each). A p-model that contains itself through
    its parts (P1's business) is not entered twice."""
    own = not path
    for name, link in _links(pm).items():
        for c in link.fixed:
            target = _link_node(ctx, pm, path, c.target, c.part)
            if target is not None and target != path + (name,):
                yield path + (name,), target, c, own
    for part in pm.parts:
        sub = ctx.target(part)
        if not isinstance(sub, ast.PModel) or id(sub) in within or sub is pm:
            continue
        for pc in part.fixed:
            target = _link_node(ctx, pm, path, pc.target, pc.part)
            source = path + (part.name, pc.link)
            if pc.link in _links(sub) and target is not None and target != source:
                yield source, target, pc, own
        yield from _fixed_edges(ctx, sub, path + (part.name,), within + (id(pm),))


@rule("Fix4", "the fixed connections between a p-model's links, its parts' included, form no "
      "cycle")
def check_Fix4_no_fixed_cycle(ctx: WFContext) -> None:
    """Links fixed to one another in a cycle (``A fixed to B``, ``B fixed to A``; or ``A``
    fixed to ``B`` and ``C``, ``B`` fixed to ``C``) weld a link to itself through the others:
    a closed chain, which each command meets differently (the SDF gets a loop of joints, a
    link the child of two, ``simulate`` refuses it, the semantics drops the motion). A
    fixed joint welds both ways, so the cycle is one of the undirected graph. It may pass
    through parts: ``Palm fixed to Root in F`` and ``part F = Finger { link Root fixed to
    Palm }``, or through the links of a part's p-model. The connection written last that
    closes a cycle is reported, once per cycle, in the p-model that writes one of the
    cycle's connections; a cycle wholly inside a part's p-model is that p-model's."""
    for _, pm in ctx.items(ast.PModel):
        edges: dict[tuple[Node, Node], Edge] = {}
        for edge in _fixed_edges(ctx, pm):
            edges.setdefault(edge[:2], edge)  # written twice: IX4's, welds once
        welded: dict[Node, dict[Node, None]] = {}  # the connections taken so far, both ways
        root: dict[Node, Node] = {}

        def find(n: Node) -> Node:
            while root.setdefault(n, n) != n:
                root[n] = root[root[n]]
                n = root[n]
            return n

        # a part's own connections first: a cycle that one of pm's closes is pm's to report
        for source, target, c, own in sorted(edges.values(), key=lambda e: e[3]):
            if find(source) == find(target):
                if own:
                    _report_cycle(ctx, pm, c, source, target, _path(welded, target, source))
                continue
            root[find(source)] = find(target)
            welded.setdefault(source, {})[target] = None
            welded.setdefault(target, {})[source] = None


def _path(welded: dict[Node, dict[Node, None]], start: Node, goal: Node) -> list[Node]:
    """The links from ``start`` to ``goal`` through the connections taken (a forest: the
    path is unique)."""
    before: dict[Node, Node | None] = {start: None}
    todo = [start]
    while todo:
        n = todo.pop()
        if n == goal:
            break
        for m in welded.get(n, {}):
            if m not in before:
                before[m] = n
                todo.append(m)
    path: list[Node] = []
    at: Node | None = goal
    while at is not None:
        path.append(at)
        at = before[at]
    return path[::-1]


def _report_cycle(ctx: WFContext, pm: ast.PModel, c: ast.FixedConnection | ast.PartFixed,
                  source: Node, target: Node, back: list[Node]) -> None:
    def name(n: Node) -> str:
        return "::".join(n)

    cycle = " → ".join(name(n) for n in [source, *back])
    ctx.error("Fix4", c, f"link {name(source)} fixed to {name(target)} closes a cycle of "
              f"fixed connections ({cycle}) in p-model {pm.name}",
              "remove one fixed connection of the cycle: fixed links are one rigid body, "
              "joined once")


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

