"""A d-model's modules, controllers and state machines as readable text
(``cyphy show --dmodel``) and as JSON.

JSON keys (documented in the README): ``modules`` (``name``, ``cycle``, ``platform``
{``name``, ``provides``, ``uses``, ``requires``}, ``controllers`` [{``name``, ``target``}],
``connections``), ``controllers`` (``name``, ``cycle``, ``uses``, ``requires``,
``provides``, ``machines`` [{``name``, ``target``}], ``connections``) and ``machines``
(``name``, ``cycle``, ``constants``, ``variables``, ``clocks``, ``inputs``, ``outputs``,
``operations``, ``states`` [{``name``, ``parent``, ``entry``, ``during``, ``exit``}],
``junctions`` [{``name``, ``kind``}], ``finals``, ``transitions`` [{``name``, ``from``,
``to``, ``trigger``, ``condition``, ``action``, ``exec``}]), and
``operation_definitions`` (the operation definitions with a behaviour: ``name``,
``parameters`` [{``name``, ``type``}] and a machine's other keys). Expressions and actions
are written in the notation; absent parts are ``null``.
"""

from __future__ import annotations

import json
from typing import Any

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.notation import action_to_notation, to_notation, type_to_notation
from cyphy.lang.resolve import Resolution
from cyphy.model.machines import Machine


def _cycle(members: tuple[object, ...]) -> str | None:
    """The cycle's length, ``e`` of ``cycleDef cycle == e`` (the whole condition otherwise)."""
    defs = [m for m in members if isinstance(m, ast.CycleDef)]
    if not defs:
        return None
    e = defs[0].expr
    if isinstance(e, ex.BinOp) and e.op == "==" and e.left == ex.Name(("cycle",)):
        return to_notation(e.right)
    return to_notation(e)


def _uses(members: tuple[object, ...], relation: str) -> list[str]:
    return ["::".join(m.interface) for m in members
            if isinstance(m, ast.InterfaceUse) and m.relation == relation]


def _connections(members: tuple[object, ...]) -> list[str]:
    return [f"{c.source}.{c.source_event} -> {c.target}.{c.target_event}"
            + (f" ({c.flag})" if c.flag else "")
            for c in members if isinstance(c, ast.Connection)]


def _target(resolution: Resolution, ref: Any) -> str:
    found = resolution.get(ref)
    return getattr(found, "name", None) or "::".join(ref.target)


def module_to_dict(m: ast.Module, resolution: Resolution) -> dict[str, Any]:
    p = m.platform
    return {
        "name": m.name,
        "cycle": _cycle(m.members),
        "platform": None if p is None else {
            "name": p.name, "provides": _uses(p.members, "provides"),
            "uses": _uses(p.members, "uses"), "requires": _uses(p.members, "requires")},
        "controllers": [{"name": r.name, "target": _target(resolution, r)}
                        for r in m.members if isinstance(r, ast.NodeRef) and r.kind == "cref"]
        + [{"name": c.name, "target": c.name} for c in m.members
           if isinstance(c, ast.Controller)],
        "connections": _connections(m.members),
    }


def controller_to_dict(c: ast.Controller, resolution: Resolution) -> dict[str, Any]:
    return {
        "name": c.name,
        "cycle": _cycle(c.members),
        "uses": _uses(c.members, "uses"),
        "requires": _uses(c.members, "requires"),
        "provides": _uses(c.members, "provides"),
        "machines": [{"name": r.name, "target": _target(resolution, r)}
                     for r in c.machine_refs] + [{"name": s.name, "target": s.name}
                                                 for s in c.machines],
        "connections": _connections(c.members),
    }


def _decl(v: ast.VarDecl) -> dict[str, Any]:
    return {"name": v.name, "type": type_to_notation(v.type),
            "value": to_notation(v.value) if v.value is not None else None}


def _action(statements: tuple[ast.Statement, ...] | None) -> str | None:
    return action_to_notation(statements) if statements else None


def machine_to_dict(m: Machine) -> dict[str, Any]:
    return {
        "name": m.name,
        "cycle": _cycle(m.decl.members),
        "constants": [_decl(v) for v in m.constants.values()],
        "variables": [_decl(v) for v in m.variables.values()],
        "clocks": list(m.clocks),
        "inputs": list(m.platform.input_events),
        "outputs": list(m.platform.output_events),
        "operations": list(m.platform.operations),
        "states": [{"name": n.key, "parent": n.parent, "entry": _action(n.actions("entry")),
                    "during": _action(n.actions("during")), "exit": _action(n.actions("exit"))}
                   for n in m.states],
        "junctions": [{"name": n.key, "kind": n.kind} for n in m.junctions],
        "finals": [n.key for n in m.nodes.values() if n.kind == "final"],
        "transitions": [{
            "name": t.name,
            "from": t.source or t.decl.source,
            "to": t.target or t.decl.target,
            "trigger": to_notation(t.decl.trigger) if t.decl.trigger is not None else None,
            "condition": (to_notation(t.decl.condition) if t.decl.condition is not None
                          else None),
            "action": _action(t.decl.action),
            "exec": t.decl.exec,
        } for t in m.transitions],
    }


