"""The scenario file (TOML) of ``cyphy gen --flowstar`` and ``cyphy reach``: what the model is
checked under (the README documents every key).

The controller is the d-model's state machine (compiled by :mod:`cyphy.verify.flowstar.machine`
into ``states`` and ``transitions``) unless the scenario gives one as a small automaton over
the d-model's events and operations (``[controller]``); the scenario also gives the
environment (how sensor inputs evolve), the initial set, the unsafe set and Flow*'s
settings. This module reads and checks the file's shape; names are checked against the model
by :mod:`cyphy.verify.flowstar.export`.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from cyphy import codes
from cyphy.diagnostics import Report, Span, did_you_mean
from cyphy.model.default_inertial import CHOICES
from cyphy.verify.flowstar.limits import MAX_BOUND, MAX_JUMPS, MAX_ORDER, MAX_PRECISION

SCENARIO = codes.code("E-SCENARIO", codes.E, "the scenario file cannot be used")
EXPORT = codes.code("E-FLOWSTAR", codes.E,
                    "the model and scenario cannot be exported to Flow*")

_TOP = {"model", "elements", "horizon", "tscale", "cycle", "consts", "init", "environment",
        "controller", "machine", "unsafe", "flowstar", "default_inertial"}
_FLOWSTAR = {"step", "order", "remainder", "cutoff", "precision", "max_jumps"}
_CAPS = {
    "order": (MAX_ORDER, "each Flow* step would take hours (orders above 20 rarely help)"),
    "precision": (MAX_PRECISION, "MPFR bits; 53 is a double, and more only slows Flow*"),
    "max_jumps": (MAX_JUMPS, "Flow* reads it as a C int, which would wrap to a negative "
                  "number and disable the bound"),
}
_WHEN = re.compile(r"\s*(not\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*\Z")


@dataclass(frozen=True)
class Environment:
    """How a sensor input evolves: its derivative (an expression), or a constant value."""

    name: str
    derivative: str | None
    value: float | None
    span: Span


@dataclass(frozen=True)
class Transition:
    source: str
    target: str
    event: str  # "" with no conjuncts: always taken
    negated: bool  # ``when = "not obstacle"``
    span: Span
    # More literals that must hold with the first (a compiled state machine's guards).
    conjuncts: tuple[tuple[str, bool], ...] = ()

    @property
    def literals(self) -> tuple[tuple[str, bool], ...]:
        """The guard: a conjunction of (event, negated); () is always true."""
        return (((self.event, self.negated),) if self.event else ()) + self.conjuncts


@dataclass(frozen=True)
class Settings:
    """Flow*'s settings. ``step`` and ``order`` are a number (fixed) or a pair (min, max):
    adaptive, which Flow* allows for one of the two at a time."""

    step: float | tuple[float, float] = 0.01
    order: int | tuple[int, int] = 6
    remainder: float = 1e-2
    cutoff: float = 1e-12
    precision: int = 53
    max_jumps: int | None = None


@dataclass
class Scenario:
    path: str
    text: str
    horizon: float
    tscale: float
    cycle: int = 1
    model: str | None = None
    elements: tuple[str, ...] = ()
    consts: dict[str, Any] = field(default_factory=dict)
    init: dict[str, tuple[float, float]] = field(default_factory=dict)
    environment: dict[str, Environment] = field(default_factory=dict)
    initial: str = ""
    states: dict[str, tuple[str, ...]] = field(default_factory=dict)  # state → calls
    transitions: list[Transition] = field(default_factory=list)
    # A compiled machine whose first cycle reads the input events: per combination of them,
    # the state it ends in (``source`` ""). Empty: the first cycle ends in ``initial``.
    first: list[Transition] = field(default_factory=list)
    unsafe: tuple[str, ...] = ()
    settings: Settings = Settings()
    machine: str | None = None  # the d-model machine to use when there is no [controller]
    default_inertial: str | None = None  # "sdf": links without mass get SDF's defaults

    @property
    def period(self) -> float:
        """One cycle in continuous time: ``cycle × tscale``."""
        return self.cycle * self.tscale

    def span(self, *keys: str) -> Span:
        """Where a key is written (the first line that names the last key after the first
        line naming each earlier one), for diagnostics: TOML readers keep no positions."""
        lines = self.text.splitlines()
        start = 0
        found = Span(self.path, 1, 1, 1, 2)
        for key in keys:
            pattern = re.compile(rf'(^|[\s\[."]){re.escape(key)}($|[\s\]."=])')
            for i in range(start, len(lines)):
                m = pattern.search(_code(lines[i]))
                if m:
                    col = m.start() + (1 if m.group(1) else 0) + 1
                    found = Span(self.path, i + 1, col, i + 1, col + len(key))
                    start = i
                    break
        return found


def _code(line: str) -> str:
    """The line without its TOML comment (a ``#`` outside a string), so that a key named in
    a comment (``# … the environment below``) is not taken for the key itself."""
    quote = ""
    for k, ch in enumerate(line):
        if quote:
            if ch == quote and line[k - 1] != "\\":
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:k]
    return line


class _Reader:
    def __init__(self, scenario: Scenario, report: Report) -> None:
        self.s, self.report = scenario, report

    def error(self, message: str, keys: tuple[str, ...], hint: str = "") -> None:
        self.report.report(SCENARIO, message, self.s.span(*keys), hint)

    def number(self, value: Any, keys: tuple[str, ...], positive: bool = False) -> float | None:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.error(f"'{'.'.join(keys)}' must be a number, not {value!r}", keys)
            return None
        if not math.isfinite(value):
            self.error(f"'{'.'.join(keys)}' must be a finite number, not {value!r}", keys,
                       "nan and inf have no meaning here: write a number")
            return None
        if positive and value <= 0:
            self.error(f"'{'.'.join(keys)}' must be positive", keys)
            return None
        return float(value)

    def unknown_keys(self, table: dict[str, Any], allowed: set[str], where: tuple[str, ...]
                     ) -> None:
        for key in table:
            if key not in allowed:
                self.error(f"unknown key '{key}'" + (f" in [{'.'.join(where)}]" if where
                                                      else ""), (*where, key),
                           did_you_mean(key, sorted(allowed)) or
                           "keys: " + ", ".join(sorted(allowed)))


def load_scenario(path: str | Path, report: Report, needs_unsafe: bool = True
                  ) -> Scenario | None:
    """The scenario, or None with diagnostics when the file cannot be read or is malformed.
    ``needs_unsafe=False`` (``simulate``, which checks nothing) lets it have no [unsafe]."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        report.report(SCENARIO, f"cannot read the scenario {p}: {err}", Span.unknown(str(p)),
                      "give the path of a TOML scenario file")
        return None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        m = re.search(r"line (\d+), column (\d+)", str(err))
        line, col = (int(m.group(1)), int(m.group(2))) if m else (1, 1)
        report.report(SCENARIO, f"not valid TOML: {err}", Span(str(p), line, col, line,
                                                                col + 1),
                      "the scenario format: docs/commands/reach.md")
        return None
    s = Scenario(str(p), text, horizon=0.0, tscale=0.0)
    r = _Reader(s, report)
    before = len([d for d in report.diagnostics if d.code is SCENARIO])
    r.unknown_keys(data, _TOP, ())
    for key in ("horizon", "tscale"):
        if key not in data:
            r.error(f"the scenario needs '{key}'", (), f"add for example `{key} = "
                    f"{'2.0' if key == 'horizon' else '0.1'}` at the top")
        else:
            setattr(s, key, r.number(data[key], (key,), positive=True) or 0.0)
    cycle = data.get("cycle", 1)
    if isinstance(cycle, bool) or not isinstance(cycle, int) or cycle <= 0:
        r.error("'cycle' must be a positive integer (time units per cycle)", ("cycle",))
    else:
        s.cycle = cycle
    if "model" in data:
        if isinstance(data["model"], str):
            s.model = data["model"]
        else:
            r.error("'model' must be the p-model's name", ("model",))
    elements = data.get("elements", [])
    if not isinstance(elements, list) or not all(isinstance(e, str) for e in elements):
        r.error("'elements' must be a list of qualified element names", ("elements",))
    else:
        s.elements = tuple(elements)
    _consts(r, data.get("consts", {}))
    _init(r, data.get("init", {}))
    _environment(r, data.get("environment", {}))
    if "machine" in data:
        if isinstance(data["machine"], str):
            s.machine = data["machine"]
        else:
            r.error("'machine' must be the name of a state machine of the d-model",
                    ("machine",))
    if "default_inertial" in data:
        if data["default_inertial"] in CHOICES:
            s.default_inertial = data["default_inertial"]
        else:
            r.error(f"'default_inertial' must be one of {', '.join(map(repr, CHOICES))}",
                    ("default_inertial",), 'write default_inertial = "sdf" (SDFormat\'s '
                    "defaults: 1 kg, identity inertia) or leave it out")
    if "controller" in data and "machine" in data:
        r.error("give either a [controller] or 'machine', not both", ("machine",),
                "without [controller] the d-model's machine is the controller")
    if "controller" in data:
        _controller(r, data["controller"])
    if needs_unsafe or "unsafe" in data:
        _unsafe(r, data.get("unsafe"))
    _settings(r, data.get("flowstar", {}))
    after = len([d for d in report.diagnostics if d.code is SCENARIO])
    return s if after == before else None


def _table(r: _Reader, value: Any, keys: tuple[str, ...]) -> dict[str, Any] | None:
    if not isinstance(value, dict):
        r.error(f"[{'.'.join(keys)}] must be a table", keys)
        return None
    return value


def _consts(r: _Reader, value: Any) -> None:
    table = _table(r, value, ("consts",))
    for name, v in (table or {}).items():
        if isinstance(v, bool) or not isinstance(v, (int, float, list, str)):
            r.error(f"constant '{name}' must be a number, a list or a string", ("consts", name))
        elif not _finite(v):
            r.error(f"constant '{name}' must be finite, not {v!r}", ("consts", name),
                    "nan and inf have no meaning here: write a number")
        else:
            r.s.consts[name] = v


def _finite(value: Any) -> bool:
    """No nan or inf anywhere in a constant's value (a number or a list of them)."""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, list):
        return all(_finite(v) for v in value)
    return True


def _positive(value: Any, kind: type) -> bool:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    if kind is int and not isinstance(value, int):
        return False
    return math.isfinite(value) and value > 0


def _init(r: _Reader, value: Any) -> None:
    table = _table(r, value, ("init",))
    for name, v in (table or {}).items():
        keys = ("init", name)
        if isinstance(v, list) and len(v) == 2:
            lo, hi = r.number(v[0], keys), r.number(v[1], keys)
            if lo is None or hi is None or not _bounded(r, name, (lo, hi), keys):
                continue
            if lo > hi:
                r.error(f"the interval of '{name}' is empty ({lo} > {hi})", keys,
                        "write [low, high]")
                continue
            r.s.init[name] = (lo, hi)
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            number = r.number(v, keys)
            if number is not None and _bounded(r, name, (number,), keys):
                r.s.init[name] = (number, number)
        else:
            r.error(f"the initial value of '{name}' must be a number or an interval "
                    "[low, high]", keys)


def _bounded(r: _Reader, name: str, values: tuple[float, ...], keys: tuple[str, ...]
             ) -> bool:
    """Whether the initial values lie within ±MAX_BOUND (reported when not)."""
    if all(abs(v) <= MAX_BOUND for v in values):
        return True
    r.error(f"the initial value of '{name}' lies beyond ±{MAX_BOUND:g}: a double keeps no "
            "digit below the units there, so boxes, simulations and Flow*'s intervals of it "
            "mean nothing", keys, "give the state's physical range")
    return False


def _environment(r: _Reader, value: Any) -> None:
    table = _table(r, value, ("environment",))
    for name, v in (table or {}).items():
        keys = ("environment", name)
        span = r.s.span(*keys)
        if isinstance(v, str):
            r.s.environment[name] = Environment(name, v, None, span)
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            number = r.number(v, keys)
            if number is not None:
                r.s.environment[name] = Environment(name, repr(number), None, span)
        elif isinstance(v, dict) and set(v) == {"derivative"} and isinstance(
                v["derivative"], (str, int, float)):
            r.s.environment[name] = Environment(name, str(v["derivative"]), None, span)
        elif isinstance(v, dict) and set(v) == {"value"}:
            number = r.number(v["value"], keys)
            if number is not None:
                r.s.environment[name] = Environment(name, None, number, span)
        else:
            r.error(f"the environment of '{name}' must be its derivative (an expression in "
                    "quotes or a number) or {{ value = NUMBER }}", keys,
                    f'for example {name} = "-0.1" or {name} = {{ value = 0.05 }}')


def _controller(r: _Reader, value: Any) -> None:
    table = _table(r, value, ("controller",))
    if table is None:
        return
    r.unknown_keys(table, {"initial", "states", "transitions"}, ("controller",))
    states = _table(r, table.get("states", {}), ("controller", "states")) or {}
    for name, st in states.items():
        keys = ("controller", "states", name)
        st = _table(r, st, keys)
        if st is None:
            continue
        r.unknown_keys(st, {"calls"}, keys)
        calls = st.get("calls", [])
        if not isinstance(calls, list) or not all(isinstance(c, str) for c in calls):
            r.error(f"'calls' of state {name} must be a list of calls in quotes", keys,
                    'for example calls = ["move(0.1, 0)"]')
            continue
        r.s.states[name] = tuple(calls)
    if not r.s.states:
        r.error("the controller needs at least one state", ("controller",),
                'add [controller.states.NAME] with calls = ["op(args)"]')
    initial = table.get("initial")
    if not isinstance(initial, str):
        r.error("the controller needs 'initial', the name of its initial state",
                ("controller",))
    elif initial not in r.s.states and r.s.states:
        r.error(f"the initial state '{initial}' is not a state of the controller",
                ("controller", "initial"), did_you_mean(initial, sorted(r.s.states)))
    else:
        r.s.initial = initial
    transitions = table.get("transitions", [])
    if not isinstance(transitions, list):
        r.error("[[controller.transitions]] must be an array of tables",
                ("controller", "transitions"))
        return
    for k, t in enumerate(transitions):
        keys = ("controller", "transitions")
        if not isinstance(t, dict):
            r.error("a transition must be a table with from, to and when", keys)
            continue
        r.unknown_keys(t, {"from", "to", "when"}, keys)
        ends = [t.get("from"), t.get("to")]
        ok = True
        for end, key in zip(ends, ("from", "to")):
            if not isinstance(end, str) or end not in r.s.states:
                r.error(f"transition {k + 1}: '{key}' must name a controller state, not "
                        f"{end!r}", (*keys, key) if isinstance(end, str) else keys,
                        did_you_mean(str(end), sorted(r.s.states)) or
                        "states: " + ", ".join(sorted(r.s.states)))
                ok = False
        when = t.get("when")
        m = _WHEN.match(when) if isinstance(when, str) else None
        if m is None:
            r.error(f"transition {k + 1}: 'when' must be an input event name or 'not EVENT'",
                    keys, 'for example when = "obstacle"')
            ok = False
        if ok and m is not None:
            r.s.transitions.append(Transition(ends[0], ends[1], m.group(2),
                                              bool(m.group(1)), r.s.span(*keys, "when")))


def _unsafe(r: _Reader, value: Any) -> None:
    if value is None:
        r.error("the scenario needs an [unsafe] set", (),
                'add [unsafe] with constraints = ["x >= 1"]')
        return
    table = _table(r, value, ("unsafe",))
    if table is None:
        return
    r.unknown_keys(table, {"constraints"}, ("unsafe",))
    cons = table.get("constraints")
    if not isinstance(cons, list) or not cons or not all(isinstance(c, str) for c in cons):
        r.error("'constraints' of [unsafe] must be a non-empty list of comparisons in quotes",
                ("unsafe",), 'for example constraints = ["LMotor_av >= 20"]')
        return
    r.s.unsafe = tuple(cons)


def _settings(r: _Reader, value: Any) -> None:
    table = _table(r, value, ("flowstar",)) or {}
    r.unknown_keys(table, _FLOWSTAR, ("flowstar",))
    values: dict[str, Any] = {}
    for key, kind in (("step", float), ("order", int)):
        v = table.get(key)
        if isinstance(v, list):  # adaptive: [min, max]
            keys = ("flowstar", key)
            if len(v) == 2 and kind is int and all(_positive(x, int) for x in v) and \
                    v[1] > MAX_ORDER:
                r.error(f"'flowstar.{key}' = {v[1]} is above {MAX_ORDER}: {_CAPS[key][1]}",
                        keys, f"write at most {MAX_ORDER}")
            elif len(v) != 2 or not all(_positive(x, kind) for x in v) or v[0] > v[1]:
                r.error(f"'flowstar.{key}' as a list is [min, max] of positive "
                        f"{'numbers' if kind is float else 'integers'}, min <= max", keys,
                        f"for example {key} = {[0.001, 0.01] if kind is float else [4, 8]}")
            else:
                values[key] = (kind(v[0]), kind(v[1]))
    if isinstance(values.get("step"), tuple) and isinstance(values.get("order"), tuple):
        r.error("Flow* adapts the step or the order, not both: make one of them a number",
                ("flowstar", "order"))
    for key in ("step", "remainder", "cutoff"):
        if key == "step" and isinstance(table.get(key), list):
            continue
        if key in table:
            v = r.number(table[key], ("flowstar", key), positive=True)
            if v is not None:
                values[key] = v
    for key in ("order", "precision", "max_jumps"):
        if key == "order" and isinstance(table.get(key), list):
            continue
        if key in table:
            v = table[key]
            if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
                r.error(f"'flowstar.{key}' must be a positive integer", ("flowstar", key))
            elif v > _CAPS[key][0]:
                r.error(f"'flowstar.{key}' = {v} is above {_CAPS[key][0]}: {_CAPS[key][1]}",
                        ("flowstar", key), f"write at most {key} = {_CAPS[key][0]}")
            else:
                values[key] = v
    r.s.settings = Settings(**values)
