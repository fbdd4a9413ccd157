"""RoboSim state machines: STM1-STM7.

A machine's transitions join nodes of the scope that declares them (STM1); the machine and
each composite state start at one initial junction (STM2); what it calls and the events it
reads and sends are those of its contexts, and of the robotic platform of the module whose
controller runs it (STM3, STM4); the names of its expressions and statements resolve (STM5).
Two warnings judge the behaviour: states no transition path reaches (STM6), and junctions
whose conditions can all be false, or two true at once, for some values (STM7, decided with
Z3, so only with ``check --consistency``).

Interfaces and types were resolved with the other names (S1); these checks stay silent about
what did not resolve there.
"""

from __future__ import annotations

from typing import Any, Iterator

from cyphy import expr as ex
from cyphy.diagnostics import Severity, did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import to_notation, type_to_notation
from cyphy.lang.scopes import is_constant, is_function, is_machine
from cyphy.model.evaluate import MATH_FUNCTIONS
from cyphy.model.machines import (Machine, called_operation, expressions, machines_of,
                                  statements)
from cyphy.wellformed.platform_services import Platform, Service, module_platform
from cyphy.wellformed.registry import WFContext, rule

SINCE = "since"


def checked_machines(ctx: WFContext) -> list[Machine]:
    """The files' machines and operation definitions, built once per check (every STM rule,
    in this module and the others, walks them)."""
    if "machines" not in ctx.cache:
        ctx.cache["machines"] = machines_of(list(ctx.files()), ctx.resolution, operations=True)
    return ctx.cache["machines"]  # type: ignore[no-any-return]


def machine_kind(m: Machine) -> str:
    """``machine M`` or ``operation Op`` (operation definitions are checked as machines)."""
    return f"{'operation' if m.decl.kind == 'operation' else 'machine'} {m.name}"


@rule("STM1", "a transition goes from and to nodes of the scope that declares it")
def check_STM1_transition_ends(ctx: WFContext) -> None:
    """Each transition names its source (``from``) and target (``to``), and both are states
    or junctions of the machine or composite state in which it is written."""
    for m in checked_machines(ctx):
        for t in m.transitions:
            scope = [n.name for n in m.children(t.container)]
            where = f"state {t.container}" if t.container else machine_kind(m)
            for end, key, span in (("from", t.source, t.decl.source_span),
                                   ("to", t.target, t.decl.target_span)):
                name = t.decl.source if end == "from" else t.decl.target
                if name is None:
                    ctx.error("STM1", t.decl, f"transition {t.name} has no '{end}'",
                              f"add '{end} NODE' naming a state or junction of {where}")
                elif key is None:
                    ctx.error("STM1", span or t.decl.span,
                              f"transition {t.name}: '{name}' is not a state or junction of "
                              f"{where}", did_you_mean(name, scope) or
                              f"nodes: {', '.join(scope) or '(none)'}")


@rule("STM2", "a machine and each composite state have one initial junction")
def check_STM2_initial_junction(ctx: WFContext) -> None:
    """Execution starts at the initial junction: a machine (and each composite state) has
    exactly one, and a transition leaves it."""
    for m in checked_machines(ctx):
        containers: list[tuple[str | None, Any]] = [(None, m.decl)]
        containers += [(n.key, n.decl) for n in m.states if n.composite]
        for key, decl in containers:
            initials = [n for n in m.children(key) if n.kind == "initial"]
            what = f"state {key}" if key else machine_kind(m)
            if not initials:
                ctx.error("STM2", decl, f"{what} has no initial junction",
                          "add 'initial i0' and a transition from it to the first state")
            for extra in initials[1:]:
                ctx.error("STM2", extra.decl, f"{what} has a second initial junction "
                          f"'{extra.name}' (the first is '{initials[0].name}')",
                          "keep one initial junction")
            for i in initials[:1]:
                if not m.outgoing(i.key):
                    ctx.error("STM2", i.decl, f"no transition leaves the initial junction "
                              f"{i.name} of {what}",
                              f"add 'transition t0 {{ from {i.name} to STATE }}'")


