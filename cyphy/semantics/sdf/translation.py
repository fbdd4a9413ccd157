"""What every SDF rule shares: the options, the result, the translation's state (names,
templates, the report, the tables of copies and connections) and the warnings the rules give,
with the tables of SDF's joint and sensor types and of the targets' needs.
"""

from __future__ import annotations

from dataclasses import field

from cyphy import codes
from cyphy.diagnostics import Report
from cyphy.lang.workspace import Workspace
from cyphy.model.elements import Body, ElaboratedModel, Joint, Link
from cyphy.model.poses import Pose
from cyphy.records import record
from cyphy.semantics.sdf.annotations import Templates
from cyphy.semantics.sdf.names import Names
from cyphy.semantics.sdf.tree import Node

NO_JOINT_TYPE = codes.code("W-SDF-JOINT", codes.W,
                           "a joint without an annotation: SDF gets a revolute joint")
NO_AXIS = codes.code("W-SDF-AXIS", codes.W,
                     "a joint whose axis neither its annotation nor an AXIS constant gives")
NO_SENSOR = codes.code("W-SDF-SENSOR", codes.W,
                       "a sensor that has no SDF sensor element (no annotation, or no SDF type)")
NO_ACTUATOR = codes.code("W-SDF-ACTUATOR", codes.W,
                         "an actuator annotation with no SDF element valid where it sits")
NO_CHILD = codes.code("W-SDF-UNCONNECTED", codes.W,
                      "a joint without a flexible connection: not written to SDF")
NO_INERTIA = codes.code("W-SDF-INERTIA", codes.W,
                        "a link with a mass but no inertia and no body to derive one from")
LOOP = codes.code("W-SDF-LOOP", codes.W,
                  "two links connected both by a joint and by a fixed connection")
NOT_TREE = codes.code("W-SDF-TREE", codes.W,
                      "the links do not form one tree: tree-based simulators cannot load it")
CUT = codes.code("W-SDF-CUT", codes.W,
                 "--target pybullet: a joint that closes a kinematic loop is left out")
GEARBOX = codes.code("W-SDF-GEARBOX", codes.W,
                     "--target pybullet: a gearbox joint is written as a revolute joint")
DRAKE = codes.code("W-SDF-DRAKE", codes.W,
                   "--target drake: an element Drake's parser refuses is left out, and that "
                   "changes the model")

JOINT_TYPES = {"Revolute": "revolute", "Prismatic": "prismatic", "Ball": "ball",
               "Universal": "universal", "Revolute2": "revolute2", "Screw": "screw",
               "Gearbox": "gearbox", "Fixed": "fixed"}
#: Joint types and the axes SDF requires of them.
AXES = {"revolute": ("axis",), "prismatic": ("axis",), "screw": ("axis",),
        "universal": ("axis", "axis2"), "revolute2": ("axis", "axis2"),
        "gearbox": ("axis", "axis2")}
SENSOR_TYPES = {"Ray": "ray", "Sonar": "sonar", "IMU": "imu", "Camera": "camera",
                "Contact": "contact", "Logical_camera": "logical_camera", "GPS": "gps",
                "Altimeter": "altimeter", "Magnetometer": "magnetometer",
                "Force_torque": "force_torque"}
#: Targets that need trees (``split_trees``, loops cut), with the name the warnings use.
TREE_TARGETS = {"pybullet": "PyBullet", "urdf": "URDF", "mjcf": "MuJoCo"}
#: Actuator templates and the SDF element they stand for, with where it is valid.
ACTUATOR_ELEMENTS = {"Light": ("light", "link"), "Physics": ("physics", "joint")}

#: The extra rotation RoboTool applies to sensor poses for CoppeliaSim (sdf-robotool.md §3).
COPPELIASIM_SENSOR = Pose.from_xyz_rpy(0.0, 0.0, 0.0, 0.0, 1.57079632679, 0.0)
#: Mass given to a link that has no inertial anywhere (L4 warns): spread over its bodies.
DEFAULT_MASS = 1.0


@record(slots=False)
class SdfOptions:
    pose: tuple[float, float, float, float, float, float] = (0.0,) * 6
    short_names: bool = False
    #: "gazebo"; "coppeliasim": RoboTool's conventions (coded names, Ry(π/2)); "pybullet":
    #: trees only (split trees, loops cut, gearboxes as revolute joints); "drake": without
    #: the elements SDFormat 1.9 removed, which Drake's parser refuses
    target: str = "gazebo"
    split_trees: bool = False  # a <world> with one <model> per tree of links


@record(frozen=False, slots=False)
class SdfDocument:
    """What the rules produce: the ``<sdf>`` element and the SDF-name → qualified-name table."""

    root: Node
    names: dict[str, str] = field(default_factory=dict)


class Translation:
    """State shared by the rules: names, templates, the report."""

    def __init__(self, model: ElaboratedModel, ws: Workspace, report: Report,
                 options: SdfOptions) -> None:
        self.model = model
        self.report = report
        self.options = options
        self.coppeliasim = options.target == "coppeliasim"
        self.drake = options.target == "drake"
        #: Trees only (loops cut, gearboxes as revolute joints): PyBullet, URDF and MJCF.
        self.pybullet = options.target in TREE_TARGETS
        self.simulator = TREE_TARGETS.get(options.target, "PyBullet")
        self.names = Names(options.short_names or self.coppeliasim)
        self.templates = Templates(ws)
        self.bodies_by_name: dict[tuple[str, ...], list[Body]] = {}
        for b in model.bodies:
            self.bodies_by_name.setdefault(b.qname[-1 - len(b.index):], []).append(b)
        self.copies: dict[tuple[tuple[str, ...], int], int] = {}
        self.joined: dict[frozenset[int], Joint] = {}
        for j in model.joints:
            key = (j.qname, id(j.parent))
            self.copies[key] = self.copies.get(key, 0) + 1
            self.joined.setdefault(frozenset((id(j.parent), id(j.child))), j)
        self.links_by_name: dict[tuple[str, ...], list[Link]] = {}
        for link in model.links:
            self.links_by_name.setdefault(link.qname[-1 - len(link.index):], []).append(link)

    def resolver(self, owner: tuple[str, ...]):  # type: ignore[no-untyped-def]
        """Element paths in an annotation (``B``, ``Link::body``) to SDF names: the link or
        body whose qualified name ends with the path, the one closest to ``owner`` first."""

        def resolve(path: tuple[str, ...]) -> str | None:
            candidates: list[Link | Body] = []
            for table in (self.links_by_name, self.bodies_by_name):
                for key, found in table.items():
                    if key[-len(path):] == path or _strip_index(key) == path[-len(key):]:
                        candidates.extend(e for e in found
                                          if e.qname[-len(path):] == path
                                          or _strip_index(e.qname)[-len(path):] == path)
            if not candidates:
                return None
            best = max(candidates, key=lambda e: _shared(e.qname, owner))
            if isinstance(best, Body):
                return self.names.body(best)[0]
            return self.names.link(best)

        return resolve


def _strip_index(qname: tuple[str, ...]) -> tuple[str, ...]:
    return tuple(c for c in qname if not c.lstrip("-").isdigit())


def _shared(a: tuple[str, ...], b: tuple[str, ...]) -> int:
    n = 0
    for x, y in zip(a, b):
        if x != y:
            break
        n += 1
    return n
