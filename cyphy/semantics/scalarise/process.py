"""A whole p-model process with scalar state: every vector or matrix field of fixed size
replaced by its components, the equations and actions rewritten by the
:class:`~cyphy.semantics.scalarise.scalariser.Scalariser`, and (for provers that need a state
for every ODE) the evolving locals and running integrals promoted to state.
"""

from __future__ import annotations

from dataclasses import replace

from cyphy import expr as ex
from cyphy.records import record
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.values import within
from cyphy.semantics.circus.walk import action_nodes, map_action
from cyphy.semantics.scalarise.scalariser import Scalariser
from cyphy.semantics.scalarise.shapes import ScalariseError, Shape, components, shape_of_type


@record(frozen=True, slots=False)
class ScalarProcess:
    """The p-model process with scalar state: ``process`` has every vector or matrix field
    of fixed size replaced by its components, and (with ``evolving_as_state``) the locals
    whose derivative appears, and one variable per running integral, added to the private
    state (``promoted``); ``held``: the numeric state variables that discrete actions write
    and no derivative determines, which every evolution keeps constant (``x' = 0``)."""

    process: c.BasicProcess
    promoted: tuple[str, ...]
    held: tuple[str, ...]


def scalar_process(pm: c.BasicProcess, evolving_as_state: bool = True) -> ScalarProcess:
    """The pass itself; raises :class:`ScalariseError` where shapes do not fit."""
    shapes: dict[str, Shape] = {}
    unsized: set[str] = set()

    def note(name: str, t: c.Type, value: ex.Expr | None = None) -> None:
        if not isinstance(t, c.TSeq):
            return
        shape = shape_of_type(t)
        if shape is None and value is not None:
            try:
                shape = Scalariser({}, frozenset()).shape(value)
            except ScalariseError:
                shape = None
        if shape:
            shapes[name] = shape
        else:
            unsized.add(name)

    for f in (*pm.state.fields, *pm.local.fields):
        note(f.name, f.type)
    for k in pm.constants:
        note(k.name, k.type, k.value)
    variables = {f.name for f in (*pm.state.fields, *pm.local.fields)}
    sc = Scalariser(shapes, frozenset(n for n in shapes if n in variables), frozenset(unsized))
    taken = variables | {k.name for k in pm.constants} | {d.name for d in pm.actions}
    for name in sorted(sc.split):
        clash = taken.intersection(components(name, shapes[name]))
        if clash:
            raise ScalariseError(ex.Name((name,)), f"the components of {name} would be named "
                                 f"like {', '.join(sorted(clash))}, which the model has")
    integrals: list[str] = []

    def integral_states(equations: list[ex.Expr]) -> list[ex.Expr]:
        added: list[ex.Expr] = []

        def replace_integral(n: ex.Expr) -> ex.Expr | None:
            if not (isinstance(n, ex.Integral) and n.lower is None and n.upper is None):
                return None
            base = n.operand.text if isinstance(n.operand, ex.Name) else "integral"
            name, k = f"{base}_int", 1
            while name in taken:
                k += 1
                name = f"{base}_int{k}"
            taken.add(name)
            integrals.append(name)
            state = ex.Name((name,), span=n.span)
            added.append(ex.BinOp("==", ex.Derivative(state, span=n.span), n.operand,
                                  span=n.span))
            return state

        out = [ex.transform(e, replace_integral)
               if any(isinstance(n, ex.Integral) for n in e.walk()) else e for e in equations]
        return out + added

    def rewrite(a: c.Action) -> c.Action | None:
        if isinstance(a, c.Evolution):
            equations = [q for e in a.equations for q in sc.predicate(e)]
            if evolving_as_state:
                equations = integral_states(equations)
            return replace(a, equations=tuple(equations))
        if isinstance(a, c.Spec):
            frame = tuple(k for n in a.frame
                          for k in (components(n, shapes[n]) if n in sc.split else [n]))
            return replace(a, frame=frame, pre=sc.condition(a.pre), post=sc.condition(a.post))
        if isinstance(a, (c.Cond, c.Guard)):
            return replace(a, cond=sc.condition(a.cond))
        if isinstance(a, c.IndexedExtChoice):
            return replace(a, where=sc.condition(a.where))
        if isinstance(a, c.Assign):
            targets, values = [], []
            for t, v in zip(a.targets, a.values):
                if t in sc.split:
                    names = components(t, shapes[t])
                    targets += names
                    values += [sc.component(v, (k,)) for k in range(len(names))]
                else:
                    targets.append(t)
                    values.append(sc.whole(v))
            return replace(a, targets=tuple(targets), values=tuple(values))
        if isinstance(a, c.Prefix):
            fields = tuple(f if isinstance(f, c.In) else replace(f, value=sc.whole(f.value))
                           for f in a.comm.fields)
            return replace(a, comm=replace(a.comm, fields=fields))
        if isinstance(a, c.Call) and a.args:
            return replace(a, args=tuple(sc.whole(x) for x in a.args))
        return None


    actions = tuple(replace(d, body=map_action(d.body, rewrite)) for d in pm.actions)
    main = map_action(pm.main, rewrite)

    def fields_of(schema: c.Schema) -> list[c.SchemaField]:
        out = []
        for f in schema.fields:
            if f.name in sc.split:
                out += [c.SchemaField(k, c.REAL, f.visible)
                        for k in components(f.name, shapes[f.name])]
            else:
                out.append(f)
        return out

    state, local = fields_of(pm.state), fields_of(pm.local)
    evolutions = [n for d in (*actions, c.ActionDef("", (), main))
                  for n in action_nodes(d.body) if isinstance(n, c.Evolution)]
    derived = {n.operand.text for ev in evolutions for e in ev.equations for n in e.walk()
               if isinstance(n, ex.Derivative) and isinstance(n.operand, ex.Name)}
    promoted: list[str] = []
    if evolving_as_state:
        promoted = [f.name for f in local if f.name in derived] + integrals
        state += [c.SchemaField(n, c.REAL) for n in promoted]
        local = [f for f in local if f.name not in derived]
        actions = tuple(initialised(d, _continuous_states(evolutions, promoted), pm.initial,
                                    pm.ranges) for d in actions)
    written = {t for d in (*actions, c.ActionDef("", (), main)) for n in action_nodes(d.body)
               for t in (n.targets if isinstance(n, c.Assign) else
                         n.frame if isinstance(n, c.Spec) else ())}
    # only numbers have a rate to hold at 0; a Boolean set-point is left to the equations;
    # a visible variable is the world's (a scenario's Init may start it, nothing holds it)
    held = tuple(f.name for f in state if f.name in written and f.name not in derived
                 and f.type in (c.REAL, c.INT, c.NAT) and not f.visible and evolving_as_state)
    if held:
        hold = tuple(ex.BinOp("==", ex.Derivative(ex.Name((h,))), ex.Num("0")) for h in held)

        def add_hold(a: c.Action) -> c.Action | None:
            if isinstance(a, c.Evolution):
                return replace(a, equations=a.equations + hold)
            return None

        actions = tuple(replace(d, body=map_action(d.body, add_hold)) for d in actions)
        main = map_action(main, add_hold)
    process = replace(pm, state=replace(pm.state, fields=tuple(state)),
                      local=replace(pm.local, fields=tuple(local)), actions=actions, main=main)
    return ScalarProcess(process, tuple(promoted), held)