# --------------------------------------------------------------------------- platform


def _platforms(ctx: WFContext) -> dict[int, list[tuple[ast.Module, Platform]]]:
    """Machine declaration id → the modules (with their platform) whose controllers run it."""
    if "machine platforms" in ctx.cache:
        return ctx.cache["machine platforms"]  # type: ignore[no-any-return]
    out: dict[int, list[tuple[ast.Module, Platform]]] = {}
    ctx.cache["machine platforms"] = out
    for f in ctx.workspace.files.values():
        for module in f.items:
            if not isinstance(module, ast.Module):
                continue
            platform = module_platform(ctx, module)
            if platform is None:
                continue
            for ctrl in _controllers(ctx, module):
                for stm in _controller_machines(ctx, ctrl):
                    out.setdefault(id(stm), []).append((module, platform))
    return out


def _controllers(ctx: WFContext, module: ast.Module) -> Iterator[ast.Controller]:
    for m in module.members:
        if isinstance(m, ast.Controller):
            yield m
        elif isinstance(m, ast.NodeRef):
            target = ctx.target(m)
            if isinstance(target, ast.Controller):
                yield target


def _controller_machines(ctx: WFContext, ctrl: ast.Controller) -> Iterator[ast.StateMachine]:
    yield from ctrl.machines
    for ref in ctrl.machine_refs:
        target = ctx.target(ref)
        if isinstance(target, ast.StateMachine):
            yield target


def _module_platforms(ctx: WFContext, m: Machine) -> list[tuple[ast.Module, Platform]]:
    return _platforms(ctx).get(id(m.decl), [])


def callee_of(ctx: WFContext, m: Machine, call: ex.Call) -> tuple[str, bool] | None:
    """The operation a call statement names and whether it is written ``$op``; None for a
    call of a function or an operation definition (checked as an expression)."""
    func = call.func
    if isinstance(func, ex.PlatformRef):
        return func.name[-1], True
    if isinstance(func, ex.Name):
        name = func.parts[-1]
        if len(func.parts) == 1 and (name in MATH_FUNCTIONS or ctx.scopes.lookup(
                m.file, func.parts, is_function)):
            return None
        if ctx.scopes.lookup(m.file, func.parts, is_machine):
            return None
        return name, False
    return None


@rule("STM3", "a machine calls operations of its output context that its platform provides")
def check_STM3_operation_calls(ctx: WFContext) -> None:
    """A call ``$op(args)`` (or ``I::op(args)``, ``op(args)``) names an operation of an
    interface that the machine's output context ``requires``, with as many arguments as the
    operation has parameters; when a module's controller runs the machine, that module's
    robotic platform provides the operation. A call ``op(args)`` of an operation definition
    passes as many arguments as the definition has parameters."""
    for m in checked_machines(ctx):
        for s, where in statements(m):
            if not (isinstance(s, ast.CallStatement) and isinstance(s.call, ex.Call)):
                continue
            defined = called_operation(m, s.call, ctx.scopes)
            if defined is not None and len(defined.params) != len(s.call.args):
                n = len(defined.params)
                ctx.error("STM3", s, f"{where}: operation {defined.name} takes {n} argument"
                          f"{'s' if n != 1 else ''}, not {len(s.call.args)}",
                          f"write {defined.name}({', '.join(p.name for p in defined.params)})")
            callee = callee_of(ctx, m, s.call)
            if callee is None:
                continue
            name, _ = callee
            op = m.platform.operations.get(name)
            if op is None:
                ctx.error("STM3", s, f"{where}: '{name}' is not an operation of the output "
                          f"context of {m.name}", did_you_mean(name, m.platform.operations)
                          or "add 'output context { requires I }' with an interface I that "
                          f"declares {name}(…)")
                continue
            if len(op.params) != len(s.call.args):
                ctx.error("STM3", s, f"{where}: {name} takes {len(op.params)} argument"
                          f"{'s' if len(op.params) != 1 else ''}, not {len(s.call.args)}",
                          f"write {name}({', '.join(p.name for p in op.params)})")
            for module, platform in _module_platforms(ctx, m):
                if name not in platform.operations:
                    ctx.error("STM3", s, f"{where}: the robotic platform "
                              f"{platform.platform.name} of module {module.name} does not "
                              f"provide the operation {name}",
                              "add 'provides I' to the platform, with the interface that "
                              f"declares {name}")


