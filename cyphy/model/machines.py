"""RoboSim state machines as the checks, ``cyphy show --dmodel``, the cycle interpreter and
the Flow* compilation see them: nodes (states, initial junctions, junctions, final states)
keyed by their path in the machine, transitions with resolved ends, the machine's constants,
variables and clocks, and the platform's events and operations its contexts name.

Built from the syntax tree and the name resolution only: nothing is evaluated here, and a
name that does not resolve is recorded (for the rules to report), never raised.
"""

from __future__ import annotations

from dataclasses import field
from typing import Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.resolve import Resolution
from cyphy.lang.scopes import Scopes, is_constant, is_machine
from cyphy.model.connections import machines_run_by, unconnected_events
from cyphy.model.evaluate import EvalError, evaluate
from cyphy.records import record


@record(slots=False)
class MachineNode:
    """A state or pseudo-state; ``key`` is its path in the machine (``Outer::Inner``)."""

    key: str
    kind: str  # state, initial, junction, final
    decl: ast.State | ast.MachineNode
    parent: str | None  # the composite state that contains it (None: the machine)

    @property
    def name(self) -> str:
        return self.decl.name

    @property
    def span(self) -> Span:
        return self.decl.span

    @property
    def composite(self) -> bool:
        return isinstance(self.decl, ast.State) and bool(
            self.decl.states or self.decl.nodes)

    def actions(self, kind: str) -> tuple[ast.Statement, ...]:
        return self.decl.actions(kind) if isinstance(self.decl, ast.State) else ()


@record(slots=False)
class MachineTransition:
    decl: ast.Transition
    container: str | None  # the composite state that declares it (None: the machine)
    source: str | None  # node keys; None when the name does not resolve
    target: str | None

    @property
    def name(self) -> str:
        return self.decl.name


@record(frozen=False, slots=False)
class Platform:
    """What a machine may use of its robotic platform: the events it reads (input
    context), the events it sends and the operations it calls (output context)."""

    input_events: dict[str, ast.EventDecl] = field(default_factory=dict)
    output_events: dict[str, ast.EventDecl] = field(default_factory=dict)
    operations: dict[str, ast.OperationSig] = field(default_factory=dict)
    variables: dict[str, ast.VarDecl] = field(default_factory=dict)
    # The variables of the interfaces the machine ``requires`` (RoboChart's rule: a required
    # variable is the context's, here the robotic platform's): it reads and assigns them,
    # and each assignment is an output of the cycle, written to the platform's mapping.
    written: dict[str, ast.VarDecl] = field(default_factory=dict)


@record(frozen=False, slots=False)
class Machine:
    decl: ast.StateMachine
    file: ast.SourceFile
    nodes: dict[str, MachineNode]
    transitions: list[MachineTransition]
    platform: Platform
    constants: dict[str, ast.VarDecl]
    variables: dict[str, ast.VarDecl]
    clocks: dict[str, ast.ClockDecl]
    #: The input events no connection of the module running the machine carries to it: they
    #: never occur for it (RoboChart). Set by :func:`select_machine`, which knows the module.
    unconnected: frozenset[str] = frozenset()

    @property
    def name(self) -> str:
        return self.decl.name

    def children(self, container: str | None) -> list[MachineNode]:
        return [n for n in self.nodes.values() if n.parent == container]

    def initial(self, container: str | None) -> MachineNode | None:
        """The initial junction of the machine (or of a composite state)."""
        return next((n for n in self.children(container) if n.kind == "initial"), None)

    def outgoing(self, key: str) -> list[MachineTransition]:
        """Transitions leaving a node, in the order written (the interpreter's priority
        among simultaneously enabled transitions)."""
        return [t for t in self.transitions if t.source == key]

    @property
    def cycle(self) -> ex.Expr | None:
        """The right side of ``cycleDef cycle == e`` (None when the machine has none)."""
        for c in self.decl.cycle_defs:
            e = c.expr
            if isinstance(e, ex.BinOp) and e.op == "==" and e.left == ex.Name(("cycle",)):
                return e.right
        return None

    @property
    def states(self) -> list[MachineNode]:
        return [n for n in self.nodes.values() if n.kind == "state"]

    @property
    def junctions(self) -> list[MachineNode]:
        return [n for n in self.nodes.values() if n.kind in ("initial", "junction")]


