"""``cyphy reach``'s verdict: the problem decomposed into independent parts, initial boxes
split, Flow* run on each in parallel processes, the results combined soundly, and an UNSAFE
confirmed by a simulated trajectory (:mod:`cyphy.verify.flowstar.simulate`).

Why each step is sound:

- **Decomposition.** The unsafe set is a conjunction of atoms. An atom needs the states it
  reads and, transitively, those their derivatives read; a state whose flow differs between
  controller modes also needs the states the transitions' events read (they choose the
  mode). Atoms whose needs are disjoint (the clocks ``t`` and ``timer`` aside, which every
  part keeps) form separate parts, and each part keeps only the states it needs: its
  automaton is the exact projection of the whole one onto them. The whole system avoids the
  conjunction as soon as one part avoids its own atoms, so SAFE needs one part SAFE. States
  nothing needs are left out (the wheels' angles of a robot whose torque is checked).
  A part whose states do not depend on the mode keeps one mode and no jumps.
  Formally: with R the reachable set of the whole automaton, S_k the set its part k's
  atoms describe (clock atoms included) and pi_k the projection onto part k's states and
  clocks, pi_k(R) is exactly the part's reachable set, and the unsafe set lies inside
  pi_k^-1(S_k); so pi_k(R) disjoint from S_k implies R disjoint from the unsafe set. That
  is the only sound combination: parts that are each UNSAFE or UNKNOWN say nothing of the
  conjunction (each conjunct may be reached at other times or from other initial
  states), and a part's UNSAFE is never the whole system's.
- **Joint fallback.** A part alone cannot see relations between its states and another
  part's (a common start, the same dynamics, timing), so when no part of a disjunct is
  proved (after splitting) its parts are run together: the disjunct on the union of their
  states, again an exact projection, whose SAFE proves the disjunct by the same argument.
  A part whose own atoms a simulated trajectory of the part enters is not split first
  (the box of that trajectory's start can never be SAFE): the joint run comes next.
- **Splitting.** The initial set is the union of the boxes, so SAFE needs every box SAFE
  (each with a completed computation); the verdicts of the boxes are reported.
- **UNSAFE** is only said with a concrete trajectory of the whole automaton from the
  initial set that enters the unsafe set; otherwise Flow*'s UNSAFE flowpipe may lie on a
  branch no trajectory takes (its enclosures take every jump whose guard they meet), and the
  verdict is UNKNOWN.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import sympy

from cyphy.verify.flowstar.constraints import dnf
from cyphy.verify.flowstar.export import render
from cyphy.verify.flowstar.first_cycle import description, settle
from cyphy.verify.flowstar.invariant import invariant_model
from cyphy.verify.flowstar.limits import MAX_ORDER
from cyphy.verify.flowstar.problem import CLOCK, TIMER, Problem, initial_interval, symbol
from cyphy.verify.flowstar.simulate import BUDGET, Witness, find_witness, unsafe_paths
from cyphy.verify.flowstar.verdict import Outcome, run_text

AUTO_SPLIT = 4  # boxes per part when a run without splitting ends UNKNOWN
#: The refinement ladder: the changes to Flow*'s settings tried, one more a round, on a run
#: left open before its box is split (splitting cannot help a loss that grows with time):
#: the step halved (the truncation error shrinks, and Picard's iteration needs h·‖A‖
#: small), the Taylor order raised by 2, the remainder estimate ×10 (Picard's iteration
#: failing to contract ends a computation early, "not completed").
LADDER = ("step", "order", "remainder")
#: Trajectories the falsification search before Flow* simulates: the centre, the corners
#: and lines through the centre of the initial box, then a first refinement.
FIRST_BUDGET = 40


@dataclass(frozen=True)
class Task:
    """One Flow* run: a part of the problem on one box of its initial set."""

    label: str
    problem: Problem
    text: str


@dataclass
class Result:
    verdict: str  # SAFE, UNSAFE, UNKNOWN or ERROR
    reason: str
    seconds: float  # wall-clock time of all the runs
    details: list[str] = field(default_factory=list)  # one line per run
    witness: Witness | None = None
    names: list[str] = field(default_factory=list)  # the witness's variables, in order
    # The model of every Flow* run, in the order run: file name (runs/NAME.NNN.model) → text
    runs: dict[str, str] = field(default_factory=dict)

    @property
    def exit_code(self) -> int:
        return {"SAFE": 0, "UNSAFE": 1, "UNKNOWN": 3}.get(self.verdict, 2)


# --------------------------------------------------------------------------- decomposition


def parts(p: Problem) -> list[Problem]:
    """The problem's independent parts (see the module's docstring), each restricted to the
    states it needs; one part when the atoms' needs overlap."""
    conjunction = dnf(p.unsafe, _variables(p))
    atoms = list(conjunction[0]) if conjunction else []
    clocks = {symbol(TIMER), symbol(CLOCK)}
    needs = [_closure(p, {str(s) for s in a.poly.free_symbols - clocks}) for a in atoms]
    events = _closure(p, _event_states(p))  # every part that depends on the mode has them
    groups: list[tuple[set[str], list[Any]]] = []
    shared = []
    for atom, need in zip(atoms, needs):
        if not need:
            shared.append(atom)  # reads the clocks only: every part keeps it
            continue
        merged = [g for g in groups if (g[0] - events) & (need - events)
                  or not (g[0] - events) or not (need - events)]
        for g in merged:
            groups.remove(g)
            need = need | g[0]
        groups.append((need, [a for g in merged for a in g[1]] + [atom]))
    if len(groups) <= 1:
        need = groups[0][0] if groups else set()
        return [_restrict(p, need, p.unsafe)]
    return [_restrict(p, need, sympy.And(*[a.relation() for a in [*atoms_, *shared]]))
            for need, atoms_ in groups]


