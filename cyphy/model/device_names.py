"""The names of an elaborated model's devices, chosen once every device exists: each
device's ports get a mangled prefix (``Proximity1_d``) unique in the model, and the relations
the blocks declare are rewritten onto those names."""

from __future__ import annotations

from dataclasses import replace

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Report
from cyphy.lang import ast
from cyphy.model.elements import Device, ElaboratedModel, glued

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


def _enclosing(candidates: list[Device], own: Device | None,
               qnames: dict[int, tuple[str, ...]]) -> Device | None:
    """The one candidate whose element encloses the relation's own: inside copy 0 of an
    indexed ``jref Axle``, the motor's ``Axle.tau`` is copy 0's, whose qualified name
    (``…::Axle::0``) begins the motor's (``…::Axle::0::Motor``)."""
    mine = qnames.get(id(own)) if own is not None else None
    if mine is None:
        return None
    around = [d for d in candidates
              if (q := qnames.get(id(d))) is not None and mine[:len(q)] == q]
    return around[0] if len(around) == 1 else None


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
            if isinstance(node, ex.Member) and isinstance(node.base, ex.Name) \
                    and len(node.base.parts) == 1:
                candidates = by_name.get(node.base.parts[0], [])
                if own is not None and own in candidates:
                    target: Device | None = own
                elif len(candidates) == 1:
                    target = candidates[0]
                else:
                    target = _enclosing(candidates, own, qnames)
                    if target is None:  # left as written, it would name no port at all
                        name = node.base.parts[0]
                        report.report(RELATION, f"the relation names {name}.{node.name}, "
                                      f"but {name} has {len(candidates)} copies: a relation "
                                      "says which one only inside one of them", node.span,
                                      "write the relation inside the indexed block (each "
                                      f"copy then relates its own {name}), or relate an "
                                      "element that is not indexed")
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
