"""Sensors and actuators, after the paper's annotation-driven translation (§5.3): an annotated
sensor is a ``<sensor>``; an actuator is a comment, with the SDF element its annotation stands
for where that element is valid (a ``<light>`` in a link, a joint's ``<physics>``).
"""

from __future__ import annotations

from cyphy.model.elements import Actuator, Sensor
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.annotations import fill
from cyphy.semantics.sdf.translation import (ACTUATOR_ELEMENTS, COPPELIASIM_SENSOR, NO_ACTUATOR,
                                             NO_SENSOR, SENSOR_TYPES, Translation)
from cyphy.semantics.sdf.tree import Comment, Node


def sensor_rule(t: Translation, sensor: Sensor, frame: Pose | None) -> list:  # type: ignore[type-arg]
    """§5.3: an annotated sensor is a ``<sensor>`` whose type is its template's (``Ray`` →
    ``ray``) and whose elements are the annotation's fields with the template's defaults.
    Its pose is the model's, relative to the link (``frame`` re-expresses it for a joint);
    ``--target coppeliasim`` adds RoboTool's ``Ry(π/2)``. Without an SDF type: a comment and
    a warning, never an invalid element."""
    annotation = sensor.annotation
    template = annotation.template[-1] if annotation is not None else None
    kind = None
    if template is not None:
        for general, sdf_type in SENSOR_TYPES.items():
            if template == general or t.templates.is_a(template, general):
                kind = sdf_type
                break
    if kind is None:
        why = "has no annotation" if template is None else \
            f"is annotated with {template}, which is no SDF sensor type"
        t.report.report(NO_SENSOR, f"sensor {sensor.name} {why}: SDF gets a comment only",
                        sensor.span, "annotate it with one of "
                        + ", ".join(SENSOR_TYPES) + " (physmod::sdf::annotations)")
        return [Comment(f"sensor {sensor.name}: {why}, so it has no SDF element")]
    pose = sensor.pose
    if pose is not None and frame is not None:
        pose = frame.compose(pose)
    if pose is not None and t.coppeliasim:
        pose = pose.compose(COPPELIASIM_SENSOR)
    node = Node("sensor", {"name": t.names.device(sensor), "type": kind})
    node.add("pose", pose)
    assert annotation is not None
    fill(node, annotation, t.templates, t.resolver(sensor.qname))
    return [Comment(f"sensor {sensor.name}"), node]


def actuator_rule(t: Translation, actuator: Actuator, where: str, frame: Pose | None
                  ) -> list:  # type: ignore[type-arg]
    """Actuators have no SDF counterpart (sdf.md decision 12): a comment with the qualified
    name and, where the annotation's template stands for an SDF element valid there (a
    ``<light>`` in a link, a joint's ``<physics>``), that element."""
    out: list = [Comment(f"actuator {actuator.name}")]  # type: ignore[type-arg]
    annotation = actuator.annotation
    if annotation is None:
        return out
    template = annotation.template[-1]
    element = next((e for general, e in ACTUATOR_ELEMENTS.items()
                    if template == general or t.templates.is_a(template, general)), None)
    if element is None or element[1] != where:
        valid = f"a <{element[0]}> is valid only in a {element[1]}" if element else \
            f"{template} stands for no SDF element"
        t.report.report(NO_ACTUATOR, f"actuator {actuator.name} in a {where}: {valid}; SDF "
                        "gets a comment only", actuator.span,
                        "annotate actuators of links with Light and of joints with Physics")
        out[0] = Comment(f"actuator {actuator.name}: {valid}")
        return out
    tag = element[0]
    if tag == "physics":
        node = Node("physics")
    else:
        node = Node(tag, {"name": t.names.device(actuator)})
        pose = actuator.pose
        if pose is not None and frame is not None:
            pose = frame.compose(pose)
        node.add("pose", pose)
    fill(node, annotation, t.templates, t.resolver(actuator.qname))
    if tag == "light" and "type" not in node.attrs:
        node.attrs["type"] = "point"
    if tag == "light":  # attributes in SDF's order: name, type
        node.attrs = {"name": node.attrs["name"], "type": node.attrs["type"]}
    out.append(node)
    return out