def _variables(p: Problem) -> set[Any]:
    return {symbol(n) for n in [*p.states, *p.inputs, TIMER, CLOCK]}


def _event_states(p: Problem) -> set[str]:
    """The states the controller's events read (``Problem.events`` holds the events its
    transitions use)."""
    return {str(s) for e in p.events.values() for s in e.free_symbols} & set(p.states)


def _closure(p: Problem, start: set[str]) -> set[str]:
    """The states ``start`` needs, transitively (held inputs count as mode-dependent)."""
    states, inputs = set(p.states), {symbol(u) for u in p.inputs}
    events = _event_states(p)
    need, todo = set(), [s for s in start if s in states or s in p.inputs]
    while todo:
        x = todo.pop()
        if x in need:
            continue
        need.add(x)
        if x in p.inputs:  # a held input changes at the jumps the events choose
            todo += sorted(events)
            continue
        free = p.rhs[x].free_symbols
        todo += sorted(str(s) for s in free if str(s) in states)
        if free & inputs:
            todo += sorted(events)
    return need & states


def _restrict(p: Problem, need: set[str], unsafe: Any) -> Problem:
    states = [x for x in p.states if x in need]
    s = p.scenario
    init = {x: _box(p, x) for x in [*states, *p.held_inputs]}
    inputs = {symbol(u) for u in p.inputs}
    moded = any(p.rhs[x].free_symbols & inputs for x in states) or \
        bool(unsafe.free_symbols & inputs)
    if moded:
        scenario = dataclasses.replace(s, init=init)
        return dataclasses.replace(p, scenario=scenario, states=states,
                                   rhs={x: p.rhs[x] for x in states}, unsafe=unsafe)
    # the mode does not matter to these states: one mode, no transitions, no jumps
    scenario = dataclasses.replace(s, init=init, states={s.initial: s.states[s.initial]},
                                   transitions=[], first=[])
    return dataclasses.replace(p, scenario=scenario, states=states,
                               rhs={x: p.rhs[x] for x in states}, inputs=[],
                               effects={s.initial: {}}, events={}, unsafe=unsafe)


