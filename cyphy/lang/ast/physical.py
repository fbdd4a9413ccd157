"""The syntax of p-models: blocks (links, bodies, joints, sensors, actuators) and
their members (poses, geometry, inertia, equations, connections), parts and solutions."""

from __future__ import annotations

from dataclasses import field
from enum import Enum
from typing import Any, Union

from cyphy.expr import Expr
from cyphy.lang.ast.core import Annotation, Node, QName, T, TypeRef, VarDecl
from cyphy.pickling import SeparatePickle
from cyphy.records import record


@record
class PoseField(Node):
    key: str  # x y z roll pitch yaw
    value: Expr


@record
class Pose(Node):
    fields: tuple[PoseField, ...]

    def get(self, key: str) -> Expr | None:
        for f in self.fields:
            if f.key == key:
                return f.value
        return None


@record
class IndexDecl(Node):
    """``index i : [a, b)`` (half-open) or ``[a, b]`` (closed)."""

    var: str
    lower: Expr
    upper: Expr
    closed: bool


@record
class FixedConnection(Node):
    """``fixed to L`` or ``fixed to L in P`` (link L of part P)."""

    target: str
    part: str | None


@record
class FlexibleConnection(Node):
    target: str
    part: str | None


@record
class Relation(Node):
    """A containment label: ``relation e``, ``relation_flexi e`` or a bare comparison."""

    expr: Expr
    flexi: bool = False
    bare: bool = False


@record
class Equation(Node):
    expr: Expr


@record
class Constraint(Node):
    expr: Expr


@record
class Instantiation(Node):
    name: str
    value: Expr


@record
class GeomArg(Node):
    name: str
    value: Expr


@record
class Shape(Node):
    """``box(length=…, width=…, height=…)``, ``cylinder(radius=…, length=…)``, ``sphere(…)``."""

    kind: str
    args: tuple[GeomArg, ...]

    def arg(self, name: str) -> Expr | None:
        for a in self.args:
            if a.name == name:
                return a.value
        return None


@record
class Mesh(Node):
    shape: str | None
    scaling: Expr | None


@record
class InertiaEntry(Node):
    name: str  # ixx ixy ixz iyy iyz izz
    value: Expr


@record
class Inertial(Node):
    """``inertial information { mass m inertia matrix {…} pose {…} }`` (in source order)."""

    mass: Expr | None
    inertia: tuple[InertiaEntry, ...] | None
    pose: Pose | None
    order: tuple[str, ...] = ()  # the member keywords in source order, for the order check


@record
class Bounce(Node):
    restitution: Expr | None
    threshold: Expr | None


@record
class FrictionEntry(Node):
    name: str
    value: Expr


@record
class Friction(Node):
    entries: tuple[FrictionEntry, ...]


@record
class LaserRetro(Node):
    value: Expr


DefMember = Union[
    Shape, Mesh, Inertial, Bounce, Friction, LaserRetro, VarDecl, Equation, Constraint,
    Annotation, Relation,
]


class BlockKind(str, Enum):
    LINK = "link"
    BODY = "body"
    JOINT = "joint"
    SENSOR = "sensor"
    ACTUATOR = "actuator"

    @property
    def ref_keyword(self) -> str:
        return self.value[0] + "ref" if self is not BlockKind.BODY else "bref"


REF_KINDS = {"lref": BlockKind.LINK, "bref": BlockKind.BODY, "jref": BlockKind.JOINT,
             "sref": BlockKind.SENSOR, "aref": BlockKind.ACTUATOR}


@record
class DefBlock(Node):
    """The ``def { … }`` of a local block: an anonymous definition."""

    members: tuple[DefMember, ...]


@record
class Definition(Node):
    """A named package-level definition (``link Tip {}``, ``sensor IR {…}``)."""

    kind: BlockKind
    name: str
    members: tuple[DefMember, ...]


class _Members:
    """Typed views of a ``members`` tuple; shared by blocks, p-models and parts."""

    __slots__ = ()
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None

    def _view(self, cls: type[T]) -> tuple[T, ...]:
        """The members of one kind, remembered on the node: the checks ask every block of a
        model of thousands for its poses, blocks, declarations… several times over."""
        views = self._views
        if views is None:
            views = {}
            object.__setattr__(self, "_views", views)
        found = views.get(cls)
        if found is None:  # (from a list: a tuple built from a generator keeps room for 10)
            found = views[cls] = tuple([m for m in self.members if isinstance(m, cls)])
        return found

    @property
    def blocks(self) -> tuple[Block, ...]:
        return self._view(Block)

    @property
    def poses(self) -> tuple[Pose, ...]:
        return self._view(Pose)

    @property
    def pose(self) -> Pose | None:
        poses = self.poses
        return poses[0] if poses else None

    @property
    def indices(self) -> tuple[IndexDecl, ...]:
        return self._view(IndexDecl)

    @property
    def index(self) -> IndexDecl | None:
        indices = self.indices
        return indices[0] if indices else None

    @property
    def declarations(self) -> tuple[VarDecl, ...]:
        return self._view(VarDecl)

    @property
    def equations(self) -> tuple[Equation, ...]:
        return self._view(Equation)

    @property
    def instantiations(self) -> tuple[Instantiation, ...]:
        return self._view(Instantiation)

    @property
    def annotations(self) -> tuple[Annotation, ...]:
        return self._view(Annotation)

    @property
    def relations(self) -> tuple[Relation, ...]:
        return self._view(Relation)


@record
class Block(SeparatePickle, _Members, Node):
    """A link, body, joint, sensor or actuator inside a p-model: local (``local link L {…}``)
    when ``ref`` is None, a reference (``jref LHinge = Revolute {…}``) otherwise."""

    kind: BlockKind
    name: str
    ref: QName | None
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def is_local(self) -> bool:
        return self.ref is None

    @property
    def definitions(self) -> tuple[DefBlock, ...]:
        return self._view(DefBlock)

    @property
    def definition(self) -> DefBlock | None:
        defs = self.definitions
        return defs[0] if defs else None

    @property
    def fixed(self) -> tuple[FixedConnection, ...]:
        return self._view(FixedConnection)

    @property
    def flexible(self) -> tuple[FlexibleConnection, ...]:
        return self._view(FlexibleConnection)


@record
class PartFixed(Node):
    """``link L fixed to T in P`` inside a part: link L of the part's p-model is fixed to T."""

    link: str
    target: str
    part: str | None


@record
class PartFlexible(Node):
    """``joint J flexibly connected to T in P`` inside a part."""

    joint: str
    target: str
    part: str | None


@record
class Part(_Members, Node):
    name: str
    pmodel: QName
    members: tuple[object, ...]
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def fixed(self) -> tuple[PartFixed, ...]:
        return self._view(PartFixed)

    @property
    def flexible(self) -> tuple[PartFlexible, ...]:
        return self._view(PartFlexible)


@record
class SolutionInput(Node):
    name: str
    type: TypeRef


@record
class Solution(Node):
    """A generated p-model+ solution block (order of members fixed by the notation)."""

    expr_name: str
    type: TypeRef
    order: int
    group: int
    method: str
    inputs: tuple[SolutionInput, ...]
    constraints: tuple[Constraint, ...]


@record
class PModel(_Members, Node):
    """``pmodel N {…}`` or, with ``fragment`` set, ``fragment N {…}``."""

    name: str
    members: tuple[object, ...]
    fragment: bool = False
    _views: dict[type, tuple[Any, ...]] | None = field(
        default=None, init=False, repr=False, compare=False)

    @property
    def parts(self) -> tuple[Part, ...]:
        return self._view(Part)
