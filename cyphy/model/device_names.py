"""The names of an elaborated model's devices, chosen once every device exists: each
device's ports get a mangled prefix (``Proximity1_d``) unique in the model, and the relations
the blocks declare are rewritten onto those names."""

from __future__ import annotations

from dataclasses import field, replace
from os.path import commonprefix
from typing import Callable, Sequence, TypeVar

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report
from cyphy.lang import ast
from cyphy.model.elements import Device, ElaboratedModel, glued
from cyphy.records import record

T = TypeVar("T")
RELATION = codes.code("E-RELATION", codes.E, "a relation names a block with several copies "
                      "from outside every one of them")


def name_devices(model: ElaboratedModel, device_names: list[tuple[Device, tuple[str, ...]]],
                 index_values: dict[int, dict[str, int]],
                 relation_queue: list[tuple[ex.Expr, ast.Block, Device | None, dict[str, int]]],
                 report: Report) -> None:
    """Mangled prefixes: the block name with its index values (``Proximity1``); where two
    collide, the enclosing part or link names are prepended until they are unique."""
    tokens = {id(d): glued(q[1:]) for d, q in device_names}  # model left out
    depth = {id(d): 1 for d, _ in device_names}
    while True:
        names: dict[str, list[int]] = {}
        for d, _ in device_names:
            t = tokens[id(d)]
            names.setdefault("_".join(t[-depth[id(d)]:]), []).append(id(d))
        clashes = [ids for ids in names.values() if len(ids) > 1]
        grew = False
        for ids in clashes:
            for i in ids:
                if depth[i] < len(tokens[i]):
                    depth[i] += 1
                    grew = True
        if not clashes or not grew:
            break
    renamed: dict[int, Device] = {}
    for device, _ in device_names:
        t = tokens[id(device)]
        prefix = "_".join(t[-depth[id(device)]:])
        renamed[id(device)] = _renamed(device, prefix,
                                       index_values.get(id(device), {}))
    for e in [*model.joints, *model.unconnected, *model.sensors,
              *model.actuators]:
        if e.device is not None and id(e.device) in renamed:
            e.device = renamed[id(e.device)]
    for j in model.links:
        for child in j.joints:
            if child.device is not None and id(child.device) in renamed:
                child.device = renamed[id(child.device)]
    _rename_relations(model, renamed, relation_queue, report)


def relation_target(candidates: Sequence[T], own: T | None,
                    qname: Callable[[T], tuple[str, ...] | None]) -> T | None:
    """The element ``Block.port`` names in a relation written in ``own``: ``own`` itself,
    the only element named ``Block``, or the one candidate nearest the relation's own, the
    one whose qualified name shares the longest beginning with its: inside copy 0 of an
    indexed ``jref Axle``, the motor's ``Axle.tau`` is copy 0's (``…::Axle::0`` begins
    ``…::Axle::0::Motor``); in copy 0 of an indexed part, a sensor's ``Knuckle.theta`` is
    that copy's knuckle (``…::Fingers::0::Root`` is shared with it, only ``…::Fingers`` with
    copy 1's). None: the relation does not say which (it is outside every copy)."""
    if own is not None and own in candidates:
        return own
    if len(candidates) == 1:
        return candidates[0]
    mine = qname(own) if own is not None else None
    if mine is None:
        return None
    shared = [(len(commonprefix([mine, q])), d) for d in candidates
              if (q := qname(d)) is not None]
    best = max((n for n, _ in shared), default=0)
    nearest = [d for n, d in shared if n == best]
    return nearest[0] if len(nearest) == 1 else None


def _ambiguous(report: Report, node: ex.Member, name: str, copies: int) -> None:
    report.report(RELATION, f"the relation names {name}.{node.name}, but {name} has "
                  f"{copies} copies: a relation says which one only inside one of them",
                  node.span, "write the relation inside the indexed block (each copy then "
                  f"relates its own {name}), or relate an element that is not indexed")


def _block_port(node: ex.Expr) -> str | None:
    """``Block`` of ``Block.port`` (a relation's name of another element's port)."""
    if isinstance(node, ex.Member) and isinstance(node.base, ex.Name) \
            and len(node.base.parts) == 1:
        return node.base.parts[0]
    return None