def _box(p: Problem, name: str) -> tuple[float, float]:
    lo, hi = initial_interval(p, name)
    return float(lo), float(hi)


def split(p: Problem, count: int) -> list[tuple[str, Problem]]:
    """``count`` boxes cut along the state with the widest initial interval (all of ``p``
    when no state is uncertain), labelled with that state's interval. A first cycle that
    reads the events is decided again on each box (one inside an event's region starts
    exactly: :func:`cyphy.verify.flowstar.first_cycle.settle`)."""
    widths = {x: hi - lo for x, (lo, hi) in ((x, _box(p, x)) for x in p.states)}
    wide = max(widths, key=lambda x: (widths[x], x), default=None)
    if count <= 1 or wide is None or widths[wide] <= 0:
        return [("", p)]
    lo, hi = _box(p, wide)
    out = []
    for k in range(count):
        a = lo + (hi - lo) * k / count
        b = hi if k == count - 1 else lo + (hi - lo) * (k + 1) / count
        init = dict(p.scenario.init)
        init[wide] = (a, b)
        scenario = dataclasses.replace(p.scenario, init=init)
        out.append((f"{wide} in [{a:.6g}, {b:.6g}]",
                    settle(dataclasses.replace(p, scenario=scenario))))
    return out


# --------------------------------------------------------------------------- running


@dataclass
class _Piece:
    """What one Flow* verdict is sought for: an independent part of a disjunct, or (when its
    parts do not each prove it) the joint problem of all its parts, with its runs so far."""

    disjunct: int
    problem: Problem
    label: str
    joint: bool = False
    tasks: list[Task] = field(default_factory=list)
    outcomes: list[Outcome] = field(default_factory=list)
    rung: int = 0  # the refinement ladder's rungs tried (:data:`LADDER`)
    split_done: bool = False
    reachable: bool = False  # a simulated trajectory of the part alone enters its atoms

    @property
    def proved(self) -> bool:
        return bool(self.outcomes) and all(o.verdict == "SAFE" for o in self.outcomes)


def check(p: Problem, name: str, binary: str, timeout: float | None = None,
          boxes: int = 1, auto_split: bool = True, jobs: int | None = None) -> Result:
    """The verdict on ``p`` (:func:`_check`), its reason ending with what the first cycle
    of a machine that reads the events in it did (exact or over-approximated:
    :func:`cyphy.verify.flowstar.first_cycle.description`)."""
    result = _check(p, name, binary, timeout, boxes, auto_split, jobs)
    note = description(p)
    if note:
        result.reason += f"; {note}"
    return result


