"""C1-C5: does each element of a platform mapping define what the software asks for?

Each check is a question to Z3 about the terms of :mod:`.encode`; a failed check is reported
with the values Z3 found (its *witness*) and, where the answer is "no solution", with the
equations that contradict each other (an unsatisfiable core). An ``unknown`` answer (a
timeout, nonlinear arithmetic Z3 gives up on, or a witness that relies on an uninterpreted
function) is reported as ``C-UNKNOWN``: never as a pass.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from itertools import combinations
from typing import Any, Iterable, Mapping

import z3

from cyphy import codes
from cyphy.diagnostics import Report, Span
from cyphy.lang import ast
from cyphy.lang.ast import Controller, StateMachine
from cyphy.lang.resolve import Resolution, check_scopes
from cyphy.lang.workspace import LIBRARY_ROOT, Workspace
from cyphy.model.elaborate import elaborate_pmodel
from cyphy.semantics.consistency.encode import Encoder, Encoding, Fact
from cyphy.translate.to_z3 import value_text
from cyphy.wellformed import WFContext
from cyphy.wellformed.platform_services import mapped_services

E, W = codes.E, codes.W
C1 = codes.code("C1", E, "an equation mapping has a solution for every argument")
C2 = codes.code("C2", E, "a mapping's equations determine each actuator input they mention")
C3 = codes.code("C3", E, "a typed input event always has a value to communicate")
C3_UNIQUE = codes.code("C3-UNIQUE", W, "a typed input event communicates one value, not a "
                       "choice")
C4 = codes.code("C4", W, "an input event's predicate can hold and can fail")
C5 = codes.code("C5", W, "two mappings that write the same actuator input ask for different "
                "values")
UNKNOWN = codes.code("C-UNKNOWN", W, "Z3 could not decide a consistency check")
CANNOT = codes.code("E-CONSISTENCY", E, "the consistency checks cannot run")

DEFAULT_TIMEOUT_MS = 10_000
_BLOCKING = re.compile(r"^(E-|S\d|PMap|IX)")
"""Errors after which the mapping's names or shape cannot be trusted (syntax, scopes,
indexing, the mapping conditions); value and geometry errors do not stop the checks."""


@dataclass
class _Outcome:
    status: str  # "sat", "unsat" or "unknown"
    model: Any = None
    core: list[Fact] = field(default_factory=list)
    reason: str = ""
    uninterpreted: bool = False  # unknown because a witness relies on them


def _assignment(model: Any, terms: Mapping[str, Any], shown: Any = str) -> str:
    return ", ".join(f"{shown(name)} = {value_text(model.eval(t, model_completion=True))}"
                     for name, t in terms.items())


def _call(enc: Encoding, model: Any) -> str:
    """``move(lv = 1, av = 0)``; ``variable level with level = 2``; with other givens."""
    params = {n: enc.given[n] for n in enc.params}
    others = {n: t for n, t in enc.given.items() if n not in params}
    if isinstance(enc.member, ast.OperationMapping):
        text = f"{enc.name}({_assignment(model, params)})"
    else:
        text = enc.label + (f" with {_assignment(model, params)}" if params else "")
    return text + (f" (and {_assignment(model, others)})" if others else "")


def _fresh(terms: Iterable[Any]) -> list[tuple[Any, Any]]:
    """Pairs (constant, a fresh copy of it): a second solution of the same equations."""
    return [(t, z3.Const(f"{t.decl().name()}'", t.sort())) for t in terms]


def _notes(facts: Iterable[Fact]) -> list[str]:
    return [f"{f.span}: {f.text}" if f.span.line else f.text for f in facts]


class _Checks:
    def __init__(self, report: Report, timeout_ms: int) -> None:
        self.report, self.timeout_ms = report, timeout_ms

    def solve(self, terms: Iterable[Any], tracked: Iterable[Fact] = (),
              uninterpreted: Iterable[str] = ()) -> _Outcome:
        s = z3.Solver()
        s.set("timeout", self.timeout_ms)
        s.set("core.minimize", True)
        s.add(*terms)
        labels: dict[str, Fact] = {}
        for i, fact in enumerate(tracked):
            label = z3.Bool(f"fact!{i}")
            labels[str(label)] = fact
            s.assert_and_track(fact.term, label)
        result = s.check()
        if result == z3.sat:
            names = sorted(set(uninterpreted))
            if names:
                return _Outcome("unknown", reason=f"a witness relies on {', '.join(names)}, "
                                "which Z3 treats as uninterpreted", uninterpreted=True)
            return _Outcome("sat", model=s.model())
        if result == z3.unsat:
            core = {str(c) for c in s.unsat_core()}
            return _Outcome("unsat", core=[f for k, f in labels.items() if k in core])
        return _Outcome("unknown", reason=s.reason_unknown())

    def unknown(self, enc: Encoding, what: str, outcome: _Outcome) -> None:
        if outcome.uninterpreted:
            hint = "Z3 knows nothing of these functions: it can show that a check passes, " \
                "not that it fails; state the relation without them, or check by hand"
        else:
            hint = f"raise --z3-timeout (milliseconds, now {self.timeout_ms}) or make the " \
                "terms linear"
        self.report.report(UNKNOWN, f"Z3 could not decide {what} for the {enc.label} "
                           f"({outcome.reason}); the check neither passed nor failed",
                           enc.member.span, hint)

    def core(self, fixed: Mapping[str, Any], model: Any, facts: list[Fact],
             extra: Iterable[Any] = ()) -> list[str]:
        """The facts that contradict each other once the witness's values are fixed."""
        pins = [t == model.eval(t, model_completion=True) for t in fixed.values()]
        out = self.solve([*pins, *extra], facts)
        if out.status != "unsat":
            return []
        return ["these contradict each other there:"] + _notes(out.core)

    # -------------------------------------------------------------------- C1, C2

    def existence(self, enc: Encoding) -> None:
        """C1: ∀ given • ∃ locals, actuator inputs • equations."""
        if not enc.equations:
            return
        body = z3.And([f.term for f in enc.equations] + enc.unknown_facts)
        unknowns = list(enc.unknowns.values())
        none = z3.ForAll(unknowns, z3.Not(body)) if unknowns else z3.Not(body)
        out = self.solve([*enc.given_facts, none], uninterpreted=enc.uninterpreted)
        if out.status == "unknown":
            self.unknown(enc, "C1 (existence)", out)
        elif out.status == "sat":
            given = {**enc.given, **enc.reads}
            notes = self.core(given, out.model, enc.equations, enc.unknown_facts)
            where = f"for {_call(enc, out.model)}" if given else "at all"
            self.report.report(
                C1, f"the equations of the {enc.label} have no solution {where}",
                enc.member.span, "correct or remove the contradicting equation, so that "
                "every call has actuator inputs that satisfy the equations", notes)

    def uniqueness(self, enc: Encoding) -> None:
        """C2: two solutions for the same givens agree on each actuator input."""
        body = z3.And([f.term for f in enc.equations] + enc.unknown_facts)
        fresh = _fresh(enc.unknowns.values())
        other = z3.substitute(body, *fresh) if fresh else body
        for name, term in enc.writes.items():
            twin = z3.substitute(term, *fresh)
            out = self.solve([*enc.given_facts, body, other, term != twin],
                             uninterpreted=enc.uninterpreted)
            if out.status == "unknown":
                self.unknown(enc, f"C2 (uniqueness of {enc.shown(name)})", out)
                continue
            if out.status != "sat":
                continue
            m = out.model
            seconds = {n: z3.substitute(t, *fresh) for n, t in enc.unknowns.items()}
            self.report.report(
                C2, f"the equations of the {enc.label} do not determine {enc.shown(name)}: "
                f"for {_call(enc, m)} it can be {value_text(m.eval(term, True))} or "
                f"{value_text(m.eval(twin, True))}", enc.member.span,
                f"add an equation that fixes {enc.shown(name)} (or the locals it depends on)",
                [f"one solution: {_assignment(m, enc.unknowns, enc.shown)}",
                 f"another: {_assignment(m, seconds, enc.shown)}"])

    # -------------------------------------------------------------------- C3, C4

    def _predicate(self, enc: Encoding) -> Any:
        """The predicate, its locals bound (the event's values are chosen when it holds)."""
        terms = [f.term for f in enc.predicate]
        pred = z3.And(terms) if terms else z3.BoolVal(True)
        return z3.Exists(enc.predicate_locals, pred) if enc.predicate_locals else pred

    def typed_event(self, enc: Encoding) -> None:
        """C3: when the predicate holds, { p | ∃ locals • equations } is not empty (an empty
        choice deadlocks); C3-UNIQUE: it has one element."""
        if not enc.values:
            return
        body = z3.And([f.term for f in enc.equations] + enc.unknown_facts)
        unknowns = [*enc.values.values(), *enc.unknowns.values()]
        setting = [f.term for f in enc.range] + enc.given_facts + [self._predicate(enc)]
        uninterpreted = enc.uninterpreted
        out = self.solve([*setting, z3.ForAll(unknowns, z3.Not(body))],
                         uninterpreted=uninterpreted)
        if out.status == "unknown":
            self.unknown(enc, "C3 (a value for the event)", out)
        elif out.status == "sat":
            state = {enc.shown(n): t for n, t in enc.reads.items()} | enc.given
            notes = self.core(state, out.model, enc.equations, enc.unknown_facts)
            when = f" when {_assignment(out.model, state)}" if state else ""
            self.report.report(
                C3, f"the {enc.label} has no value to communicate{when}: "
                f"{{ {enc.member.param} | ∃ locals • equations }} is empty, so the "
                "platform deadlocks", enc.member.span,
                f"make the equations give {enc.member.param} a value whenever the predicate "
                "holds", notes + enc.range_notes)
            return
        fresh = _fresh(unknowns)
        differ = z3.Or([v != z3.substitute(v, *fresh) for v in enc.values.values()])
        out = self.solve([*setting, body, z3.substitute(body, *fresh), differ],
                         uninterpreted=uninterpreted)
        if out.status == "unknown":
            self.unknown(enc, "C3-UNIQUE (one value for the event)", out)
        elif out.status == "sat":
            m = out.model
            state = {enc.shown(n): t for n, t in enc.reads.items()} | enc.given
            when = f" when {_assignment(m, state)}" if state else ""
            seconds = {n: z3.substitute(t, *fresh) for n, t in enc.values.items()}
            self.report.report(
                C3_UNIQUE, f"the {enc.label} may communicate more than one value{when}: "
                f"{_assignment(m, enc.values)} or {_assignment(m, seconds)}",
                enc.member.span, f"add equations that fix {enc.member.param}, unless the "
                "software must cope with a nondeterministic choice", enc.range_notes)

    def predicate(self, enc: Encoding) -> None:
        """C4: the predicate is satisfiable and not valid over the sensors' range."""
        if not enc.predicate:
            return
        setting = list(enc.given_facts)
        if enc.predicate_locals:
            setting += [f.term for f in enc.equations] + enc.unknown_facts
        never = self.solve(setting, [*enc.predicate, *enc.range], enc.uninterpreted)
        span = enc.predicate[0].span
        if never.status == "unknown":
            self.unknown(enc, "C4 (the predicate can hold)", never)
        elif never.status == "unsat":
            self.report.report(
                C4, f"the predicate of the {enc.label} can never hold: the event never "
                "happens", span, "correct the predicate's bounds",
                ["these contradict each other:"] + _notes(never.core) + enc.range_notes)
            return
        pred = z3.And([f.term for f in enc.predicate])
        always = self.solve([*setting, z3.Not(pred)], enc.range, enc.uninterpreted)
        if always.status == "unknown":
            self.unknown(enc, "C4 (the predicate can fail)", always)
        elif always.status == "unsat":
            self.report.report(
                C4, f"the predicate of the {enc.label} always holds: the event happens in "
                "every cycle", span, "correct the predicate's bounds",
                [f"range used: {n}" for n in _notes(always.core)] + enc.range_notes)

    # -------------------------------------------------------------------- C5

    def conflicts(self, encs: list[Encoding]) -> None:
        """C5: two writers of one actuator input whose values for it can differ."""
        writers = [e for e in encs if e.writes and not (
            isinstance(e.member, ast.EventMapping) and e.member.direction == "input")]
        for a, b in combinations(writers, 2):
            shared = [w for w in a.writes if w in b.writes]
            notes: list[str] = []
            for w in shared:
                out = self.solve([*a.given_facts, *a.unknown_facts, *(f.term for f in a.equations),
                                  *b.given_facts, *b.unknown_facts, *(f.term for f in b.equations),
                                  a.writes[w] != b.writes[w]],
                                 uninterpreted=a.uninterpreted | b.uninterpreted)
                if out.status == "unknown":
                    self.unknown(b, f"C5 (conflict with the {a.label} on {a.shown(w)})", out)
                elif out.status == "sat":
                    m = out.model
                    notes.append(f"{a.shown(w)}: {_call(a, m)} sets it to "
                                 f"{value_text(m.eval(a.writes[w], True))}, {_call(b, m)} to "
                                 f"{value_text(m.eval(b.writes[w], True))}")
            if notes:
                inputs = [a.shown(w) for w in shared if any(n.startswith(a.shown(w) + ":")
                                                            for n in notes)]
                self.report.report(
                    C5, f"the {a.label} and the {b.label} both write "
                    f"{' and '.join(inputs)}, with different values: the software must not "
                    "use both in one cycle", b.member.span,
                    "keep the calls in different cycles (the paper's reason for PMap11), or "
                    "let one element drive these inputs", notes)


