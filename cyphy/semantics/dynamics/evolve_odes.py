"""Evolve as an explicit ODE ``x' = f(state)``: what the axiomatic Isabelle dialect needs.

The CyPhyCircus ``Evolve`` holds the model's equations as a DAE with existentially quantified
locals; Ax_CyPhyCircus's evolution takes one explicit derivative per continuous variable
(``../shared/spec/isabelle.md`` section 1.3). The equations are reduced by the path that
``cyphy solve`` and the Flow* exporter take (:func:`cyphy.semantics.dynamics.equations.assemble`, with
the whole model's equations of motion, then :func:`cyphy.semantics.dynamics.reduce.reduce_system`), and
the result is put back into the expression AST for the Isabelle printer. Both sides are
scalar by the same pass (:mod:`cyphy.semantics.scalarise`): the theory's state has a field
``X_k`` per component of a vector ``X``, and the reduction names its components so:

- every reduced state gets its ODE (device locals such as ``LMotor_av`` and the states that
  stand for integrals, ``LMotor_int1``, are no state-schema fields: the caller adds them to
  the alphabet, because an evolving variable must be one);
- every state-schema field that the reduction gives as a function ``y = g(x, u)`` of the
  states (an output such as ``LMotor_T``) gets ``y' = dg/dt`` by the chain rule, so that it
  follows the states while they evolve (it holds ``y = g`` only where it held at the start);
- derivatives of inputs are zero (during Evolve the software changes nothing), and the
  equations that are the semantics' own (``timer' = 1``) are kept as they are.

SymPy is imported here, so only the axiomatic path of ``cyphy gen --isabelle`` imports it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import sympy

from cyphy import codes
from cyphy import expr as ex
from cyphy.semantics.dynamics.obstacles import obstacle_code, obstacle_hint
from cyphy.semantics.dynamics.reduce import Reduced, reduce_system
from cyphy.translate.to_sympy import T, NotAnExpression, to_expr
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.circus import ast as c
from cyphy.semantics.dynamics.equations import ASSEMBLY, AssemblyError, System, assemble
from cyphy.semantics.scalarise.shapes import components, type_shape

NOT_EXPLICIT = codes.code("E-ISABELLE-ODE", codes.E,
                          "Evolve cannot be written as the explicit ODE of the axiomatic "
                          "Isabelle dialect")
HINT = ("use the default dialect (--isabelle-dialect utp), which keeps the equations as they "
        "are, restrict Evolve to the elements that matter (--isabelle-element, as for `cyphy "
        "solve --element`), or make the equations solvable")


@dataclass(frozen=True)
class ExplicitOde:
    """``variable' = rhs``; ``kind`` says where it comes from: ``state`` (a reduced state),
    ``output`` (the chain rule on an output's solution), ``input`` (a world input, at its
    rate) or ``given`` (the semantics' own equation, ``timer' = 1``)."""

    variable: str
    rhs: ex.Expr
    kind: str
    value: ex.Expr | None = None  # an output's: its value as a function of the states


@dataclass
class EvolveOdes:
    odes: list[ExplicitOde] = field(default_factory=list)
    added: list[str] = field(default_factory=list)  # evolving variables no schema field holds
    # the rate of each world input that varies (``u' = u_rate``): constant during one
    # evolution, chosen afresh before each (no schema field holds it either)
    rates: list[str] = field(default_factory=list)


def explicit_odes(model: ElaboratedModel, evolution: c.Evolution, state_fields: set[str],
                  elements: tuple[str, ...], report: Report, where: Span,
                  world: frozenset[str] = frozenset()) -> EvolveOdes | None:
    """The explicit ODEs of ``evolution``, or None with every reason reported (``where`` is
    the span for what no equation locates: the mapping's). The inputs of the equations
    among ``world`` (the visible fields: what the world sets) vary: ``u' = u_rate``, the
    outputs' chain rule through them too, so an explicit ODE, which has no free variable,
    does not freeze them (the utp dialect leaves them free)."""
    if not _check_elements(model, elements, report, where):
        return None
    try:
        system = assemble(model, list(elements) or None)
    except AssemblyError as err:  # e.g. a kinematic tree without equations of motion
        report.report(getattr(err, "code", ASSEMBLY), err.message, err.span, err.hint)
        return None
    fields = {k for n in state_fields for k in _components(system, n)}
    reduced = reduce_system(system, frozenset(fields))
    if reduced.obstacles:
        for o in reduced.obstacles:
            span = o.span or (o.equations[0].span if o.equations else where)
            notes = list(o.notes) or [f"{eq.origin}: equation at {eq.span}"
                                      for eq in o.equations]
            structural = o.kind.endswith("determined")  # the model's fault, not the target's
            report.report(obstacle_code(o) if structural else NOT_EXPLICIT,
                          f"Evolve cannot be reduced to explicit ODEs: {o.message}", span,
                          obstacle_hint(o) if structural else HINT, notes)
        return None
    ports = {p.mangled for d in model.devices for p in d.ports}
    return _build(system, reduced, evolution, fields, ports, report, where, world)


def _check_elements(model: ElaboratedModel, elements: tuple[str, ...], report: Report,
                    where: Span) -> bool:
    qualified = {e.name for e in [*model.joints, *model.unconnected, *model.sensors,
                                  *model.actuators]}
    ok = True
    for q in elements:
        if not any(n == q or n.startswith(q + "::") for n in qualified):
            report.report(NOT_EXPLICIT, f"--isabelle-element '{q}' names no element of "
                          f"{model.name}", where, did_you_mean(q, qualified) or
                          f"qualified names start with the p-model: {model.name}::…")
            ok = False
    return ok


def _build(system: System, reduced: Reduced, evolution: c.Evolution, state_fields: set[str],
           ports: set[str], report: Report, where: Span,
           world: frozenset[str] = frozenset()) -> EvolveOdes | None:
    zero = {s: 0 for name, s in reduced.symbols.items() if name.startswith("der_")}
    symbol = {name: reduced.symbols.get(name, sympy.Symbol(name, real=True))
              for name in [*reduced.states, *reduced.outputs]}
    out = EvolveOdes()
    rhs: dict[str, Any] = {}
    values: dict[str, Any] = {}  # the outputs' solutions over the states
    failed = False

    def fail(message: str, name: str) -> None:
        nonlocal failed
        failed = True
        report.report(NOT_EXPLICIT, message, _span_of(system, name, where), HINT)

    for s in reduced.states:
        rhs[s] = sympy.expand(reduced.rhs[s].xreplace(zero))
    known = {symbol[s] for s in rhs} | {sympy.Symbol(k, real=True) for u in system.variables
                                        for k in _components(system, u)}
    known |= {sympy.Symbol(p, real=True) for p in system.parameters}
    determined = set(reduced.states) | set(reduced.outputs)
    inputs = sorted(k for u in system.variables for k in _components(system, u)
                    if (k in world or u in world) and k not in determined)
    rate = {u: sympy.Symbol(f"{u}_rate", real=True) for u in inputs}
    for u in inputs:
        if f"{u}_rate" in state_fields or f"{u}_rate" in symbol:
            fail(f"{u}_rate, the rate of the world input {u}, is already a variable", u)
    for s, f in rhs.items():
        if f.has(T):
            fail(f"the ODE of {s} depends on time itself", s)
        extra = sorted(str(x) for x in f.free_symbols - known)
        if extra:
            fail(f"the ODE of {s} needs {', '.join(extra)}, which no equation determines", s)
    for name in sorted(reduced.outputs):
        if name not in state_fields or name in rhs:
            continue
        g = reduced.outputs[name].xreplace(zero)
        if g.has(T):
            fail(f"{name} depends on time itself", name)
            continue
        rhs_y = sum((sympy.diff(g, symbol[s]) * rhs[s] for s in rhs), sympy.Integer(0))
        rhs_y += sum((sympy.diff(g, sympy.Symbol(u, real=True)) * rate[u] for u in inputs),
                     sympy.Integer(0))
        rhs[name] = sympy.expand(rhs_y)
        values[name] = g
    printed: dict[str, ex.Expr] = {}
    solutions: dict[str, ex.Expr] = {}
    for name, value in rhs.items():
        try:
            printed[name] = to_expr(value)
            if name in values:
                solutions[name] = to_expr(sympy.expand(values[name]))
        except NotAnExpression as err:
            fail(f"the ODE of {name} has a term the printers cannot write: {err}", name)
    if failed:
        return None
    for s in reduced.states:
        out.odes.append(ExplicitOde(s, printed[s], "state"))
        if s not in state_fields:
            out.added.append(s)
    for name in sorted(set(rhs) - set(reduced.states)):
        out.odes.append(ExplicitOde(name, printed[name], "output", solutions[name]))
    for u in inputs:
        out.odes.append(ExplicitOde(u, ex.Name((f"{u}_rate",)), "input"))
        out.rates.append(f"{u}_rate")
    for eq in evolution.equations:  # the semantics' own equations (timer' = 1): no port's
        if isinstance(eq, ex.BinOp) and eq.op == "==" and isinstance(eq.left, ex.Derivative) \
                and isinstance(eq.left.operand, ex.Name) \
                and eq.left.operand.text in state_fields - ports:
            out.odes.append(ExplicitOde(eq.left.operand.text, eq.right, "given"))
    return out


def _components(system: System, name: str) -> list[str]:
    """The scalar variables of ``name`` as the scalarisation names them (itself if scalar)."""
    return components(name, type_shape(system.variables.get(name)) or ())


def _span_of(system: System, name: str, where: Span) -> Span:
    """The first equation that mentions ``name`` (or a component of it)."""
    for eq in system.equations:
        if any(isinstance(n, ex.Name) and (n.text == name or name.startswith(n.text + "_"))
               for n in eq.expr.walk()):
            return eq.span
    return where
