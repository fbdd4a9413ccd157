"""What may appear where: the grammar accepts any member in any block so that misplaced ones get
a diagnostic naming the block (``E-MEMBER``), not a bare parse error.

Block-in-block containment (a link inside a link, anything inside a body) is left to the
well-formedness conditions L5 and L7, which the paper states for exactly that purpose.
"""

from __future__ import annotations

from typing import Iterable

from cyphy import codes
from cyphy.diagnostics import Report
from cyphy.lang import ast

K = ast.BlockKind

_BLOCK_MEMBERS: dict[K, tuple[type, ...]] = {
    K.LINK: (ast.Pose, ast.IndexDecl, ast.DefBlock, ast.Block, ast.FixedConnection,
             ast.Relation, ast.VarDecl, ast.Equation, ast.Constraint),
    K.BODY: (ast.Pose, ast.IndexDecl, ast.DefBlock, ast.Block, ast.Relation, ast.VarDecl),
    K.JOINT: (ast.Pose, ast.IndexDecl, ast.DefBlock, ast.Block, ast.FlexibleConnection,
              ast.Instantiation, ast.Annotation, ast.Relation, ast.VarDecl, ast.Equation,
              ast.Constraint),
    K.SENSOR: (ast.Pose, ast.IndexDecl, ast.DefBlock, ast.Block, ast.Annotation, ast.Relation,
               ast.Instantiation, ast.VarDecl, ast.Equation, ast.Constraint),
    K.ACTUATOR: (ast.Pose, ast.IndexDecl, ast.DefBlock, ast.Block, ast.Annotation, ast.Relation,
                 ast.Instantiation, ast.VarDecl, ast.Equation, ast.Constraint),
}

_DEVICE_DEF = (ast.VarDecl, ast.Equation, ast.Constraint, ast.Annotation, ast.Relation)
_DEF_MEMBERS: dict[K, tuple[type, ...]] = {
    K.LINK: (ast.Inertial, ast.VarDecl, ast.Equation, ast.Constraint, ast.Relation),
    K.BODY: (ast.Shape, ast.Mesh, ast.Inertial, ast.Bounce, ast.Friction, ast.LaserRetro,
             ast.VarDecl, ast.Relation),
    K.JOINT: _DEVICE_DEF,
    K.SENSOR: _DEVICE_DEF,
    K.ACTUATOR: _DEVICE_DEF,
}

_PMODEL_MEMBERS = (ast.Block, ast.Part, ast.VarDecl, ast.Equation, ast.Constraint, ast.Solution,
                   ast.Relation)

SHAPE_ARGS = {
    "box": ("length", "width", "height"),
    "cylinder": ("radius", "length"),
    "sphere": ("radius",),
}
INERTIA_ENTRIES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")

_MEMBER_NAMES = {
    ast.Pose: "a pose", ast.IndexDecl: "an index", ast.DefBlock: "a def block",
    ast.FixedConnection: "a fixed connection", ast.FlexibleConnection: "a flexible connection",
    ast.Instantiation: "an instantiation", ast.Annotation: "an annotation",
    ast.Relation: "a relation", ast.VarDecl: "a declaration", ast.Equation: "an equation",
    ast.Constraint: "a Constraint", ast.Part: "a part", ast.Solution: "a solution",
    ast.Shape: "a geometry", ast.Mesh: "a mesh", ast.Inertial: "inertial information",
    ast.Bounce: "bounce", ast.Friction: "friction", ast.LaserRetro: "laser retro",
}


def _what(member: object) -> str:
    if isinstance(member, ast.Block):
        return f"{member.kind.value} {member.name}"
    return _MEMBER_NAMES.get(type(member), type(member).__name__)


def check_placement(files: Iterable[ast.SourceFile], report: Report) -> None:
    for file in files:
        for item in file.items:
            if isinstance(item, ast.PModel):
                _pmodel(item, report)
            elif isinstance(item, ast.Definition):
                _def_members(item.kind, item.members, f"{item.kind.value} definition {item.name}",
                             report)


def _misplaced(member: object, where: str, report: Report, hint: str = "") -> None:
    span = getattr(member, "span")
    report.report(codes.MEMBER, f"{_what(member)} cannot appear in {where}", span,
                  hint or "move it to a block that can hold it, or remove it")


def _pmodel(pm: ast.PModel, report: Report) -> None:
    where = f"{'fragment' if pm.fragment else 'p-model'} {pm.name}"
    for m in pm.members:
        if isinstance(m, ast.Relation) and m.bare:
            _misplaced(m, where, report, "write 'relation' before it, inside the block it labels")
        elif not isinstance(m, _PMODEL_MEMBERS):
            _misplaced(m, where, report)
        elif isinstance(m, ast.Block):
            _block(m, report)
        elif isinstance(m, ast.Part):
            _once(m.poses, "pose", f"part {m.name}", report)
            _once(m.indices, "index", f"part {m.name}", report)