def _check(p: Problem, name: str, binary: str, timeout: float | None, boxes: int,
           auto_split: bool, jobs: int | None) -> Result:
    """The verdict on ``p``: see the module's docstring. First a simulation search for a
    witness over each disjunct's whole initial set (falsification first: no Flow* run when a
    trajectory is found); then every run of a round goes to one pool of ``jobs`` Flow*
    processes: the disjuncts of the unsafe set, their independent parts, the boxes of each.
    Every box Flow* leaves open is searched for a witness too. Later rounds retry what the
    first left open with finer settings (:data:`LADDER`, one rung a round), then on
    smaller boxes, then run the parts of a disjunct that none of them proved jointly."""
    started = time.perf_counter()
    jobs = jobs or os.cpu_count() or 1
    disjuncts = p.disjuncts()
    searched: dict[tuple[str, int], Witness | None] = {}  # witness searches, by model text
    runs: dict[str, str] = {}
    files: dict[int, str] = {}  # id of a task → its file among ``runs``
    for d in disjuncts:
        witness = _search(searched, render(d, name), [], FIRST_BUDGET)
        if witness is not None:
            return Result("UNSAFE", "a simulated trajectory from the initial set enters the "
                          f"unsafe set at t = {witness.entry.time:.6g} (found by the "
                          "simulation search before any Flow* run)",
                          time.perf_counter() - started, [], witness,
                          [*d.states, *d.held_inputs])
    pieces: list[_Piece] = []
    for j, d in enumerate(disjuncts):
        ps = parts(d)
        pieces += [_Piece(j, part, _part_label(part, k, len(ps), j, len(disjuncts)))
                   for k, part in enumerate(ps)]
    pending = {id(pc): (pc, _tasks(pc.problem, name, pc.label, boxes)) for pc in pieces}
    notes: list[str] = []  # the runs a later round replaced by finer settings or boxes

    def details() -> list[str]:
        return notes + [f"  {t.label}: {o.verdict} ({o.reason}) [{files[id(t)]}]"
                        for pc in pieces for t, o in zip(pc.tasks, pc.outcomes)]

    while pending:
        for _, ts in pending.values():
            for t in ts:
                files[id(t)] = f"runs/{name}.{len(runs) + 1:03d}.model"
                runs[files[id(t)]] = t.text
        outcomes = _run_round({key: ts for key, (_, ts) in pending.items()}, binary, timeout,
                              jobs)
        for key, (pc, ts) in pending.items():
            pc.tasks, pc.outcomes = ts, outcomes[key]
        several = {pc.disjunct for pc in pieces if not pc.joint and any(
            q.disjunct == pc.disjunct and q is not pc and not q.joint for q in pieces)}
        found = _confirm(disjuncts, name, [pc for pc, _ in pending.values()], several,
                         searched)
        if found is not None:
            witness, names, outcome = found
            return Result("UNSAFE", "a simulated trajectory from the initial set enters the "
                          f"unsafe set at t = {witness.entry.time:.6g} (Flow*: "
                          f"{outcome.reason}{_paths(outcome)})",
                          time.perf_counter() - started, details(), witness, names, runs)
        errors = [o for pc in pieces for o in pc.outcomes if o.verdict == "ERROR"]
        if errors:
            return Result("ERROR", errors[0].reason, time.perf_counter() - started, details(),
                          runs=runs)
        proved = {pc.disjunct for pc in pieces if pc.proved}
        if len(proved) == len(disjuncts):
            break
        pending = _next_round(disjuncts, pieces, proved, name, boxes, auto_split, notes)
    elapsed = time.perf_counter() - started
    proved = {pc.disjunct for pc in pieces if pc.proved}
    if len(proved) == len(disjuncts):
        count = sum(len(pc.outcomes) for pc in pieces)
        what = "every disjunct of the unsafe set" if len(disjuncts) > 1 else "the initial set"
        jointly = " (its independent parts jointly: none proved it alone)" if any(
            pc.joint and pc.proved for pc in pieces) else ""
        scope = _for_all_time(disjuncts, name, binary, timeout, runs, notes)
        return Result("SAFE", f"Flow* proved {what} safe{jointly} in {count} run"
                      f"{'s' if count > 1 else ''}, every computation completed; {scope}",
                      time.perf_counter() - started, details(), runs=runs)
    unsafe = [o for pc in pieces for o in pc.outcomes if o.verdict == "UNSAFE"]
    if unsafe:
        return Result("UNKNOWN", "Flow* found a flowpipe inside the unsafe set, but no "
                      "simulated trajectory from the initial set enters it: the flowpipe may "
                      "lie on a spurious branch (a jump its enclosure allows and no "
                      f"trajectory takes){_paths(unsafe[0])}", elapsed, details(), runs=runs)
    open_ = [t.label for pc in pieces if pc.disjunct not in proved
             for t, o in zip(pc.tasks, pc.outcomes) if o.verdict != "SAFE"]
    return Result("UNKNOWN", "not proved: " + "; ".join(open_[:6]) +
                  (" …" if len(open_) > 6 else ""), elapsed, details(), runs=runs)


