"""The CyPhyCircus semantics of a platform mapping, and the generators built on it: text,
LaTeX (``--cyphycircus``, ``--latex``) and the Isabelle session (``--isabelle``)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from cyphy.backends.circus.latex import STYLE, program_to_latex
from cyphy.backends.circus.pdf import PdfError, typeset
from cyphy.backends.circus.text import program_to_text
from cyphy.deep import deep
from cyphy.pipeline.check import CheckOptions, CheckResult, check
from cyphy.pipeline.generated import Generated


@dataclass(frozen=True)
class SemanticsGenOptions:
    """Options of the generators built on the CyPhyCircus semantics (``--cyphycircus``,
    ``--latex``, ``--isabelle``)."""

    mapping: str | None = None  # the mapping (or its p-model) to translate
    system_name: str | None = None  # the name of the whole system (default: the mapping's)
    tscale: float | None = None
    consts: dict[str, object] = field(default_factory=dict)
    search_paths: tuple[str, ...] = ()
    pdf: bool = False  # --latex: also typeset with pdflatex
    dialect: str = "utp"  # --isabelle: "utp" (utp-main 2020) or "axiomatic" (Ax_CyPhyCircus)
    elements: tuple[str, ...] = ()  # --isabelle axiomatic: the elements Evolve's ODE covers
    default_inertial: str | None = None  # see ElaborateOptions
    machine: str | None = None  # the d-model's state machine D is written from (default: as simulate)


@deep
def semantics(paths: Sequence[str | Path], options: SemanticsGenOptions = SemanticsGenOptions()
              ) -> tuple[CheckResult, Any]:
    """Check the files (and the files they use) and apply the paper's rules to the chosen
    platform mapping: ``(check result, Semantics or None)``."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.semantics.circus.build import SemanticsOptions, build_semantics

    # The value checks concern geometry and inertia, which the semantics does not use.
    checked = check(paths, CheckOptions(search_paths=options.search_paths,
                                        consts=dict(options.consts),
                                        neighbours_as_targets=True, value_checks=False,
                                        find_in_folder="mapping"))
    if checked.report.has_errors or checked.resolution is None:
        return checked, None
    built = build_semantics(checked.workspace, checked.resolution, checked.report,
                            SemanticsOptions(options.mapping, options.system_name,
                                             options.tscale, dict(options.consts),
                                             options.default_inertial, options.machine))
    return checked, built


@deep
def generate_cyphycircus(paths: Sequence[str | Path], target: str,
                         options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """``target`` ``"text"``: ``<N>.cpc`` (Unicode, reads like the paper's Figure 18);
    ``"latex"``: ``<N>.tex`` with ``cyphycircus.sty`` (and ``<N>.pdf`` with ``pdf``). Both
    with the names table ``<N>.names.json``."""
    checked, built = semantics(paths, options)
    result = Generated(checked.report, checked.sources)
    if built is None or checked.report.has_errors:
        return result
    stem = built.program.system.name
    if target == "text":
        result.files[f"{stem}.cpc"] = program_to_text(built.program)
    else:
        document = program_to_latex(built.program)
        result.files[f"{stem}.tex"] = document
        result.files["cyphycircus.sty"] = STYLE
        if options.pdf:
            try:
                result.files[f"{stem}.pdf"] = typeset(document, {"cyphycircus.sty": STYLE})
            except PdfError as err:
                # lazy: NumPy: `cyphy check` must not pay for it
                from cyphy.semantics.circus.build import NO_PDF

                checked.report.report(NO_PDF, str(err), built.mapping.span, err.hint)
                result.files.clear()
                return result
    table = dict(built.names.items())
    result.files[f"{stem}.names.json"] = json.dumps(table, indent=2, sort_keys=True) + "\n"
    return result


@deep
def generate_isabelle(paths: Sequence[str | Path],
                      options: SemanticsGenOptions = SemanticsGenOptions()) -> Generated:
    """The Isabelle session of one platform mapping: ``ROOT``, the prelude, the theory, a
    README and the names table. Files are empty when the model has errors."""
    # lazy: NumPy: `cyphy check` must not pay for it
    from cyphy.backends.isabelle.session import session_files

    checked, built = semantics(paths, options)
    generated = Generated(checked.report, dict(checked.sources))
    if built is None or checked.report.has_errors:
        return generated
    files = session_files(built, options, checked.report)
    if files is not None:
        generated.files = files
    return generated