@rule("STM4", "a machine reads and sends events of its contexts and of its platform")
def check_STM4_events(ctx: WFContext) -> None:
    """``$e`` in a condition or trigger names an input event (an event of an interface the
    input context ``uses``) and ``$e!v`` an output event; when a module's controller runs
    the machine, its robotic platform uses the input events. ``$e?x`` binds a variable.
    A value travels only with a typed event: ``$e!v`` and ``$e?x`` name typed events, and a
    typed output event is sent with its value (``$e!v``, not ``$e``); the value's type is
    STM8's."""
    for m in checked_machines(ctx):
        sent = {id(s.event) for s, _ in statements(m) if isinstance(s, ast.SendStatement)}
        _check_event_values(ctx, m)
        called = {id(s.call.func) if isinstance(s.call, ex.Call) else id(s.call)
                  for s, _ in statements(m) if isinstance(s, ast.CallStatement)}
        for e, where in expressions(m):
            for node in e.walk():
                if not isinstance(node, ex.PlatformRef) or id(node) in called:
                    continue
                name = node.name[-1]
                if id(node) in sent or name in m.platform.output_events and \
                        name not in m.platform.input_events:
                    if name not in m.platform.output_events:
                        ctx.error("STM4", node, f"{where}: '{name}' is not an output event "
                                  f"of {m.name}", did_you_mean(name, m.platform.output_events)
                                  or "add 'output context { uses I }' with an interface I "
                                  f"that declares event {name}")
                    continue
                if name in m.platform.written and name not in m.platform.input_events:
                    _check_provided(ctx, m, node, name, where)  # ``$speed``: as ``speed``
                    continue
                if name not in m.platform.input_events:
                    ctx.error("STM4", node, f"{where}: '{name}' is not an input event of "
                              f"{m.name}", did_you_mean(name, m.platform.input_events) or
                              "add 'input context { uses I }' with an interface I that "
                              f"declares event {name}")
                    continue
                if node.binding is not None and node.binding not in m.variables:
                    ctx.error("STM4", node, f"{where}: '${name}?{node.binding}' binds "
                              f"'{node.binding}', which is not a variable of {m.name}",
                              did_you_mean(node.binding, m.variables) or
                              f"declare 'var {node.binding}: …'")
                for module, platform in _module_platforms(ctx, m):
                    if name in m.platform.input_events and name not in platform.events:
                        ctx.error("STM4", node, f"{where}: the robotic platform "
                                  f"{platform.platform.name} of module {module.name} has no "
                                  f"event {name}", "add 'uses I' to the platform, with the "
                                  f"interface that declares event {name}")


def _check_event_values(ctx: WFContext, m: Machine) -> None:
    """STM4's shape of a communication: a value on an untyped event, none on a typed one
    (the platform's mapping of a typed event has a parameter, PMap5, that nothing would
    define; an untyped one has nowhere to put the value)."""
    for s, where in statements(m):
        if isinstance(s, ast.SendStatement) and isinstance(s.event, ex.PlatformRef):
            name = s.event.name[-1]
            event = m.platform.output_events.get(name)
            if event is not None and event.type is None:
                ctx.error("STM4", s, f"{where}: '${name}!…' sends a value, but the event "
                          f"{name} has no type", f"write '${name}' to send it, or declare "
                          f"'event {name}: TYPE'")
        elif isinstance(s, ast.CallStatement) and isinstance(s.call, ex.PlatformRef):
            name = s.call.name[-1]
            event = m.platform.output_events.get(name)
            if event is None and name not in m.platform.operations:
                # ``$e`` as a statement sends e: simulate would call an operation e
                ctx.error("STM4", s, f"{where}: '${name}' as a statement sends {name}, but "
                          f"{name} is not an output event of {m.name}" +
                          (": it is an input event, which the machine reads in a condition"
                           if name in m.platform.input_events else ""),
                          f"read it in a condition ('condition ${name}')"
                          if name in m.platform.input_events else
                          did_you_mean(name, m.platform.output_events) or
                          "add 'output context { uses I }' with an interface I that "
                          f"declares event {name}")
            if event is not None and event.type is not None and \
                    name not in m.platform.input_events:
                ctx.error("STM4", s, f"{where}: '${name}' sends no value, but the event "
                          f"{name} carries a value of type {type_to_notation(event.type)}",
                          f"write '${name}!VALUE'")
    for e, where in expressions(m):
        for node in e.walk():
            if not isinstance(node, ex.PlatformRef) or node.binding is None:
                continue
            name = node.name[-1]
            event = m.platform.input_events.get(name)
            if event is not None and event.type is None:
                ctx.error("STM4", node, f"{where}: '${name}?{node.binding}' binds the value "
                          f"of {name}, but the event has no type", f"read it as '${name}', "
                          f"or declare 'event {name}: TYPE'")


