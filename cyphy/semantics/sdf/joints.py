"""Rule 5 and Rule 1's last line: one ``<joint>`` per joint instance (its type from the
annotation's template, its axes with their limits, its sensors and actuators), and a
``fixed`` joint per fixed connection instance.
"""

from __future__ import annotations

from cyphy.model.elements import AnnotationValue, FixedJoint, Joint, glued
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.annotations import fill
from cyphy.semantics.sdf.devices import actuator_rule, sensor_rule
from cyphy.semantics.sdf.translation import (AXES, DRAKE, GEARBOX, JOINT_TYPES, LOOP, NO_AXIS,
                                             NO_JOINT_TYPE, Translation)
from cyphy.semantics.sdf.tree import Comment, Node


def joint_rule(t: Translation, joint: Joint) -> list:  # type: ignore[type-arg]
    """Rule 5: one ``<joint>`` per joint instance. Elaboration made the instances (the cross
    product of the copies of the joint's link and of its target); a copy for one of several
    targets is named after its target. The type comes from the annotation's template (no
    annotation: ``revolute`` and a warning), the pose is relative to the child link, every
    axis the type needs is written with a ``<limit>``, and the joint's actuators are comments
    (or, for a ``Physics`` annotation, the joint's ``<physics>``)."""
    assert joint.parent is not None and joint.child is not None
    parent, child = t.names.link(joint.parent), t.names.link(joint.child)
    copies = t.copies[(joint.qname, id(joint.parent))]
    suffix = "__to__" + "__".join(glued(joint.child.qname[1:], "_")) if copies > 1 else ""
    annotation = joint.annotation
    template = annotation.template[-1] if annotation is not None else None
    kind = _joint_type(t, template)
    if annotation is None:
        t.report.report(NO_JOINT_TYPE, f"joint {joint.name} has no annotation: it is written "
                        "as a revolute joint", joint.span,
                        "annotate it, e.g. `annotation Revolute { axis = Axis { xyz = "
                        "(|0,0,1|) } }`")
    elif kind is None:
        t.report.report(NO_JOINT_TYPE, f"joint {joint.name}: annotation {template} is not an "
                        "SDF joint type; it is written as a revolute joint", joint.span,
                        "use one of " + ", ".join(JOINT_TYPES))
    kind = kind or "revolute"
    annotated_axes = frozenset(AXES.get(kind, ()))  # written by _axis, with their defaults
    if kind == "gearbox" and t.pybullet:
        kind = "revolute"
        t.report.report(GEARBOX, f"joint {joint.name} is a gearbox, which {t.simulator} does not "
                        "know: it is written as a revolute joint about its first axis",
                        joint.span, "couple it in PyBullet with p.createConstraint(…, "
                        "p.JOINT_GEAR, …) and setting its gearRatio")
    qualified = joint.name
    node = Node("joint", {"name": t.names.joint(joint, qualified, suffix),
                          "type": kind})
    node.add("pose", joint.pose)
    node.add("parent", parent)
    node.add("child", child)
    resolve = t.resolver(joint.qname)
    if annotation is not None:
        fill(node, annotation, t.templates, resolve, skip=annotated_axes)
    if kind != "gearbox":  # a gearbox written for PyBullet: its coupling has no meaning here
        node.children = [c for c in node.children if not (
            isinstance(c, Node) and c.tag in ("gearbox_ratio", "gearbox_reference_body"))]
    for name in AXES.get(kind, ()):
        node.children.append(_axis(t, joint, name))
    if kind == "gearbox" and node.find("gearbox_reference_body") is None:
        node.add("gearbox_reference_body", parent)
    elif kind == "gearbox":
        ref = node.find("gearbox_reference_body")
        if ref is not None and ref.text == "__default__":
            ref.text = parent
    for sensor in joint.sensors:
        local = joint.local_pose.inverse() if joint.local_pose is not None else None
        node.children.extend(sensor_rule(t, sensor, local))
    for actuator in joint.actuators:
        local = joint.local_pose.inverse() if joint.local_pose is not None else None
        node.children.extend(actuator_rule(t, actuator, "joint", local))
    return [Comment(f"joint {qualified} from {joint.parent.name} to {joint.child.name}"), node]


