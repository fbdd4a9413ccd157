"""Elaboration: from the resolved syntax tree to the :class:`ElaboratedModel`.

One walk over the chosen p-model instantiates parts (their constants bound by
``instantiation``, evaluated in the container's scope), replicates indexed blocks once per
index value, merges references with their definitions, evaluates constants (lazily, so
constants may use one another) and composes poses innermost first. Connections are resolved in
a second pass, once every link instance exists, because a joint may point into a part declared
after it, and a part may connect a joint of its own p-model (``joint J flexibly connected to
…``).
"""

from __future__ import annotations

import math

from collections.abc import Iterator, Mapping
from dataclasses import field, replace
from typing import Any

from cyphy import codes, collector, progress
from cyphy import expr as ex
from cyphy.diagnostics import Report, Span
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.workspace import Workspace
from cyphy.limits import max_copies
from cyphy.model import inertia as inertia_math
from cyphy.model.body_inertia import distribute_mass, solid_inertia
from cyphy.model.choose import choose_pmodel
from cyphy.model.device_names import RelationSites, name_devices
from cyphy.model.elements import (
    Actuator, AnnotationValue, Body, Device, ElaboratedModel, FixedJoint, Joint, Link, Port,
    Sensor,
)
from cyphy.model.environment import EVAL, Binding, Context, Env
from cyphy.model.evaluate import Value
from cyphy.model.poses import Pose
from cyphy.records import record

INDEX = codes.code("E-INDEX", codes.E, "an index range that is not a range of integers")

DEVICE_KINDS = (ast.DeclKind.INPUT, ast.DeclKind.OUTPUT, ast.DeclKind.INOUT,
                ast.DeclKind.LOCAL, ast.DeclKind.CONST)
POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")


@record(frozen=False, slots=False)
class _Instance:
    """One instance of a p-model (the top model or a part copy) and its links and parts."""

    prefix: tuple[str, ...]
    pmodel: ast.PModel
    file: ast.SourceFile
    env: Env
    frame: Pose | None
    links: dict[str, list[Link]] = field(default_factory=dict)
    parts: dict[str, list[_Instance]] = field(default_factory=dict)
    joint_clauses: dict[str, ast.PartFlexible] = field(default_factory=dict)
    container: _Instance | None = None
    index: dict[str, int] = field(default_factory=dict)  # a part copy's index values


@record(frozen=False, slots=False)
class _PendingJoint:
    prototype: Joint
    block: ast.Block
    target: str | None
    part: str | None
    instance: _Instance  # where the target is looked up



# --------------------------------------------------------------------------- elaboration


def elaborate(ws: Workspace, resolution: Resolution, report: Report, model: str | None = None,
              consts: Mapping[str, Value] | None = None, strict_consts: bool = True
              ) -> ElaboratedModel | None:
    """Elaborate one p-model of the workspace (see :func:`choose_pmodel`)."""
    chosen = choose_pmodel(ws, model, report)
    if chosen is None:
        return None
    return elaborate_pmodel(ws, resolution, report, *chosen, consts,
                            strict_consts=strict_consts)


def elaborate_pmodel(ws: Workspace, resolution: Resolution, report: Report, pm: ast.PModel,
                     file: ast.SourceFile, consts: Mapping[str, Value] | None = None,
                     devices: bool = True, strict_consts: bool = True) -> ElaboratedModel:
    """Elaborate the given p-model (as the top-level model) of ``file``. Without
    ``devices`` the model has links, bodies, joints (with their axes and annotations) and
    their values, but no sensors, actuators, devices, equations or relations: the value
    checks need geometry, not behaviour, and devices are most of the work on a large
    model."""
    ctx = Context(ws, resolution, report, consts or {})
    reported: set[str] = set()
    if consts:  # a misspelt --const would be ignored, and the constant stay without a value
        # lazy: reading --const values needs the parser (Lark), a warm cache does not
        from cyphy.model.constants import declared_constants, unknown_constants

        for key, hint in unknown_constants(consts, declared_constants(ws.files.values())):
            report.report(codes.OPTION, f"--const {key}: the model has no constant {key!r}",
                          Span.unknown("<command line>"), hint)
            reported.add(key)
    with collector.paused():  # see cyphy/collector.py
        model = _Elaborator(ctx, devices).run(pm, file)
    if devices:
        ctx.report_instantiated()
    if devices and strict_consts:  # the whole model: every constant it declares was seen
        # a name no file declares is reported once, above; this adds those of other models
        ctx.report_unknown_consts(pm.span, frozenset(reported))
    return model