def _for_all_time(disjuncts: list[Problem], name: str, binary: str, timeout: float | None,
                  runs: dict[str, str], notes: list[str]) -> str:
    """Which SAFE it is: for every horizon when, for each disjunct, some independent part's
    initial box is an inductive invariant that one cycle keeps clear of the unsafe set
    (:mod:`cyphy.verify.flowstar.invariant`, one Flow* run per part), else up to the
    horizon. The runs are recorded in ``runs`` and ``notes``."""
    horizon = f"up to the horizon of {disjuncts[0].scenario.horizon:g} s"
    candidates = [(j, part, invariant_model(part, name)) for j, d in enumerate(disjuncts)
                  for part in parts(d)]
    candidates = [(j, part, text) for j, part, text in candidates if text is not None]
    if not {j for j, _, _ in candidates} >= set(range(len(disjuncts))):
        if any(d.scenario.first for d in disjuncts):
            return f"{horizon} (no invariant to check: the first cycle may end in several " \
                "modes)"
        return f"{horizon} (no invariant to check: the clock is read, or a point " \
            "coordinate changes over a cycle)"
    tasks = [Task(f"invariant of {part.scenario.initial} [{', '.join(part.states)}]", part,
                  text) for _, part, text in candidates]
    outcomes = [run_text(t.text, binary, timeout, 1) for t in tasks]  # one jump: a cycle
    for task, outcome in zip(tasks, outcomes):
        file = f"runs/{name}.{len(runs) + 1:03d}.model"
        runs[file] = task.text
        notes.append(f"  {task.label}: {outcome.verdict} ({outcome.reason}) [{file}]")
    # a SAFE counts only when a jump reached a sink: more flowpipes than the cycle alone
    # has (its steps and the one ending on the guard), else the check would be vacuous
    held = {j for (j, part, _), o in zip(candidates, outcomes) if o.verdict == "SAFE" and
            (o.flowpipes or 0) >= _cycle_flowpipes(part) + 1}
    if held >= set(range(len(disjuncts))):
        period = disjuncts[0].scenario.period
        return ("for every horizon: one cycle of "
                f"{period:g} s from the initial box ends inside it and avoids the unsafe "
                "set (an inductive invariant, checked by Flow*)")
    return f"{horizon} (the initial box is not proved invariant over one cycle)"


def _cycle_flowpipes(p: Problem) -> int:
    """The most flowpipes one cycle alone can take: its steps (the smallest step, when
    adaptive) and the one ending on the guard ``timer = cycle × tscale``."""
    step = p.scenario.settings.step
    smallest = step[0] if isinstance(step, tuple) else step
    return math.ceil(p.scenario.period / smallest - 1e-9) + 1


def _next_round(disjuncts: list[Problem], pieces: list[_Piece], proved: set[int], name: str,
                boxes: int, auto_split: bool, notes: list[str]
                ) -> dict[int, tuple[_Piece, list[Task]]]:
    """What to run next for each disjunct not proved: its pieces whose one run ended open,
    with the next rung of :data:`LADDER`; when the ladder is spent, on ``AUTO_SPLIT`` boxes
    (not a part whose own atoms a trajectory enters: the box of that trajectory's start
    would stay unsafe); when nothing is left to split, its parts jointly (:func:`joint`),
    unless one of them timed out."""
    pending: dict[int, tuple[_Piece, list[Task]]] = {}
    for j, d in enumerate(disjuncts):
        if j in proved:
            continue
        mine = [pc for pc in pieces if pc.disjunct == j]
        retried = False
        for pc in mine:
            if not auto_split or pc.split_done or pc.reachable or \
                    len(pc.outcomes) != 1 or not _open(pc.outcomes[0]):
                continue
            o = pc.outcomes[0]
            if pc.rung < len(LADDER):
                pc.rung += 1
                finer, what = refine(pc.problem, pc.rung)
                notes.append(f"  {pc.tasks[0].label}: {o.verdict} ({o.reason}); retried "
                             f"with {what}")
                pending[id(pc)] = (pc, _tasks(finer, name, f"{pc.label} [{what}]", 1))
                retried = True
                continue
            if boxes > 1:
                continue
            pc.split_done = True
            ts = _tasks(pc.problem, name, pc.label, AUTO_SPLIT)
            if len(ts) > 1:
                notes.append(f"  {pc.tasks[0].label}: {o.verdict} ({o.reason}); split into "
                             f"{AUTO_SPLIT} boxes")
                pending[id(pc)] = (pc, ts)
                retried = True
        if retried or len(mine) < 2 or any(pc.joint for pc in mine) or \
                any(_timed_out(o) for pc in mine for o in pc.outcomes):
            continue  # (the joint run, larger than a part that timed out, would too)
        whole = joint(d)
        where = f"disjunct {j + 1}/{len(disjuncts)}, " if len(disjuncts) > 1 else ""
        pc = _Piece(j, whole, f"{where}parts jointly [{', '.join(whole.states)}]", joint=True)
        pieces.append(pc)
        pending[id(pc)] = (pc, _tasks(whole, name, pc.label, boxes))
    return pending


