"""The reduced ODE system (``cyphy solve``) as text, LaTeX or JSON."""

from __future__ import annotations

import json
from typing import Any

import sympy

from cyphy.semantics.dynamics.reduce import Reduced


def _sorted(d: dict[str, Any]) -> list[tuple[str, Any]]:
    return sorted(d.items())


def definition_text(value: Any) -> str:
    """A definition's value (a SymPy expression or an articulated-body polynomial) in
    ``sympy.sstr``'s notation."""
    return value.text() if hasattr(value, "text") else sympy.sstr(value)


def _sympy_value(value: Any, symbols: dict[str, Any]) -> Any:
    return value.to_sympy(symbols) if hasattr(value, "to_sympy") else value


def odes_to_text(r: Reduced, closed: dict[str, Any] | None) -> str:
    out = [f"states: {', '.join(r.states) or '(none)'}",
           f"inputs: {', '.join(r.inputs) or '(none)'}",
           f"parameters: {', '.join(r.parameters) or '(none)'}", ""]
    if r.definitions:
        out += ["definitions (in order: each uses the states, inputs, parameters and the "
                "definitions above it)"]
        out += [f"  {n} = {definition_text(v)}" for n, v in r.definitions] + [""]
    out += [f"{s}' = {sympy.sstr(r.rhs[s])}" for s in r.states]
    if r.outputs:
        out += ["", "where"] + [f"  {n} = {sympy.sstr(v)}" for n, v in _sorted(r.outputs)]
    if closed:
        out += ["", "closed form (constant inputs; <state>_0 is the initial value):"]
        out += [f"{s}(t) = {sympy.sstr(closed[s])}" for s in r.states if s in closed]
    return "\n".join(out) + "\n"


def odes_to_latex(r: Reduced, closed: dict[str, Any] | None) -> str:
    lines = [r"\begin{align*}"]
    symbols: dict[str, Any] = {}
    rows = [f"  {sympy.latex(sympy.Symbol(n))} &= {sympy.latex(_sympy_value(v, symbols))}"
            for n, v in r.definitions]
    rows += [f"  \\dot{{{sympy.latex(sympy.Symbol(s))}}} &= {sympy.latex(r.rhs[s])}"
             for s in r.states]
    if closed:
        rows += [f"  {sympy.latex(sympy.Symbol(s))}(t) &= {sympy.latex(closed[s])}"
                 for s in r.states if s in closed]
    lines.append(" \\\\\n".join(rows))
    lines.append(r"\end{align*}")
    return "\n".join(lines) + "\n"


def odes_to_json(r: Reduced, closed: dict[str, Any] | None) -> str:
    data = {
        "states": r.states, "inputs": r.inputs, "parameters": r.parameters,
        "definitions": [{"name": n, "value": definition_text(v)} for n, v in r.definitions],
        "odes": {s: sympy.sstr(r.rhs[s]) for s in r.states},
        "outputs": {n: sympy.sstr(v) for n, v in _sorted(r.outputs)},
        "closed_form": {s: sympy.sstr(v) for s, v in (closed or {}).items()} or None,
        "obstacles": [{"kind": o.kind, "message": o.message, "variables": list(o.variables),
                       "equations": [f"{e.origin} at {e.span}" for e in o.equations]}
                      for o in r.obstacles],
    }
    return json.dumps(data, indent=2) + "\n"
