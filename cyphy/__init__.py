"""cyphy: RoboSim models to SDF, CyPhyCircus, Isabelle/UTP and Flow* (see README.md)."""


def _version() -> str:
    """The installed distribution's version (pyproject.toml is its one source)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("cyphy")
    except PackageNotFoundError:  # a source tree on sys.path, never installed
        return "0+unknown"


__version__ = _version()