@record(frozen=False, slots=False)
class RelationSites:
    """What E-RELATION needs when a model is elaborated without devices (``check``): every
    joint, sensor and actuator by name, with its qualified name and block, and each relation
    with its element's. Whether a block has a device (ports or equations) is asked only of
    the blocks a relation names or is written in; the choice is :func:`relation_target`'s
    over the elements with devices, as naming the devices makes it, so ``check`` refuses
    what ``gen`` refuses without building the devices."""

    by_name: dict[str, list[tuple[tuple[str, ...], ast.Block]]] = field(default_factory=dict)
    relations: list[tuple[ex.Expr, tuple[str, ...], ast.Block]] = field(default_factory=list)

    def add(self, qname: tuple[str, ...], block: ast.Block) -> None:
        self.by_name.setdefault(block.name, []).append((qname, block))
        self.relations += [(r.expr, qname, block) for r in block.relations]

    def check(self, report: Report, has_device: Callable[[ast.Block], bool]) -> None:
        known: dict[int, bool] = {}

        def device(block: ast.Block) -> bool:
            if id(block) not in known:
                known[id(block)] = has_device(block)
            return known[id(block)]

        for expr, qname, block in self.relations:
            own = qname if device(block) else None
            for node in expr.walk():
                name = _block_port(node)
                if name is None:
                    continue
                candidates = [q for q, b in self.by_name.get(name, []) if device(b)]
                if relation_target(candidates, own, lambda q: q) is None:
                    assert isinstance(node, ex.Member)
                    _ambiguous(report, node, name, len(candidates))


def _rename_relations(model: ElaboratedModel, renamed: dict[int, Device],
                      relation_queue: list[tuple[ex.Expr, ast.Block, Device | None,
                                                 dict[str, int]]], report: Report) -> None:
    mangled = {p.mangled for d in renamed.values() for p in d.ports}
    by_name: dict[str, list[Device]] = {}
    qnames: dict[int, tuple[str, ...]] = {}
    for e in [*model.joints, *model.unconnected, *model.sensors,
              *model.actuators]:
        if e.device is not None:
            by_name.setdefault(e.simple_name, []).append(e.device)
            qnames[id(e.device)] = e.qname
    for expr, block, device, values in relation_queue:
        own = renamed.get(id(device)) if device is not None else None

        def paths(node: ex.Expr, own: Device | None = own) -> ex.Expr | None:
            """``Block.port`` first, so that a block named like a port of this device
            (joint ``J``, motor constant ``J``) is still read as the block."""
            name = _block_port(node)
            if name is not None:
                assert isinstance(node, ex.Member)
                candidates = by_name.get(name, [])
                target = relation_target(candidates, own, lambda d: qnames.get(id(d)))
                if target is None:  # left as written, it would name no port at all
                    _ambiguous(report, node, name, len(candidates))
                port = target.port(node.name) if target is not None else None
                if port is not None:
                    return ex.Name((port.mangled,), span=node.span)
            return None

        def names(node: ex.Expr, own: Device | None = own) -> ex.Expr | None:
            if isinstance(node, ex.Name) and len(node.parts) == 1 and own is not None:
                port = own.port(node.parts[0])
                if port is not None:
                    return ex.Name((port.mangled,), span=node.span)
                if node.parts[0] in values:
                    return ex.Num(str(values[node.parts[0]]), span=node.span)
            return None

        def own_names(node: ex.Expr) -> ex.Expr | None:
            if isinstance(node, ex.Name) and node.text in mangled:
                return None  # already a mangled port from the first pass
            return names(node)

        expr = ex.transform(ex.transform(expr, paths), own_names)
        model.relations.append(expr)


def _renamed(device: Device, prefix: str, values: dict[str, int]) -> Device:
    ports = tuple(replace(p, mangled=f"{prefix}_{p.name}") for p in device.ports)
    names = {p.name: p.mangled for p in ports}

    def swap(node: ex.Expr) -> ex.Expr | None:
        if isinstance(node, ex.Name) and len(node.parts) == 1:
            n = node.parts[0]
            if n in names:
                return ex.Name((names[n],), span=node.span)
            if n in values:
                return ex.Num(str(values[n]), span=node.span)
        return None

    return Device(prefix, ports, device.equations, device.constraints,
                  rename=lambda e: ex.transform(e, swap))
