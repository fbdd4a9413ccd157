"""The equations of a p-model instance, assembled for solving (no SymPy here).

All device equations (already renamed to their instances by elaboration), the containment
relations, and optionally the effect of one mapping element (``move(0.1, 0)``: the operation
mapping's equations with the operation's parameters bound, its locals renamed ``move_dsl``
and element paths replaced by the ports they name). ``integral(e)`` becomes a new state
``z`` with ``derivative(z) == e`` here, so the solver sees differential equations only.
"""

from __future__ import annotations

from dataclasses import field, replace
from typing import Any, Callable

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.lang.scopes import Scopes, is_interface
from cyphy.model.elements import Device, ElaboratedModel
from cyphy.model.evaluate import Value
from cyphy.records import record
from cyphy.semantics.dynamics.errors import AssemblyError, DynamicsError
from cyphy.semantics.dynamics.joint_forces import stop_expr
from cyphy.semantics.dynamics.motion import motion_equations
from cyphy.semantics.dynamics.tree import STANDARD_GRAVITY, coordinate_names
from cyphy.semantics.scalarise.shapes import component_name, components, type_shape


ASSEMBLY = codes.code("E-SOLVE", codes.E, "the equations to solve cannot be assembled")
OBSTACLE = codes.code("E-REDUCE", codes.E,
                      "the equations cannot be reduced to explicit first-order ODEs")
OVERDETERMINED = codes.code("E-OVERDETERMINED", codes.E,
                            "more equations than unknowns: equations compete for a variable")
UNDERDETERMINED = codes.code("E-UNDERDETERMINED", codes.E,
                             "no equation determines a variable the evolution needs")


@record(frozen=True, slots=False)
class Equation:
    expr: ex.Expr  # lhs == rhs, in mangled names
    origin: str  # what it comes from: a device prefix, "relation" or "mapping move"
    span: Span


@record(frozen=False, slots=False)
class System:
    equations: list[Equation] = field(default_factory=list)
    variables: dict[str, ast.TypeRef] = field(default_factory=dict)  # time-dependent
    inputs: set[str] = field(default_factory=set)  # given from outside
    parameters: dict[str, Value | None] = field(default_factory=dict)  # constants
    kinds: dict[str, str] = field(default_factory=dict)  # variable → input/output/local…
    # named intermediate quantities of the equations of motion, in order (each uses the
    # variables and the definitions before it): ``cyphy.semantics.dynamics.articulated.Definition``
    definitions: list[Any] = field(default_factory=list)
    # device prefix → the span of the element that declares it in the user's files: where a
    # diagnostic about a library device's equation points (the library is not the user's)
    places: dict[str, Span] = field(default_factory=dict)
    # the joints' efforts (``<Joint>_tau``): the equations of motion give a joint's
    # acceleration from its effort, never an effort from a prescribed motion
    efforts: set[str] = field(default_factory=set)
    # the sensors' outputs (their measurements): solved as outputs even where no state's
    # derivative needs them, so that `solve` and `simulate` show what each sensor reads
    measured: set[str] = field(default_factory=set)


def assemble(model: ElaboratedModel, elements: list[str] | None = None,
             mapping: ast.PlatformMapping | None = None, call: ex.Call | None = None,
             call_params: tuple[str, ...] = (),
             gravity: tuple[float, float, float] | None = None,
             definitions: bool = False, floating_base: bool = False) -> System:
    """The equations of the model (or of the named elements and what they contain); the
    whole model's include the kinematic tree's equations of motion under ``gravity``
    (default −9.81 m/s² along z), the root bodies fixed to the world or, with
    ``floating_base``, free (their six coordinates are new variables of the system). With
    ``definitions`` they are the explicit accelerations as named definitions, linear in the
    size of the tree (``System.definitions``, for ``cyphy solve`` and ``simulate``), joints
    of several coordinates and the floating base included; otherwise the joint-space
    equations ``tau == M(q)*a + h(q, v)`` written out (:func:`motion`), as the printers that
    need closed expressions take them (written out, the articulated-body
    definitions of a 2-joint arm already take 10⁵ nodes and SymPy's expansion of them 7 s,
    measured)."""
    system = System()
    devices = _devices(model, elements)
    for device in devices:
        _add_device(system, device)
    _add_places(system, model, devices)
    known = {p.mangled for d in devices for p in d.ports}
    if definitions:
        _add_explicit_motion(system, model, gravity, None if not elements else known,
                             floating_base)
    else:
        _add_motion(system, model, gravity, None if not elements else known, floating_base)
    for relation in model.relations:  # all of them for the whole model: never one dropped
        functions = {id(n.func) for n in relation.walk() if isinstance(n, ex.Call)}
        names = {n.text for n in relation.walk()
                 if isinstance(n, ex.Name) and id(n) not in functions}  # sin is no variable
        if not elements or names <= known | set(system.parameters):
            system.equations.append(Equation(relation, "relation", relation.span))
    for twist in fixed_root_twists(model, floating_base):
        if {n.text for n in twist.expr.walk() if isinstance(n, ex.Name)} <= known:
            system.equations.append(twist)
    if mapping is not None and call is not None:
        _add_mapping_call(system, model, mapping, call, call_params)
    _integrals_to_states(system)
    defined = _defined_by_others(system)
    for name, kind in system.kinds.items():
        if kind == "input" and name not in defined:
            system.inputs.add(name)
    return system


