"""A verdict for all time: the Flow* model that checks that the scenario's initial box is an
inductive invariant of the sampled system.

The argument. The automaton is time-invariant when nothing reads the global clock ``t``
(no ODE, event or unsafe atom; functions of time are states whose initial box would have to
recur, which a point box never does). During the first cycle it stays in the initial mode
(jumps happen only at ``timer = cycle × tscale``). If every state a jump at the end of that
cycle leads to is again in the initial mode and inside the initial box (the timer is reset
to 0, its start), every later cycle starts inside the box too, so the reachable set for
every horizon is the union of one cycle's flows from the box; if those avoid the unsafe set,
the system is safe for all time.

The model checks exactly that with one Flow* run: the initial mode over one cycle (its own
unsafe set), each of its jumps redirected, with its guard and reset, to one sink mode per
face of the box (sink ``k``'s unsafe set is the closed outside of face ``k``, ``x >= hi`` or
``x <= lo``: SAFE means the post-jump set lies strictly inside) and jumps to any other mode
to a sink that is unsafe everywhere. Sinks do not move (every derivative 0) and are checked
for one step. A coordinate no flow or reset of the cycle changes (or that a reset sets to
a constant inside its interval) is inside by construction and gets no face; any other
coordinate with a point interval cannot recur strictly inside, so no model is written.
"""

from __future__ import annotations

from typing import Any

import sympy

from cyphy.verify.flowstar.constraints import dnf
from cyphy.verify.flowstar.export import (mode_jumps, ode_form, orders_setting, signed_number,
                                          steps_setting)
from cyphy.verify.flowstar.printer import number
from cyphy.verify.flowstar.problem import (CLOCK, TIMER, Problem, initial_interval, mode_values,
                                           symbol)


def invariant_model(p: Problem, name: str) -> str | None:
    """The Flow* model (see the module docstring), or None when the argument does not
    apply (the clock is read, a point coordinate changes over the cycle, or the first cycle
    may end in several modes)."""
    s = p.scenario
    clocks = {symbol(TIMER), symbol(CLOCK)}
    if s.first:  # the cycles may start in several modes: the argument is for one
        return None
    if p.unsafe.free_symbols & clocks or any(symbol(CLOCK) in f.free_symbols
                                             for f in p.rhs.values()) or \
            any(e.free_symbols & clocks for e in p.events.values()):
        return None
    held = p.held_inputs
    variables = [*p.states, *held, TIMER, CLOCK]
    var_syms = {symbol(v) for v in variables}
    mode = s.initial
    values = mode_values(p, mode)
    rhs = {x: sympy.expand(p.rhs[x].xreplace(values)) for x in p.states}
    rhs.update({u: sympy.Integer(0) for u in held})
    rhs.update({TIMER: sympy.Integer(1), CLOCK: sympy.Integer(1)})
    jumps = [(target, guard, _resets(p, target)) for source, target, guard in
             mode_jumps(p, var_syms, set()) if source == mode]
    faces = []
    for v in [*p.states, *held]:
        lo, hi = (sympy.nsimplify(b) for b in initial_interval(p, v))
        if _unchanged(v, rhs[v], lo, hi, jumps):
            continue
        if lo == hi:
            return None
        faces += [(v, ">=", hi), (v, "<=", lo)]
    unsafe = dnf(p.unsafe.xreplace(values), var_syms)
    if len(unsafe) > 1:
        return None  # one conjunction per run: the caller checks Problem.disjuncts()
    period = sympy.Rational(repr(s.period))
    step = s.settings.step[1] if isinstance(s.settings.step, tuple) else s.settings.step
    form, texts = ode_form(rhs, [symbol(v) for v in variables])
    still, _ = ode_form({v: sympy.Integer(0) for v in variables}, [symbol(v) for v in variables])
    sinks = [f"cyphy_face{k + 1}" for k in range(len(faces))] + ["cyphy_elsewhere"]
    lines = [f"# cyphy: is the initial box of {mode} invariant over one cycle of "
             f"{number(period)} s? (SAFE: yes, and the cycle avoids the unsafe set)",
             "hybrid reachability", "{", f" state var {', '.join(variables)}", "",
             " setting", " {", steps_setting(s.settings.step),
             f"  time {number(period + sympy.Rational(repr(float(step))))}",
             f"  remainder estimation {number(s.settings.remainder)}",
             "  identity precondition", f"  gnuplot octagon {CLOCK}, {TIMER}",
             orders_setting(s.settings.order), f"  cutoff {number(s.settings.cutoff)}",
             f"  precision {s.settings.precision}", f"  tm output {name}", "  max jumps 1",
             "  print off", " }", "", " modes", " {", f"  {mode}", "  {", f"   {form}", "   {"]
    lines += [f"    {x}' = {texts[x]}" for x in variables]
    lines += ["   }", "   inv", "   {", f"    {TIMER} <= {number(period)}", "   }", "  }"]
    for sink in sinks:
        lines += [f"  {sink}", "  {", f"   {still}", "   {"]
        lines += [f"    {x}' = 0" for x in variables]
        lines += ["   }", "   inv", "   {", "   }", "  }"]
    lines += [" }", "", " jumps", " {"]
    for target, guard, resets in jumps:
        atoms = [f"{TIMER} = {number(period)}"] + [a.text() for a in guard]
        reset = [f"{TIMER}' := 0"] + [f"{u}' := {signed_number(v)}" for u, v in resets.items()]
        for sink in (sinks[:-1] if target == mode else sinks[-1:]):
            lines += [f"  {mode} -> {sink}", f"  guard {{ {'  '.join(atoms)} }}",
                      f"  reset {{ {'  '.join(reset)} }}", "  parallelotope aggregation { }"]
    lines += [" }", "", " init", " {", f"  {mode}", "  {"]
    for v in [*p.states, *held]:
        lo, hi = initial_interval(p, v)
        lines.append(f"   {v} in [{signed_number(lo)}, {signed_number(hi)}]")
    lines += [f"   {TIMER} in [0, 0]", f"   {CLOCK} in [0, 0]", "  }", " }", "}", "",
              "unsafe", "{", f" {mode}", " {"]
    lines += [f"  {a.text()}" for a in unsafe[0]] if unsafe else [f"  {CLOCK} <= -1"]
    lines.append(" }")
    for sink, (v, rel, bound) in zip(sinks, faces):
        lines += [f" {sink}", " {", f"  {v} {rel} {signed_number(bound)}", " }"]
    lines += [f" {sinks[-1]}", " {", f"  {CLOCK} >= 0", " }", "}"]
    return "\n".join(lines) + "\n"


def _resets(p: Problem, target: str) -> dict[str, Any]:
    """The held inputs a jump into ``target`` sets (as the export's resets)."""
    return {u: p.effects[target][u] for u in p.held_inputs if u in p.effects[target]}


def _unchanged(v: str, flow: Any, lo: Any, hi: Any,
               jumps: list[tuple[str, Any, dict[str, Any]]]) -> bool:
    """Whether ``v`` ends the cycle inside [lo, hi] whatever happens: it does not flow and
    every reset of it is a constant inside the interval."""
    return flow == 0 and all(v not in resets or lo <= sympy.nsimplify(resets[v]) <= hi
                             for _, _, resets in jumps)
