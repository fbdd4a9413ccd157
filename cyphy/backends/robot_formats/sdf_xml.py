"""Writing the SDF tree as XML (sdf.md decisions 4, 8 and 15).

The rules (:mod:`cyphy.semantics.sdf.rules`) give values as Python objects; this module prints them:

* numbers with Python's shortest round-trip ``repr``, after removing float noise: a value
  within 8 ulps of a 15-digit decimal prints as that decimal (a computed
  ``0.30000000000000004`` or ``0.41 - 0.43 = -0.020000000000000018`` prints ``0.3``,
  ``-0.02``, while π/2 keeps its digits), a value within 1e-12 of an integer as that integer,
  and ``-0.0`` as ``0``; integers as integers; booleans ``true``/``false``;
* vectors with single spaces (``0 1 0``), never RoboTool's ``010``;
* poses as ``x y z roll pitch yaw`` with ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``, roll and yaw in
  (−π, π], pitch in [−π/2, π/2]; at gimbal lock yaw is 0 (as :meth:`Pose.to_xyz_rpy`);
* comments made safe (``--`` cannot occur inside an XML comment).

Output is byte-identical for the same tree: attributes and children keep their order, and
indentation is two spaces.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

from cyphy import collector
from cyphy.model.array import Array
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.tree import Comment, Node, Text

_GIMBAL = 1e-7  # |cos pitch| below which roll and yaw turn about one axis (SciPy's threshold)


def number(value: float | int | bool) -> str:
    """One number as SDF prints it (see the module docstring)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int) or hasattr(value, "__index__"):  # NumPy's integers too
        return str(int(value))
    v = float(value)
    if not math.isfinite(v):
        return repr(v)
    nearest = round(v)
    if abs(v - nearest) <= 1e-12 * max(1.0, abs(v)):
        v = float(nearest)
    elif len(repr(v)) > 17:  # 16-17 significant digits: noise after a short decimal?
        short = float(f"{v:.15g}")
        if abs(short - v) <= 8 * math.ulp(v):
            v = short
    if v == 0.0:
        return "0"
    text = repr(v)
    return text[:-2] if text.endswith(".0") else text


def xyz_rpy(pose: Pose) -> tuple[float, float, float, float, float, float]:
    """``(x, y, z, roll, pitch, yaw)`` of a pose, written out (SciPy costs 50 µs a call)."""
    r = pose.rotation
    pitch = math.atan2(-r[2][0], math.hypot(r[0][0], r[1][0]))
    if math.cos(pitch) < _GIMBAL:  # gimbal lock: yaw = 0, roll carries the rest
        yaw = 0.0
        roll = math.atan2(r[0][1], r[1][1]) if pitch > 0 else math.atan2(-r[0][1], r[1][1])
    else:
        roll = math.atan2(r[2][1], r[2][2])
        yaw = math.atan2(r[1][0], r[0][0])
    x, y, z = pose.position
    return (x, y, z, _half_open(roll), pitch, _half_open(yaw))


def _half_open(angle: float) -> float:
    return math.pi if angle <= -math.pi + 1e-12 else angle


def text_of(value: Text) -> str | None:
    """The XML text of an element's value."""
    if value is None:
        return None
    if isinstance(value, str):
        return value
    if isinstance(value, Pose):
        return " ".join(number(v) for v in xyz_rpy(value))
    if isinstance(value, Array):
        return " ".join(number(v) for v in value.flat)
    if isinstance(value, (tuple, list)):
        return " ".join(number(v) if not isinstance(v, str) else v for v in value)
    return number(value)  # type: ignore[arg-type]


def safe_comment(text: str) -> str:
    """Comment text that keeps the document well-formed: no ``--``, no trailing ``-``."""
    while "--" in text:
        text = text.replace("--", "- -")
    return f" {text} "  # the spaces keep a trailing '-' away from the closing '-->'


def _element(node: Node) -> ET.Element:
    element = ET.Element(node.tag, node.attrs)
    element.text = text_of(node.text)
    for child in node.children:
        if isinstance(child, Comment):
            element.append(ET.Comment(safe_comment(child.text)))
        else:
            element.append(_element(child))
    return element


def to_xml(root: Node) -> str:
    """The document as text: an XML declaration, then the tree indented by two spaces."""
    with collector.paused():  # an element per node, all live until written
        tree = _element(root)
        ET.indent(tree, space="  ")
        return "<?xml version='1.0' encoding='utf-8'?>\n" + ET.tostring(
            tree, encoding="unicode") + "\n"


def names_json(names: dict[str, str]) -> str:
    """The name table (``<model>.names.json``): every SDF name → its qualified RoboSim name."""
    return json.dumps(names, indent=2, ensure_ascii=False) + "\n"


def model_config(name: str, sdf_file: str = "model.sdf", description: str = "") -> str:
    """Gazebo's ``model.config`` for a model folder (sdf.md decision 14)."""
    model = ET.Element("model")
    ET.SubElement(model, "name").text = name
    ET.SubElement(model, "version").text = "1.0"
    ET.SubElement(model, "sdf", {"version": "1.6"}).text = sdf_file
    ET.SubElement(model, "description").text = description or \
        f"{name}, generated by cyphy from a RoboSim p-model"
    ET.indent(model, space="  ")
    return "<?xml version='1.0' encoding='utf-8'?>\n" + ET.tostring(
        model, encoding="unicode") + "\n"