def _block(block: ast.Block, report: Report) -> None:
    where = f"{block.kind.value} {block.name}"
    allowed = _BLOCK_MEMBERS[block.kind]
    for m in block.members:
        if isinstance(m, ast.Relation) and m.bare and not (
                block.ref is not None and block.kind in (K.SENSOR, K.ACTUATOR)):
            _misplaced(m, where, report, "a relation without the keyword 'relation' is only "
                       "allowed in sref and aref blocks: write 'relation …'")
        elif not isinstance(m, allowed):
            _misplaced(m, where, report)
        elif isinstance(m, ast.Block):
            _block(m, report)
    if block.ref is not None:
        for d in block.definitions:
            _misplaced(d, f"reference {where}", report,
                       f"a {block.kind.ref_keyword} takes its definition from "
                       f"{'::'.join(block.ref)}; set values with 'instantiation' instead")
    _once(block.definitions, "def", where, report)
    _once(block.poses, "pose", where, report)
    _once(block.indices, "index", where, report)
    for d in block.definitions:
        _def_members(block.kind, d.members, f"the definition of {where}", report)


def _once(items: tuple[object, ...], what: str, where: str, report: Report) -> None:
    for extra in items[1:]:
        report.report(codes.DUPLICATE_MEMBER, f"{where} has more than one {what}",
                      getattr(extra, "span"), f"merge the {what} blocks into one")


def _def_members(kind: K, members: Iterable[object], where: str, report: Report) -> None:
    members = list(members)
    allowed = _DEF_MEMBERS[kind]
    for m in members:
        if isinstance(m, (ast.Shape, ast.Mesh)) and not isinstance(m, allowed):
            _misplaced(m, where, report, "a geometry belongs to a body: put it in "
                       "'local body B { def { … } }' inside the link")
        elif not isinstance(m, allowed):
            _misplaced(m, where, report)
        elif isinstance(m, ast.Shape):
            _shape(m, report)
        elif isinstance(m, ast.Inertial):
            _inertial(m, report)
    geometry = [m for m in members if isinstance(m, (ast.Shape, ast.Mesh))]
    for extra in geometry[1:]:
        report.report(codes.DUPLICATE_MEMBER, f"{where} has more than one geometry",
                      extra.span, "a body has one shape; use several bodies for more")
    inertials = [m for m in members if isinstance(m, ast.Inertial)]
    for extra in inertials[1:]:
        report.report(codes.DUPLICATE_MEMBER, f"{where} has more than one inertial information",
                      extra.span, "merge them into one")


def _shape(shape: ast.Shape, report: Report) -> None:
    expected = SHAPE_ARGS[shape.kind]
    given = [a.name for a in shape.args]
    form = f"{shape.kind}({', '.join(n + '=…' for n in expected)})"
    for a in shape.args:
        if a.name not in expected:
            report.report(codes.MEMBER, f"{shape.kind} has no argument '{a.name}'", a.span,
                          f"write {form}")
        elif given.count(a.name) > 1 and given.index(a.name) != shape.args.index(a):
            report.report(codes.DUPLICATE_MEMBER, f"{shape.kind} argument '{a.name}' is given "
                          "twice", a.span, f"write {form}")
    missing = [n for n in expected if n not in given]
    if missing:
        report.report(codes.MEMBER, f"{shape.kind} lacks {', '.join(missing)}", shape.span,
                      f"write {form}")


def _inertial(inertial: ast.Inertial, report: Report) -> None:
    if inertial.mass is None:
        report.report(codes.MEMBER, "inertial information without a mass", inertial.span,
                      "start it with 'mass <value>'")
    canonical = [k for k in ("mass", "inertia", "pose") if k in inertial.order]
    if list(dict.fromkeys(inertial.order)) != canonical:
        report.report(codes.ORDER, "inertial information lists "
                      f"{', '.join(inertial.order)}; RoboTool expects mass, inertia matrix, pose",
                      inertial.span, "reorder the members: mass, inertia matrix, pose")
    if inertial.inertia is not None:
        names = [e.name for e in inertial.inertia]
        for e in inertial.inertia:
            if e.name not in INERTIA_ENTRIES:
                report.report(codes.MEMBER, f"inertia matrix has no entry '{e.name}'", e.span,
                              "entries are " + " ".join(INERTIA_ENTRIES))
        missing = [n for n in INERTIA_ENTRIES if n not in names]
        if missing:
            report.report(codes.MEMBER, f"inertia matrix lacks {', '.join(missing)}",
                          inertial.span, "give all six: " + " ".join(INERTIA_ENTRIES))
