"""The elaborated model as a readable tree (``cyphy show``) and as JSON.

JSON keys (documented in the README): ``model``, ``links`` (``name``, ``pose``,
``inertial`` {``mass``, ``com``, ``inertia``, ``source``}, ``bodies``, ``sensors``,
``actuators``), ``joints`` (``name``, ``parent``, ``child``, ``pose`` relative to the child,
``annotation``, ``axis``, ``device``), ``unconnected`` (joints without a flexible
connection, same keys), ``fixed`` (``name``, ``parent``, ``child``),
``devices`` (``prefix``, ``ports`` [{``name``, ``kind``, ``mangled``, ``value``}],
``equations``), ``relations``, ``constants``, ``missing`` and ``motion`` (the kinematic
tree's equations of motion per moving body, in tree order: ``joint``, ``kind``, ``parent``
joint or null for the world, ``links`` it moves as one body, ``mass``, ``com`` in the body
frame, ``screw`` axis in the body frame, and ``equations``: the Newton–Euler equations in
the joint's variables; or ``{"error": message}``). A pose is
``[x, y, z, roll, pitch, yaw]`` (metres, radians), or ``null`` when it depends on a constant
without a value.
"""

from __future__ import annotations

import json
from typing import Any

from cyphy.lang.notation import to_notation
from cyphy.model.array import Array
from cyphy.model.elements import (
    AnnotationValue, Body, Device, ElaboratedModel, Joint, Link, Sensor,
)
from cyphy.model.poses import Pose, clean
from cyphy.semantics.dynamics import rigid_body as dynamics
from cyphy.semantics.dynamics.link_equations import link_equations


def _number(v: float) -> float | int:
    c = clean(float(v))
    return int(c) if c.is_integer() and abs(c) < 1e15 else c


def _value(v: Any) -> Any:
    if isinstance(v, Array):
        return [_value(x) for x in v.tolist()]
    if isinstance(v, list):
        return [_value(x) for x in v]
    if isinstance(v, bool) or v is None or isinstance(v, str):
        return v
    if isinstance(v, (int, float)):
        return _number(v)
    if isinstance(v, tuple):
        return "::".join(v)
    if isinstance(v, AnnotationValue):
        return _annotation(v)
    return str(v)


def _pose(p: Pose | None) -> list[float | int] | None:
    return None if p is None else [_number(x) for x in p.to_xyz_rpy()]


def _annotation(a: AnnotationValue | None) -> dict[str, Any] | None:
    if a is None:
        return None
    return {"template": "::".join(a.template), "args": {n: _value(v) for n, v in a.args}}


def _device(d: Device | None) -> dict[str, Any] | None:
    if d is None:
        return None
    return {
        "prefix": d.prefix,
        "ports": [{"name": p.name, "kind": p.kind.value, "mangled": p.mangled,
                   "value": _value(p.value)} for p in d.ports],
        "equations": [to_notation(e) for e in d.equations],
    }


def _sensor(s: Sensor) -> dict[str, Any]:
    return {"name": s.name, "definition": s.definition, "pose": _pose(s.pose),
            "annotation": _annotation(s.annotation),
            "device": s.device.prefix if s.device else None}


def _body(b: Body) -> dict[str, Any]:
    return {"name": b.name, "pose": _pose(b.pose),
            "geometry": b.geometry.kind if hasattr(b.geometry, "kind") else (
                "mesh" if b.geometry is not None else None),
            "size": {k: _value(v) for k, v in b.size.items()},
            "surface": {k: _value(v) for k, v in b.surface.items()}}


def _link(link: Link) -> dict[str, Any]:
    inertial = None
    if link.inertial is not None:
        inertial = {"mass": _number(link.inertial.mass), "com": _pose(link.inertial.com),
                    "inertia": [_number(x) for x in link.inertial.inertia],
                    "source": link.inertial_source}
    return {"name": link.name, "pose": _pose(link.pose), "inertial": inertial,
            "bodies": [_body(b) for b in link.bodies],
            "sensors": [_sensor(s) for s in link.sensors],
            "actuators": [_sensor(a) for a in link.actuators]}


def _joint(j: Joint) -> dict[str, Any]:
    return {"name": j.name, "definition": j.definition,
            "parent": j.parent.name if j.parent else None,
            "child": j.child.name if j.child else None, "pose": _pose(j.pose),
            "annotation": _annotation(j.annotation), "axis": _value(j.axis),
            "device": j.device.prefix if j.device else None,
            "sensors": [_sensor(s) for s in j.sensors],
            "actuators": [_sensor(a) for a in j.actuators]}


