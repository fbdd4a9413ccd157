"""The library entry points behind the CLI: values in, results with diagnostics out.

A thin facade: each entry point composes the stages (:mod:`cyphy.pipeline`, the semantics,
the back ends) and returns values; the stages decide which diagnostics to report. Topics live
in their own modules (``solve``, ``simulate``, ``semantics``, ``robot_formats``, ``view``,
``machines``, ``theory``) and are re-exported here, so ``from cyphy import api; api.check(...)`` is the one
way in. Nothing here prints or exits; :mod:`cyphy.cli` renders what these functions return.

The names are imported on first use (PEP 562): ``from cyphy.api import check`` loads the
checker only, not the semantics, SymPy or NumPy behind the other topics, which keeps
``cyphy check`` and ``cyphy gen --sdf`` within issue 24's start-up budget.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # what the names are, for type checkers and the import graph
    from cyphy.api.animate import AnimateError, Animation, animate
    from cyphy.api.machines import machine_interpreter
    from cyphy.api.robot_formats import (SdfGenOptions, TreeGenOptions, generate_mjcf,
                                         generate_sdf, generate_urdf, robot)
    from cyphy.api.semantics import (SemanticsGenOptions, generate_cyphycircus,
                                     generate_isabelle, semantics)
    from cyphy.api.simulate import SimulateOptions, SimulateResult, simulate
    from cyphy.api.solve import SolveOptions, SolveResult, UsageError, solve, unknown_elements
    from cyphy.api.theory import check_theory
    from cyphy.api.view import ViewRequest, view
    from cyphy.pipeline.check import CheckOptions, CheckResult, check
    from cyphy.pipeline.elaborate import ElaborateOptions, ElaborateResult, elaborate
    from cyphy.pipeline.generated import Generated

#: Each public name → the module that defines it.
_HOME: dict[str, str] = {
    **dict.fromkeys(("AnimateError", "Animation", "animate"), "cyphy.api.animate"),
    **dict.fromkeys(("machine_interpreter",), "cyphy.api.machines"),
    **dict.fromkeys(("SdfGenOptions", "TreeGenOptions", "generate_mjcf", "generate_sdf",
                     "generate_urdf", "robot"), "cyphy.api.robot_formats"),
    **dict.fromkeys(("SemanticsGenOptions", "generate_cyphycircus", "generate_isabelle",
                     "semantics"), "cyphy.api.semantics"),
    **dict.fromkeys(("SimulateOptions", "SimulateResult", "simulate"), "cyphy.api.simulate"),
    **dict.fromkeys(("SolveOptions", "SolveResult", "UsageError", "solve", "unknown_elements"),
                    "cyphy.api.solve"),
    **dict.fromkeys(("check_theory",), "cyphy.api.theory"),
    **dict.fromkeys(("ViewRequest", "view"), "cyphy.api.view"),
    **dict.fromkeys(("CheckOptions", "CheckResult", "check"), "cyphy.pipeline.check"),
    **dict.fromkeys(("ElaborateOptions", "ElaborateResult", "elaborate"),
                    "cyphy.pipeline.elaborate"),
    **dict.fromkeys(("Generated",), "cyphy.pipeline.generated"),
}

__all__ = sorted(_HOME)


def __getattr__(name: str) -> Any:
    """A public name, imported from its module the first time it is asked for."""
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value  # asked once: later lookups do not come back here
    return value


class _Facade(types.ModuleType):
    """This package, so that loading a topic does not hide its entry point: the import system
    binds a loaded submodule on its package (``cyphy.api.semantics`` the module), and four
    topics are named like the function they define (``semantics``, ``simulate``, ``solve``,
    ``view``); the function is what ``cyphy.api`` exports under that name."""

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(value, types.ModuleType) and _HOME.get(name) == value.__name__:
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Facade


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOME))
