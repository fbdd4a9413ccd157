"""Helpers of the tests of the theory's ``D``: a bench of the dcmotor p-model under a
machine of ``tests/data``, ``simulate`` and ``animate`` run in-process for their JSON, and a
runner of ``D``'s actions (the AST the printers print) on a dictionary state."""

from __future__ import annotations

import contextlib
import io
import json
import operator
import shutil
from pathlib import Path

from cyphy import expr as ex
from cyphy.cli import main
from cyphy.semantics.circus import ast as c

ROOT = Path(__file__).resolve().parent.parent


def bench(folder: Path, data: Path, scenario: str) -> tuple[Path, Path]:
    """``folder`` with the dcmotor p-model and the ``.rsm`` files of ``data``, and beside it
    the scenario ``scenario`` (its text)."""
    folder.mkdir()
    for source in [ROOT / "examples" / "dcmotor" / "DCMotorBase.rsm", *data.glob("*.rsm")]:
        shutil.copy(source, folder)
    path = folder.parent / f"{data.name}.toml"
    path.write_text(scenario)
    return folder, path


def run_json(command: str, target: Path, scenario: Path, samples: int) -> dict:
    """``simulate`` or ``animate`` of ``target`` under ``scenario``, JSON."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main([command, str(target), "--scenario", str(scenario), "--samples",
                     str(samples), "--format", "json", "-q"]) == 0
    return json.loads(out.getvalue())


_BINARY = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
           "==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le,
           ">": operator.gt, ">=": operator.ge, "/\\": lambda a, b: bool(a and b),
           "\\/": lambda a, b: bool(a or b)}


class RunD:
    """Runs ``D``'s cycle actions on a dictionary state: reads the cycle's events, takes the
    step, records what it writes, in order. The automaton's ``D`` (``Write`` sends the
    mode's calls) and the cycle written out (``Start``, calls made inside ``Step``) alike."""

    def __init__(self, d: c.BasicProcess) -> None:
        self.actions = {a.name: a.body for a in d.actions}
        self.name = d.name
        self.state: dict[str, object] = {}
        self.events: dict[str, object] = {}
        self.written: list[tuple[str, tuple[float, ...]]] = []

    def value(self, e: ex.Expr, bound: dict[str, object]) -> object:
        if isinstance(e, ex.Name):
            return bound[e.text] if e.text in bound else self.state[e.text]
        if isinstance(e, ex.Num):
            return float(e.text)
        if isinstance(e, ex.Bool):
            return e.value
        if isinstance(e, ex.UnaryOp):
            inner = self.value(e.operand, bound)
            return (not inner) if e.op == "not" else -inner  # type: ignore[operator]
        assert isinstance(e, ex.BinOp), e
        return _BINARY[e.op](self.value(e.left, bound), self.value(e.right, bound))

    def run(self, a: c.Action, bound: dict[str, object]) -> None:
        if isinstance(a, c.Call):
            self.run(self.actions[a.name], bound)
        elif isinstance(a, c.Seq):
            for item in a.items:
                self.run(item, bound)
        elif isinstance(a, c.Cond):
            self.run(a.then if self.value(a.cond, bound) else a.orelse, bound)
        elif isinstance(a, c.Assign):
            values = [self.value(v, bound) for v in a.values]
            self.state.update(zip(a.targets, values))
        elif isinstance(a, c.Prefix) and a.comm.channel == "registerRead":
            value = self.events.get(str(a.comm.tag))
            present = value is not None and value is not False
            given = [present, float(value) if present and value is not True else 0.0]
            names = [f.name for f in a.comm.fields]  # type: ignore[union-attr]
            self.run(a.then, {**bound, **dict(zip(names, given))})
        elif isinstance(a, c.Prefix):
            self.written.append((str(a.comm.tag), tuple(
                float(self.value(f.value, bound)) for f in a.comm.fields)))  # type: ignore
            self.run(a.then, bound)
        else:
            assert isinstance(a, c.Skip), a

    def cycle(self, events: dict[str, object], first: bool) -> tuple:
        """One cycle with ``events`` (name → None or False when absent, True or the value
        when present); what it wrote."""
        self.events, self.written = events, []
        if f"{self.name}Start" in self.actions:
            names = ["Init", "Read", "Start"] if first else ["Read", "Step"]
        else:
            names = ["Init", "Read", "Write"] if first else ["Read", "Step", "Write"]
        for n in names:
            self.run(c.Call(self.name + n), {})
        return tuple(self.written)


def written_session(folder: Path, scenario: Path, dialect: str, session: Path) -> str:
    """The theory of ``folder`` in ``dialect`` with ``D`` written (no ``W-SEMANTICS-DMODEL``),
    its session written to ``session`` and passing ``check-theory``; the main theory's text."""
    from cyphy import api

    generated = api.generate_isabelle([folder], api.SemanticsGenOptions(
        dialect=dialect, scenario=str(scenario)))
    codes = [d.code.id for d in generated.report.diagnostics]
    assert not generated.report.has_errors and "W-SEMANTICS-DMODEL" not in codes, codes
    session.mkdir()
    for name, text in generated.files.items():
        (session / name).write_text(text)
    assert main(["check-theory", str(session)]) == 0
    return next(t for n, t in generated.files.items() if n.endswith(".thy")
                and "Prelude" not in n)


def animated_as_simulated(session: Path, folder: Path, scenario: Path, samples: int,
                          names: tuple[str, ...] = ("Motor_av", "Motor_i", "Range_distance"),
                          tolerance: float = 1e-5) -> tuple[list[str], "np.ndarray"]:
    """``animate`` of the theory and ``simulate`` of the model agree on ``names`` (the
    dcmotor's speed and current and the obstacle's distance; empty: every state both
    report) within ``tolerance`` at every sample; the animation's columns and rows."""
    import numpy as np

    anim = run_json("animate", session, scenario, samples)
    sim = run_json("simulate", folder, scenario, samples)
    columns, rows = anim["columns"], np.array(anim["rows"])
    assert np.allclose(rows[:, 0], sim["t"])
    for col in names or [c for c in columns[1:] if c in sim["columns"]]:
        gap = np.max(np.abs(rows[:, columns.index(col)] - sim["columns"][col]))
        assert gap < tolerance, (col, gap)
    return columns, rows
