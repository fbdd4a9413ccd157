"""One platform-mapping element as Z3 terms: what is given, what is unknown, what it says.

An element (operation, output event, variable or input event mapping) is first rewritten into
the p-model's names by :func:`cyphy.semantics.dynamics.equations.member_equations` (locals
``move_dsl``, ports ``LMotor_das``), then printed by :mod:`cyphy.translate.to_z3`. Each name falls
into one class:

* given: the operation's parameters (the d-model chooses them), the mapped variable, an
  output event's value, time ``t``, other ports of the p-model, and constants without a value;
* unknown: the element's locals and the actuator inputs it writes;
* values: a typed input event's parameter (one variable per field used, ``su.shoulderAngle``);
* reads: sensor outputs (input event mappings), constrained by the sensor's equations when
  every constant of those has a value (the sensor's *range*).

Z3 constants are named after the element (``move:LMotor_das``) so that the conflict check can
put two elements side by side without their unknowns meeting.

Vector and matrix ports, locals and parameters (a gyroscope's ``measuredAngularVelocity``, an
actuator's wrench) are checked component by component: the element's equations and predicate,
and a sensor's equations for its range, go through the scalarisation the Isabelle printers and
the reduction use (:meth:`cyphy.semantics.scalarise.Scalariser.predicate`), so
``T.wrench == (|0, 0, f|)`` is three equations on the scalars ``T_wrench_1`` … ``T_wrench_3``,
each its own Z3 constant, shown as ``T.wrench[3]``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import z3

from cyphy import expr as ex
from cyphy.translate.to_z3 import UnsupportedNode, Z3Printer, rational
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.lang.notation import to_notation, type_to_notation
from cyphy.lang.scopes import Scopes, is_constant
from cyphy.model.elements import Device, ElaboratedModel, Port
from cyphy.semantics.dynamics.equations import member_equations
from cyphy.semantics.scalarise.scalariser import Scalariser
from cyphy.semantics.scalarise.shapes import ScalariseError, shape_of_type
from cyphy.semantics.scalarise.shapes import components as scalar_names
from cyphy.semantics.circus.values import type_of

Member = ast.OperationMapping | ast.EventMapping | ast.VariableMapping
Service = ast.OperationSig | ast.EventDecl | ast.VarDecl | None


@dataclass(frozen=True)
class Fact:
    """One equation or predicate conjunct as a Z3 term, with where it was written."""

    term: Any
    span: Span
    text: str


@dataclass
class Encoding:
    member: Member
    label: str  # "operation move", "input event obstacle"
    given: dict[str, Any] = field(default_factory=dict)  # shown name → Z3 constant
    params: list[str] = field(default_factory=list)  # the given names that are parameters
    unknowns: dict[str, Any] = field(default_factory=dict)  # locals and written inputs
    writes: dict[str, Any] = field(default_factory=dict)  # mangled actuator input → constant
    reads: dict[str, Any] = field(default_factory=dict)  # mangled sensor output → constant
    values: dict[str, Any] = field(default_factory=dict)  # typed input event's value
    given_facts: list[Any] = field(default_factory=list)  # nat ≥ 0, t ≥ 0
    unknown_facts: list[Any] = field(default_factory=list)
    equations: list[Fact] = field(default_factory=list)
    predicate: list[Fact] = field(default_factory=list)  # conjuncts of the predicate
    predicate_locals: list[Any] = field(default_factory=list)
    range: list[Fact] = field(default_factory=list)  # sensor equations of the reads
    range_notes: list[str] = field(default_factory=list)
    written: dict[str, str] = field(default_factory=dict)  # mangled port → path as written
    free_constants: list[str] = field(default_factory=list)
    uninterpreted: set[str] = field(default_factory=set)
    problem: str | None = None  # why it cannot be encoded (then nothing else is meaningful)
    problem_span: Span | None = None
    unknown_name: bool = False  # the problem is a name that denotes nothing: an error
    #: a component's scalar name → (the vector's name, the index as written, its element type)
    components: dict[str, tuple[str, str, ast.TypeRef]] = field(default_factory=dict)

    @property
    def name(self) -> str:
        return self.member.name

    def shown(self, name: str) -> str:
        """A port as the mapping writes it (``Core::LHinge::LMotor.das``), a local as
        declared (``dsl`` for ``move_dsl``); a component with its index (``T.wrench[3]``)."""
        found = self.components.get(name)
        if found is not None:
            return f"{self.shown(found[0])}[{found[1]}]"
        if name in self.written:
            return self.written[name]
        prefix = self.member.name + "_"
        return name[len(prefix):] if name.startswith(prefix) else name


def label_of(member: Member) -> str:
    if isinstance(member, ast.EventMapping):
        return f"{member.direction} event {member.name}"
    if isinstance(member, ast.VariableMapping):
        return f"variable {member.name}"
    return f"operation {member.name}"


class UnknownName(UnsupportedNode):
    """A name that denotes nothing (a misspelt port the earlier checks let through)."""


class Encoder:
    """Encodes the elements of one platform mapping against its elaborated p-model."""

    def __init__(self, model: ElaboratedModel, mapping: ast.PlatformMapping,
                 file: ast.SourceFile, scopes: Scopes, consts: Mapping[str, object]) -> None:
        self.model, self.mapping, self.file = model, mapping, file
        self.scopes, self.consts = scopes, consts
        self.ports: dict[str, tuple[str, Port, Device]] = {}
        for role, elements in (("actuator", model.actuators), ("sensor", model.sensors),
                               ("joint", [*model.joints, *model.unconnected])):
            for e in elements:
                if e.device is not None:
                    for p in e.device.ports:
                        self.ports.setdefault(p.mangled, (role, p, e.device))

    def encode(self, member: Member, service: Service) -> Encoding:
        enc = Encoding(member, label_of(member))
        params = _parameters(member, service)
        bound: dict[str, ex.Expr] = {p: ex.Name((f"{member.name}.{p}",)) for p in params}
        found = member_equations(self.model, self.mapping, member, bound)
        enc.written = found.ports
        mapping_locals = {d.name: d.type for d in self.mapping.declarations
                          if d.kind is not ast.DeclKind.CONST}
        locals_ = {**mapping_locals, **found.locals}
        typed: dict[str, ast.TypeRef] = {m: port.type for m, (_, port, _) in self.ports.items()}
        typed.update((n, t) for n, t in locals_.items() if t is not None)
        typed.update((f"{member.name}.{p}", t) for p, t in params.items() if t is not None)
        scalars = _scalariser(typed, enc.components)
        symbols = _Symbols(self, enc, member, params, locals_)
        printer = Z3Printer(symbols)
        written = [to_notation(eq.expr) for eq in member.equations] + [
            f"{to_notation(s.target)} = {to_notation(s.value)}" for a in member.actions
            for s in a.statements if isinstance(s, ast.Assign)]
        try:
            for eq, text in zip(found.equations, written):
                for part, note in _components(scalars, eq.expr):
                    enc.equations.append(Fact(printer.defined(part), eq.span, text + note))
            used: set[str] = set()
            for pred, original in zip(found.predicates, member.predicates):
                for part, text in zip(ex.conjuncts(pred.expr), ex.conjuncts(original.expr)):
                    for scalar, note in _components(scalars, part):
                        enc.predicate.append(Fact(printer.defined(scalar),
                                                  part.span if part.span.line else pred.span,
                                                  to_notation(text) + note))
                        used |= {n.text for n in scalar.walk() if isinstance(n, ex.Name)}
            enc.predicate_locals = [symbols.table[n] for n in sorted(used)
                                    if symbols.is_local(n) and n in symbols.table]
        except UnsupportedNode as err:
            enc.problem, enc.problem_span = str(err), err.node.span
            enc.unknown_name = isinstance(err, UnknownName)
            return enc
        except ScalariseError as err:
            enc.problem, enc.problem_span = str(err), err.node.span
            return enc
        read_ports = {enc.components[r][0] if r in enc.components else r for r in enc.reads}
        for mangled in sorted(read_ports):
            self._sensor_range(enc, mangled)
        enc.uninterpreted = printer.uninterpreted
        return enc

    def _sensor_range(self, enc: Encoding, mangled: str) -> None:
        """The sensor's equations, so that a predicate is judged over the values the sensor
        can give (``voltage == a/(distance + b) + c``), when its constants are all known;
        per component where its ports are vectors."""
        role, port, device = self.ports[mangled]
        missing = [p.mangled for p in device.of_kind(ast.DeclKind.CONST) if p.value is None]
        if missing:
            enc.range_notes.append(
                f"the equations of sensor {device.prefix} were not used for the range of "
                f"{enc.shown(mangled)}: {', '.join(missing)} ha{'s' if len(missing) == 1 else 've'}"
                " no value (give them with --const)")
            return
        own = {p.mangled: p for p in device.ports}
        table: dict[str, Any] = {}
        scalars = _scalariser({p.mangled: p.type for p in device.ports}, {})

        def symbol(name: str, node: ex.Expr) -> Any:
            base = name.rstrip("'")
            if name == base and name in enc.reads:  # the port read (or a component of it)
                return enc.reads[name]
            p = own.get(base)
            if p is not None and p.kind is ast.DeclKind.CONST:
                return _value(p.value, node)
            if name not in table:  # the sensor's inputs and locals: any value
                table[name] = z3.Real(f"{enc.name}:{name}")
            return table[name]

        printer = Z3Printer(symbol)
        try:
            facts = [Fact(printer.defined(part), e.span, f"{device.prefix}: {to_notation(e)}"
                          + note) for e in device.equations for part, note in
                     _components(scalars, e)]
        except (UnsupportedNode, ScalariseError) as err:
            enc.range_notes.append(f"the equations of sensor {device.prefix} were not used for "
                                   f"the range of {enc.shown(mangled)}: {err}")
            return
        if printer.uninterpreted:
            enc.range_notes.append(f"the equations of sensor {device.prefix} were not used: "
                                   f"they call {', '.join(sorted(printer.uninterpreted))}")
            return
        enc.range.extend(facts)


def _value(value: object, node: ex.Expr) -> Any:
    if isinstance(value, bool):
        return z3.BoolVal(value)
    if isinstance(value, (int, float)):
        return rational(value)
    raise UnsupportedNode(node, f"the constant {to_notation(node)} is not a number")


def _scalariser(typed: Mapping[str, ast.TypeRef],
                components: dict[str, tuple[str, str, ast.TypeRef]]) -> Scalariser:
    """The scalarisation of the names in ``typed`` that are vectors or matrices (each one
    split into its components); their components are recorded in ``components``."""
    shapes, unsized = {}, set()
    for name, t in typed.items():
        if not isinstance(t, (ast.VectorType, ast.MatrixType)):
            continue
        shape = shape_of_type(type_of(t))
        if shape is None:
            unsized.add(name)
            continue
        shapes[name] = shape
        for k, scalar in enumerate(scalar_names(name, shape)):
            index = str(k + 1) if len(shape) == 1 else f"{k // shape[1] + 1}, {k % shape[1] + 1}"
            components[scalar] = (name, index, t.element)
    return Scalariser(shapes, frozenset(shapes), frozenset(unsized))


def _components(scalars: Scalariser, e: ex.Expr) -> list[tuple[ex.Expr, str]]:
    """The scalar equations of ``e`` with a note of which component each is (none when
    ``e`` is scalar)."""
    parts = scalars.predicate(e)
    for part in parts:
        item = next((n for n in part.walk() if isinstance(n, ex.Index)), None)
        if item is not None:
            raise ScalariseError(item, f"{to_notation(item)} is an item of a vector whose "
                                 "components are not variables here (a constant, or a vector "
                                 "whose size is not declared)")
    if len(parts) == 1:
        return [(parts[0], "")]
    return [(p, f" (component {k + 1})") for k, p in enumerate(parts)]


def _parameters(member: Member, service: Service) -> dict[str, ast.TypeRef | None]:
    """The element's given names and their types: an operation's parameters, an event's
    value, the mapped variable."""
    if isinstance(member, ast.OperationMapping):
        if isinstance(service, ast.OperationSig):
            return {p.name: p.type for p in service.params}
        return {}
    if isinstance(member, ast.EventMapping):
        if member.param is None:
            return {}
        return {member.param: service.type if isinstance(service, ast.EventDecl) else None}
    return {member.name: service.type if isinstance(service, ast.VarDecl) else None}


class _Symbols:
    """The printer's ``symbol`` callback for one element: what each name denotes."""

    def __init__(self, encoder: Encoder, enc: Encoding, member: Member,
                 params: dict[str, ast.TypeRef | None], locals: dict[str, ast.TypeRef]) -> None:
        self.encoder, self.enc, self.member = encoder, enc, member
        self.params = {f"{member.name}.{p}": (p, t) for p, t in params.items()}
        self.locals = locals
        self.table: dict[str, Any] = {}
        self._expanding: set[str] = set()
        self.value_given = not (isinstance(member, ast.EventMapping) and
                                member.direction == "input")

    def is_local(self, name: str) -> bool:
        found = self.enc.components.get(name)
        return (found[0] if found is not None else name) in self.locals

    def __call__(self, name: str, node: ex.Expr) -> Any:
        if name in self.table:
            return self.table[name]
        enc = self.enc
        component = enc.components.get(name.rstrip("'"))
        if component is not None:  # a vector's component: classified as the vector is
            prime = name[len(name.rstrip("'")):]
            term = self._classify(name, component[0] + prime, component[2], node)
        else:
            term = self._classify(name, name, None, node)
        self.table[name] = term
        return term

    def _classify(self, name: str, whole: str, element: ast.TypeRef | None,
                  node: ex.Expr) -> Any:
        """The Z3 constant of ``name`` (``whole`` itself, or a component of the vector
        ``whole`` of ``element`` type), recorded as a given, an unknown, a write or a read."""
        enc = self.enc
        head = next((p for p in self.params if whole == p or whole.startswith(p + ".")), None)
        if head is not None:
            shown, type_ = self.params[head]
            shown += whole[len(head):]
            if element is not None:
                shown += f"[{enc.components[name][1]}]"
            field_type = element if element is not None else type_ if whole == head else None
            term, fact = _constant(f"{enc.name}:{shown}", field_type, node)
            (enc.given if self.value_given else enc.values)[shown] = term
            if self.value_given:
                enc.params.append(shown)
            (enc.given_facts if self.value_given else enc.unknown_facts).extend(fact)
        elif whole.rstrip("'") in self.encoder.ports:
            role, port, _ = self.encoder.ports[whole.rstrip("'")]
            term, fact = _constant(f"{enc.name}:{name}", element or port.type, node)
            if role == "actuator" and port.kind in (ast.DeclKind.INPUT, ast.DeclKind.INOUT) \
                    and whole == port.mangled:
                enc.writes[name] = enc.unknowns[name] = term
                enc.unknown_facts.extend(fact)
            elif role == "sensor" and port.kind in (ast.DeclKind.OUTPUT, ast.DeclKind.INOUT) \
                    and whole == port.mangled:
                enc.reads[name] = term
                enc.given_facts.extend(fact)
            else:
                enc.given[enc.shown(name)] = term
                enc.given_facts.extend(fact)
        elif whole.rstrip("'") in self.locals:
            term, fact = _constant(f"{enc.name}:{name}",
                                   element or self.locals.get(whole), node)
            enc.unknowns[name] = term
            enc.unknown_facts.extend(fact)
        elif name == "t":
            term = z3.Real(f"{enc.name}:t")
            enc.given["t"] = term
            enc.given_facts.append(term >= 0)
        else:
            term = self._constant_value(name, node)
        return term

    def _constant_value(self, name: str, node: ex.Expr) -> Any:
        """A constant: ``--const``, then its declared value (printed, so exact), else a free
        constant the checks treat as given."""
        enc = self.enc
        for key, value in self.encoder.consts.items():
            if key == name or key.endswith("::" + name):
                return _value(value, node)
        found = self.encoder.scopes.lookup(self.encoder.file, tuple(name.split("::")),
                                           is_constant)
        decl = found[0] if found else None
        if isinstance(decl, ast.VarDecl) and decl.value is not None and \
                name not in self._expanding:
            self._expanding.add(name)
            try:
                return Z3Printer(self).doprint(decl.value)
            finally:
                self._expanding.discard(name)
        if decl is None:
            raise UnknownName(node, f"{to_notation(node)} is neither a port of p-model "
                              f"{self.encoder.model.name}, nor a parameter, local or constant "
                              f"of the {enc.label}")
        term, _ = _constant(f"{enc.name}:{name}", decl.type, node)
        enc.given[name] = term
        enc.free_constants.append(name)
        return term


def _constant(name: str, type_: ast.TypeRef | None, node: ex.Expr) -> tuple[Any, list[Any]]:
    """A Z3 constant of the type's sort, with the facts its type states (``nat`` ≥ 0)."""
    if type_ is None or isinstance(type_, ast.NamedType):
        return z3.Real(name), []  # a field of a record, or a type we do not know: a real
    if isinstance(type_, ast.PrimitiveType):
        if type_.name == "boolean":
            return z3.Bool(name), []
        if type_.name in ("int", "nat"):
            term = z3.Int(name)
            return term, [term >= 0] if type_.name == "nat" else []
        if type_.name == "real":
            return z3.Real(name), []
    raise UnsupportedNode(node, f"{to_notation(node)} has type {type_to_notation(type_)}, "
                          "which the consistency checks do not handle")
