"""The elaborated model: what a p-model really is once parts are instantiated, indexed blocks
replicated, references merged with their definitions, constants evaluated and poses composed.

Every stage after the checks (SDF, CyPhyCircus, Flow*, the value checks) reads these classes
instead of the syntax tree. Qualified names follow RoboTool's comments: the components joined
by ``::`` with each index value as a component of its own (``IJFIL::Bottom::2::PJ::0``).
Values that depend on a constant without a value are ``None`` (symbolic); the constant is
listed in ``ElaboratedModel.missing``.
"""

from __future__ import annotations

from dataclasses import field
from typing import Callable, Union

from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.model.evaluate import Value
from cyphy.model.inertia import Inertial
from cyphy.model.poses import Pose
from cyphy.records import record


@record
class Port:
    """A variable of a device instance: its declared name, kind, type and mangled name."""

    name: str
    kind: ast.DeclKind  # INPUT, OUTPUT, INOUT, LOCAL or CONST
    type: ast.TypeRef
    mangled: str
    value: Value | None = None  # constants: the evaluated value, when there is one
    initial: ex.Expr | None = None  # declared initial value (inputs, locals)


class Device:
    """The behaviour of a joint, sensor or actuator instance: its definition's variables and
    equations, renamed to the instance (``LMotor_das``; ``Proximity1_voltage``).

    Equations are renamed when first read: elaboration makes every instance, but only some
    commands look at behaviour (SDF generation never does)."""

    __slots__ = ("prefix", "ports", "_equations", "_constraints", "_rename")

    def __init__(self, prefix: str, ports: tuple[Port, ...], equations: tuple[ex.Expr, ...],
                 constraints: tuple[ex.Expr, ...] = (),
                 rename: Callable[[ex.Expr], ex.Expr] | None = None) -> None:
        self.prefix = prefix
        self.ports = ports
        self._equations = equations
        self._constraints = constraints
        self._rename = rename

    def _renamed(self) -> None:
        if self._rename is not None:
            rename, self._rename = self._rename, None
            self._equations = tuple(rename(e) for e in self._equations)
            self._constraints = tuple(rename(e) for e in self._constraints)

    @property
    def equations(self) -> tuple[ex.Expr, ...]:
        self._renamed()
        return self._equations

    @property
    def constraints(self) -> tuple[ex.Expr, ...]:
        self._renamed()
        return self._constraints

    def __repr__(self) -> str:
        return f"Device({self.prefix!r}, {len(self.ports)} ports)"

    def port(self, name: str) -> Port | None:
        for p in self.ports:
            if p.name == name:
                return p
        return None

    def of_kind(self, *kinds: ast.DeclKind) -> tuple[Port, ...]:
        return tuple(p for p in self.ports if p.kind in kinds)


@record
class AnnotationValue:
    """An evaluated annotation: the template (qualified), and each argument's value: a
    number, boolean, string, vector, an element path (tuple of names) or a nested
    annotation. Defaults of the template are not filled in here (the SDF rules do that)."""

    template: tuple[str, ...]
    args: tuple[tuple[str, Union[Value, "AnnotationValue", tuple[str, ...], None]], ...]
    span: Span = field(compare=False, repr=False, default=Span.unknown())

    def get(self, name: str) -> Value | AnnotationValue | tuple[str, ...] | None:
        for n, v in self.args:
            if n == name:
                return v
        return None


@record(frozen=False, slots=False, eq=False)
class Element:
    """Base of every elaborated element. ``qname`` is the tuple of name components."""

    qname: tuple[str, ...]
    span: Span
    index: dict[str, int] = field(default_factory=dict)  # index variables bound in this copy

    @property
    def name(self) -> str:
        """The qualified name as RoboTool writes it: ``Model::part::link::2``."""
        return "::".join(self.qname)

    @property
    def simple_name(self) -> str:
        return next(c for c in reversed(self.qname) if not c.lstrip("-").isdigit())


@record(frozen=False, slots=False, eq=False)
class Body(Element):
    link: Link | None = None
    pose: Pose | None = None  # relative to the link
    geometry: ast.Shape | ast.Mesh | None = None
    size: dict[str, Value | None] = field(default_factory=dict)  # evaluated geometry arguments
    mesh_uri: str | None = None
    inertial: Inertial | None = None  # as given by the body (inertia solid-filled if absent)
    surface: dict[str, Value | None] = field(default_factory=dict)