def check_consistency(ws: Workspace, resolution: Resolution, report: Report,
                      consts: Mapping[str, object] | None = None,
                      timeout_ms: int = DEFAULT_TIMEOUT_MS) -> None:
    """Run C1-C5 on every platform mapping of the user's files."""

    ctx = WFContext(ws, resolution, Report(), dict(consts or {}))
    mappings = list(ctx.mappings())
    if not mappings:

        if any(isinstance(i, (StateMachine, Controller)) for f in ctx.files()
               for i in f.items):
            return  # d-model behaviour only: its Z3 check is the machine rule STM7
        first = next(iter(ws.targets), "<input>")
        report.report(CANNOT, "no platform mapping among the files to check for consistency",
                      Span.unknown(str(first)), "name the mapping file (map M dmodel … to "
                      "pmodel … { … })")
        return
    if any(_BLOCKING.match(d.code.id) for d in report.errors):
        for _, mapping in mappings:
            report.report(CANNOT, f"the consistency of mapping {mapping.name} was not checked: "
                          "the files have errors", mapping.span, "correct the errors above first")
        return
    checks = _Checks(report, timeout_ms)
    groups: dict[int, tuple[Any, list[Any]]] = {}
    for site, member, service in mapped_services(ctx):
        groups.setdefault(id(site.mapping), (site, []))[1].append((member, service))
    for site, members in groups.values():
        if site.pmodel is None or site.pmodel_file is None:
            report.report(CANNOT, f"the p-model of mapping {site.mapping.name} is unknown",
                          site.mapping.pmodel_span, "import the p-model's file")
            continue
        if site.pmodel_file.path not in ws.targets:
            resolution = _resolve_all(ws)
        model = elaborate_pmodel(ws, resolution, Report(), site.pmodel, site.pmodel_file,
                                 ctx.consts)  # type: ignore[arg-type]
        encoder = Encoder(model, site.mapping, site.file, ctx.scopes, ctx.consts)
        encodings = []
        for member, service in members:
            enc = encoder.encode(member, service)
            if enc.problem is not None and enc.unknown_name:
                report.report(CANNOT, f"the consistency of the {enc.label} cannot be checked: "
                              f"{enc.problem}", enc.problem_span or member.span,
                              "name a port as 'Link::Block.port' (see cyphy show)")
                continue
            if enc.problem is not None:
                report.report(UNKNOWN, f"the consistency of the {enc.label} was not checked: "
                              f"{enc.problem}", enc.problem_span or member.span,
                              "the checks handle numbers and booleans (records by their "
                              "fields); this element is neither passed nor failed")
                continue
            encodings.append(enc)
            if isinstance(member, ast.EventMapping) and member.direction == "input":
                checks.typed_event(enc)
                checks.predicate(enc)
            else:
                checks.existence(enc)
                checks.uniqueness(enc)
        checks.conflicts(encodings)


def _resolve_all(ws: Workspace) -> Resolution:
    """Name resolution of every model file beside the user's (``cyphy check Mapping.rsm``
    names only the mapping, but its p-model's references must resolve to elaborate it)."""


    library = str(LIBRARY_ROOT)
    others = [p for p in ws.files if not p.startswith(library)]
    return check_scopes(replace(ws, targets=others), Report())