def _devices(model: ElaboratedModel, elements: list[str] | None) -> list[Device]:
    if not elements:
        return model.devices
    chosen: list[Device] = []
    for e in [*model.joints, *model.unconnected, *model.sensors, *model.actuators]:
        if e.device is None:
            continue
        if any(e.name == q or e.name.startswith(q + "::") for q in elements):
            if e.device not in chosen:
                chosen.append(e.device)
    return chosen


def _add_device(system: System, device: Device) -> None:
    for p in device.ports:
        if p.kind is ast.DeclKind.CONST:
            system.parameters[p.mangled] = p.value
        else:
            system.variables[p.mangled] = p.type
            system.kinds[p.mangled] = p.kind.value.lower()
    for e in device.equations:
        system.equations.append(Equation(e, device.prefix, e.span))


def _add_places(system: System, model: ElaboratedModel, devices: list[Device]) -> None:
    for e in [*model.joints, *model.unconnected, *model.sensors, *model.actuators]:
        if e.device is not None and e.device in devices:
            system.places.setdefault(e.device.prefix, e.span)
    for joint in model.joints:
        port = joint.device.port("tau") if joint.device in devices else None
        if port is not None:
            system.efforts.add(port.mangled)
    for sensor in model.sensors:
        if sensor.device is not None and sensor.device in devices:
            system.measured.update(p.mangled for p in sensor.device.of_kind(ast.DeclKind.OUTPUT))


def _add_motion(system: System, model: ElaboratedModel,
                gravity: tuple[float, float, float] | None, known: set[str] | None,
                floating_base: bool = False) -> None:
    """The equations of motion (:func:`motion`) that the system takes. For chosen elements
    (``known``: their ports), a joint's equation enters when every joint variable it names is
    among them, as a relation does: a wheel whose motion depends on its own joint only keeps
    it, a link coupled to joints left out does not. A tree without equations of motion (too
    large to write out, a link without mass elsewhere) is then reported only for the whole
    model: chosen elements keep the equations they had before."""
    if known is not None and not any(j.device is not None and
                                     any(p.mangled in known for p in j.device.ports)
                                     for j in model.joints):
        return  # no joint chosen: nothing to derive (and no tree to build)
    try:
        equations = motion(model, gravity, floating_base)
    except DynamicsError:
        if known is None:
            raise
        return
    for equation in equations:
        functions = {id(n.func) for n in equation.expr.walk() if isinstance(n, ex.Call)}
        names = {n.text for n in equation.expr.walk()
                 if isinstance(n, ex.Name) and id(n) not in functions}  # sin is no variable
        if known is None or names <= known | set(system.parameters):
            system.equations.append(equation)
            for name in sorted(names - set(system.variables) - set(system.parameters)):
                system.variables[name] = ast.PrimitiveType("real")  # a floating base's
                system.kinds[name] = "local"


