"""Links, bodies and devices: L1-L8, B1-B3, J1-J3, SE1-SE3, AC1-AC3, JSA1.

Every element of a p-model is a link, body, joint, sensor or actuator block, either *local*
(``local link L { def { … } }``: the block holds its own, anonymous definition) or a *reference*
(``lref L = Tip``: the block points at a named package-level definition). The conditions of the
``*1``-``*3`` families say that this realisation is well-kinded and that named and anonymous
definitions are not confused; L4-L8 say what a link, a body and a device may hold; JSA1 says how
the containment of a sensor or actuator is labelled.

Related conditions checked elsewhere: a ``def`` block inside a reference block, a second ``def``
and a part or a connection inside a block that cannot hold one are placement errors
(``E-MEMBER``, ``E-DUPLICATE``, :mod:`cyphy.lang.placement`); a reference whose target does
not resolve is S1. The rules here skip what they cannot know (an unresolved reference) rather
than report it a second time. One overlap is deliberate: a connection to a body is S1 ("no link
B") and also L7, whose message says what ``B`` is and where it sits.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.diagnostics import Severity
from cyphy.lang import ast
from cyphy.lang.scopes import is_definition
from cyphy.wellformed.registry import BlockSite, WFContext, per_node, rule

K = ast.BlockKind
_DEVICES = (K.SENSOR, K.ACTUATOR)
_HOLD_NOTHING = (K.BODY, K.SENSOR, K.ACTUATOR)


# --------------------------------------------------------------------------- helpers


def _child(site: BlockSite, child: ast.Block) -> str:
    return f"{site.qualified}::{child.name}"


def _a(word: str) -> str:
    return ("an " if word[0] in "aeiou" else "a ") + word


def _definition_name(ctx: WFContext, d: ast.Definition) -> str:
    """``physmod::sensors::IR`` for a definition of a package, ``Tip`` in the global one."""
    package = ctx.workspace.file_package.get(d.span.file, ())
    return "::".join((*package, d.name))


def _definition_members(ctx: WFContext, block: ast.Block) -> tuple[object, ...] | None:
    """The members of a block's definition: those of its ``def`` blocks when local, those of
    the named definition it refers to otherwise. None when that definition is unknown (an
    unresolved reference, S1, or one of the wrong kind, L1/B1/…)."""
    if block.is_local:
        return tuple(m for d in block.definitions for m in d.members)
    target = ctx.target(block)
    if isinstance(target, ast.Definition) and target.kind is block.kind:
        return target.members
    return None


def _inertial(members: tuple[object, ...]) -> ast.Inertial | None:
    for m in members:
        if isinstance(m, ast.Inertial):
            return m
    return None


def _bodies(ctx: WFContext, link: ast.Block) -> list[tuple[ast.Block, tuple[object, ...] | None]]:
    return [(b, _definition_members(ctx, b)) for b in link.blocks if b.kind is K.BODY]


# --------------------------------------------------------------------------- *1: reference kinds


def _reference_kind(ctx: WFContext, rule_id: str, kind: K) -> None:
    for site in ctx.blocks_of(kind):
        block = site.block
        if block.is_local:
            continue
        target = ctx.target(block)
        if not isinstance(target, ast.Definition) or target.kind is kind:
            continue  # unresolved (S1) or well-kinded
        ref = "::".join(block.ref or ())
        full = _definition_name(ctx, target)
        ctx.error(rule_id, block,
                  f"{kind.ref_keyword} {site.qualified} refers to {ref}, which is "
                  f"{_a(target.kind.value)} definition{f' ({full})' if full != ref else ''}, "
                  f"not {_a(kind.value)} definition",
                  f"refer to {_a(kind.value)} definition (declared '{kind.value} Name {{ … }}'),"
                  f" or use '{target.kind.ref_keyword}' where {_a(target.kind.value)} belongs")


@rule("L1", "the definition referenced by a reference link is a link definition")
def check_L1_lref_target_is_link(ctx: WFContext) -> None:
    """The definition referenced by a reference link (``lref L = D``) is a link definition:
    ``D`` must be declared ``link D {…}``, not as a body, joint, sensor or actuator. (A ``D``
    that does not resolve at all is S1.)"""
    _reference_kind(ctx, "L1", K.LINK)


@rule("B1", "the definition referenced by a reference body is a body definition")
def check_B1_bref_target_is_body(ctx: WFContext) -> None:
    """The definition referenced by a reference body (``bref B = D``) is a body definition
    (``body D {…}``)."""
    _reference_kind(ctx, "B1", K.BODY)


@rule("J1", "the definition referenced by a reference joint is a joint definition")
def check_J1_jref_target_is_joint(ctx: WFContext) -> None:
    """The definition referenced by a reference joint (``jref J = D``) is a joint definition
    (``joint D {…}``, such as ``physmod::joints::Revolute``)."""
    _reference_kind(ctx, "J1", K.JOINT)


@rule("SE1", "the definition referenced by a reference sensor is a sensor definition")
def check_SE1_sref_target_is_sensor(ctx: WFContext) -> None:
    """The definition referenced by a reference sensor (``sref S = D``) is a sensor definition
    (``sensor D {…}``, such as ``physmod::sensors::IR``)."""
    _reference_kind(ctx, "SE1", K.SENSOR)


@rule("AC1", "the definition referenced by a reference actuator is an actuator definition")
def check_AC1_aref_target_is_actuator(ctx: WFContext) -> None:
    """The definition referenced by a reference actuator (``aref A = D``) is an actuator
    definition (``actuator D {…}``, such as ``physmod::actuators::SpeedControlMotor``)."""
    _reference_kind(ctx, "AC1", K.ACTUATOR)


# --------------------------------------------------------------------------- *2: local definitions

_DEF_EXAMPLE = {
    K.LINK: "def { inertial information { mass … } }",
    K.BODY: "def { box(length = …, width = …, height = …) }",
    K.JOINT: "def { input … output … equation … }",
    K.SENSOR: "def { input … output … equation … }",
    K.ACTUATOR: "def { input … output … equation … }",
}


def _local_definition(ctx: WFContext, rule_id: str, kind: K) -> None:
    for site in ctx.blocks_of(kind):
        block = site.block
        if block.is_local and not block.definitions:
            ctx.error(rule_id, block,
                      f"local {kind.value} {site.qualified} has no definition: a local "
                      f"{kind.value} holds its {kind.value} definition in a 'def {{ … }}' block",
                      f"add '{_DEF_EXAMPLE[kind]}' to it (an empty 'def {{ }}' is allowed), or "
                      f"refer to a named definition with '{kind.ref_keyword} {block.name} = …'")


@rule("L2", "a local link has a link definition (its def block)")
def check_L2_local_link_has_definition(ctx: WFContext) -> None:
    """The definition of a local link is a link definition. In the notation that definition is
    the anonymous ``def { … }`` written inside the link, and what may stand in it is fixed by
    the kind (a geometry in a link's ``def`` is a placement error, ``E-MEMBER``); what remains
    to check is that the definition is there at all: a local link without ``def`` has no
    definition. (RoboTool's own models write ``def { }`` even when it is empty.)"""
    _local_definition(ctx, "L2", K.LINK)


@rule("B2", "a local body has a body definition (its def block)")
def check_B2_local_body_has_definition(ctx: WFContext) -> None:
    """The definition of a local body is a body definition: the ``def { … }`` inside the body
    (its geometry, inertial information, surface properties). As for L2, a local body must
    have one."""
    _local_definition(ctx, "B2", K.BODY)


@rule("J2", "a local joint has a joint definition (its def block)")
def check_J2_local_joint_has_definition(ctx: WFContext) -> None:
    """The definition of a local joint is a joint definition: the ``def { … }`` inside the
    joint (its inputs, outputs, constants, equations, annotation). As for L2, a local joint
    must have one."""
    _local_definition(ctx, "J2", K.JOINT)


@rule("SE2", "a local sensor has a sensor definition (its def block)")
def check_SE2_local_sensor_has_definition(ctx: WFContext) -> None:
    """The definition of a local sensor is a sensor definition: the ``def { … }`` inside the
    sensor. As for L2, a local sensor must have one."""
    _local_definition(ctx, "SE2", K.SENSOR)


@rule("AC2", "a local actuator has an actuator definition (its def block)")
def check_AC2_local_actuator_has_definition(ctx: WFContext) -> None:
    """The definition of a local actuator is an actuator definition: the ``def { … }`` inside
    the actuator. As for L2, a local actuator must have one."""
    _local_definition(ctx, "AC2", K.ACTUATOR)


# --------------------------------------------------------------------------- *3: named vs anonymous


def _anonymous_definition(ctx: WFContext, rule_id: str, kind: K) -> None:
    for site in ctx.blocks_of(kind):
        block = site.block
        if not block.is_local:
            continue
        named = [d for d in ctx.scopes.lookup(site.file, (block.name,), is_definition(kind))
                 if isinstance(d, ast.Definition)]
        if not named:
            continue
        ctx.error(rule_id, block,
                  f"local {kind.value} {site.qualified} has the name of the {kind.value} "
                  f"definition {_definition_name(ctx, named[0])}, but its own definition is "
                  "the anonymous def inside it",
                  f"rename the local {kind.value}, or write '{kind.ref_keyword} {block.name} = "
                  f"{named[0].name}' to use the named definition")


@rule("L3", "a local link is not named after a link definition (its own is anonymous)",
      Severity.WARNING)
def check_L3_local_link_definition_is_anonymous(ctx: WFContext) -> None:
    """A link definition declared in a package has a name; one inside a local link has none.
    The notation makes both true by construction (``link D {…}`` at the top level needs a name,
    ``def { … }`` cannot take one), so cyphy checks the confusion the condition prevents: a
    local link named like a link definition visible from its file (declared in its package,
    imported, or global). Its definition is the anonymous ``def``, not the named one, yet a
    reader, and an ``lref … = Name`` elsewhere, sees one name for both. A warning: cyphy
    itself resolves the name unambiguously (references only ever name definitions)."""
    _anonymous_definition(ctx, "L3", K.LINK)


@rule("B3", "a local body is not named after a body definition (its own is anonymous)",
      Severity.WARNING)
def check_B3_local_body_definition_is_anonymous(ctx: WFContext) -> None:
    """A body definition declared in a package has a name; one inside a local body has none.
    As for L3: warn about a local body named like a visible body definition (``body D {…}``),
    whose definition it is not."""
    _anonymous_definition(ctx, "B3", K.BODY)


@rule("J3", "a local joint is not named after a joint definition (its own is anonymous)",
      Severity.WARNING)
def check_J3_local_joint_definition_is_anonymous(ctx: WFContext) -> None:
    """A joint definition declared in a package has a name; one inside a local joint has none.
    As for L3: warn about a local joint named like a visible joint definition (such as
    ``local joint Revolute`` with ``physmod::joints::Revolute`` imported)."""
    _anonymous_definition(ctx, "J3", K.JOINT)


@rule("SE3", "a local sensor is not named after a sensor definition (its own is anonymous)",
      Severity.WARNING)
def check_SE3_local_sensor_definition_is_anonymous(ctx: WFContext) -> None:
    """A sensor definition declared in a package has a name; one inside a local sensor has
    none. As for L3: warn about a local sensor named like a visible sensor definition (such as
    ``local sensor IR`` with ``physmod::sensors::IR`` imported)."""
    _anonymous_definition(ctx, "SE3", K.SENSOR)


@rule("AC3", "a local actuator is not named after an actuator definition (its own is "
      "anonymous)", Severity.WARNING)
def check_AC3_local_actuator_definition_is_anonymous(ctx: WFContext) -> None:
    """An actuator definition declared in a package has a name; one inside a local actuator
    has none. As for L3: warn about a local actuator named like a visible actuator definition
    (such as ``local actuator SpeedControlMotor`` with the library's imported)."""
    _anonymous_definition(ctx, "AC3", K.ACTUATOR)


# --------------------------------------------------------------------------- L4-L8


@rule("L4", "a link has inertial information in its definition or in one of its bodies",
      Severity.WARNING)
def check_L4_link_has_inertial(ctx: WFContext) -> None:
    """A link has inertial information somewhere: in its definition (its ``def`` or the link
    definition its ``lref`` names) or in the definition of at least one of its bodies (local
    or ``bref``). Otherwise SDF would get invented defaults for its mass and inertia. Links
    whose definition or a body's is unknown (an unresolved or ill-kinded reference) are
    skipped."""
    for site in ctx.blocks_of(K.LINK):
        own = _definition_members(ctx, site.block)
        if own is None or _inertial(own) is not None:
            continue
        bodies = _bodies(ctx, site.block)
        if any(members is None or _inertial(members) is not None for _, members in bodies):
            continue
        where = (f"neither its definition nor its bodies ({', '.join(b.name for b, _ in bodies)}) "
                 "give one" if bodies else "its definition gives none and it has no body")
        ctx.error("L4", site.block, f"link {site.qualified} has no inertial information: {where}",
                  "add 'inertial information { mass … inertia matrix { … } }' to the link's "
                  "def (or to the def of one of its bodies)")


@rule("L5", "a link contains no links and no parts")
def check_L5_no_links_in_links(ctx: WFContext) -> None:
    """A link contains no links and no parts: only joints, sensors, actuators, bodies and
    fixed connections. Links are composed by connecting them (``fixed to``, joints), never by
    nesting. (A part written inside a link is already a placement error, ``E-MEMBER``, since
    a part is not a block; this rule reports the links.)"""
    for site in ctx.blocks_of(K.LINK):
        for child in site.block.blocks:
            if child.kind is K.LINK:
                ctx.error("L5", child, f"link {_child(site, child)} is inside link "
                          f"{site.qualified}: a link contains no links",
                          f"declare {child.name} in the p-model and attach it to "
                          f"{site.block.name} with 'fixed to {site.block.name}' or a joint")


@rule("L6", "a link has no fixed connection to itself")
def check_L6_no_fixed_to_self(ctx: WFContext) -> None:
    """A link has no fixed connection to itself: ``fixed to L`` inside link ``L`` (with no
    ``in P``, which would name link ``L`` of part ``P``, another link)."""
    for site in ctx.blocks_of(K.LINK):
        for fixed in site.block.fixed:
            if fixed.part is None and fixed.target == site.block.name:
                ctx.error("L6", fixed, f"link {site.qualified} is fixed to itself",
                          "name another link of the p-model, 'L in P' for link L of part P, "
                          "or remove the connection")


@per_node
def _body_paths(pm: ast.PModel) -> dict[str, str]:
    """Bodies of a p-model (at any depth) by name → their qualified name."""
    out: dict[str, str] = {}
    stack: list[tuple[ast.Block, tuple[str, ...]]] = [(b, (pm.name,)) for b in pm.blocks]
    while stack:
        block, path = stack.pop()
        if block.kind is K.BODY:
            out.setdefault(block.name, "::".join((*path, block.name)))
        stack.extend((b, (*path, block.name)) for b in block.blocks)
    return out


@per_node
def _links(pm: ast.PModel) -> set[str]:
    return {b.name for b in pm.blocks if b.kind is K.LINK}


def _connected_pmodel(ctx: WFContext, pm: ast.PModel, part: str | None) -> ast.PModel | None:
    """The p-model a connection target is looked up in: ``pm`` itself, or the p-model of
    its part ``part`` (None when that part or its p-model is unknown, S1)."""
    if part is None:
        return pm
    for p in pm.parts:
        if p.name == part:
            target = ctx.target(p)
            return target if isinstance(target, ast.PModel) else None
    return None


def _body_instead_of_link(ctx: WFContext, pm: ast.PModel | None, name: str) -> str | None:
    """The qualified name of the body that ``name`` denotes in ``pm`` where a link is expected,
    or None (a link of that name exists, or no body has it)."""
    if pm is None or name in _links(pm):
        return None
    return _body_paths(pm).get(name)


@rule("L7", "bodies, sensors and actuators contain no blocks; nothing is connected to or from "
      "a body")
def check_L7_bodies_and_devices_are_leaves(ctx: WFContext) -> None:
    """Bodies, sensors and actuators contain no other blocks (no link, body, joint, sensor or
    actuator inside them), and nothing is connected to or from a body: the target of a
    ``fixed to``/``flexibly connected to`` (of a link, a joint or a part) and the source link
    of a part's connection are links, never bodies. (Connections written inside a body are
    already placement errors, ``E-MEMBER``; a target that names nothing at all is S1.)"""
    for site in ctx.blocks():
        block = site.block
        if block.kind in _HOLD_NOTHING:
            for child in block.blocks:
                ctx.error("L7", child, f"{block.kind.value} {site.qualified} contains "
                          f"{child.kind.value} {_child(site, child)}: bodies, sensors and "
                          "actuators contain no other blocks",
                          f"move {child.name} to the link (or joint) that holds "
                          f"{block.name}")
        for c in (*block.fixed, *block.flexible):
            body = _body_instead_of_link(ctx, _connected_pmodel(ctx, site.pmodel, c.part),
                                         c.target)
            if body is not None:
                verb = "fixed" if isinstance(c, ast.FixedConnection) else "flexibly connected"
                ctx.error("L7", c, f"{block.kind.value} {site.qualified} is {verb} to "
                          f"{body}, a body: connections go to links",
                          f"connect to the link that holds {c.target}")
    for _, pm in ctx.pmodels():
        for part in pm.parts:
            inner = _connected_pmodel(ctx, pm, part.name)
            for c in (*part.fixed, *part.flexible):
                source = c.link if isinstance(c, ast.PartFixed) else c.joint
                body = _body_instead_of_link(ctx, inner, source)
                if body is not None:
                    ctx.error("L7", c, f"part {pm.name}::{part.name} connects {body}, a body: "
                              "connections go from links (and joints)",
                              f"connect the link that holds {source}")
                body = _body_instead_of_link(ctx, _connected_pmodel(ctx, pm, c.part), c.target)
                if body is not None:
                    ctx.error("L7", c, f"part {pm.name}::{part.name} is connected to {body}, "
                              "a body: connections go to links",
                              f"connect to the link that holds {c.target}")


@rule("L8", "if a link's definition gives an inertial, none of its bodies gives one")
def check_L8_single_inertial(ctx: WFContext) -> None:
    """If a link definition gives an inertial (in the link's ``def`` or in the link definition
    its ``lref`` names), none of the bodies of that link gives one (in its ``def`` or its
    ``bref``'s body definition): the link's mass would be stated twice."""
    for site in ctx.blocks_of(K.LINK):
        own = _definition_members(ctx, site.block)
        if own is None or _inertial(own) is None:
            continue
        for body, members in _bodies(ctx, site.block):
            inertial = _inertial(members) if members is not None else None
            if inertial is None:
                continue
            where = "" if body.is_local else f" (in body definition {'::'.join(body.ref or ())})"
            ctx.error("L8", inertial if body.is_local else body,
                      f"link {site.qualified} gives inertial information in its definition, and "
                      f"so does its body {_child(site, body)}{where}",
                      "state the link's inertial information once: remove it from the body or "
                      "from the link's def")


# --------------------------------------------------------------------------- JSA1


_PREDICATE_OPS = {"!=", "<", "<=", ">", ">=", "==", "/\\", "\\/", "=>", "<=>"}


def _equality_problem(e: ex.Expr) -> str | None:
    """Why ``e`` is not an equality or a conjunction of equalities (None when it is)."""
    if isinstance(e, ex.BinOp) and e.op == "/\\":
        return _equality_problem(e.left) or _equality_problem(e.right)
    if isinstance(e, ex.BinOp) and e.op == "==":
        for side in (e.left, e.right):
            if isinstance(side, ex.BinOp) and side.op in _PREDICATE_OPS:
                return f"a chained comparison ('{side.op}' inside '==')"
        return None
    if isinstance(e, ex.BinOp):
        return f"its operator is '{e.op}'"
    return "it is not a comparison"


@rule("JSA1", "the relation of a sensor's or actuator's containment is a conjunction of "
      "equalities")
def check_JSA1_device_relation_is_equalities(ctx: WFContext) -> None:
    """The relation that labels the containment of a sensor or actuator (``relation e``, or a
    bare ``e`` in an ``sref``/``aref``, for example ``relation LMotor.T == LHinge.tau``) is an
    equality or a conjunction (``/\\``) of equalities: it identifies ports of the device with
    ports of its container, and nothing else. Relations written in the device's ``def`` are
    checked too."""
    for site in ctx.blocks():
        block = site.block
        if block.kind not in _DEVICES:
            continue
        relations = [*block.relations,
                     *(m for d in block.definitions for m in d.members
                       if isinstance(m, ast.Relation))]
        container = site.container.name if site.container is not None else "Container"
        for rel in relations:
            problem = _equality_problem(rel.expr)
            if problem is not None:
                ctx.error("JSA1", rel,
                          f"the relation of {block.kind.value} {site.qualified} is not an "
                          f"equality or a conjunction of equalities: {problem}",
                          f"write it as '{block.name}.port == {container}.port' (join "
                          "several with /\\)")