def build_machine(stm: ast.StateMachine, file: ast.SourceFile, resolution: Resolution
                  ) -> Machine:
    nodes: dict[str, MachineNode] = {}
    pending: list[tuple[ast.Transition, str | None]] = []

    def walk(members: tuple[object, ...], parent: str | None) -> None:
        prefix = f"{parent}::" if parent else ""
        for m in members:
            if isinstance(m, ast.State):
                key = prefix + m.name
                nodes.setdefault(key, MachineNode(key, "state", m, parent))
                walk(m.members, key)
            elif isinstance(m, ast.MachineNode):
                key = prefix + m.name
                nodes.setdefault(key, MachineNode(key, m.kind, m, parent))
            elif isinstance(m, ast.Transition):
                pending.append((m, parent))

    walk(stm.members, None)
    transitions = []
    for t, parent in pending:
        transitions.append(MachineTransition(t, parent, _end(nodes, parent, t.source),
                                             _end(nodes, parent, t.target)))
    variables = {v.name: v for v in stm.variables if v.kind is ast.DeclKind.VAR}
    constants = {v.name: v for v in stm.variables if v.kind is ast.DeclKind.CONST}
    for p in stm.params:
        constants.setdefault(p.name, ast.VarDecl(ast.DeclKind.CONST, p.name, p.type, None,
                                                 span=p.span))
    clocks = {c.name: c for c in stm.clocks}
    return Machine(stm, file, nodes, transitions, machine_platform(stm, resolution),
                   constants, variables, clocks)


def _end(nodes: dict[str, MachineNode], parent: str | None, name: str | None) -> str | None:
    """A transition's end, looked up in the scope that declares the transition."""
    if name is None:
        return None
    key = f"{parent}::{name}" if parent else name
    return key if key in nodes else None


def machine_platform(stm: ast.StateMachine, resolution: Resolution) -> Platform:
    """Events and operations of the interfaces a machine's contexts name: ``uses`` in the
    input context gives input events, ``uses`` in the output context output events,
    ``requires`` operations (and ``provides``, variables)."""
    p = Platform()
    direct = [(u, "input" if u.relation == "uses" else "output")
              for u in stm.members if isinstance(u, ast.InterfaceUse)]
    uses = direct + [(u, c.direction) for c in stm.contexts for u in c.members]
    for use, direction in uses:
        interface = resolution.get(use)
        if not isinstance(interface, ast.Interface):
            continue
        for e in interface.events:
            if use.relation == "uses":
                (p.input_events if direction == "input" else p.output_events).setdefault(
                    e.name, e)
        if use.relation in ("requires", "provides"):
            for op in interface.operations:
                p.operations.setdefault(op.name, op)
            for v in interface.variables:
                p.variables.setdefault(v.name, v)
                if use.relation == "requires" and v.kind is ast.DeclKind.VAR:
                    p.written.setdefault(v.name, v)
    return p


def machines_of(files: Iterator[ast.SourceFile] | list[ast.SourceFile], resolution: Resolution,
                operations: bool = False) -> list[Machine]:
    """Every state machine (top-level or inside a controller) of the files, in file order;
    with ``operations``, also every operation definition that has a behaviour (nodes or
    transitions: ``operation op() { terminates }`` only declares one)."""
    out = []
    for f, stm in _behaviours(files):
        if stm.kind == "stm" or operations and (stm.nodes or stm.states or stm.transitions):
            out.append(build_machine(stm, f, resolution))
    return out


def _behaviours(files: Iterator[ast.SourceFile] | list[ast.SourceFile]
                ) -> Iterator[tuple[ast.SourceFile, ast.StateMachine]]:
    for f in files:
        for item in f.items:
            stms = [item] if isinstance(item, ast.StateMachine) else list(
                item.machines) if isinstance(item, ast.Controller) else []
            for stm in stms:
                yield f, stm


def called_operation(machine: Machine, call: ex.Call, scopes: Scopes
                     ) -> ast.StateMachine | None:
    """The operation definition a call ``op(args)`` (without ``$``) names, if any."""
    if not isinstance(call.func, ex.Name):
        return None
    found = [d for d in scopes.lookup(machine.file, call.func.parts, is_machine)
             if isinstance(d, ast.StateMachine) and d.kind == "operation"]
    return found[0] if found else None


