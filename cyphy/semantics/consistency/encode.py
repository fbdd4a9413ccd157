"""One platform-mapping element as Z3 terms: what is given, what is unknown, what it says.

An element (operation, output event, variable or input event mapping) is first rewritten into
the p-model's names by :func:`cyphy.semantics.equations.member_equations` (locals
``move_dsl``, ports ``LMotor_das``), then printed by :mod:`cyphy.backends.z3`. Each name falls
into one class:

* given: the operation's parameters (the d-model chooses them), the mapped variable, an
  output event's value, time ``t``, other ports of the p-model, and constants without a value;
* unknown: the element's locals and the actuator inputs it writes;
* values: a typed input event's parameter (one variable per field used, ``su.shoulderAngle``);
* reads: sensor outputs (input event mappings), constrained by the sensor's equations when
  every constant of those has a value (the sensor's *range*).

Z3 constants are named after the element (``move:LMotor_das``) so that the conflict check can
put two elements side by side without their unknowns meeting.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import z3

from cyphy import expr as ex
from cyphy.backends.z3 import UnsupportedNode, Z3Printer, rational
from cyphy.diagnostics import Span
from cyphy.lang import ast
from cyphy.lang.notation import to_notation, type_to_notation
from cyphy.lang.scopes import Scopes, is_constant
from cyphy.model.elements import Device, ElaboratedModel, Port
from cyphy.semantics.equations import member_equations

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

    @property
    def name(self) -> str:
        return self.member.name

    def shown(self, name: str) -> str:
        """A port as the mapping writes it (``Core::LHinge::LMotor.das``), a local as
        declared (``dsl`` for ``move_dsl``)."""
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


def _conjuncts(e: ex.Expr) -> list[ex.Expr]:
    if isinstance(e, ex.BinOp) and e.op == "/\\":
        return _conjuncts(e.left) + _conjuncts(e.right)
    return [e]


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
        symbols = _Symbols(self, enc, member, params, {**mapping_locals, **found.locals})
        printer = Z3Printer(symbols)
        written = [to_notation(eq.expr) for eq in member.equations] + [
            f"{to_notation(s.target)} = {to_notation(s.value)}" for a in member.actions
            for s in a.statements if isinstance(s, ast.Assign)]
        try:
            for eq, text in zip(found.equations, written):
                enc.equations.append(Fact(printer.defined(eq.expr), eq.span, text))
            for pred, original in zip(found.predicates, member.predicates):
                for part, text in zip(_conjuncts(pred.expr), _conjuncts(original.expr)):
                    enc.predicate.append(Fact(printer.defined(part),
                                              part.span if part.span.line else pred.span,
                                              to_notation(text)))
                used = {n.text for n in pred.expr.walk() if isinstance(n, ex.Name)}
                enc.predicate_locals = [symbols.table[n] for n in sorted(used)
                                        if n in symbols.locals and n in symbols.table]
        except UnsupportedNode as err:
            enc.problem, enc.problem_span = str(err), err.node.span
            enc.unknown_name = isinstance(err, UnknownName)
            return enc
        for mangled in sorted(enc.reads):
            self._sensor_range(enc, mangled, symbols)
        enc.uninterpreted = printer.uninterpreted
        return enc

    def _sensor_range(self, enc: Encoding, mangled: str, symbols: _Symbols) -> None:
        """The sensor's equations, so that a predicate is judged over the values the sensor
        can give (``voltage == a/(distance + b) + c``), when its constants are all known."""
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

        def symbol(name: str, node: ex.Expr) -> Any:
            base = name.rstrip("'")
            if base == mangled and name == base:
                return enc.reads[mangled]
            p = own.get(base)
            if p is not None and p.kind is ast.DeclKind.CONST:
                return _value(p.value, node)
            if name not in table:  # the sensor's inputs and locals: any value
                table[name] = z3.Real(f"{enc.name}:{name}")
            return table[name]

        printer = Z3Printer(symbol)
        try:
            facts = [Fact(printer.defined(e), e.span, f"{device.prefix}: {to_notation(e)}")
                     for e in device.equations]
        except UnsupportedNode as err:
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

    def __call__(self, name: str, node: ex.Expr) -> Any:
        if name in self.table:
            return self.table[name]
        enc = self.enc
        head = next((p for p in self.params if name == p or name.startswith(p + ".")), None)
        if head is not None:
            shown, type_ = self.params[head]
            shown += name[len(head):]
            field_type = type_ if name == head else None
            term, fact = _constant(f"{enc.name}:{shown}", field_type, node)
            (enc.given if self.value_given else enc.values)[shown] = term
            if self.value_given:
                enc.params.append(shown)
            (enc.given_facts if self.value_given else enc.unknown_facts).extend(fact)
        elif name.rstrip("'") in self.encoder.ports:
            role, port, _ = self.encoder.ports[name.rstrip("'")]
            term, fact = _constant(f"{enc.name}:{name}", port.type, node)
            if role == "actuator" and port.kind in (ast.DeclKind.INPUT, ast.DeclKind.INOUT) \
                    and name == port.mangled:
                enc.writes[name] = enc.unknowns[name] = term
                enc.unknown_facts.extend(fact)
            elif role == "sensor" and port.kind in (ast.DeclKind.OUTPUT, ast.DeclKind.INOUT) \
                    and name == port.mangled:
                enc.reads[name] = term
                enc.given_facts.extend(fact)
            else:
                enc.given[enc.shown(name)] = term
                enc.given_facts.extend(fact)
        elif name.rstrip("'") in self.locals:
            term, fact = _constant(f"{enc.name}:{name}", self.locals.get(name), node)
            enc.unknowns[name] = term
            enc.unknown_facts.extend(fact)
        elif name == "t":
            term = z3.Real(f"{enc.name}:t")
            enc.given["t"] = term
            enc.given_facts.append(term >= 0)
        else:
            term = self._constant_value(name, node)
        self.table[name] = term
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