def model_to_dict(m: ElaboratedModel) -> dict[str, Any]:
    return {
        "model": m.name,
        "links": [_link(link) for link in m.links],
        "joints": [_joint(j) for j in m.joints],
        "unconnected": [_joint(j) for j in m.unconnected],
        "fixed": [{"name": f.name, "parent": f.parent.name if f.parent else None,
                   "child": f.child.name if f.child else None} for f in m.fixed],
        "devices": [_device(d) for d in m.devices],
        "relations": [to_notation(r) for r in m.relations],
        "constants": {k: _value(v) for k, v in m.constants.items()},
        "missing": sorted(m.missing),
        "motion": _motion(m),
    }


def _motion(m: ElaboratedModel) -> list[dict[str, Any]] | dict[str, str]:
    """Per moving body (the links one joint moves), its Newton–Euler equations in the body
    frame (:mod:`cyphy.semantics.dynamics.link_equations`: screw axis ``A``, spatial inertia ``G``,
    the Adjoint ``X`` from the parent's frame, twist ``V`` and its derivative ``dV``, the
    wrench ``F`` the joint transmits, the joint effort), printed in the notation. ``cyphy
    solve`` solves them for the accelerations by the articulated-body algorithm, whose twist
    and acceleration definitions are the components of ``V`` and ``dV``."""

    try:
        tree = dynamics.kinematic_tree(m)
    except dynamics.DynamicsError as err:
        return {"error": err.message}
    out = []
    for body in link_equations(tree):
        joint = body.joint
        mass = float(joint.inertia[3, 3])
        out.append({
            "joint": joint.name, "kind": joint.kind,
            "parent": tree.joints[joint.parent].name if joint.parent >= 0 else None,
            "links": list(joint.body), "mass": _number(mass),
            "com": [_number(v) for v in _com(joint.inertia, mass)],
            "screw": [_number(v) for v in joint.screw],
            "equations": [to_notation(e) for e in body.equations]})
    return out


def _com(inertia: Any, mass: float) -> list[float]:
    """The centre of mass from a spatial inertia's ``m[c]`` block."""
    c = inertia[0:3, 3:6] / mass
    return [float(c[2, 1]), float(c[0, 2]), float(c[1, 0])]


def model_to_json(m: ElaboratedModel) -> str:
    return json.dumps(model_to_dict(m), indent=2) + "\n"


def _fmt_pose(p: list[float | int] | None) -> str:
    if p is None:
        return "pose symbolic (needs a constant without a value)"
    return "pose " + " ".join(f"{v:g}" for v in p)


def model_to_text(m: ElaboratedModel) -> str:
    d = model_to_dict(m)
    out = [f"p-model {d['model']}"]
    for link in d["links"]:
        out.append(f"  link {link['name']}  {_fmt_pose(link['pose'])}")
        if link["inertial"]:
            i = link["inertial"]
            out.append(f"    inertial ({i['source']}): mass {i['mass']:g}, "
                       f"com {' '.join(f'{v:g}' for v in (i['com'] or []))}, "
                       f"inertia {' '.join(f'{v:g}' for v in i['inertia'])}")
        for b in link["bodies"]:
            size = ", ".join(f"{k}={v}" for k, v in b["size"].items())
            out.append(f"    body {b['name']}  {_fmt_pose(b['pose'])}  {b['geometry']}({size})")
        for kind in ("sensors", "actuators"):
            for s in link[kind]:
                out.append(f"    {kind[:-1]} {s['name']} ({s['definition']})  "
                           f"{_fmt_pose(s['pose'])}")
    for j in d["joints"]:
        out.append(f"  joint {j['name']} ({j['definition']}): {j['parent']} -> {j['child']}  "
                   f"{_fmt_pose(j['pose'])} (relative to the child)")
        for kind in ("sensors", "actuators"):
            for s in j[kind]:
                out.append(f"    {kind[:-1]} {s['name']} ({s['definition']})")
    for f in d["fixed"]:
        out.append(f"  fixed {f['parent']} -> {f['child']}")
    for dev in d["devices"]:
        ports = ", ".join(f"{p['kind']} {p['mangled']}" + (f" = {p['value']}"
                          if p["value"] is not None else "") for p in dev["ports"])
        out.append(f"  device {dev['prefix']}: {ports}")
        for e in dev["equations"]:
            out.append(f"    {e}")
    for r in d["relations"]:
        out.append(f"  relation {r}")
    if d["missing"]:
        out.append("  constants without values: " + ", ".join(d["missing"]))
    motion = d["motion"]
    if isinstance(motion, dict):
        out.append(f"  no equations of motion: {motion['error']}")
    for body in motion if isinstance(motion, list) else []:
        out.append(f"  motion of {', '.join(body['links'])} (joint {body['joint']}, "
                   f"{body['kind']}): mass {body['mass']:g}, com "
                   f"{' '.join(f'{v:g}' for v in body['com'])}, screw A = "
                   f"({', '.join(f'{v:g}' for v in body['screw'])})")
        for e in body["equations"]:
            out.append(f"    {e}")
    return "\n".join(out) + "\n"