def _add_explicit_motion(system: System, model: ElaboratedModel,
                         gravity: tuple[float, float, float] | None,
                         known: set[str] | None, floating_base: bool = False) -> None:
    """The explicit equations of motion (:func:`cyphy.semantics.dynamics.articulated.model_motion`):
    ``<J>_a == <J>_qdd`` per joint (``<J>_a[k] == <J>_qdd_k`` for a joint of several
    coordinates), with the articulated-body algorithm's named definitions; a floating base's
    coordinates are new variables with ``derivative(<Root>_x) == <Root>_vx``,
    ``derivative(<Root>_vx) == <Root>_ax`` and ``<Root>_ax == <Root>_qdd_1`` …. For chosen
    elements (``known``: their ports), a joint's equation enters when every joint variable
    it depends on (through the definitions) is among them, as a relation does (a floating
    base's variables always are): a wheel whose motion depends on its own joint only keeps
    it, a link coupled to joints left out does not. A tree without equations of motion (a
    link without mass elsewhere) is then reported only for the whole model: chosen elements
    keep the equations they had before."""
    # lazy: NumPy, through the algorithms; a cached tree needs neither
    from cyphy.semantics.dynamics.articulated import model_motion

    if known is not None and not any(j.device is not None and
                                     any(p.mangled in known for p in j.device.ports)
                                     for j in model.joints):
        return  # no joint chosen: nothing to derive (and no tree to build)
    try:
        motion = model_motion(model, gravity or STANDARD_GRAVITY, floating_base)
    except DynamicsError:
        if known is None:
            raise
        return
    if motion is None:
        return
    free = {n for joint, _ in motion.accelerations if joint.kind == "floating"
            for v in ("theta", "v", "a") for n in coordinate_names(joint, v)}
    uses: dict[str, set[str]] = {}  # definition → the variables it depends on
    for d in motion.definitions:
        names: set[str] = set()
        for atom in d.value.atoms():
            names |= uses.get(atom, {atom})
        uses[d.name] = names

    taken = set(system.variables) | set(system.parameters) | {  # and their components
        c for n, t in system.variables.items() for c in components(n, type_shape(t) or ())}
    clash = sorted((set(uses) | free) & taken)
    if clash:
        joint = next((d.joint for d in motion.definitions if d.name == clash[0]),
                     motion.accelerations[0][0])
        raise DynamicsError(f"the equations of motion name a quantity {clash[0]}, which is "
                            "already a variable of the model", joint.element.span,
                            "rename the device whose variable it is")
    allowed: set[str] | None = None
    if known is not None:  # a vector port's components are known with it
        allowed = known | free | set(system.parameters) | {
            component_name(n, k) for joint, _ in motion.accelerations if joint.dof > 1
            for n in known for k in range(joint.dof)}
    added = False
    for joint, accelerations in motion.accelerations:
        span = joint.element.span
        equations: list[ex.Expr] = []
        if joint.kind == "floating":
            for position, speed, acceleration in zip(
                    *(coordinate_names(joint, v) for v in ("theta", "v", "a"))):
                for left, right in ((position, speed), (speed, acceleration)):
                    equations.append(ex.BinOp("==", ex.Derivative(ex.Name((left,), span=span),
                                                                  span=span),
                                              ex.Name((right,), span=span), span=span))
            lefts: list[ex.Expr] = [ex.Name((n,), span=span)
                                    for n in coordinate_names(joint, "a")]
            for n in sorted(free & set(coordinate_names(joint, "theta") +
                                       coordinate_names(joint, "v") +
                                       coordinate_names(joint, "a"))):
                system.variables[n] = ast.PrimitiveType("real")
                system.kinds[n] = "local"
            depends = set(coordinate_names(joint, "a"))
        else:
            device = joint.element.device
            assert device is not None
            port = device.port("a")
            assert port is not None
            whole = ex.Name((port.mangled,), span=span)
            lefts = [whole] if joint.dof == 1 else [
                ex.Index(whole, (ex.Num(str(k), span=span),), span=span)
                for k in range(1, joint.dof + 1)]
            depends = {port.mangled}
        if allowed is not None and not (depends | {v for name in accelerations
                                                    for v in uses[name]}) <= allowed:
            continue
        for left, name in zip(lefts, accelerations):
            equations.append(ex.BinOp("==", left, ex.Name((name,), span=span), span=span))
        for equation in equations:
            system.equations.append(Equation(equation, f"{joint.prefix} motion", span))
        added = True
    if added:
        system.definitions.extend(motion.definitions)
        _add_stops(system, motion.stops)


def _add_stops(system: System, stops: tuple[Any, ...]) -> None:
    """Each bounded coordinate's limit effort ``<q>_stop`` (a local variable the definitions
    use) and its equation, the contact model of
    :func:`cyphy.semantics.dynamics.joint_forces.stop_expr`."""
    for stop in stops:
        span = stop.joint.element.span
        system.variables[stop.name] = ast.PrimitiveType("real")
        system.kinds[stop.name] = "local"
        value = stop_expr(stop.forces, stop.inertia, ex.Name((stop.position,), span=span),
                          ex.Name((stop.rate,), span=span))  # scalar names, as the
        # definitions use them (a vector port's component: ``W_theta_2``)
        system.equations.append(Equation(ex.BinOp("==", ex.Name((stop.name,), span=span),
                                                  value, span=span),
                                         f"{stop.joint.prefix} limit", span))