def refine(p: Problem, rung: int) -> tuple[Problem, str]:
    """``p`` with the first ``rung`` changes of :data:`LADDER` to Flow*'s settings, and
    what they are (for the report)."""
    settings = p.scenario.settings
    changes: dict[str, Any] = {}
    for key in LADDER[:rung]:
        value = getattr(settings, key)
        if key == "step":
            changes[key] = tuple(v / 2 for v in value) if isinstance(value, tuple) \
                else value / 2
        elif key == "order":
            changes[key] = tuple(min(v + 2, MAX_ORDER) for v in value) \
                if isinstance(value, tuple) else min(value + 2, MAX_ORDER)
        else:
            changes[key] = value * 10
    what = ", ".join(f"{k} {_setting(v)}" for k, v in changes.items())
    scenario = dataclasses.replace(p.scenario,
                                   settings=dataclasses.replace(settings, **changes))
    return dataclasses.replace(p, scenario=scenario), what


def _setting(value: Any) -> str:
    return f"[{value[0]:g}, {value[1]:g}]" if isinstance(value, tuple) else f"{value:g}"


def joint(p: Problem) -> Problem:
    """The conjunction ``p`` on the states all its parts need together: the one problem in
    which Flow* can use relations between the parts' states (no part alone can)."""
    need = set().union(*(set(part.states) for part in parts(p)))
    return _restrict(p, need, p.unsafe)


def _run_round(tasks: dict[Any, list[Task]], binary: str, timeout: float | None, jobs: int
               ) -> dict[Any, list[Outcome]]:
    flat = [(key, t) for key, ts in tasks.items() for t in ts]
    results = _run_all([t for _, t in flat], binary, timeout, jobs)
    out: dict[Any, list[Outcome]] = {key: [] for key in tasks}
    for (key, _), outcome in zip(flat, results):
        out[key].append(outcome)
    return out


def _open(outcome: Outcome) -> bool:
    """Whether smaller boxes may help: UNKNOWN or an unconfirmed UNSAFE, not a timeout."""
    return outcome.verdict in ("UNKNOWN", "UNSAFE") and not _timed_out(outcome)


def _timed_out(outcome: Outcome) -> bool:
    return outcome.reason.startswith("Flow* did not finish")


def _search(searched: dict[tuple[str, int], Witness | None], text: str,
            hints: list[list[str]], budget: int) -> Witness | None:
    """:func:`find_witness` on the model ``text``, once per model and budget."""
    key = (text, budget)
    if key not in searched:
        searched[key] = find_witness(text, hints, budget)
    return searched[key]


