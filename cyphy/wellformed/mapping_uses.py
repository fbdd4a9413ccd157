"""Platform mappings, cyphy's own conditions on what a mapping's members say (PMap13-PMap17).

The paper's PMap conditions judge which names a member may read and write; these judge
whether it says what the software means: a value the software passes that nothing reads
(``operation drive { equation Motor.das == 10 }``: ``drive(w)`` ignores ``w``), a typed
input event whose value nothing gives, two mappings of one module onto one p-model (which
one would ``gen`` use?), and one member writing the same input twice (``das == w`` and
``das == 2*w``: no value satisfies both unless ``w = 0``; ``simulate`` refused them with
"does not determine Motor_das uniquely", far from the cause), and a derivative, which the
instant a mapping holds at does not have.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.diagnostics import Severity
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.wellformed.platform_services import (
    MemberMapping, Site, in_user_file, label_of, members_of, service_of, sites,
)
from cyphy.wellformed.registry import WFContext, rule


def _names_in(members: object) -> set[str]:
    """The simple names the given equations, predicates and actions mention."""
    return {node.parts[0] for e in ast.expressions_in(members) for node in e.walk()
            if isinstance(node, ex.Name) and len(node.parts) == 1}


def _passed(site: Site, member: MemberMapping) -> list[tuple[str, object]]:
    """What the software hands the member: an operation's parameters (with the member as
    the place to point at), a typed output event's parameter, a platform variable."""
    service = service_of(site, member)
    if service is None:
        return []  # PMap4
    if isinstance(member, ast.OperationMapping) and isinstance(service.decl, ast.OperationSig):
        return [(p.name, member) for p in service.decl.params]
    if isinstance(member, ast.EventMapping) and member.direction == "output" and member.param:
        return [(member.param, member.param_span or member)]
    if isinstance(member, ast.VariableMapping):
        return [(member.name, member)]
    return []


@rule("PMap13", "a mapping reads what the software passes it: the operation's parameters, the "
      "output event's value, the variable", Severity.WARNING)
def check_PMap13_passed_values_read(ctx: WFContext) -> None:
    """``drive(w)`` mapped by ``equation Motor.das == 10`` drives the motor at 10 whatever
    the software asks: a parameter (an output event's value, a mapped variable) that no
    equation, predicate or action of its mapping mentions is likely misspelt or forgotten.
    A warning: a mapping may ignore a value on purpose."""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        for member in members_of(site.mapping):
            if not member.members:
                continue  # PMap6
            read = _names_in(member.members)
            for name, where in _passed(site, member):
                if name not in read:
                    ctx.error(
                        "PMap13", where, f"the mapping of {label_of(member)} never reads "
                        f"'{name}': the software's value is ignored",
                        f"use '{name}' in an equation (Motor.das == {name}), or drop the "
                        "parameter from the d-model if the platform ignores it")


@rule("PMap14", "a typed input event's mapping gives the event's value")
def check_PMap14_input_value_given(ctx: WFContext) -> None:
    """``input event echo ? r { predicate … }`` with equations that never mention ``r``
    leaves the value the software reads unconstrained (any real): the semantics chooses it
    arbitrarily. ``r`` must appear in an equation or an action (``equation r ==
    Eye.voltage``). A mapping with no equations at all is PMap6's."""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        for member in members_of(site.mapping):
            if not (isinstance(member, ast.EventMapping) and member.direction == "input"
                    and member.param and (member.equations or member.actions)):
                continue
            if member.param not in _names_in((*member.equations, *member.actions)):
                ctx.error("PMap14", member.param_span or member,
                          f"the mapping of {label_of(member)} never gives its value "
                          f"'{member.param}': no equation or action mentions it",
                          f"add 'equation {member.param} == …' with the sensor output the "
                          "event carries")


@rule("PMap15", "one mapping per d-model module and p-model")
def check_PMap15_one_mapping(ctx: WFContext) -> None:
    """Two mappings of one module onto one p-model (``BenchMapping`` in ``Mapping.rsm``,
    ``BenchMapping2`` in another file) give each operation and event two meanings; the
    commands would pick one (``gen --isabelle`` refused: "several platform mappings"). The
    second, in the order the files are read, is reported. Only the files given are compared:
    a folder of alternative mappings (``tests/mappings``) is checked one file at a time."""
    first: dict[tuple[int, int], ast.PlatformMapping] = {}
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        module = ctx.target(site.mapping)
        if not isinstance(module, ast.Module) or site.pmodel is None:
            continue
        key = (id(module), id(site.pmodel))
        if key not in first:
            first[key] = site.mapping
            continue
        earlier = first[key]
        ctx.error("PMap15", site.mapping, f"mapping {site.mapping.name} maps module "
                  f"{module.name} onto p-model {site.pmodel.name}, as mapping {earlier.name} "
                  f"does ({earlier.span.file}:{earlier.span.line})",
                  "keep one mapping per module and p-model: merge the two, or delete one")


def _written(member: MemberMapping) -> list[tuple[str, ex.Expr, ex.Expr, bool]]:
    """Each ``target == value`` equation and ``target = value`` assignment of the member, a
    target being a name, a port or one entry of either (``wrench[3]``): (target as written,
    target, value, whether by an action)."""
    out: list[tuple[str, ex.Expr, ex.Expr, bool]] = []
    for eq in member.equations:
        e = eq.expr
        if isinstance(e, ex.BinOp) and e.op == "==" and _target(e.left):
            out.append((to_notation(e.left), e.left, e.right, False))
    for action in member.actions:
        for s in action.statements:
            if isinstance(s, ast.Assign):
                out.append((to_notation(s.target), s.target, s.value, True))
    return out