@rule("STM5", "the names of a machine's expressions and statements resolve")
def check_STM5_names(ctx: WFContext) -> None:
    """Expressions name the machine's constants, variables and parameters, constants and
    functions in scope, and clocks only as ``since(C)``; ``#C`` names a clock; an assignment
    changes a variable. A variable of an interface the machine ``requires`` is the robotic
    platform's, which must provide it."""
    for m in checked_machines(ctx):
        known = set(m.constants) | set(m.variables)
        shared = set(m.platform.written) - known
        for e, where in expressions(m):
            for node in _free_names(e):
                name = node.text
                if name in shared:
                    _check_provided(ctx, m, node, name, where)
                    continue
                if name in known or ctx.scopes.lookup(m.file, node.parts, is_constant):
                    continue
                if name in m.clocks:
                    ctx.error("STM5", node, f"{where}: the clock {name} is read as a value",
                              f"write since({name}): the time since #{name}")
                elif (service := _platform_variable(ctx, m, name)) is not None:
                    ctx.error("STM5", node, f"{where}: unknown name '{name}': the platform's "
                              f"variable {name} ({service.origin}) is not required by {m.name}",
                              f"add 'requires {service.origin.split()[-1]}' to the output "
                              f"context of {m.name}"
                              if service.origin.startswith("interface ") else
                              f"declare var {name} in an interface the platform provides and "
                              f"{m.name} requires")
                else:
                    ctx.error("STM5", node, f"{where}: unknown name '{name}'",
                              did_you_mean(name, known | set(m.clocks)) or
                              f"declare it in {m.name} ('var {name}: real' or 'const …')")
        for s, where in statements(m):
            if isinstance(s, ast.ClockReset) and s.clock not in m.clocks:
                ctx.error("STM5", s, f"{where}: '#{s.clock}' resets no clock of {m.name}",
                          did_you_mean(s.clock, m.clocks) or f"declare 'clock {s.clock}'")
            elif isinstance(s, ast.Assign):
                base = root(s.target)
                if isinstance(base, ex.Name) and base.text in m.constants:
                    ctx.error("STM5", s, f"{where}: '{base.text}' is a constant; it cannot be "
                              "assigned", f"declare it with 'var {base.text}: …'")
                elif (part := _platform_part(s.target, m, shared)) is not None:
                    # a write is one output with the whole value: the mapping's effect
                    ctx.error("STM5", s.target, f"{where}: one part of the platform variable "
                              f"{part} cannot be written alone", f"assign all of {part}")


def _platform_variable(ctx: WFContext, m: Machine, name: str) -> Service | None:
    """The variable ``name`` of the robotic platform of a module that runs the machine, if
    it has one (an unknown name that the machine meant as the platform's)."""
    for _module, platform in _module_platforms(ctx, m):
        if name in platform.variables:
            return platform.variables[name]
    return None


