"""cyphy: RoboSim models to SDF, CyPhyCircus, Isabelle/UTP and Flow* (see README.md)."""

from __future__ import annotations


def __getattr__(name: str) -> str:
    """``cyphy.__version__``, read from the installed distribution's metadata (pyproject.toml
    is its one source) when first asked for: importlib.metadata costs every command's start
    otherwise."""
    if name != "__version__":
        raise AttributeError(f"module 'cyphy' has no attribute {name!r}")
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("cyphy")
    except PackageNotFoundError:  # a source tree on sys.path, never installed
        return "0+unknown"
