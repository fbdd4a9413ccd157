"""``animate --scenario FILE``: the scenario ``simulate`` and ``reach`` read, turned into the
``--const`` and ``--input`` values ``animate`` takes (the command line's own options win).

The theory stays the only model: the scenario gives values, never equations. Its names are
RoboSim's (``Block::const``, ``Motor_av``); the session's ``names.tsv`` (written by ``cyphy gen
--isabelle`` beside the theories) relates them to the theory's identifiers."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from cyphy.constant_keys import names_constant
from cyphy.diagnostics import Report
from cyphy.verify.animate.errors import AnimateError


@dataclass
class ScenarioValues:
    """What the scenario gives: constants (theory names), inputs (``NAME=EXPR`` of t),
    the horizon and ``tscale``; ``unused`` lists its [consts] keys no theory name matches."""

    consts: dict[str, float] = field(default_factory=dict)
    inputs: dict[str, str] = field(default_factory=dict)
    horizon: float | None = None
    tscale: float | None = None
    unused: list[str] = field(default_factory=list)
    # an input whose rate reads the state → (that rate, its start): no closed form
    state_dependent: dict[str, tuple[str, float]] = field(default_factory=dict)


def _names(folder: Path) -> list[tuple[str, str, str]]:
    """The session's names.tsv rows: RoboSim's qualified name, the theory's identifier and,
    for a device's constant, its definition-qualified name (``SpeedControlMotor::R``); empty
    when the session has none (then only the theory's own identifiers match)."""
    table = folder / "names.tsv"
    try:
        lines = table.read_text(encoding="utf-8").splitlines()[1:]
    except (OSError, UnicodeDecodeError):
        return []
    out = []
    for row in lines:
        cells = row.split("\t")
        if len(cells) >= 3:
            out.append((cells[0], cells[2], cells[3] if len(cells) > 3 else ""))
    return out


def _targets(key: str, names: list[tuple[str, str, str]]) -> list[str]:
    """The theory constants a [consts] key sets, as ``simulate`` reads the key
    (``cyphy.model.environment``): the theory identifier or a qualified name exactly; else
    every constant whose qualified or definition-qualified name is the key or ends with
    ``::key`` (``SpeedControlMotor::R`` sets the R of each SpeedControlMotor, not another
    block's R; a bare ``R`` sets every R)."""
    if any(ident == key for _, ident, _ in names):
        return [key]
    exact = [ident for qualified, ident, _ in names if qualified == key]
    if exact:
        return exact
    return sorted({ident for qualified, ident, definition in names
                   if names_constant(key, qualified.rsplit("::", 1)[-1], qualified,
                                     definition)})


def theory_values(given: dict[str, float], folder: Path) -> dict[str, float]:
    """``--const`` values by theory identifier: a name is read as a scenario's [consts] key
    is (:func:`_targets`: the identifier, or RoboSim's name, ``lv``, ``Pulse::fast``,
    ``SpeedControlMotor::R``), so ``animate`` takes the names ``simulate`` takes; one that
    matches nothing is kept, for the animation to refuse with a did-you-mean."""
    names = _names(folder)
    out: dict[str, float] = {}
    for key, value in given.items():
        for ident in _targets(key, names) or [key]:
            out[ident] = value
    return out


def _start(lo_hi: tuple[float, float]) -> float:
    """An [init] value: a number, or an interval's midpoint (one run of the set)."""
    lo, hi = lo_hi
    return (lo + hi) / 2


def read(path: Path, folder: Path) -> ScenarioValues:
    """The scenario's values for animating the session in ``folder``; :class:`AnimateError`
    (exit 2) when the file cannot be read, with the scenario reader's diagnostic."""
    import sympy  # lazy: an environment's derivative is integrated symbolically

    from cyphy.verify.flowstar.scenario import load_scenario  # lazy: only with --scenario
    report = Report()
    scenario = load_scenario(path, report, needs_unsafe=False)
    if scenario is None:
        first = next((d for d in report.diagnostics), None)
        raise AnimateError("E-ANIMATE-SCENARIO", first.message if first else
                           f"cannot read the scenario {path}", path=path,
                           line=first.span.line if first else 0, status=2,
                           hint=first.hint if first and first.hint else "")
    names = _names(folder)
    out = ScenarioValues(horizon=scenario.horizon or None, tscale=scenario.tscale or None)
    for key, value in scenario.consts.items():
        targets = _targets(key, names)
        if not targets or isinstance(value, bool) or not isinstance(value, (int, float)):
            out.unused.append(key)
            continue
        for ident in targets:
            out.consts[ident] = float(value)
    t = sympy.Symbol("t")
    for name, env in scenario.environment.items():
        start = _start(scenario.init[name]) if name in scenario.init else 0.0
        if env.value is not None:
            out.inputs[name] = repr(float(env.value))
            continue
        rate = sympy.sympify(env.derivative, locals={"t": t})
        if rate.free_symbols - {t}:
            out.state_dependent[name] = (str(env.derivative), start)
            continue
        out.inputs[name] = str(sympy.nsimplify(start) + sympy.integrate(rate, (t, 0, t)))
    return out