def _check_provided(ctx: WFContext, m: Machine, node: ex.Name, name: str, where: str) -> None:
    """A variable of a required interface is the robotic platform's: each module whose
    controller runs the machine has a platform that provides it (else nothing holds it)."""
    for module, platform in _module_platforms(ctx, m):
        if name not in platform.variables:
            ctx.error("STM5", node, f"{where}: the robotic platform {platform.platform.name} "
                      f"of module {module.name} does not provide the variable {name}",
                      "add 'provides I' to the platform, with the interface that declares "
                      f"var {name}")


def root(e: ex.Expr) -> ex.Expr:
    """The variable an assignment's target is part of: ``x`` of ``x[1]``, ``$x`` of
    ``$x[1]``."""
    while isinstance(e, (ex.Index, ex.Member)):
        e = e.base
    return e



def _platform_part(target: ex.Expr, m: Machine, shared: set[str]) -> str | None:
    """The platform variable of which an assignment's target is one part: ``pair`` of
    ``pair[1]`` (a name the machine does not declare) or of ``$pair[1]``; None for a whole
    variable or a machine's own."""
    if isinstance(target, (ex.Name, ex.PlatformRef)):
        return None
    target = root(target)
    if isinstance(target, ex.PlatformRef):
        return target.name[-1] if target.name[-1] in m.platform.written else None
    return target.text if isinstance(target, ex.Name) and target.text in shared else None


def _free_names(e: ex.Expr) -> Iterator[ex.Name]:
    """Names read as values: not called functions, not ``since``'s clock, not record
    fields."""
    stack = [e]
    while stack:
        node = stack.pop()
        if isinstance(node, ex.Name):
            yield node
        elif isinstance(node, ex.Call):
            if isinstance(node.func, ex.Name) and node.func.text == SINCE:
                continue
            if not isinstance(node.func, (ex.Name, ex.PlatformRef)):
                stack.append(node.func)
            stack.extend(node.args)
        elif isinstance(node, ex.Member):
            stack.append(node.base)
        else:
            stack.extend(node.children())


# --------------------------------------------------------------------------- behaviour


@rule("STM6", "every state of a machine can be reached from its initial junction",
      Severity.WARNING)
def check_STM6_reachable(ctx: WFContext) -> None:
    """Following transitions from the initial junction (whatever their conditions), every
    state is reached; entering a composite state enters its initial junction."""
    for m in checked_machines(ctx):
        start = m.initial(None)
        if start is None:
            continue  # STM2
        seen = {start.key}
        todo = [start.key]
        while todo:
            key = todo.pop()
            nexts = [t.target for t in m.outgoing(key) if t.target is not None]
            node = m.nodes[key]
            if node.composite:
                inner = m.initial(key)
                nexts += [inner.key] if inner else []
            parent = node.parent  # leaving a composite state from inside: its transitions
            while parent is not None:
                nexts += [t.target for t in m.outgoing(parent) if t.target is not None]
                parent = m.nodes[parent].parent
            for n in nexts:
                if n not in seen:
                    seen.add(n)
                    todo.append(n)
        for n in m.states:
            if n.key not in seen:
                ctx.error("STM6", n.decl, f"state {n.key} of {m.name} is unreachable: no "
                          "transition path from the initial junction enters it",
                          "add a transition to it, or remove it")


@rule("STM7", "a junction always has exactly one enabled transition (with --consistency)",
      Severity.WARNING)
def check_STM7_junction_conditions(ctx: WFContext) -> None:
    """A machine must not stop in a junction: for all values of the variables, constants,
    clocks and events, some transition leaving a junction is enabled (else the machine is
    stuck), and no two are (else the choice is nondeterministic). Decided with Z3, so only
    with ``check --consistency`` (plain ``check`` never imports Z3); functions other than
    ``abs``, ``min``, ``max`` are uninterpreted, so a warning about them may be a false
    alarm."""
    if not ctx.z3:
        return
    for m in checked_machines(ctx):
        for j in m.junctions:
            out = m.outgoing(j.key)
            if not out or all(t.decl.condition is None and t.decl.trigger is None
                              for t in out) and len(out) == 1:
                continue
            _junction(ctx, m, j, out)


