"""The library entry points behind the CLI: values in, results with diagnostics out.

A thin facade: each entry point composes the stages (:mod:`cyphy.pipeline`, the semantics,
the back ends) and returns values; the stages decide which diagnostics to report. Topics live
in their own modules (``solve``, ``simulate``, ``semantics``, ``robot_formats``, ``view``,
``machines``) and are re-exported here, so ``from cyphy import api; api.check(...)`` is the one
way in. Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.
"""

from cyphy.api.machines import machine_interpreter
from cyphy.api.robot_formats import (SdfGenOptions, TreeGenOptions, generate_mjcf, generate_sdf,
                                     generate_urdf, robot)
from cyphy.api.semantics import (SemanticsGenOptions, generate_cyphycircus, generate_isabelle,
                                 semantics)
from cyphy.api.simulate import SimulateOptions, SimulateResult, simulate
from cyphy.api.solve import SolveOptions, SolveResult, UsageError, solve, unknown_elements
from cyphy.api.theory import check_theory
from cyphy.api.view import ViewRequest, view
from cyphy.pipeline.check import CheckOptions, CheckResult, check
from cyphy.pipeline.elaborate import ElaborateOptions, ElaborateResult, elaborate
from cyphy.pipeline.generated import Generated

__all__ = [
    "CheckOptions", "CheckResult", "ElaborateOptions", "ElaborateResult", "Generated",
    "SdfGenOptions", "SemanticsGenOptions", "SimulateOptions", "SimulateResult",
    "SolveOptions", "SolveResult", "TreeGenOptions", "UsageError", "ViewRequest", "check",
    "check_theory", "elaborate", "generate_cyphycircus", "generate_isabelle", "generate_mjcf",
    "generate_sdf", "generate_urdf", "machine_interpreter", "robot", "semantics", "simulate", "solve",
    "unknown_elements", "view",
]