def _joint_type(t: Translation, template: str | None) -> str | None:
    if template is None:
        return None
    for general, kind in JOINT_TYPES.items():
        if t.templates.is_a(template, general) or template == general:
            return kind
    return None


def _axis(t: Translation, joint: Joint, name: str) -> Node:
    """The joint's ``<axis>`` (or ``<axis2>``): the annotation's, its missing ``xyz`` taken from
    the joint's AXIS constant (for the first axis), else ``0 0 1`` with a warning; always with
    the template's defaults, so always with a ``<limit>``."""
    given = joint.annotation.get(name) if joint.annotation is not None else None
    value = given if isinstance(given, AnnotationValue) else AnnotationValue(("Axis",), ())
    if value.get("xyz") is None:
        xyz = joint.axis if name == "axis" else None
        if xyz is None:
            t.report.report(NO_AXIS, f"joint {joint.name}: no {name} direction in its "
                            "annotation or AXIS constant; SDF gets 0 0 1", joint.span,
                            f"give it, e.g. `{name} = Axis {{ xyz = (|0,0,1|) }}`")
        else:
            value = AnnotationValue(value.template, (("xyz", xyz), *value.args), value.span)
    node = Node(name)
    # SDFormat 1.9 removed <axis><initial_position> (a joint's position is a state, not a
    # property); Drake's parser, which converts our 1.6 files up, refuses it as an error.
    skip = frozenset({"initial_position"}) if t.drake else frozenset()
    fill(node, value, t.templates, t.resolver(joint.qname), skip)
    initial = value.get("initial_position")
    if t.drake and isinstance(initial, (int, float)) and initial != 0:
        t.report.report(DRAKE, f"joint {joint.name}: its {name}'s initial_position "
                        f"{initial:g} is left out (SDFormat 1.9 removed it and Drake refuses "
                        "it): Drake starts the joint at 0", joint.span,
                        "set the position in Drake (plant.SetPositions), or give the joint "
                        "pose the initial position")
    return node


def fixed_rule(t: Translation, fixed: FixedJoint, turned: bool = False
               ) -> list[Node | Comment]:
    """Rule 1, last line: a fixed connection instance is a ``fixed`` joint whose parent is the
    link that declares ``fixed to`` and whose child is its target (sdf.md decision 10).
    ``turned`` (tree targets only, :mod:`~cyphy.semantics.sdf.orientation`): the same rigid
    attachment written from the target to the declaring link, so that the links form a
    tree; its pose stays the identity, which puts the joint at its new child's frame."""
    assert fixed.parent is not None and fixed.child is not None
    parent, child = t.names.link(fixed.parent), t.names.link(fixed.child)
    qualified = f"{fixed.parent.name}::fixedJoint::{fixed.child.name}"
    node = Node("joint", {"name": t.names.fixed(fixed.parent, fixed.child, qualified),
                          "type": "fixed"})
    node.add("pose", Pose.identity())
    node.add("parent", child if turned else parent)
    node.add("child", parent if turned else child)
    both = t.joined.get(frozenset((id(fixed.parent), id(fixed.child))))
    if both is not None:
        t.report.report(LOOP, f"links {fixed.parent.name} and {fixed.child.name} are connected "
                        f"by joint {both.name} and by a fixed connection", fixed.span,
                        "keep either the joint or the fixed connection")
    what = f"fixed joint {qualified} from {fixed.parent.name} to {fixed.child.name}"
    if turned:
        what += f", turned round for {t.simulator} (from {fixed.child.name}) to make a tree"
    return [Comment(what), node]
