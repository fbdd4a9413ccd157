"""The rules of p-models: blocks and their members, parts, connections, solutions."""

from __future__ import annotations

from typing import Any

from lark import Token

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Diagnostic, did_you_mean
from cyphy.lang import ast
from cyphy.lang.builder.base import BuilderBase, Tagged, name_of, text_of, unescape
from cyphy.lang.reductions import Pos

POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")


class PModelRules(BuilderBase):
    """Methods of the p-model rules."""

    def pmodel(self, pos: Pos, c: list[Any]) -> ast.PModel:
        return ast.PModel(name_of(c[0]), self._flat(c[1:]), False, span=self._span(pos))

    def fragment(self, pos: Pos, c: list[Any]) -> ast.PModel:
        return ast.PModel(name_of(c[0]), self._flat(c[1:]), True, span=self._span(pos))

    def block_kind(self, pos: Pos, c: list[Token]) -> ast.BlockKind:
        return ast.BlockKind(str(c[0]))

    def ref_kind(self, pos: Pos, c: list[Token]) -> ast.BlockKind:
        return ast.REF_KINDS[str(c[0])]

    def definition(self, pos: Pos, c: list[Any]) -> ast.Definition:
        return ast.Definition(c[0], name_of(c[1]), self._flat(c[2:]), span=self._span(pos))

    def local_block(self, pos: Pos, c: list[Any]) -> ast.Block:
        return ast.Block(c[0], name_of(c[1]), None, self._flat(c[2:]), span=self._span(pos))

    def ref_block(self, pos: Pos, c: list[Any]) -> ast.Block:
        kind, name, target, *members = c
        return ast.Block(kind, name_of(name), target.parts, self._flat(members),
                         span=self._span(pos))

    def def_block(self, pos: Pos, c: list[Any]) -> ast.DefBlock:
        return ast.DefBlock(self._flat(c), span=self._span(pos))

    def equation(self, pos: Pos, c: list[Any]) -> ast.Equation:
        return ast.Equation(c[0], span=self._span(pos))

    def constraint(self, pos: Pos, c: list[Any]) -> ast.Constraint:
        return ast.Constraint(c[0], span=self._span(pos))

    def relation(self, pos: Pos, c: list[Any]) -> ast.Relation:
        return ast.Relation(c[0], span=self._span(pos))

    def relation_flexi(self, pos: Pos, c: list[Any]) -> ast.Relation:
        return ast.Relation(c[0], flexi=True, span=self._span(pos))

    def bare_relation(self, pos: Pos, c: list[Any]) -> ast.Relation:
        span = self._span(pos)
        return ast.Relation(ex.BinOp(c[1], c[0], c[2], span=span), bare=True, span=span)

    def instantiation(self, pos: Pos, c: list[Any]) -> ast.Instantiation:
        return ast.Instantiation(name_of(c[0]), c[1], span=self._span(pos))

    def fixed(self, pos: Pos, c: list[Any]) -> ast.FixedConnection:
        return ast.FixedConnection(name_of(c[0]), name_of(c[1]) if c[1] else None,
                                   span=self._span(pos))

    def flexible(self, pos: Pos, c: list[Any]) -> ast.FlexibleConnection:
        return ast.FlexibleConnection(name_of(c[0]), name_of(c[1]) if c[1] else None,
                                      span=self._span(pos))

    def part(self, pos: Pos, c: list[Any]) -> ast.Part:
        name, target, *members = c
        return ast.Part(name_of(name), target.parts, self._flat(members), span=self._span(pos))

    def part_fixed(self, pos: Pos, c: list[Any]) -> ast.PartFixed:
        return ast.PartFixed(name_of(c[0]), name_of(c[1]), name_of(c[2]) if c[2] else None,
                             span=self._span(pos))

    def part_flexible(self, pos: Pos, c: list[Any]) -> ast.PartFlexible:
        return ast.PartFlexible(name_of(c[0]), name_of(c[1]), name_of(c[2]) if c[2] else None,
                                span=self._span(pos))

    def pose(self, pos: Pos, c: list[Any]) -> ast.Pose:
        return ast.Pose(tuple(c), span=self._span(pos))

    def pose_field(self, pos: Pos, c: list[Any]) -> ast.PoseField:
        key, span = name_of(c[0]), self._span(pos)
        if key not in POSE_KEYS:
            self.diagnostics.append(Diagnostic(
                codes.MEMBER, f"a pose has no field '{key}'", self._tok_span(c[0]),
                (did_you_mean(key, POSE_KEYS) + " ").lstrip()
                + "the fields are " + ", ".join(POSE_KEYS)))
        return ast.PoseField(key, c[1], span=span)

    def index(self, pos: Pos, c: list[Any]) -> ast.IndexDecl:
        return ast.IndexDecl(name_of(c[0]), c[1], c[2], c[3], span=self._span(pos))

    def half_open(self, pos: Pos, c: list[Any]) -> bool:
        return False

    def closed(self, pos: Pos, c: list[Any]) -> bool:
        return True

    # ----- body properties
    def shape_kind(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    def shape(self, pos: Pos, c: list[Any]) -> ast.Shape:
        return ast.Shape(c[0], self._flat(c[1:]), span=self._span(pos))

    def geom_arg(self, pos: Pos, c: list[Any]) -> ast.GeomArg:
        return ast.GeomArg(name_of(c[0]), c[1], span=self._span(pos))

    def mesh_shape(self, pos: Pos, c: list[Token]) -> Tagged:
        return Tagged("shape", unescape(str(c[0])), self._span(pos))

    def mesh_scaling(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("scaling", c[0], self._span(pos))

    def mesh(self, pos: Pos, c: list[Tagged]) -> ast.Mesh:
        span = self._span(pos)
        values: dict[str, Any] = {}
        for t in c:
            if t.tag in values:
                self._duplicate(t.tag, "mesh", t.span)
            values.setdefault(t.tag, t.value)
        return ast.Mesh(values.get("shape"), values.get("scaling"), span=span)

    def mass(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("mass", c[0], self._span(pos))

    def inertia_matrix(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("inertia", tuple(c), self._span(pos))

    def inertia_entry(self, pos: Pos, c: list[Any]) -> ast.InertiaEntry:
        return ast.InertiaEntry(name_of(c[0]), c[1], span=self._span(pos))

    def inertial(self, pos: Pos, c: list[Any]) -> ast.Inertial:
        values: dict[str, Any] = {}
        order = []
        for item in c:
            tag, value, span = (("pose", item, item.span) if isinstance(item, ast.Pose)
                                else (item.tag, item.value, item.span))
            if tag in values:
                self._duplicate(tag, "inertial information", span)
            values.setdefault(tag, value)
            order.append(tag)
        return ast.Inertial(values.get("mass"), values.get("inertia"), values.get("pose"),
                            tuple(order), span=self._span(pos))

    def restitution(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("restitution", c[0], self._span(pos))

    def threshold(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("threshold", c[0], self._span(pos))

    def bounce(self, pos: Pos, c: list[Tagged]) -> ast.Bounce:
        values = {t.tag: t.value for t in c}
        return ast.Bounce(values.get("restitution"), values.get("threshold"),
                          span=self._span(pos))

    def friction_entry(self, pos: Pos, c: list[Any]) -> ast.FrictionEntry:
        return ast.FrictionEntry(name_of(c[0]), c[1], span=self._span(pos))

    def friction(self, pos: Pos, c: list[Any]) -> ast.Friction:
        return ast.Friction(tuple(c), span=self._span(pos))

    def laser_retro(self, pos: Pos, c: list[Any]) -> ast.LaserRetro:
        return ast.LaserRetro(c[0], span=self._span(pos))

    # ----- solutions
    def solution(self, pos: Pos, c: list[Any]) -> ast.Solution:
        name, type_, order, group, method, *rest = c
        return ast.Solution(
            name_of(name), type_, int(str(order).split(".")[0]), int(str(group).split(".")[0]),
            name_of(method),
            tuple(x for x in rest if isinstance(x, ast.SolutionInput)),
            tuple(x for x in rest if isinstance(x, ast.Constraint)),
            span=self._span(pos),
        )

    def solution_input(self, pos: Pos, c: list[Any]) -> ast.SolutionInput:
        return ast.SolutionInput(name_of(c[0]), c[1], span=self._span(pos))

    # ----- mappings
