"""Elaboration without devices (what the value checks V1-V5 read) gives the same links, bodies
and joints as the full elaboration; annotations are evaluated once per copy where they need
to be, and shared where they are literal; V4's plain-float comparison is NumPy's."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy import api
from cyphy.diagnostics import Report
from cyphy.model.choose import top_level_pmodels
from cyphy.model.elaborate import elaborate_pmodel
from cyphy.model.elements import AnnotationValue, ElaboratedModel
from conftest import EXAMPLES, ROOT, corpus_project_folders

sys.path.insert(0, str(ROOT / "benchmarks"))
from synthetic import chain_model, tree_model, write_model  # noqa: E402


def _both(paths: list[Path]) -> list[tuple[ElaboratedModel, ElaboratedModel]]:
    checked = api.check(paths, api.CheckOptions(wellformedness=False))
    assert checked.resolution is not None
    ws = checked.workspace
    return [tuple(elaborate_pmodel(ws, checked.resolution, Report(), pm, f, devices=d)
                  for d in (True, False))  # type: ignore[misc]
            for pm, f in top_level_pmodels(ws)]


def _value(v: Any) -> Any:
    """A comparable form of an evaluated value (NumPy arrays do not compare with ==)."""
    if isinstance(v, np.ndarray):
        return ("array", v.shape, tuple(v.reshape(-1).tolist()))
    if isinstance(v, dict):
        return tuple((k, _value(x)) for k, x in v.items())
    if isinstance(v, AnnotationValue):
        return (v.template, _value(dict(v.args)))
    return v


def _geometry(m: ElaboratedModel) -> dict[str, list[tuple[Any, ...]]]:
    return {
        "links": [(l.name, l.pose, l.inertial, l.inertial_source,
                   [b.name for b in l.bodies], [j.name for j in l.joints]) for l in m.links],
        "bodies": [(b.name, b.pose, b.geometry, _value(b.size), _value(b.surface), b.inertial,
                    b.mesh_uri, b.link.name if b.link else None) for b in m.bodies],
        "joints": [(j.name, j.local_pose, j.pose, _value(j.axis), _value(j.annotation),
                   j.definition,
                    j.target_copy, j.parent.name if j.parent else None,
                    j.child.name if j.child else None) for j in m.joints],
        "unconnected": [j.name for j in m.unconnected],
        "fixed": [(f.name, f.parent.name, f.child.name) for f in m.fixed],
    }


def _assert_same_geometry(paths: list[Path]) -> None:
    pairs = _both(paths)
    assert pairs, "no top-level p-model"
    for full, geometry in pairs:
        assert _geometry(geometry) == _geometry(full)
        assert geometry.sensors == [] and geometry.actuators == []
        assert all(j.device is None for j in geometry.joints)


def test_marxbot_geometry_without_devices() -> None:
    _assert_same_geometry([EXAMPLES / "marxbot"])


@pytest.mark.parametrize("text", [tree_model(13, 3, sensors_per_link=3), chain_model(6)],
                         ids=["tree13x3", "chain6"])
def test_synthetic_geometry_without_devices(tmp_path: Path, text: str) -> None:
    _assert_same_geometry([write_model(tmp_path, text)])


@pytest.mark.parametrize("folder", corpus_project_folders(), ids=lambda p: p.name)
def test_corpus_geometry_without_devices(folder: Path) -> None:
    checked = api.check([folder], api.CheckOptions(wellformedness=False))
    if checked.report.has_errors or not top_level_pmodels(checked.workspace):
        pytest.skip("the project does not resolve, or has no top-level p-model")
    _assert_same_geometry([folder])


INDEXED_ANNOTATIONS = """\
import physmod::joints::Revolute
import physmod::sdf::annotations::*
pmodel Fan {
  local link Hub {
    def { inertial information { mass 1.0 } }
    jref Blade = Revolute {
      index k : [0,3)
      annotation Revolute { axis = Axis { xyz = (|k,1,0|) } }
      instantiation AXIS = (|0,1,0|)
      flexibly connected to Tip
    }
    jref Fixed = Revolute {
      index k : [0,3)
      annotation Revolute { axis = Axis { xyz = (|0,0,1|) } }
      instantiation AXIS = (|0,0,1|)
      flexibly connected to Tip
    }
  }
  local link Tip { def { inertial information { mass 1.0 } } }
}
"""


@pytest.mark.parametrize("devices", [True, False])
def test_indexed_annotations_per_copy_or_shared(tmp_path: Path, devices: bool) -> None:
    """An annotation that uses the index is evaluated for each copy (the first, the second
    and a later one); a literal one is evaluated once and shared by every copy."""
    ((full, geometry),) = _both([write_model(tmp_path, INDEXED_ANNOTATIONS, "fan.rsm")])
    m = full if devices else geometry
    blades = [j for j in m.joints if j.simple_name == "Blade"]
    fixed = [j for j in m.joints if j.simple_name == "Fixed"]
    assert len(blades) == len(fixed) == 3
    xyz = [tuple(np.asarray(j.annotation.get("axis").get("xyz")).tolist()) for j in blades]
    assert xyz == [(0.0, 1.0, 0.0), (1.0, 1.0, 0.0), (2.0, 1.0, 0.0)]
    assert all(j.annotation is fixed[0].annotation for j in fixed)
    assert all(tuple(np.asarray(j.axis).tolist()) == (0.0, 1.0, 0.0) for j in blades)


_COMPONENT = st.one_of(st.floats(-2, 2, allow_nan=False),
                       st.sampled_from([0.0, 1.0, -1.0, 1e-10, 1 + 1e-6, float("nan")]))


@settings(max_examples=200, deadline=None)
@given(st.lists(_COMPONENT, min_size=3, max_size=3), st.lists(_COMPONENT, min_size=3, max_size=3))
def test_v4_allclose_is_numpys(a: list[float], b: list[float]) -> None:
    """V4 compares directions in plain floats; it must agree with ``numpy.allclose``."""
    from cyphy.wellformed.values import _allclose

    assert _allclose(a, b) == bool(np.allclose(a, b, atol=1e-9))