def _target(e: ex.Expr) -> bool:
    """Whether ``e`` names what an equation writes: a name, a port, or an entry of one."""
    if isinstance(e, ex.Index):
        e = e.base
    return isinstance(e, (ex.Name, ex.Member))


def _cells(target: ex.Expr, value: ex.Expr) -> dict[tuple[str, int | None], str]:
    """What a write sets, entry by entry: ``(vector, k)`` for an entry ``k`` (numbered from
    1, as the notation numbers them) with the text of its value, ``(name, None)`` for the
    whole of a name or port whose value is not written entry by entry."""
    if isinstance(target, ex.Index) and len(target.args) == 1 and \
            isinstance(target.args[0], ex.Num) and target.args[0].is_integer:
        return {(to_notation(target.base), int(target.args[0].text)): to_notation(value)}
    whole = to_notation(target)
    if isinstance(value, ex.Vector) and len(value.rows) == 1:
        return {(whole, k): to_notation(item) for k, item in enumerate(value.rows[0], 1)}
    return {(whole, None): to_notation(value)}


def _overlap(cells: dict[tuple[str, int | None], str],
             before: dict[tuple[str, int | None], str]) -> tuple[bool, bool]:
    """Whether two writes set a common entry, and whether they give it different values (an
    entry written whole by one and by value by the other: different, unless both are whole
    and equal)."""
    common, differ = False, False
    for (name, k), value in cells.items():
        for (other, j), earlier in before.items():
            if name != other or k is not None and j is not None and k != j:
                continue
            common = True
            differ = differ or (k is None) != (j is None) or value != earlier
    return common, differ


@rule("PMap16", "a mapping writes each actuator input and local once")
def check_PMap16_written_once(ctx: WFContext) -> None:
    """``equation Motor.das == w`` and ``equation Motor.das == 2*w`` in one member hold
    together only when ``w = 0``; ``action das = w; das = 0`` overwrites the first value
    before the platform sees it. Either way one of the two is a mistake. The same holds of
    a vector written whole and one of its entries (``wrench == (|0, 0, f, 0, 0, 0|)`` and
    ``wrench[3] == 2*f``), or an entry written twice. (An equation written twice word for
    word, or an entry given the value the whole vector's literal gives it, is harmless and
    passes.)"""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        for member in members_of(site.mapping):
            if member.equations and member.actions:
                continue  # PMap6: one or the other
            seen: list[tuple[ex.Expr, ex.Expr, dict[tuple[str, int | None], str]]] = []
            for text, target, value, action in _written(member):
                cells = _cells(target, value)
                clash = None
                for earlier, before, written in seen:
                    common, differ = _overlap(cells, written)
                    if common and (action or differ):
                        clash = (earlier, before)
                        break
                seen.append((target, value, cells))
                if clash is None:
                    continue
                line = getattr(clash[0], "span").line
                other, before = to_notation(clash[0]), to_notation(clash[1])
                said = f"line {line} gives it {before}" if other == text else \
                    f"line {line} gives {other} {before}"
                ctx.error("PMap16", target, f"the mapping of {label_of(member)} writes {text} "
                          f"again ({said}, this line {to_notation(value)})",
                          "give each input one equation (or one assignment): combine the "
                          "two, or write the other input you meant")


@rule("PMap17", "a mapping's equations, predicates and actions hold at an instant: no "
      "derivative")
def check_PMap17_no_derivative(ctx: WFContext) -> None:
    """A mapping relates the software's call or event to the platform at the instant it
    happens; ``derivative(Motor.das) == w`` or ``das == derivative(w)`` asks for a rate the
    instant does not have (a parameter is constant over it). Every command that gives a
    mapping meaning refuses it (``gen --isabelle``: "no counterpart for Derivative";
    ``simulate``: "does not determine Motor_das uniquely"), so ``check`` does, at the
    derivative. A rate belongs in the p-model's equations (an actuator's dynamics)."""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        for member in members_of(site.mapping):
            for e in ast.expressions_in(member.members):
                for node in e.walk():
                    if isinstance(node, ex.Derivative):
                        ctx.error("PMap17", node, f"the mapping of {label_of(member)} takes "
                                  f"{to_notation(node)}: a mapping holds at an instant, which "
                                  "has no rate", "map the value itself, and write the rate "
                                  "in the actuator's equations (its definition in the "
                                  "p-model)")


@rule("PMap18", "a mapping declares its locals inside the member that uses them")
def check_PMap18_locals_in_members(ctx: WFContext) -> None:
    """The semantics gives a mapping's locals one meaning: each member's are existentially
    quantified over that member's equations and named ``<member>_<name>`` (semantics.md,
    "Local schema" and "Names"); a ``var`` at the top of the mapping belongs to no member,
    so it has no name and no quantifier there, and ``gen --isabelle`` and ``simulate``
    refuse an equation that uses it. ``check`` refuses it where it is declared. (A
    ``const`` at the top is the mapping's, and every member may read it.)"""
    for site in sites(ctx):
        if not in_user_file(ctx, site.mapping):
            continue
        users = {}
        for member in members_of(site.mapping):
            for name in _names_in(member.members):
                users.setdefault(name, label_of(member))
        for decl in site.mapping.declarations:
            if decl.kind is ast.DeclKind.CONST:
                continue  # a constant of the whole mapping: every member may read it
            used = users.get(decl.name)
            where = f"the mapping of {used}" if used else "the operation's or event's mapping"
            ctx.error("PMap18", decl, f"'{decl.name}' is declared at the top of mapping "
                      f"{site.mapping.name}: a mapping's local belongs to one operation, "
                      "event or variable mapping, which quantifies it over its equations",
                      f"move 'var {decl.name}: …' into {where} (one copy per member that "
                      "uses it)")
