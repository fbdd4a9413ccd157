"""pytest fixtures for the SDF validation tools.

Use them in a test module with ``pytest_plugins = ["sdf_tools.fixtures"]``.

A missing libsdformat or PyBullet FAILS the tests (sdf.md decision 2: a missing
library must not turn CI green). On a developer machine without them, set
``CYPHY_SKIP_SDF_TOOLS=1`` to skip instead; that variable is ignored when ``CI``
is set.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import pytest

from .validate import SdfToolsMissing, build_checker, pybullet_load

OPT_OUT = "CYPHY_SKIP_SDF_TOOLS"


def _missing(error: SdfToolsMissing) -> None:
    if os.environ.get(OPT_OUT) and not os.environ.get("CI"):
        pytest.skip(f"{error} ({OPT_OUT} is set)")
    pytest.fail(f"{error}\n(set {OPT_OUT}=1 to skip on a developer machine)", pytrace=False)


@pytest.fixture(scope="session")
def sdf_checker() -> Path:
    """The compiled ``sdfcheck`` binary (built once per session)."""
    try:
        return build_checker()
    except SdfToolsMissing as e:
        _missing(e)
        raise


@pytest.fixture(scope="session")
def pybullet_loader() -> Callable[..., str | None]:
    """``validate.pybullet_load``, after checking that PyBullet is installed."""
    import importlib.util

    if importlib.util.find_spec("pybullet") is None:
        _missing(SdfToolsMissing("pybullet is not installed; `pip install -e '.[test]'`"))
    return pybullet_load
