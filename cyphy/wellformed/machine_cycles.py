"""What ends a machine's cycle: an ``exec`` on every loop of transitions (STM13), a natural
number of cycles to ``wait`` (STM14).

Under RoboSim's cycle semantics a machine takes transitions until it rests in a state or
meets ``exec``; the cycle's inputs (its events, its clocks' counts) do not change while it
does. A loop of transitions none of which is an ``exec`` transition, through states whose
actions neither ``exec``, ``wait``, nor change a variable (nor reset a clock the loop's
conditions read), therefore runs forever once its conditions hold: their values cannot
change before the loop comes round again.
``simulate`` and ``reach`` refused such a machine at run time ("took 10000 steps without
ending its cycle"), and ``gen --isabelle`` left ``D`` opaque; ``check`` refuses it at the
loop's first transition. A loop whose actions change a variable may end (a counter): it is
left alone.
"""

from __future__ import annotations

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.notation import to_notation
from cyphy.model.machines import Machine, MachineTransition, statements
from cyphy.wellformed.indexing import evaluate_in
from cyphy.wellformed.machines import checked_machines
from cyphy.wellformed.registry import WFContext, rule


def _may_end(statements: tuple[ast.Statement, ...] | None) -> bool:
    """Whether the actions may end the cycle or change what the loop's conditions read:
    ``exec``, ``wait``, an assignment, or a call of an operation definition (which may do
    any of these). A clock reset changes ``since(C)`` once, to 0: it may end the loop only
    when the loop's conditions read ``C`` (:func:`_resets_read`)."""
    for s in statements or ():
        if isinstance(s, (ast.ExecStatement, ast.WaitStatement, ast.Assign)):
            return True
        if isinstance(s, ast.CallStatement) and not (
                isinstance(s.call, ex.PlatformRef) or isinstance(s.call, ex.Call)
                and isinstance(s.call.func, ex.PlatformRef)):
            return True
    return False


def _node_may_end(m: Machine, key: str) -> bool:
    node = m.nodes[key]
    if node.kind == "final" or node.composite:
        return True  # a final state ends the machine; a composite one enters its own
    return any(_may_end(node.actions(kind)) for kind in ("entry", "during", "exit"))


def _loop(m: Machine) -> list[MachineTransition] | None:
    """A loop of transitions without ``exec`` through nodes whose actions cannot end it,
    starting at the first such transition written that is on one; None without one."""
    edges = [t for t in m.transitions if t.source is not None and t.target is not None
             and not t.decl.exec and not _may_end(t.decl.action)
             and not _node_may_end(m, t.source) and not _node_may_end(m, t.target)]
    leaving: dict[str, list[MachineTransition]] = {}
    for t in edges:
        leaving.setdefault(str(t.source), []).append(t)
    for first in edges:
        loop = [first] if first.target == first.source else None
        if loop is None:
            rest = _path(leaving, str(first.target), str(first.source), {str(first.target)})
            loop = None if rest is None else [first, *rest]
        if loop is not None and not _resets_read(m, loop) and not _contradictory(loop):
            return loop
    return None


def _contradictory(loop: list[MachineTransition]) -> bool:
    """Whether the loop's guards cannot all hold in one cycle: one requires a literal (``$e``,
    ``x > 1``) and another its negation (``not $e``), as written. The loop is then never
    completed (A to B on ``$near``, B to A on ``not $near``), and the machine rests.
    Contradictions that need arithmetic to see are not found (the loop is then reported)."""
    texts = {to_notation(part) for t in loop for e in (t.decl.trigger, t.decl.condition)
             if e is not None for part in ex.conjuncts(e)}
    return any(isinstance(part, ex.UnaryOp) and part.op == "not" and
               to_notation(part.operand) in texts
               for t in loop for e in (t.decl.trigger, t.decl.condition) if e is not None
               for part in ex.conjuncts(e))


def _resets_read(m: Machine, loop: list[MachineTransition]) -> bool:
    """Whether the loop resets a clock that its conditions read (``#C`` and ``since(C)``):
    the condition may then change once the clock is reset, and end the loop."""
    actions = [s for t in loop for s in t.decl.action or ()]
    for t in loop:
        node = m.nodes[str(t.source)]
        actions += [s for kind in ("entry", "during", "exit") for s in node.actions(kind)]
    reset = {s.clock for s in actions if isinstance(s, ast.ClockReset)}
    read = {n.args[0].text for t in loop for e in (t.decl.trigger, t.decl.condition)
            if e is not None for n in e.walk() if isinstance(n, ex.Call) and
            isinstance(n.func, ex.Name) and n.func.text == "since" and n.args and
            isinstance(n.args[0], ex.Name)}
    return bool(reset & read)


def _path(leaving: dict[str, list[MachineTransition]], start: str, goal: str,
          seen: set[str]) -> list[MachineTransition] | None:
    """Transitions from ``start`` to ``goal`` through nodes not yet ``seen`` (depth first)."""
    for t in leaving.get(start, []):
        if t.target == goal:
            return [t]
        if t.target in seen:
            continue
        seen.add(str(t.target))
        rest = _path(leaving, str(t.target), goal, seen)
        if rest is not None:
            return [t, *rest]
    return None


@rule("STM13", "a machine's cycle ends: every loop of transitions has an exec, or an action "
      "that may end it")
def check_STM13_cycle_ends(ctx: WFContext) -> None:
    """A loop of transitions without ``exec``, whose states' and transitions' actions neither
    ``exec``, ``wait``, assign a variable, reset a clock its conditions read, nor call an
    operation definition, never ends the cycle once its conditions hold (they read only what the cycle does not
    change). Reported at its first transition, naming the loop; a loop whose guards contradict
    each other as written (``$e`` on one, ``not $e`` on another) is never completed and is
    accepted."""
    for m in checked_machines(ctx):
        loop = _loop(m)
        if loop is None:
            continue
        through = " → ".join([str(loop[0].source), *(str(t.target) for t in loop)])
        names = ", ".join(t.name for t in loop)
        ctx.error("STM13", loop[0].decl, f"transition{'s' if len(loop) > 1 else ''} {names} "
                  f"of {m.name} loop ({through}) with no exec: once their conditions hold, "
                  "the machine takes them for ever and its cycle never ends",
                  f"mark one of them exec ('transition {loop[0].name} {{ from "
                  f"{loop[0].decl.source} to {loop[0].decl.target} exec … }}'), so that "
                  "the machine rests until the next cycle")


@rule("STM14", "wait(n) waits a natural number of cycles")
def check_STM14_wait_cycles(ctx: WFContext) -> None:
    """``wait(n)`` ends the cycle ``n`` times: ``n`` is a whole number, not negative
    (``simulate`` and ``reach`` refused ``wait(-1)`` or ``wait(0.5)`` when the machine
    reached it). ``n`` is evaluated with the machine's constants and those in scope; one
    that reads a variable, or a constant without a value, is left to the run."""
    for m in checked_machines(ctx):
        names = {**m.variables, **m.constants}
        for s, where in statements(m):
            if not isinstance(s, ast.WaitStatement):
                continue
            value, _ = evaluate_in(ctx, m.file, names, s.cycles)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                continue
            if value < 0 or value != int(value):
                ctx.error("STM14", s.cycles, f"{where}: wait({value:g}) waits a number of "
                          "cycles that is not a natural number", "write wait(n) with n a "
                          "whole number of cycles, 0 or more")
