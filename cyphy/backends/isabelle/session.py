"""The Isabelle session of a platform mapping's semantics, and what it reports: inconsistent
axioms, what Isabelle's scalar state cannot hold, and constructs not yet translatable. The policy of ``cyphy gen --isabelle``, kept with the
printer that knows it so the API only composes."""

from __future__ import annotations

from typing import Any

from cyphy import codes
from cyphy.backends.isabelle.axioms import INCONSISTENT_AXIOMS, unsatisfiable_axioms
from cyphy.backends.isabelle.theory import UNTRANSLATABLE, IsabelleError, generate_session
from cyphy.diagnostics import Report
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.walk import action_nodes


def session_files(built: Any, options: Any, report: Report
                  ) -> tuple[dict[str, str], c.ActionDef] | None:
    """The session's files (``ROOT``, the prelude, the theory, a README, the names table)
    for ``built`` (a :class:`cyphy.semantics.circus.build.Semantics`) under ``options``
    (its ``dialect``, ``system_name``, ``elements``), with the theory's ``Init`` as printed
    (what it starts differs between the dialects); None when an error was reported."""
    span = built.mapping.span
    why = unsatisfiable_axioms(built.program.globals)
    if why is not None:
        report.report(INCONSISTENT_AXIOMS, why, span,
                      "check the d-model's cycle restriction and --tscale: a theory with "
                      "inconsistent axioms proves anything")
        return None
    try:
        if options.dialect == "axiomatic":
            session = _axiomatic_session(built, options, report)
            if session is None:
                return None
        else:
            session = generate_session(built.program, built.names, options.system_name)
    except IsabelleError as err:
        where = err.span if err.span is not None and err.span.line > 0 else span
        if err.shapes:
            report.report(codes.S3, f"{err} (Isabelle's state is scalar: each equation "
                          "between vectors or matrices is written per component)", where,
                          "give both sides the same size (a m x n matrix equals only a m x n "
                          "one; a product needs the left's columns to equal the right's rows)")
        else:
            report.report(UNTRANSLATABLE, str(err), where,
                          "this construct cannot be written in Isabelle/UTP yet; the text and "
                          "LaTeX printers (--cyphycircus, --latex) show it")
        return None
    files: dict[str, str] = session.files
    return files, session.actions["Init"]


def _axiomatic_session(built: Any, options: Any, report: Report) -> Any:
    """The Ax_CyPhyCircus session, with Evolve reduced to explicit ODEs (SymPy); None when
    the equations cannot be reduced (E-ISABELLE-ODE reported)."""
    from cyphy.backends.isabelle.ax_theory import generate_ax_session  # lazy: SymPy

    pm = built.program.pmodel
    evolutions = [n for d in pm.actions for n in action_nodes(d.body)
                  if isinstance(n, c.Evolution)]
    odes = None
    if evolutions:
        from cyphy.semantics.dynamics.evolve_odes import explicit_odes  # lazy: SymPy

        odes = explicit_odes(built.model, evolutions[0], {f.name for f in pm.state.fields},
                             options.elements, report, built.mapping.span,
                             frozenset(f.name for f in pm.state.fields if f.visible))
        if odes is None:
            return None
    return generate_ax_session(built.program, built.names, odes,
                               options.system_name, options.elements)