def _confirm(disjuncts: list[Problem], name: str, pieces: list[_Piece], several: set[int],
             searched: dict[tuple[str, int], Witness | None]
             ) -> tuple[Witness, list[str], Outcome] | None:
    """A witness for one of the runs Flow* left open (UNSAFE, UNKNOWN or unfinished),
    searched on the whole automaton (with that run's disjunct) from that run's box, guided
    by Flow*'s unsafe paths when it called the run UNSAFE. When there is none and the run
    was an UNSAFE of one of several parts (``several``: their disjuncts), the part's own
    atoms are searched on the part alone: when a trajectory enters them, splitting that
    part cannot prove it. ``searched`` keeps each model's search (the parts of a disjunct
    share the whole automaton on the same box)."""
    for pc in pieces:
        budget = max(BUDGET // len(pc.tasks), 30)  # the boxes of a split share one budget
        for task, outcome in zip(pc.tasks, pc.outcomes):
            if outcome.verdict not in ("UNSAFE", "UNKNOWN"):
                continue
            whole = _whole(disjuncts[pc.disjunct], task.problem)
            # Flow*'s paths name the whole automaton's modes unless the part dropped them
            same = task.problem.scenario.states.keys() == whole.scenario.states.keys() and \
                task.problem.scenario.transitions == whole.scenario.transitions
            hints = unsafe_paths(outcome.counterexample) if same else []
            witness = _search(searched, render(_settled(whole, disjuncts[pc.disjunct]), name),
                              hints, budget)
            if witness is not None:
                return witness, [*whole.states, *whole.held_inputs], outcome
            if outcome.verdict == "UNSAFE" and not pc.joint and pc.disjunct in several and \
                    not pc.reachable:
                pc.reachable = _search(searched, render(task.problem, name),
                                       unsafe_paths(outcome.counterexample),
                                       budget) is not None
    return None


def _settled(p: Problem, base: Problem) -> Problem:
    """``p`` with ``base``'s Flow* settings: the ladder's finer settings change nothing a
    simulation does, so the search of a box is not repeated for each rung."""
    return dataclasses.replace(p, scenario=dataclasses.replace(
        p.scenario, settings=base.scenario.settings))


def _part_label(part: Problem, k: int, n: int, j: int, m: int) -> str:
    where = [f"disjunct {j + 1}/{m}"] if m > 1 else []
    if n > 1:
        where.append(f"part {k + 1}/{n} [{', '.join(part.states)}]")
    return ", ".join(where) or "run"


def _tasks(part: Problem, name: str, label: str, boxes: int) -> list[Task]:
    return [Task(f"{label}{': ' + box if box else ''}", piece, _runnable(render(piece, name)))
            for box, piece in split(part, boxes)]


def _runnable(text: str) -> str:
    """The model as run: the Taylor-model dump and counterexample file only (``tm output``),
    not the gnuplot file, whose writing can take longer than the computation."""
    return re.sub(r"^(\s*)output (\w+)$", r"\1tm output \2", text, count=1, flags=re.M)


def _run_all(tasks: list[Task], binary: str, timeout: float | None, jobs: int
             ) -> list[Outcome]:
    required = [t.problem.required_jumps for t in tasks]
    if len(tasks) == 1 or jobs <= 1:
        return [run_text(t.text, binary, timeout, r) for t, r in zip(tasks, required)]
    with ThreadPoolExecutor(max_workers=min(jobs, len(tasks))) as pool:  # one Flow* each
        return list(pool.map(lambda tr: run_text(tr[0].text, binary, timeout, tr[1]),
                             zip(tasks, required)))


def _whole(p: Problem, box: Problem) -> Problem:
    """The whole problem on the initial box of a run (a part's box, others unchanged)."""
    init = {x: _box(p, x) for x in [*p.states, *p.held_inputs]}
    init.update(box.scenario.init)
    return dataclasses.replace(p, scenario=dataclasses.replace(p.scenario, init=init))


def _paths(outcome: Outcome) -> str:
    paths = unsafe_paths(outcome.counterexample)
    if not paths:
        return ""
    shown = " -> ".join(_compress(max(paths, key=len)))
    return f"; Flow*'s unsafe flowpipe on the path {shown}"


def _compress(modes: list[str]) -> list[str]:
    out: list[str] = []
    for m in modes:
        if out and out[-1].split(" ×")[0] == m:
            count = int(out[-1].split(" ×")[1]) + 1 if " ×" in out[-1] else 2
            out[-1] = f"{m} ×{count}"
        else:
            out.append(m)
    return out