def operation_definitions(machine: Machine, files: list[ast.SourceFile],
                          resolution: Resolution, scopes: Scopes) -> dict[str, Machine]:
    """The operation definitions the machine calls, and those they call, by the name they
    are called with: what the interpreter runs inline."""
    where = {id(stm): f for f, stm in _behaviours(files)}
    out: dict[str, Machine] = {}
    todo = [machine]
    while todo:
        m = todo.pop()
        for s, _ in statements(m):
            if not (isinstance(s, ast.CallStatement) and isinstance(s.call, ex.Call)):
                continue
            decl = called_operation(m, s.call, scopes)
            name = s.call.func.parts[-1] if isinstance(s.call.func, ex.Name) else ""
            if decl is None or name in out or id(decl) not in where:
                continue
            out[name] = build_machine(decl, where[id(decl)], resolution)
            todo.append(out[name])
    return out


def statements(machine: Machine) -> Iterator[tuple[ast.Statement, str]]:
    """Every statement of the machine with where it is (``entry of S``, ``transition t``)."""
    for n in machine.nodes.values():
        for kind in ("entry", "during", "exit"):
            for s in n.actions(kind):
                yield s, f"{kind} action of {n.key}"
    for t in machine.transitions:
        for s in t.decl.action or ():
            yield s, f"transition {t.name}"


def expressions(machine: Machine) -> Iterator[tuple[ex.Expr, str]]:
    """Every expression of the machine's behaviour, with where it is."""
    for t in machine.transitions:
        for e in (t.decl.trigger, t.decl.condition):
            if e is not None:
                yield e, f"transition {t.name}"
    for s, where in statements(machine):
        for e in statement_expressions(s):
            yield e, where


def statement_expressions(s: ast.Statement) -> tuple[ex.Expr, ...]:
    if isinstance(s, ast.Assign):
        return (s.target, s.value)
    if isinstance(s, ast.CallStatement):
        return (s.call,)
    if isinstance(s, ast.SendStatement):
        return (s.event, s.value)
    if isinstance(s, ast.WaitStatement):
        return (s.cycles,)
    return ()


def global_constants(machine: Machine, scopes: Scopes) -> dict[str, object]:
    """Values of the constants declared outside the machine that its expressions name
    (``PI`` of ``physmod::math``, a package's ``const``), by name; a constant without a
    value, or whose value cannot be computed, is left out (the interpreter then reports
    the name where it is used)."""
    local = set(machine.constants) | set(machine.variables) | set(machine.clocks)
    names = sorted({n.text for e, _ in expressions(machine) for n in e.walk()
                    if isinstance(n, ex.Name) and n.text not in local})
    names += sorted({n.text for d in machine.constants.values() if d.value is not None
                     for n in d.value.walk() if isinstance(n, ex.Name)} - local - set(names))
    values: dict[str, object] = {}
    todo = list(names)
    for _ in range(8):  # constants defined by constants, a few levels deep
        left = []
        for name in todo:
            found = scopes.lookup(machine.file, tuple(name.split("::")), is_constant)
            decl = found[0] if found else None
            if not isinstance(decl, ast.VarDecl) or decl.value is None:
                continue
            try:
                values[name] = evaluate(decl.value, values)
            except EvalError:
                left.append(name)
                todo += [n.text for n in decl.value.walk() if isinstance(n, ex.Name)
                         and n.text not in values and n.text not in todo]
        if not left:
            break
        todo = left
    return values