def dmodel_to_dict(files: list[ast.SourceFile], resolution: Resolution,
                   machines: list[Machine]) -> dict[str, Any]:
    items = [i for f in files for i in f.items]
    return {
        "modules": [module_to_dict(m, resolution) for m in items if isinstance(m, ast.Module)],
        "controllers": [controller_to_dict(c, resolution) for c in items
                        if isinstance(c, ast.Controller)]
        + [controller_to_dict(c, resolution) for m in items if isinstance(m, ast.Module)
           for c in m.members if isinstance(c, ast.Controller)],
        "machines": [machine_to_dict(m) for m in machines if m.decl.kind == "stm"],
        "operation_definitions": [
            {"name": m.name,
             "parameters": [{"name": p.name, "type": type_to_notation(p.type)}
                            for p in m.decl.params],
             **{k: v for k, v in machine_to_dict(m).items() if k != "name"},
             "constants": [_decl(v) for n, v in m.constants.items()
                           if n not in {p.name for p in m.decl.params}]}
            for m in machines if m.decl.kind == "operation"],
    }


def dmodel_to_json(data: dict[str, Any]) -> str:
    return json.dumps(data, indent=2) + "\n"


def dmodel_to_text(data: dict[str, Any]) -> str:
    out: list[str] = []
    for m in data["modules"]:
        out.append(f"module {m['name']}" + (f" (cycle {m['cycle']})" if m["cycle"] else ""))
        p = m["platform"]
        if p is not None:
            rel = "; ".join(f"{k} {', '.join(p[k])}" for k in ("provides", "uses", "requires")
                            if p[k])
            out.append(f"  robotic platform {p['name']}" + (f": {rel}" if rel else ""))
        for c in m["controllers"]:
            out.append(f"  controller {c['name']} = {c['target']}")
        out += [f"  connection {c}" for c in m["connections"]]
    for c in data["controllers"]:
        out.append(f"controller {c['name']}" + (f" (cycle {c['cycle']})" if c["cycle"] else ""))
        for k in ("uses", "requires", "provides"):
            if c[k]:
                out.append(f"  {k} {', '.join(c[k])}")
        for s in c["machines"]:
            out.append(f"  machine {s['name']} = {s['target']}")
        out += [f"  connection {x}" for x in c["connections"]]
    behaviours = [("machine", m, "") for m in data["machines"]] + [
        ("operation", m, "(" + ", ".join(f"{p['name']}: {p['type']}" for p in m["parameters"])
         + ")") for m in data.get("operation_definitions", [])]
    for kind, m, params in behaviours:
        out.append(f"{kind} {m['name']}{params}" +
                   (f" (cycle {m['cycle']})" if m["cycle"] else ""))
        for key in ("constants", "variables"):
            for v in m[key]:
                value = f" = {v['value']}" if v["value"] is not None else ""
                out.append(f"  {key[:-1] if key != 'constants' else 'constant'} {v['name']}: "
                           f"{v['type']}{value}")
        for key, label in (("clocks", "clocks"), ("inputs", "input events"),
                           ("outputs", "output events"), ("operations", "operations")):
            if m[key]:
                out.append(f"  {label}: {', '.join(m[key])}")
        out.append(f"  states ({len(m['states'])}):")
        for s in m["states"]:
            acts = "; ".join(f"{k} {s[k]}" for k in ("entry", "during", "exit") if s[k])
            out.append(f"    {s['name']}" + (f"  [{acts}]" if acts else ""))
        if m["junctions"]:
            out.append("  junctions: " + ", ".join(
                f"{j['name']} ({j['kind']})" if j["kind"] == "initial" else j["name"]
                for j in m["junctions"]))
        if m["finals"]:
            out.append("  final states: " + ", ".join(m["finals"]))
        out.append(f"  transitions ({len(m['transitions'])}):")
        for t in m["transitions"]:
            parts = [f"    {t['name']}: {t['from']} -> {t['to']}"]
            if t["exec"]:
                parts.append("exec")
            if t["trigger"]:
                parts.append(f"trigger {t['trigger']}")
            if t["condition"]:
                parts.append(f"[{t['condition']}]")
            if t["action"]:
                parts.append(f"/ {t['action']}")
            out.append(" ".join(parts))
    return "\n".join(out) + "\n"