FIXED_ROOT = "fixed root"  # the origin of the equations fixed_root_twists gives


def fixed_root_twists(model: ElaboratedModel, floating_base: bool = False) -> list[Equation]:
    """The parent twist of every joint whose parent is a root link, and its rate, are zero:
    ``J_pV == (|0, …, 0|)`` and ``J_pA == (|0, …, 0|)``. A root link is fixed to the world
    (the equations of motion assume it, :func:`motion`), so the parent's twist is the
    world's; nothing else in the model gives these inputs, which left them free in
    ``Evolve`` and stopped ``simulate`` on a whole model. With ``floating_base`` the root
    moves and its twist is its own state: no equation."""
    if floating_base:
        return []
    children = {j.child.name for j in model.joints if j.child is not None}
    out: list[Equation] = []
    for joint in model.joints:
        if joint.parent is None or joint.child is None or joint.device is None \
                or joint.parent.name in children:
            continue
        span = joint.span
        for name in ("pV", "pA"):
            port = joint.device.port(name)
            size = _vector_size(port.type) if port is not None else None
            if port is None or size is None:
                continue
            zero = ex.Vector((tuple(ex.Num("0", span=span) for _ in range(size)),), span=span)
            out.append(Equation(ex.BinOp("==", ex.Name((port.mangled,), span=span), zero,
                                         span=span), f"{joint.device.prefix} {FIXED_ROOT}", span))
    return out


def _vector_size(t: ast.TypeRef) -> int | None:
    """The length of ``vector(T, n)`` with a literal ``n``, else None."""
    if isinstance(t, ast.VectorType) and isinstance(t.size, ex.Num) and t.size.is_integer:
        return int(t.size.text)
    return None


def motion(model: ElaboratedModel,
           gravity: tuple[float, float, float] | None = None,
           floating_base: bool = False) -> list[Equation]:
    """The equations of motion of the kinematic tree (:mod:`cyphy.semantics.dynamics.rigid_body`), which
    relate each joint's effort to the accelerations of the bodies it moves: one
    ``<Joint>_tau == M(q)*a + h(q, v)`` per coordinate in tree order (``<Joint>_tau[k]`` for
    a joint of several), under ``gravity`` (default −9.81 m/s² along z), the root fixed to
    the world or, with ``floating_base``, free (``derivative(<Root>_x) == <Root>_vx`` …, and
    ``0 == M(q)*a + h(q, v)`` for its six coordinates). The one source of these equations for
    ``cyphy solve`` (through :func:`assemble`) and the CyPhyCircus ``Evolve``; raises
    ``DynamicsError`` when the tree has none."""
    return [Equation(equation, f"{joint.prefix} motion", equation.span)
            for equation, joint in motion_equations(model, gravity or STANDARD_GRAVITY,
                                                    floating_base)]


def _add_mapping_call(system: System, model: ElaboratedModel, mapping: ast.PlatformMapping,
                      call: ex.Call, params: tuple[str, ...]) -> None:
    name = call.func.text if isinstance(call.func, ex.Name) else ""
    op: ast.OperationMapping | ast.EventMapping | ast.VariableMapping | None = next(
        (o for o in mapping.operations if o.name == name), None) or next(
        (e for e in mapping.events if e.direction == "output" and e.name == name), None) or next(
        (v for v in mapping.variables if v.name == name), None)
    if op is None:
        raise AssemblyError(f"mapping {mapping.name} has no operation '{name}'", call.span,
                            "name an operation of the mapping: " +
                            ", ".join(o.name for o in mapping.operations))
    if len(params) != len(call.args):
        raise AssemblyError(f"{name} takes {len(params)} argument"
                            f"{'s' if len(params) != 1 else ''}, not {len(call.args)}",
                            call.span, f"call it as {name}({', '.join(params)})")
    bound = dict(zip(params, call.args))
    found = member_equations(model, mapping, op, bound)
    for local, type_ in found.locals.items():
        system.variables[local] = type_
        system.kinds[local] = "local"
    system.equations.extend(found.equations)


