"""cyphy: RoboSim models to SDF, CyPhyCircus, Isabelle/UTP and Flow* (see README.md)."""

from __future__ import annotations

import os

# SymPy's caches hold 1000 entries unless told otherwise, read once when SymPy is imported
# (cyphy imports it lazily, after this): reducing a 60-link arm's equations thrashed them,
# and the cost grew with the square of the model's size (3.0 times the time for twice the
# links; 2.0 with 100000 entries, measured). A value set in the environment is kept.
os.environ.setdefault("SYMPY_CACHE_SIZE", "100000")


def __getattr__(name: str) -> str:
    """``cyphy.__version__``, read from the installed distribution's metadata (pyproject.toml
    is its one source) when first asked for: importlib.metadata costs every command's start
    otherwise."""
    if name != "__version__":
        raise AttributeError(f"module 'cyphy' has no attribute {name!r}")
    # lazy: importlib.metadata costs milliseconds at every start; only __version__ reads it
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("cyphy")
    except PackageNotFoundError:  # a source tree on sys.path, never installed
        return "0+unknown"