def open_constants(machine: Machine, scopes: Scopes, given: set[str] = frozenset()
                   ) -> dict[str, ast.VarDecl]:
    """The constants without a value that ``machine`` declares or reads from outside it
    (the paper's open constants: the model is a family), by the name its expressions use,
    the declaration's first; ``given`` names those a command gives (``--const``), which are
    not open. An operation's parameters are bound at each call, so never open."""
    params = {p.name for p in machine.decl.params}
    out: dict[str, ast.VarDecl] = {}
    for name, decl in machine.constants.items():
        if decl.value is None and name not in params and name not in given:
            out[name] = decl
    local = set(machine.constants) | set(machine.variables) | set(machine.clocks) | params
    for e, _ in expressions(machine):
        for node in e.walk():
            if not isinstance(node, ex.Name) or node.text in local or node.text in out or \
                    node.parts[-1] in given:
                continue
            found = scopes.lookup(machine.file, node.parts, is_constant)
            decl = found[0] if found else None
            if isinstance(decl, ast.VarDecl) and decl.value is None:
                out[node.text] = decl
    return out


def select_machine(files: list[ast.SourceFile], resolution: Resolution, pmodel: str | None,
                   name: str | None) -> tuple[Machine | None, tuple[str, str]]:
    """The machine that controls ``pmodel``: the one named ``name``, else the only one the
    controllers of the module mapped onto ``pmodel`` run, else the only one of the files.
    None with a message and a hint when there is no such single machine."""
    machines = machines_of(files, resolution)
    if name is not None:
        chosen = [m for m in machines if m.name == name]
        if chosen:
            return _connect(chosen[0], files, resolution, pmodel), ("", "")
        return None, (f"no state machine '{name}' among the files",
                      did_you_mean(name, [m.name for m in machines]) or
                      "machines: " + (", ".join(m.name for m in machines) or "(none)"))
    running = run_by_mapped_module(files, resolution, pmodel) if pmodel else set()
    chosen = [m for m in machines if id(m.decl) in running] or machines
    if len(chosen) == 1:
        return _connect(chosen[0], files, resolution, pmodel), ("", "")
    if chosen:
        return None, (f"the d-model has several state machines "
                      f"({', '.join(m.name for m in chosen)})",
                      'name one with --machine NAME (or machine = "NAME" in the scenario)')
    return None, ("the files have no state machine",
                  "add the d-model's files, or a [controller] table")


def select_machines(files: list[ast.SourceFile], resolution: Resolution, pmodel: str | None,
                    name: str | None) -> tuple[list[Machine], tuple[str, str]]:
    """The machines that control ``pmodel``: as :func:`select_machine`, except that when the
    module mapped onto ``pmodel`` runs several (one per controller, or a controller with
    several), all of them, in the order its controllers declare them: the module runs them
    all, every cycle. Empty with a message and a hint when there is none to choose."""
    machine, problem = select_machine(files, resolution, pmodel, name)
    if machine is not None:
        return [machine], problem
    if name is not None or pmodel is None:
        return [], problem
    running = run_by_mapped_module(files, resolution, pmodel)
    by_id = {id(m.decl): m for m in machines_of(files, resolution)}
    chosen = [by_id[i] for i in running if i in by_id]
    if len(chosen) > 1:
        return [_connect(m, files, resolution, pmodel) for m in chosen], ("", "")
    return [], problem


def _connect(machine: Machine, files: list[ast.SourceFile], resolution: Resolution,
             pmodel: str | None) -> Machine:
    """The machine with the input events its module does not carry to it (in the module
    mapped onto ``pmodel``, when there is one) marked ``unconnected``."""
    mapped = {id(m) for m in _mapped_modules(files, resolution, pmodel)} if pmodel else set()
    machine.unconnected = unconnected_events(files, resolution, machine.decl,
                                             machine.platform.input_events, mapped or None)
    return machine


def _mapped_modules(files: list[ast.SourceFile], resolution: Resolution, pmodel: str
                    ) -> Iterator[ast.Module]:
    """The modules that the mappings onto ``pmodel`` map."""
    for f in files:
        for mapping in f.items:
            if isinstance(mapping, ast.PlatformMapping) and mapping.pmodel[-1] == pmodel:
                module = resolution.get(mapping)
                if isinstance(module, ast.Module):
                    yield module


def run_by_mapped_module(files: list[ast.SourceFile], resolution: Resolution, pmodel: str
                          ) -> dict[int, None]:
    """Ids of the machines that the controllers of the module mapped onto ``pmodel`` run,
    in the order the module declares its controllers and they their machines."""
    return dict.fromkeys(id(stm) for module in _mapped_modules(files, resolution, pmodel)
                         for *_, stm in machines_run_by(module, resolution))
