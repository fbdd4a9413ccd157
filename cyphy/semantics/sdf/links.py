"""Rules 2-4 and 6: links (``<link>`` with its pose, inertial, bodies, sensors and actuators),
bodies (a ``<collision>`` and a ``<visual>``), inertials (a link's own, else combined from
its bodies) and the order of declarations (a container's parts before its own links).
"""

from __future__ import annotations

from cyphy.lang import ast
from cyphy.model.body_inertia import distribute_mass  # the same spreading as a mass-only link
from cyphy.model.elements import Body, ElaboratedModel, Link
from cyphy.model.inertia import Inertial
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.devices import actuator_rule, sensor_rule
from cyphy.semantics.sdf.translation import DEFAULT_MASS, NO_INERTIA, Translation
from cyphy.semantics.sdf.tree import Comment, Node


def parts_rule(model: ElaboratedModel) -> list[Link]:
    """Rule 6: the declarations of a container come part by part (each part's own parts
    first, recursively), then the container's own links, in declaration order."""
    children: dict[tuple[str, ...], list[tuple[str, ...]]] = {}
    own: dict[tuple[str, ...], list[Link]] = {}
    for link in model.links:
        container = link.qname[:len(link.qname) - 1 - len(link.index)]
        own.setdefault(container, []).append(link)
        for depth in range(len(container), 1, -1):
            parent, sub = container[:depth - 1], container[:depth]
            kids = children.setdefault(parent, [])
            if sub not in kids:
                kids.append(sub)
    out: list[Link] = []

    def emit(prefix: tuple[str, ...]) -> None:
        for sub in children.get(prefix, []):
            emit(sub)
        out.extend(own.get(prefix, []))

    emit((model.name,))
    return out


def link_rule(t: Translation, link: Link) -> list:  # type: ignore[type-arg]
    """Rule 2: a link is a ``<link>`` with its pose relative to the model frame, its inertial
    (Rule 4), a collision and a visual per body (Rule 3), its sensors and its actuators."""
    node = Node("link", {"name": t.names.link(link)})
    node.add("pose", link.pose)
    node.children.append(inertial_rule(t, link))
    for body in link.bodies:
        node.children.extend(body_rule(t, body))
    for sensor in link.sensors:
        node.children.extend(sensor_rule(t, sensor, Pose.identity()))
    for actuator in link.actuators:
        node.children.extend(actuator_rule(t, actuator, "link", Pose.identity()))
    return [Comment(f"link {link.name}"), node]


def inertial_rule(t: Translation, link: Link) -> Node:
    """Rule 4: the link's own inertial if it has one; otherwise the combination of its bodies'
    (mass, centre of mass, inertia by rotation and the parallel-axis theorem), which
    elaboration computes. A link with no mass anywhere (warning L4) gets ``DEFAULT_MASS``
    spread over its bodies by volume, or SDF's default (1 kg, unit inertia) without bodies.
    A mass with no inertia and no body geometry gets SDF's unit inertia and a warning."""
    inertial = link.inertial
    if inertial is None:
        inertial = _default_inertial(link)
    elif inertial.inertia == (0.0,) * 6:
        t.report.report(NO_INERTIA, f"link {link.name} gives a mass but no inertia matrix and "
                        "has no body to compute one from: SDF gets the unit inertia",
                        link.span, "add `inertia matrix { … }` or a body with a geometry")
        inertial = Inertial(inertial.mass, inertial.com, (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))
    node = Node("inertial")
    node.add("pose", inertial.com)
    node.add("mass", inertial.mass)
    inertia = node.add("inertia")
    for key, value in zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), inertial.inertia):
        inertia.add(key, value)
    return node


def _default_inertial(link: Link) -> Inertial:
    unit = Inertial(DEFAULT_MASS, Pose.identity(), (0.0,) * 6)
    spread = distribute_mass(unit, link.bodies) if link.bodies else None
    return spread or Inertial(DEFAULT_MASS, Pose.identity(), (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))


def body_rule(t: Translation, body: Body) -> list:  # type: ignore[type-arg]
    """Rule 3: a body is a ``<collision>`` and a ``<visual>`` (different names) with its pose
    relative to the link and its geometry; the surface (bounce, friction) and laser retro are
    collision properties only (sdf.md decision 8)."""
    collision_name, visual_name = t.names.body(body)
    collision = Node("collision", {"name": collision_name})
    visual = Node("visual", {"name": visual_name})
    for node in (collision, visual):
        node.add("pose", body.pose)
        node.children.append(_geometry(body))
    s = body.surface
    if "laser_retro" in s:
        collision.add("laser_retro", s["laser_retro"])
    if any(k in s for k in ("restitution_coefficient", "threshold", "coefficient1",
                            "coefficient2", "direction", "slip1", "slip2")):
        surface = collision.add("surface")
        if "restitution_coefficient" in s or "threshold" in s:
            bounce = surface.add("bounce")
            _optional(bounce, "restitution_coefficient", s.get("restitution_coefficient"))
            _optional(bounce, "threshold", s.get("threshold"))
        friction_keys = ("coefficient1", "coefficient2", "direction", "slip1", "slip2")
        if any(k in s for k in friction_keys):
            ode = surface.add("friction").add("ode")
            for key, tag in zip(friction_keys, ("mu", "mu2", "fdir1", "slip1", "slip2")):
                _optional(ode, tag, s.get(key))
    return [Comment(f"body {body.name}"), collision, visual]


def _optional(node: Node, tag: str, value: object) -> None:
    if value is not None:
        node.add(tag, value)  # type: ignore[arg-type]


def _geometry(body: Body) -> Node:
    geometry = Node("geometry")
    g, size = body.geometry, body.size
    if isinstance(g, ast.Shape) and g.kind == "box":
        geometry.add("box").add("size", (size.get("length"), size.get("width"),
                                         size.get("height")))
    elif isinstance(g, ast.Shape) and g.kind == "cylinder":
        cylinder = geometry.add("cylinder")
        cylinder.add("radius", size.get("radius"))
        cylinder.add("length", size.get("length"))
    elif isinstance(g, ast.Shape) and g.kind == "sphere":
        geometry.add("sphere").add("radius", size.get("radius"))
    elif isinstance(g, ast.Mesh):
        mesh = geometry.add("mesh")
        mesh.add("uri", body.mesh_uri or "")
        scale = size.get("scaling")
        if scale is not None:
            mesh.add("scale", (scale,) * 3 if isinstance(scale, (int, float)) else scale)
    else:
        geometry.add("empty")
    return geometry