@record(frozen=False, slots=False)
class MemberEquations:
    """One mapping element's equations in the p-model's names (see :func:`member_equations`)."""

    equations: list[Equation] = field(default_factory=list)  # equations, then actions
    predicates: list[Equation] = field(default_factory=list)
    locals: dict[str, ast.TypeRef] = field(default_factory=dict)  # renamed local → type
    ports: dict[str, str] = field(default_factory=dict)  # mangled port → path as written


def member_equations(model: ElaboratedModel, mapping: ast.PlatformMapping,
                     member: ast.OperationMapping | ast.EventMapping | ast.VariableMapping,
                     bound: dict[str, ex.Expr]) -> MemberEquations:
    """The equations (and predicates) of one operation, event or variable mapping with the
    names in ``bound`` (its parameters) replaced, its locals renamed ``move_dsl`` and element
    paths replaced by the ports they name (``Core::LHinge::LMotor.das`` → ``LMotor_das``).
    Assignments of actions become equations ``target == value``, later ones reading what
    earlier ones assigned."""
    name = member.name
    out = MemberEquations()
    local = {d.name: f"{name}_{d.name}" for d in member.declarations
             if d.kind is not ast.DeclKind.CONST}
    consts = {d.name: d for d in [*mapping.declarations, *member.declarations]
              if d.kind is ast.DeclKind.CONST}
    for d in member.declarations:
        if d.kind is not ast.DeclKind.CONST:
            out.locals[local[d.name]] = d.type
    scoped: dict[str, ex.Expr] = {n: ex.Name((m,)) for n, m in local.items()}
    scoped.update({n: d.value for n, d in consts.items() if d.value is not None})
    scoped.update(bound)
    swap = mapping_renamer(model, port_index(model), scoped, out.ports)

    origin = f"mapping {name}"
    for eq in member.equations:
        out.equations.append(Equation(ex.transform(eq.expr, swap), origin, eq.span))
    for p in member.predicates:
        out.predicates.append(Equation(ex.transform(p.expr, swap), origin, p.span))
    assigned: dict[ex.Expr, ex.Expr] = {}
    for action in member.actions:
        for s in action.statements:
            if isinstance(s, ast.Assign):
                target = ex.transform(s.target, swap)
                value = ex.transform(ex.transform(s.value, swap), assigned.get)
                assigned[target] = value
                out.equations.append(Equation(ex.BinOp("==", target, value, span=s.span),
                                              origin, s.span))
    return out


def mapping_renamer(model: ElaboratedModel, ports: dict[tuple[str, ...], str],
                    scoped: dict[str, ex.Expr], seen: dict[str, str] | None = None
                    ) -> Callable[[ex.Expr], ex.Expr | None]:
    """The replacement function (for :func:`cyphy.expr.transform`) that puts a mapping
    expression in the model's names: element paths become the ports they name
    (``Core::LHinge::LMotor.das`` → ``LMotor_das``, recorded in ``seen`` with the path as
    written) and plain names in ``scoped`` (parameters, locals, constants) their
    replacement."""

    def swap(node: ex.Expr) -> ex.Expr | None:
        steps = element_steps(node)
        if steps is not None and len(steps) > 1:
            mangled = ports.get(port_key(model, steps))
            if mangled is not None:
                if seen is not None:
                    seen.setdefault(mangled, to_notation(node))
                return ex.Name((mangled,), span=node.span)
        if isinstance(node, ex.Name) and len(node.parts) == 1:
            found = scoped.get(node.parts[0])
            if found is not None:
                return replace(found, span=node.span) if isinstance(found, ex.Name) else found
        return None

    return swap


def input_event_predicate(model: ElaboratedModel, mapping: ast.PlatformMapping,
                          event: ast.EventMapping) -> ex.Expr | None:
    """The conjunction of an input event mapping's predicates in mangled names (Rule 4's
    ``pred``), or None when the mapping gives no predicate."""
    preds = [p.expr for p in member_equations(model, mapping, event, {}).predicates]
    if not preds:
        return None
    return ex.conjunction(preds)


def port_index(model: ElaboratedModel) -> dict[tuple[str, ...], str]:
    out: dict[tuple[str, ...], str] = {}
    for e in [*model.joints, *model.unconnected, *model.sensors, *model.actuators]:
        if e.device is not None:
            for p in e.device.ports:
                out[e.qname + (p.name,)] = p.mangled
    return out


def element_steps(node: ex.Expr) -> list[str] | None:
    if isinstance(node, ex.Name):
        return list(node.parts)
    if isinstance(node, ex.Member):
        base = element_steps(node.base)
        return None if base is None else base + [node.name]
    if isinstance(node, ex.Index) and len(node.args) == 1 and isinstance(node.args[0], ex.Num):
        base = element_steps(node.base)
        return None if base is None else base + [node.args[0].text]
    return None