def _continuous_states(evolutions: list[c.Evolution], promoted: list[str]) -> list[str]:
    """The promoted variables that are states of an ODE: the derivative of each is on the
    left of an equation (``x' = v``, ``J * av' = T``; a running integral's own equation is
    one). A local whose derivative is only read (``Kd * e'``) is algebraic: its equation
    gives its value, which an initial assignment could contradict."""
    on_left = {n.operand.text for ev in evolutions for e in ev.equations
               if isinstance(e, ex.BinOp) and e.op == "==" for n in e.left.walk()
               if isinstance(n, ex.Derivative) and isinstance(n.operand, ex.Name)}
    return [n for n in promoted if n in on_left]


def initialised(d: c.ActionDef, states: list[str], initial: tuple[tuple[str, ex.Expr], ...],
                 ranges: tuple[tuple[str, ex.Expr, ex.Expr], ...] = ()) -> c.ActionDef:
    """``Init`` with every continuous state assigned too: a scenario's value or its declared
    initial value, else 0 (spec Rule 2: private variables start at 0; a running integral is
    the integral from 0), or, for a scenario's interval, a specification that starts it in
    the interval. Without it the ODEs' states, once they are state, would start anywhere.
    ``Init`` is an assignment, followed by the scenario's specification when it has one."""
    parts = d.body.items if isinstance(d.body, c.Seq) else (d.body,)
    if d.name != "Init" or not isinstance(parts[0], c.Assign) or not states:
        return d
    assign, rest = parts[0], parts[1:]
    values, boxes = dict(initial), {n: (lo, hi) for n, lo, hi in ranges}
    framed = {n for p in rest if isinstance(p, c.Spec) for n in p.frame}
    missing = [n for n in states if n not in assign.targets and n not in framed]
    points = [n for n in missing if n not in boxes]
    boxed = [(n, *boxes[n]) for n in missing if n in boxes]
    assign = c.Assign(assign.targets + tuple(points), assign.values + tuple(
        values.get(n, ex.Num("0")) for n in points))
    parts = (assign, *rest, *((within(boxed),) if boxed else ()))
    return replace(d, body=parts[0] if len(parts) == 1 else c.Seq(parts))
