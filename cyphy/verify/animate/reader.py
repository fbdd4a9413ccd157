"""The session as ``animate`` runs it, read from the theory text alone.

The declarations come from :func:`cyphy.verify.theory.utp_types.read_theory` (the layout
``cyphy check-theory`` reads) and every action body is parsed with the same grammar,
``utp_terms.lark``; this module adds what running needs: each definition's place in its file
(for diagnostics), the constants' values (definitions, and axioms of the form ``name = value``),
each process's state fields, and the composition ``N = (D [| cs |] P) \\ cs``."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.model import Definition, Process, TheoryModel, declared, line_of
from cyphy.verify.animate.terms import evaluate_hol
from cyphy.verify.theory.session import SessionError, read_session
from cyphy.verify.theory.utp_types import TypeError_, parser, read_theory

#: The import that marks the axiomatic dialect (Ax_CyPhyCircus), read by ``ax_reader``.
_AXIOMATIC = "Ax_CyPhyCircus"


def _main_theory(folder: Path) -> tuple[Path, str, bool]:
    """The session's theory that states the composition (the one ``animate`` runs)."""
    try:
        session, findings = read_session(folder)
    except SessionError as err:
        raise AnimateError("E-ANIMATE-SESSION", f"{err}", status=2,
                           hint="give the folder cyphy gen --isabelle wrote (it has a ROOT "
                           "file and the theories)") from None
    for finding in findings:
        if finding.code in ("T-LEX", "T-ENCODING", "T-IO", "T-NOT-THEORY", "T-MISSING"):
            raise AnimateError("E-ANIMATE-READ", finding.message, path=finding.path,
                               line=finding.line, status=2)
    for theory in session.theories:
        if any(_AXIOMATIC in imp for imp in theory.imports):
            return theory.path, theory.text, True
    for theory in reversed(session.theories):
        if re.search(r'^definition \w+ :: "\w+ process"', theory.text, re.M):
            return theory.path, theory.text, False
    last = session.theories[-1] if session.theories else None
    raise AnimateError("E-ANIMATE-OPAQUE", "no theory of the session states the composition "
                       "N = (D [| cs |] P) \\ cs (a process definition)",
                       path=last.path if last else folder, status=1,
                       hint="the d-model process D is stated only when its state machine "
                       "compiles (cyphy gen warns W-SEMANTICS-DMODEL otherwise); choose one "
                       "with cyphy gen --machine NAME")


def _parse(text: str, start: str, path: Path, line: int) -> Any:
    from lark.exceptions import LarkError  # lazy: only a failed parse needs the class
    try:
        return parser().parse(text, start=start)
    except LarkError as err:
        column = getattr(err, "column", 0)
        near = f" at column {column}" if isinstance(column, int) and column > 0 else ""
        raise AnimateError("E-ANIMATE-READ", f"a term animate cannot read{near}: "
                           f"{str(err).splitlines()[0][:160]}", path=path, line=line,
                           status=2) from None


def _hol_value(tree: Any, values: dict[str, Any]) -> Any:
    return evaluate_hol(tree, values.__getitem__)


def _channel_set(expr: str) -> set[str]:
    """The channel names of ``(({tock, c} ∪ range d) ∪ range e)``."""
    names = set(re.findall(r"range (\w+)", expr))
    for inside in re.findall(r"\{([^}]*)\}", expr):
        names.update(w.strip() for w in inside.split(",") if w.strip())
    return names


def read_model(folder: Path) -> TheoryModel:
    """The composition the session states, read from its text; :class:`AnimateError` when
    the folder is not a session or its theory uses what the reader does not know."""
    path, text, axiomatic = _main_theory(folder)
    if axiomatic:
        from cyphy.verify.animate.ax_reader import read_ax_model  # lazy: one dialect a run
        return read_ax_model(path, text)
    try:
        th = read_theory(text)
    except (TypeError_, AttributeError, ValueError) as err:
        raise AnimateError("E-ANIMATE-READ", f"cannot read the theory's declarations: {err}",
                           path=path, status=2) from None
    values: dict[str, Any] = {}
    for name, _typ, value in th.values:
        line = line_of(text, rf"^definition {re.escape(name)} ::")
        try:
            values[name] = _hol_value(_parse(value, "hol", path, line), values)
        except KeyError as err:
            raise AnimateError("E-ANIMATE-READ", f"{name}'s value names {err}, which is not "
                               "defined before it", path=path, line=line, status=2) from None
    open_constants = {name: line_of(text, rf"^(consts )?\s*{re.escape(name)} ::")
                      for name in th.constants
                      if name not in values and not name.startswith(("registerRead_",
                                                                     "registerWrite_"))
                      and name not in th.lenses and name != "tock"
                      and name not in {d[0] for d in th.definitions}
                      and declared(text, name, "real|nat|int|bool")}
    truths = {name for name in open_constants if declared(text, name, "bool")}
    wholes = {name: kind for name in open_constants for kind in ("int", "nat")
              if declared(text, name, kind)}
    axioms = [(_parse(ax, "hol", path, line_of(text, re.escape(ax))),
               line_of(text, re.escape(ax))) for ax in th.axioms]
    definitions: dict[str, Definition] = {}
    for name, params, _typ, body in th.definitions:
        line = line_of(text, rf"^definition {re.escape(name)} ::")
        definitions[name] = Definition(name, params, _parse(body, "action", path, line + 1),
                                       path, line)
    if not th.compositions:
        raise AnimateError("E-ANIMATE-OPAQUE", "the theory does not state the composition",
                           path=path, status=1)
    comp = th.compositions[0]
    name, _chan, d_state, d_main, cs, p_state, p_main, _cs2 = comp
    channel_expr = next((e for n, _t, e in th.channel_sets if n == cs), None)
    if channel_expr is None:
        raise AnimateError("E-ANIMATE-READ", f"the channel set {cs} is not defined",
                           path=path, line=line_of(text, rf"^definition {name} ::"), status=2)
    fields = _fields(text)
    processes = []
    for state, main in ((d_state, d_main), (p_state, p_main)):
        if main not in definitions:
            raise AnimateError("E-ANIMATE-READ", f"the composition runs {main}, which is not "
                               "defined", path=path, line=line_of(text, rf"^definition {name} ::"),
                               status=2)
        processes.append(Process(state, main, fields.get(state, {})))
    return TheoryModel(path, definitions, values, open_constants, _channel_set(channel_expr),
                       processes, name, axioms, truths=truths, wholes=wholes)



def _fields(text: str) -> dict[str, dict[str, str]]:
    """Each alphabet's fields, an extension's including its parent's (``A = B +``)."""
    blocks = re.finditer(r"^alphabet (\w+) =(?: (\w+) \+)?\n((?:  \w+ :: .*\n)+)", text, re.M)
    out: dict[str, dict[str, str]] = {}
    for m in blocks:
        own = dict(re.findall(r"  (\w+) :: \"?([^\"\n]*)\"?", m.group(3)))
        out[m.group(1)] = {**out.get(m.group(2) or "", {}), **own}
    return out