def port_key(model: ElaboratedModel, steps: list[str]) -> tuple[str, ...]:
    """Mapping paths are rooted at a link or at the p-model: ``Core::LHinge::LMotor.das``."""
    if steps and steps[0] == model.name:
        steps = steps[1:]
    return (model.name, *steps)


def _integrals_to_states(system: System) -> None:
    """``integral(e)`` → a new state ``z`` with ``derivative(z) == e`` (``z(0) = 0``)."""
    counter = 0
    added: list[Equation] = []

    def replace(node: ex.Expr, origin: str, span: Span) -> ex.Expr | None:
        nonlocal counter
        if isinstance(node, ex.Integral) and node.lower is None:
            counter += 1
            name = f"{origin.split()[-1]}_int{counter}"
            system.variables[name] = ast.PrimitiveType("real")
            system.kinds[name] = "local"
            state = ex.Name((name,), span=node.span)
            added.append(Equation(ex.BinOp("==", ex.Derivative(state, span=node.span),
                                           node.operand, span=node.span), origin, span))
            return state
        return None

    system.equations = [Equation(ex.transform(eq.expr, lambda n, o=eq.origin, s=eq.span:
                                              replace(n, o, s)), eq.origin, eq.span)
                        for eq in system.equations] + added


def _defined_by_others(system: System) -> set[str]:
    """Inputs that a relation, a mapping or the fixed root sets are not free inputs."""
    out: set[str] = set()
    for eq in system.equations:
        if eq.origin == "relation" or eq.origin.startswith("mapping") \
                or eq.origin.endswith(FIXED_ROOT):
            out.update(n.text for n in eq.expr.walk() if isinstance(n, ex.Name))
    return out


def parse_call(text: str) -> ex.Call:
    """``move(0.1, 0)`` as an expression (the value of ``--mapping-call``)."""
    # lazy: the parser loads Lark, which a warm run must not
    from cyphy.lang.parser import parse_text

    result = parse_text(f"const call: real = {text}", "<--mapping-call>")
    item: Any = result.file.items[0] if result.file and result.file.items else None
    if result.diagnostics or item is None or not isinstance(item.value, ex.Call):
        raise AssemblyError(f"cannot read the call '{text}'", Span.unknown("<--mapping-call>"),
                            "write it as name(arg, …), for example move(0.1, 0)")
    return item.value


def mapping_operation(ws: Any, resolution: Any, model: ElaboratedModel, text: str
                      ) -> tuple[ast.PlatformMapping, ex.Call, tuple[str, ...]]:
    """The mapping of the model's p-model, the parsed call and the operation's parameter
    names (from the d-model's operation signature); a "call" ``e(v)`` of an output event
    the mapping maps (``output event e ? p { … }``) has the mapping's parameter ``p``."""
    call = parse_call(text)
    mappings = [(f, i) for f in ws.user_files() for i in f.items
                if isinstance(i, ast.PlatformMapping) and i.pmodel[-1] == model.name]
    if not mappings:
        raise AssemblyError(f"no platform mapping of p-model {model.name} among the files",
                            call.span, "name the mapping file (or its folder) too")
    file, mapping = mappings[0]
    module = resolution.get(mapping)
    name = call.func.text if isinstance(call.func, ex.Name) else ""
    params: tuple[str, ...] | None = None
    platform = module.platform if isinstance(module, ast.Module) else None
    if platform is not None:
        sigs = list(platform.operations)
        scopes = Scopes(ws)
        module_file = next((f for f in ws.files.values() if module in f.items), file)
        for use in platform.interface_uses:
            if use.relation == "provides":
                for i in scopes.lookup(module_file, use.interface, is_interface):
                    sigs.extend(i.operations)
        sig = next((s for s in sigs if s.name == name), None)
        if sig is not None:
            params = tuple(p.name for p in sig.params)
    if params is None:  # an output event: its mapping's parameter, if typed
        event = next((e for e in mapping.events if e.direction == "output" and e.name == name),
                     None)
        if event is not None:
            params = (event.param,) if event.param else ()
    if params is None and any(v.name == name for v in mapping.variables):
        params = (name,)  # a machine's write of a platform variable: its mapping's effect
    if params is None:
        raise AssemblyError(f"the d-model provides no operation '{name}'", call.span,
                            "call an operation of the robotic platform")
    return mapping, call, params