def _junction(ctx: WFContext, m: Machine, j: Any, out: list[Any]) -> None:
    import z3  # lazy: Z3 takes about 0.1 s to import; only a junction's or a guard's check needs it

    from cyphy.translate.to_z3 import UnsupportedNode  # lazy: imports Z3 (see above)

    try:
        guards, assumptions = _guard_terms(ctx, m, [t.decl for t in out])
    except (UnsupportedNode, z3.Z3Exception):
        return  # an expression Z3 has no counterpart for: nothing decided
    solver = z3.Solver()
    solver.set("timeout", 2000)
    solver.add(*assumptions)
    solver.push()
    solver.add(z3.Not(z3.Or(*guards)))
    if solver.check() == z3.sat:
        ctx.error("STM7", j.decl, f"junction {j.key} of {m.name}: for some values no "
                  "transition leaving it is enabled, and the machine would be stuck there",
                  "conditions: " + "; ".join(
                      f"{t.name}: {to_notation(t.decl.condition) if t.decl.condition else 'true'}"
                      for t in out) + " (add the missing case)")
    solver.pop()
    for a in range(len(out)):
        for b in range(a + 1, len(out)):
            solver.push()
            solver.add(guards[a], guards[b])
            if solver.check() == z3.sat:
                ctx.error("STM7", out[b].decl, f"junction {j.key} of {m.name}: transitions "
                          f"{out[a].name} and {out[b].name} can be enabled at once",
                          "make their conditions exclusive (the interpreter takes the one "
                          "written first)")
            solver.pop()


def _guard_terms(ctx: WFContext, m: Machine, transitions: list[ast.Transition]
                 ) -> tuple[list[Any], list[Any]]:
    """Each transition's trigger and condition as a Z3 formula, and what is assumed of the
    unknowns (clocks are non-negative, natural numbers too, divisors are not zero).
    Constants with a literal value are that value; everything else is an unknown of its
    declared type: events and booleans are Booleans, ``int``/``nat`` integers."""
    import z3  # lazy: Z3 (see _junction)

    from cyphy.translate.to_z3 import Z3Printer, rational  # lazy: imports Z3 (see _junction)

    symbols: dict[str, Any] = {}
    assumptions: list[Any] = []

    def declared(name: str) -> Any:
        decl = m.variables.get(name) or m.constants.get(name)
        if decl is not None and isinstance(decl.value, ex.Num) and name in m.constants:
            return rational(decl.value.text)
        kind = decl.type.name if decl is not None and isinstance(
            decl.type, ast.PrimitiveType) else "real"
        if name in ctx.consts and isinstance(ctx.consts[name], (int, float)) and \
                not isinstance(ctx.consts[name], bool):
            return rational(ctx.consts[name])
        if kind == "boolean":
            return z3.Bool(name)
        if kind in ("int", "nat"):
            v = z3.Int(name)
            if kind == "nat":
                assumptions.append(v >= 0)
            return v
        return z3.Real(name)

    def symbol(name: str, node: ex.Expr) -> Any:
        if name not in symbols:
            symbols[name] = declared(name)
        return symbols[name]

    class Printer(Z3Printer):
        def _print_PlatformRef(self, e: ex.PlatformRef) -> Any:
            key = "$" + e.text
            if key not in symbols:
                symbols[key] = z3.Real(key) if e.name[-1] in m.platform.variables \
                    else z3.Bool(key)
            return symbols[key]

        def _print_Call(self, e: ex.Call) -> Any:
            if isinstance(e.func, ex.Name) and e.func.text == SINCE and len(e.args) == 1 \
                    and isinstance(e.args[0], ex.Name):
                key = f"since({e.args[0].text})"
                if key not in symbols:
                    symbols[key] = z3.Real(key)
                    assumptions.append(symbols[key] >= 0)
                return symbols[key]
            return super()._print_Call(e)

    printer = Printer(symbol)
    guards = []
    for t in transitions:
        parts = [printer.defined(e) for e in (t.trigger, t.condition) if e is not None]
        guards.append(z3.And(*parts) if parts else z3.BoolVal(True))
    assumptions += [d != 0 for d in printer.divisors]
    return guards, assumptions