@record(frozen=False, slots=False, eq=False)
class Sensor(Element):
    link: Link | None = None
    joint: Joint | None = None  # when the sensor is contained in a joint
    pose: Pose | None = None  # relative to the link
    annotation: AnnotationValue | None = None
    device: Device | None = None
    definition: str | None = None  # qualified name of the definition it realises


@record(frozen=False, slots=False, eq=False)
class Actuator(Sensor):
    pass


@record(frozen=False, slots=False, eq=False)
class Joint(Element):
    parent: Link | None = None
    child: Link | None = None
    local_pose: Pose | None = None  # relative to the parent link, as written
    pose: Pose | None = None  # relative to the child link (SDF 1.6)
    annotation: AnnotationValue | None = None
    axis: Value | None = None  # the definition's AXIS constant, when it has one
    device: Device | None = None
    definition: str | None = None
    target_copy: int = 0  # which target instance, when the target is replicated
    sensors: list[Sensor] = field(default_factory=list)
    actuators: list[Actuator] = field(default_factory=list)


@record(frozen=False, slots=False, eq=False)
class FixedJoint(Element):
    parent: Link | None = None
    child: Link | None = None


@record(frozen=False, slots=False, eq=False)
class Link(Element):
    pose: Pose | None = None  # relative to the p-model (the model frame)
    inertial: Inertial | None = None  # own, or combined from the bodies
    inertial_source: str = "none"  # "link", "bodies" or "none"
    bodies: list[Body] = field(default_factory=list)
    sensors: list[Sensor] = field(default_factory=list)
    actuators: list[Actuator] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)  # joints this link contains (parent)
    device: Device | None = None


ModelElement = Union[Link, Body, Joint, FixedJoint, Sensor, Actuator]


@record(frozen=False, slots=False, eq=False)
class ElaboratedModel:
    name: str
    pmodel: ast.PModel
    links: list[Link] = field(default_factory=list)
    bodies: list[Body] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)  # connected: parent and child known
    unconnected: list[Joint] = field(default_factory=list)  # no `flexibly connected to`
    fixed: list[FixedJoint] = field(default_factory=list)
    sensors: list[Sensor] = field(default_factory=list)
    actuators: list[Actuator] = field(default_factory=list)
    relations: list[ex.Expr] = field(default_factory=list)  # containment relations, renamed
    constants: dict[str, Value] = field(default_factory=dict)  # qualified name → value
    missing: dict[str, list[Span]] = field(default_factory=dict)  # constants with no value
    # Joints whose copies do not match their replicated target one for one (IX3): the joint,
    # how many copies it has, and the target's copies (each copy is joined to all of them).
    mismatched: list[tuple[Joint, int, list[Link]]] = field(default_factory=list)

    @property
    def devices(self) -> list[Device]:
        out = [e.device for e in [*self.joints, *self.unconnected, *self.sensors,
                                  *self.actuators, *self.links] if e.device is not None]
        seen: set[str] = set()
        unique = []
        for d in out:
            if d.prefix not in seen:
                seen.add(d.prefix)
                unique.append(d)
        return unique

    def element(self, name: str) -> ModelElement | None:
        for e in self.all_elements():
            if e.name == name:
                return e
        return None

    def all_elements(self) -> list[ModelElement]:
        return [*self.links, *self.bodies, *self.joints, *self.fixed, *self.sensors,
                *self.actuators]

    def kinematic_graph(self):  # type: ignore[no-untyped-def]
        """Links as nodes (by qualified name), joints and fixed connections as edges from
        parent to child (a NetworkX MultiDiGraph; edge attribute ``element``)."""
        import networkx as nx  # lazy: only the tree exports and checks ask for the graph

        graph = nx.MultiDiGraph()
        for link in self.links:
            graph.add_node(link.name, element=link)
        for j in [*self.joints, *self.fixed]:
            if j.parent is not None and j.child is not None:
                graph.add_edge(j.parent.name, j.child.name, key=j.name + f"#{id(j)}",
                               element=j)
        return graph


def is_index_value(component: str) -> bool:
    """Index values are the qualified-name components that are integers (names never are)."""
    return component.lstrip("-").isdigit()


def glued(components: tuple[str, ...], separator: str = "") -> list[str]:
    """Qualified-name components with each index value glued to the name before it:
    ``('Core', 'Proximity', '1')`` → ``['Core', 'Proximity1']`` (device prefixes), or with
    ``separator="_"`` ``['Core', 'Proximity_1']`` (SDF names)."""
    out: list[str] = []
    for c in components:
        if is_index_value(c) and out:
            out[-1] += separator + c
        else:
            out.append(c)
    return out