class _Elaborator:
    def __init__(self, ctx: Context, devices: bool = True) -> None:
        self.ctx = ctx
        self.devices = devices
        self.model: ElaboratedModel
        self.pending: list[_PendingJoint] = []
        self.pending_fixed: list[tuple[Link, str, str | None, _Instance, Span]] = []
        self.device_names: list[tuple[Device, tuple[str, ...]]] = []
        self.index_values: dict[int, dict[str, int]] = {}
        self.literal_annotations: dict[  # instance, first value, literal only (None: unknown)
            int, tuple[ast.TemplateInstance, AnnotationValue, bool | None]] = {}
        self.relation_queue: list[tuple[ex.Expr, ast.Block, Device | None,
                                        dict[str, int]]] = []
        self.sites = RelationSites()  # without devices: E-RELATION from names alone
        self.copies = 0  # of indexed blocks and parts, against limits.max_copies()
        self.part_index: dict[int, dict[int, dict[str, int]]] = {}  # see _target_values
        self.too_many = False

    def run(self, pm: ast.PModel, file: ast.SourceFile) -> ElaboratedModel:
        self.model = ElaboratedModel(pm.name, pm)
        top = self._instance((pm.name,), pm, file, Pose.identity(), None, {})
        progress.step(f"{len(self.model.links)} links: connecting the joints")
        self._connect(top)
        if self.devices:
            progress.step(f"{len(self.model.links)} links: naming the devices")
            name_devices(self.model, self.device_names, self.index_values,
                         self.relation_queue, self.ctx.report)
        else:
            self.sites.check(self.ctx.report, self._has_device)
        self.model.constants = dict(sorted(self.ctx.constants.items()))
        self.model.missing = dict(sorted(self.ctx.missing.items()))
        return self.model

    # ----- p-model instances and parts
    def _pmodel_env(self, pm: ast.PModel, file: ast.SourceFile,
                    prefix: tuple[str, ...], overrides: dict[str, tuple[ex.Expr, Env]]) -> Env:
        env = Env(self.ctx, file)  # a part sees its own package's constants, not the container's
        names: dict[str, Binding | Value] = {}
        for d in pm.declarations:
            if d.kind is ast.DeclKind.CONST:
                expr, oenv = overrides.get(d.name, (None, None))
                names[d.name] = self.ctx.binding(d, None, "::".join(prefix + (d.name,)),
                                                 f"{pm.name}::{d.name}", expr, oenv)
        pm_env = env.child(names)
        for b in names.values():
            if isinstance(b, Binding) and b.env is None and b.expr is not None:
                b.env = pm_env
        return pm_env

    def _instance(self, prefix: tuple[str, ...], pm: ast.PModel, file: ast.SourceFile,
                  frame: Pose | None, container: _Instance | None,
                  overrides: dict[str, tuple[ex.Expr, Env]],
                  clauses: tuple[ast.PartFlexible, ...] = ()) -> _Instance:
        env = self._pmodel_env(pm, file, prefix, overrides)
        inst = _Instance(prefix, pm, file, env, frame, container=container)
        # `part p = P { joint J flexibly connected to … }`: known before P's joints are made
        inst.joint_clauses = {c.joint: c for c in clauses}
        for m in pm.members:
            if isinstance(m, ast.Part):
                self._part(m, inst)
            elif isinstance(m, ast.Block) and m.kind is ast.BlockKind.LINK:
                for values, link_env in self._copies(m, env):
                    self._link(m, inst, values, link_env)
        for m in pm.members:
            if not isinstance(m, ast.Block):
                continue
            if m.kind is ast.BlockKind.JOINT:  # p-model+ files (Pendulum.pm)
                for values, joint_env in self._copies(m, env):
                    self._joint(m, None, inst, values, joint_env, prefix)
            elif m.kind in (ast.BlockKind.SENSOR, ast.BlockKind.ACTUATOR):  # fragments
                for values, block_env in self._copies(m, env):
                    self._device_block(m, None, None, values, block_env,
                                       inst.frame or Pose.identity(), prefix)
        return inst

    def _part(self, part: ast.Part, inst: _Instance) -> None:
        target = self.ctx.resolution.get(part)
        if not isinstance(target, ast.PModel):
            return
        target_file = self.ctx.file_of.get(id(target), inst.file)
        copies = []
        for values, env in self._copies(part, inst.env):
            # A fragment is inlined: its elements belong to the container, under its names.
            prefix = inst.prefix if target.fragment else (
                inst.prefix + (part.name,) + tuple(str(v) for v in values.values()))
            overrides = {i.name: (i.value, env) for i in part.instantiations}
            local = self._pose(part.pose, env)
            frame = inst.frame.compose(local) if inst.frame and local else None
            sub = self._instance(prefix, target, target_file, frame, inst, overrides,
                                 part.flexible)
            sub.index = dict(values)
            for clause in part.fixed:
                for link in sub.links.get(clause.link, []):
                    self.pending_fixed.append((link, clause.target, clause.part, inst,
                                               clause.span))
            copies.append(sub)
        inst.parts[part.name] = copies

    def _copies(self, node: ast.Block | ast.Part, env: Env
                ) -> Iterator[tuple[dict[str, int], Env]]:
        """One (index values, env) per copy of an indexed block; one copy otherwise."""
        index = node.index
        if index is None:
            yield {}, env
            return
        lo = self.ctx.evaluate(index.lower, env)
        hi = self.ctx.evaluate(index.upper, env)
        if lo is None or hi is None:
            return
        if not all(isinstance(v, int) and not isinstance(v, bool) for v in (lo, hi)):
            self.ctx.report.report(INDEX, f"index {index.var} of {node.name} ranges over "
                                   f"[{lo}, {hi}{']' if index.closed else ')'}, not integers",
                                   index.span, "use integer bounds")
            return
        count = max(0, hi - lo + (1 if index.closed else 0))  # type: ignore[operator]
        if self.copies + count > max_copies():
            if not self.too_many:
                self.too_many = True
                self.ctx.report.report(INDEX, f"index {index.var} of {node.name} would make "
                                       f"{self.copies + count} copies in all, more than the "
                                       f"limit of {max_copies()}", index.span,
                                       "use smaller ranges, or raise the limit with "
                                       "--max-copies N")
            return
        self.copies += count
        for v in range(lo, hi + 1 if index.closed else hi):  # type: ignore[operator]
            yield {index.var: v}, env.child({index.var: v})

    # ----- blocks
    def _qname(self, base: tuple[str, ...], block: ast.Block, values: dict[str, int]
               ) -> tuple[str, ...]:
        return base + (block.name,) + tuple(str(v) for v in values.values())

    def _definition(self, block: ast.Block) -> ast.Definition | None:
        target = self.ctx.resolution.get(block)
        return target if isinstance(target, ast.Definition) else None

    def _members(self, block: ast.Block) -> list[Any]:
        """The definition's members: the referenced definition's, then the local def's."""
        out: list[Any] = []
        definition = self._definition(block)
        if definition is not None:
            out.extend(definition.members)
        for d in block.definitions:
            out.extend(d.members)
        return out

    def _block_env(self, block: ast.Block, env: Env, qname: tuple[str, ...]) -> Env:
        """The block's constants: its definition's, overridden by its instantiations
        (evaluated in the container's scope)."""
        definition = self._definition(block)
        def_name = definition.name if definition is not None else block.name
        overrides = {i.name: i.value for i in block.instantiations}
        names: dict[str, Binding | Value] = {}
        for m in self._members(block) + list(block.declarations):
            if isinstance(m, ast.VarDecl) and m.kind is ast.DeclKind.CONST:
                names[m.name] = self.ctx.binding(
                    m, None, "::".join(qname + (m.name,)), f"{def_name}::{m.name}",
                    overrides.get(m.name), env if m.name in overrides else None)
        block_env = env.child(names)
        for b in names.values():
            if isinstance(b, Binding) and b.env is None:
                b.env = block_env
        return block_env

    def _link(self, block: ast.Block, inst: _Instance, values: dict[str, int], env: Env
              ) -> None:
        qname = self._qname(inst.prefix, block, values)
        env = self._block_env(block, env, qname)
        local = self._pose(block.pose, env)
        link = Link(qname, block.span, dict(values))
        link.pose = inst.frame.compose(local) if inst.frame and local else None
        inst.links.setdefault(block.name, []).append(link)
        self.model.links.append(link)
        progress.step(f"{len(self.model.links)} links")  # a 90,000-link model takes a while
        for child in block.blocks:
            for cvalues, cenv in self._copies(child, env):
                if child.kind is ast.BlockKind.BODY:
                    self._body(child, link, cvalues, cenv)
                elif child.kind in (ast.BlockKind.SENSOR, ast.BlockKind.ACTUATOR):
                    self._device_block(child, link, None, cvalues, cenv, Pose.identity(),
                                       qname)
                elif child.kind is ast.BlockKind.JOINT:
                    self._joint(child, link, inst, cvalues, cenv, qname)
        for fixed in block.fixed:
            self.pending_fixed.append((link, fixed.target, fixed.part, inst, fixed.span))
        self._link_inertial(block, link, env)

    def _body(self, block: ast.Block, link: Link, values: dict[str, int], env: Env) -> None:
        qname = self._qname(link.qname, block, values)
        env = self._block_env(block, env, qname)
        body = Body(qname, block.span, dict(values), link=link)
        body.pose = self._pose(block.pose, env)
        for m in self._members(block):
            if isinstance(m, ast.Shape):
                body.geometry = m
                body.size = {a.name: self.ctx.evaluate(a.value, env) for a in m.args}
            elif isinstance(m, ast.Mesh):
                body.geometry = m
                body.mesh_uri = m.shape
                body.size = {"scaling": self.ctx.evaluate(m.scaling, env)}
            elif isinstance(m, ast.Inertial):
                body.inertial = self._inertial(m, env, body)
            elif isinstance(m, ast.Bounce):
                body.surface["restitution_coefficient"] = self.ctx.evaluate(m.restitution, env)
                body.surface["threshold"] = self.ctx.evaluate(m.threshold, env)
            elif isinstance(m, ast.Friction):
                for entry in m.entries:
                    body.surface[entry.name] = self.ctx.evaluate(entry.value, env)
            elif isinstance(m, ast.LaserRetro):
                body.surface["laser_retro"] = self.ctx.evaluate(m.value, env)
        link.bodies.append(body)
        self.model.bodies.append(body)

    def _inertial(self, m: ast.Inertial, env: Env, body: Body | None
                  ) -> inertia_math.Inertial | None:
        # All evaluated before any is found missing (see _pose).
        mass = self.ctx.evaluate(m.mass, env)
        com = self._pose(m.pose, env) if m.pose is not None else Pose.identity()
        entries = {e.name: self.ctx.evaluate(e.value, env) for e in m.inertia or ()}
        if not isinstance(mass, (int, float)) or isinstance(mass, bool) or com is None:
            return None
        if m.inertia is not None:
            values = [entries.get(k) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
            if any(not isinstance(v, (int, float)) for v in values):
                return None
            return inertia_math.Inertial(float(mass), com, tuple(float(v) for v in values))
        solid = solid_inertia(body, float(mass)) if body is not None else None
        if solid is None:
            return inertia_math.Inertial(float(mass), com, (0.0,) * 6)
        if not all(math.isfinite(v) for v in solid):
            assert body is not None
            self.ctx.report.report(EVAL, f"the inertia of body {body.name} (mass {mass:g}, "
                                   "from its size) is not a finite number (overflow)", m.span,
                                   "give the body a size and mass of a physical object")
            return None
        return inertia_math.Inertial(float(mass), com, solid)

    def _link_inertial(self, block: ast.Block, link: Link, env: Env) -> None:
        own = [m for m in self._members(block) if isinstance(m, ast.Inertial)]
        if own:
            inertial = self._inertial(own[0], env, None)
            if inertial is not None and inertial.inertia == (0.0,) * 6 and link.bodies \
                    and inertial.mass > 0:
                inertial = distribute_mass(inertial, link.bodies) or inertial
            link.inertial, link.inertial_source = inertial, "link"
            return
        parts = []
        for body in link.bodies:
            if body.inertial is None or body.pose is None:
                continue
            parts.append(replace(body.inertial, com=body.pose.compose(body.inertial.com)))
        if parts and all(p.mass > 0 for p in parts):  # V1 reports non-positive masses
            link.inertial, link.inertial_source = inertia_math.combine(parts), "bodies"

    # ----- devices: joints, sensors, actuators
    def _device_block(self, block: ast.Block, link: Link | None, joint: Joint | None,
                      values: dict[str, int], env: Env, frame: Pose, base: tuple[str, ...]
                      ) -> Sensor | None:
        qname = self._qname(base, block, values)
        if not self.devices:  # only the names its relations need
            self._relations(block, None, env, values, qname)
            return None
        env = self._block_env(block, env, qname)
        cls = Sensor if block.kind is ast.BlockKind.SENSOR else Actuator
        element = cls(qname, block.span, dict(values), link=link, joint=joint)
        local = self._pose(block.pose, env)
        element.pose = frame.compose(local) if local is not None else None
        element.annotation = self._annotation(block, env)
        element.device = self._device(block, env, qname, values)
        definition = self._definition(block)
        element.definition = definition.name if definition is not None else None
        self._relations(block, element.device, env, values, qname)
        owner: Joint | Link | None = joint or link
        if isinstance(element, Actuator):
            if owner is not None:
                owner.actuators.append(element)
            self.model.actuators.append(element)
        else:
            if owner is not None:
                owner.sensors.append(element)
            self.model.sensors.append(element)
        return element

    def _joint(self, block: ast.Block, link: Link | None, inst: _Instance,
               values: dict[str, int], env: Env, base: tuple[str, ...]) -> None:
        qname = self._qname(base, block, values)
        env = self._block_env(block, env, qname)
        joint = Joint(qname, block.span, dict(values), parent=link)
        joint.local_pose = self._pose(block.pose, env)
        joint.annotation = self._annotation(block, env)
        joint.device = self._device(block, env, qname, values) if self.devices else None
        definition = self._definition(block)
        joint.definition = definition.name if definition is not None else None
        joint.axis = self._axis(block, env)
        self._relations(block, joint.device, env, values, qname)
        frame = joint.local_pose or Pose.identity()
        for child in block.blocks:
            if child.kind in (ast.BlockKind.SENSOR, ast.BlockKind.ACTUATOR) and link:
                for cvalues, cenv in self._copies(child, env):
                    self._device_block(child, link, joint, cvalues, cenv, frame, qname)
        connections = block.flexible
        if connections:
            for c in connections:
                self.pending.append(_PendingJoint(joint, block, c.target, c.part, inst))
        elif block.name in inst.joint_clauses and inst.container is not None:
            clause = inst.joint_clauses[block.name]
            self.pending.append(_PendingJoint(joint, block, clause.target, clause.part,
                                              inst.container))
        else:
            self.pending.append(_PendingJoint(joint, block, None, None, inst))

    def _port_declarations(self, block: ast.Block) -> list[ast.VarDecl]:
        return [m for m in self._members(block) + list(block.declarations)
                if isinstance(m, ast.VarDecl) and m.kind in DEVICE_KINDS]

    def _port_value(self, d: ast.VarDecl, env: Env) -> Value | None:
        return env[d.name] if d.kind is ast.DeclKind.CONST and d.name in env else None

    def _axis(self, block: ast.Block, env: Env) -> Value | None:
        """The value of the joint's ``AXIS`` constant (its device's ``AXIS`` port), if any."""
        for d in self._port_declarations(block):
            if d.name == "AXIS":
                return self._port_value(d, env)
        return None

    def _device(self, block: ast.Block, env: Env, qname: tuple[str, ...],
                values: dict[str, int]) -> Device | None:
        decls = self._port_declarations(block)
        equations = [m.expr for m in self._members(block) + list(block.equations)
                     if isinstance(m, ast.Equation)]
        constraints = [m.expr for m in self._members(block) if isinstance(m, ast.Constraint)]
        if not decls and not equations:
            return None
        ports = []
        for d in decls:
            ports.append(Port(d.name, d.kind, d.type, d.name, self._port_value(d, env),
                              d.value if d.kind is not ast.DeclKind.CONST else None))
        device = Device("", tuple(ports), tuple(equations), tuple(constraints))
        self.device_names.append((device, qname))
        self.index_values[id(device)] = values
        return device

    def _relations(self, block: ast.Block, device: Device | None, env: Env,
                   values: dict[str, int], qname: tuple[str, ...]) -> None:
        if not self.devices:
            self.sites.add(qname, block)
            return
        for rel in block.relations:
            self.relation_queue.append((rel.expr, block, device, values))

    def _has_device(self, block: ast.Block) -> bool:
        """Whether :meth:`_device` makes a device of the block (ports or equations)."""
        return bool(self._port_declarations(block)) or any(
            isinstance(m, ast.Equation) for m in self._members(block) + list(block.equations))

    def _annotation(self, block: ast.Block, env: Env) -> AnnotationValue | None:
        """The block's own annotation wins over its definition's (sdf-robotool.md 1.4)."""
        own = list(block.annotations) + [m for d in block.definitions for m in d.members
                                         if isinstance(m, ast.Annotation)]
        definition = self._definition(block)
        inherited = [m for m in (definition.members if definition else ())
                     if isinstance(m, ast.Annotation)]
        chosen = (own or inherited or [None])[0]
        if chosen is None:
            return None
        file = self.ctx.file_of.get(id(definition)) if not own and definition else None
        # An inherited annotation sees the block's constants (the definition's, as the
        # reference instantiates them), then the names of the definition's file.
        return self._template_value(chosen.instance,
                                    env if file is None else Env(self.ctx, file, env))

    def _template_value(self, inst: ast.TemplateInstance, env: Env) -> AnnotationValue:
        """The evaluated annotation. One that names nothing (literals only, the common case)
        is evaluated once and shared by every copy of an indexed block. Whether it names
        nothing is asked when it is met a second time: most annotations are met once."""
        seen = self.literal_annotations.get(id(inst))
        if seen is None or seen[0] is not inst:  # first sight
            value = self._evaluate_template(inst, env)
            self.literal_annotations[id(inst)] = (inst, value, None)
            return value
        _, first, literal = seen
        if literal is None:  # second sight: is it literal only?
            literal = not any(isinstance(n, ex.Name) for e in ast.expressions_in(inst)
                              for n in e.walk())
            self.literal_annotations[id(inst)] = (inst, first, literal)
        return first if literal else self._evaluate_template(inst, env)

    def _evaluate_template(self, inst: ast.TemplateInstance, env: Env) -> AnnotationValue:
        template = self.ctx.template_name(env.file, inst.template)
        args: list[tuple[str, Any]] = []
        for a in inst.args:
            if isinstance(a.value, ast.TemplateInstance):
                args.append((a.name, self._evaluate_template(a.value, env)))
            elif isinstance(a.value, ex.Name) and a.value.text not in env \
                    and not isinstance(env._find(a.value.text), Binding):
                # An element path (Rod::my_body); a constant without a value is not one:
                # evaluating it records it as missing (E-CONST when SDF needs it).
                args.append((a.name, a.value.parts))
            else:
                args.append((a.name, self.ctx.evaluate(a.value, env)))
        return AnnotationValue((template,), tuple(args), inst.span)

    def _pose(self, pose: ast.Pose | None, env: Env) -> Pose | None:
        if pose is None:
            return Pose.identity()
        # Every field is evaluated, even after one without a value: each records the
        # constants it misses, and a generator reports them all at once.
        values = [0.0 if pose.get(key) is None else self.ctx.evaluate(pose.get(key), env)
                  for key in POSE_KEYS]
        if any(not isinstance(v, (int, float)) or isinstance(v, bool) for v in values):
            return None
        return Pose.from_xyz_rpy(*(float(v) for v in values))

    # ----- second pass: connections and names
    def _connect(self, top: _Instance) -> None:
        groups: dict[tuple[int, int, str | None, str | None], list[_PendingJoint]] = {}
        for p in self.pending:  # the copies of one joint block, in one p-model instance
            groups.setdefault((id(p.block), id(p.instance), p.target, p.part), []).append(p)
        for copies in groups.values():
            first = copies[0]
            targets = (self._targets(first.instance, first.target, first.part)
                       if first.target is not None else [])
            for p, children in zip(copies, self._pair(copies, targets, first.instance)):
                self._join(p.prototype, children)
        for link, target, part, inst, span in self.pending_fixed:
            for child in self._targets(inst, target, part):
                qname = link.qname + ("fixedJoint",) + child.qname
                self.model.fixed.append(FixedJoint(qname, span, dict(link.index),
                                                   parent=link, child=child))

    def _pair(self, copies: list[_PendingJoint], targets: list[Link], inst: _Instance
              ) -> list[list[Link]]:
        """The children of each copy of a joint: the one target; or, for a replicated target,
        element i to element i (the copy of the joint, or of the link holding it, whose index
        values are those of the target copy). A joint whose copies do not match the target's
        one for one is recorded (IX3 reports it) and joined to every target copy, as
        RoboTool does, so that the model stays whole for the other checks."""
        if len(targets) <= 1:
            return [targets] * len(copies)
        own = [tuple((p.prototype.index or (p.prototype.parent.index
                                            if p.prototype.parent else {})).values())
               for p in copies]
        theirs = self._target_values(targets, inst)
        if len(set(own)) == len(own) and sorted(own) == sorted(theirs) \
                and len(set(theirs)) == len(theirs):
            by_values = dict(zip(theirs, targets))
            return [[by_values[v]] for v in own]
        self.model.mismatched.append((copies[0].prototype, len(copies), list(targets)))
        return [targets] * len(copies)

    def _target_values(self, targets: list[Link], inst: _Instance) -> list[tuple[int, ...]]:
        """What tells the copies of a replicated target apart: its part copy's index values
        (a link in an indexed part), then its own."""
        part_of = self.part_index.get(id(inst))
        if part_of is None:  # once per instance: a model may connect many joints into it
            part_of = self.part_index[id(inst)] = {
                id(l): sub.index for subs in inst.parts.values() for sub in subs
                for ls in sub.links.values() for l in ls}
        return [tuple(part_of.get(id(l), {}).values()) + tuple(l.index.values())
                for l in targets]

    def _join(self, proto: Joint, children: list[Link]) -> None:
        if not children:  # PMap1/Flex report it; there is nothing to join
            self.model.unconnected.append(proto)
            return
        for k, child in enumerate(children):
            joint = proto if k == 0 else replace(proto, sensors=list(proto.sensors),
                                                 actuators=list(proto.actuators))
            joint.child, joint.target_copy = child, k
            if proto.parent is not None and proto.parent.pose and child.pose \
                    and proto.local_pose:
                joint.pose = child.pose.inverse().compose(
                    proto.parent.pose.compose(proto.local_pose))
            self.model.joints.append(joint)
            if proto.parent is not None:
                proto.parent.joints.append(joint)

    def _targets(self, inst: _Instance, link: str, part: str | None) -> list[Link]:
        if part is None:
            return list(inst.links.get(link, []))
        return [l for sub in inst.parts.get(part, []) for l in sub.links.get(link, [])]
