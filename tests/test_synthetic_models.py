"""The synthetic models of benchmarks/synthetic.py check cleanly and elaborate to what they say."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from cyphy import api
from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
from synthetic import chain_model, tree_model, write_model  # noqa: E402

HAS_ELABORATE = hasattr(api, "elaborate")
needs_elaborate = pytest.mark.skipif(not HAS_ELABORATE, reason="api.elaborate is not there yet")


def _write(tmp_path: Path, text: str) -> Path:
    return write_model(tmp_path, text)


@pytest.mark.parametrize("text", [chain_model(5), tree_model(7), chain_model(3, sensors_per_link=4),
                                  tree_model(400, lean=True)],
                         ids=["chain5", "tree7", "chain3x4", "lean tree400"])
def test_synthetic_models_check_without_diagnostics(tmp_path: Path, text: str) -> None:
    result = api.check([_write(tmp_path, text)])
    assert [(d.code.id, d.message) for d in result.report.diagnostics] == []


def _elaborate(tmp_path: Path, text: str):  # type: ignore[no-untyped-def]
    result = api.elaborate([_write(tmp_path, text)], api.ElaborateOptions())
    assert [(d.code.id, d.message) for d in result.report.diagnostics] == []
    assert result.model is not None
    return result.model


def _distinct(names: list[str]) -> None:
    assert len(set(names)) == len(names), sorted(names)


@needs_elaborate
def test_chain_elaborates(tmp_path: Path) -> None:
    m = _elaborate(tmp_path, chain_model(5))
    assert m.name == "Chain5"
    assert (len(m.links), len(m.joints), len(m.bodies), len(m.sensors), len(m.actuators)) \
        == (5, 4, 5, 5, 4)
    assert m.fixed == []
    # Only the library devices' own parameters (IR::a, the motor constants) have no value.
    assert not [name for name, spans in m.missing.items()
                if any(str(tmp_path) in str(span.file) for span in spans)]
    assert [link.name for link in m.links] == [f"Chain5::L{k}" for k in range(5)]
    assert {(j.name, j.parent.name, j.child.name) for j in m.joints} == {
        (f"Chain5::L{k}::J{k}", f"Chain5::L{k}", f"Chain5::L{k + 1}") for k in range(4)}
    _distinct([e.name for e in m.all_elements()])
    # Poses: L_k sits 0.1·k above the model origin with yaw 0.1·k; every pose is known.
    for k, link in enumerate(m.links):
        x, y, z, roll, pitch, yaw = link.pose.to_xyz_rpy()
        assert (x, y, roll, pitch) == pytest.approx((0, 0, 0, 0), abs=1e-12)
        assert (z, yaw) == pytest.approx((0.1 * k, 0.1 * k), abs=1e-12)
    for joint in m.joints:
        assert joint.pose is not None


@needs_elaborate
def test_tree_elaborates(tmp_path: Path) -> None:
    m = _elaborate(tmp_path, tree_model(7))
    assert (len(m.links), len(m.joints), len(m.bodies), len(m.sensors), len(m.actuators)) \
        == (7, 6, 7, 7, 6)
    # L0 has children L1..L3, L1 has L4..L6 (branching 3).
    assert {(j.parent.name, j.child.name) for j in m.joints} == {
        ("Tree7::L0", "Tree7::L1"), ("Tree7::L0", "Tree7::L2"), ("Tree7::L0", "Tree7::L3"),
        ("Tree7::L1", "Tree7::L4"), ("Tree7::L1", "Tree7::L5"), ("Tree7::L1", "Tree7::L6")}
    _distinct([e.name for e in m.all_elements()])


@needs_elaborate
def test_index_expansion_gives_distinct_names(tmp_path: Path) -> None:
    m = _elaborate(tmp_path, chain_model(3, sensors_per_link=4))
    assert len(m.sensors) == 12
    assert {s.name for s in m.sensors} == {
        f"Chain3::L{k}::S{k}::{i}" for k in range(3) for i in range(4)}
    _distinct([e.name for e in m.all_elements()])
    for s in m.sensors:
        assert s.qname[-1].isdigit()
        assert s.pose.position[1] == pytest.approx(0.01 * int(s.qname[-1]), abs=1e-12)


def test_the_large_check_benchmark_runs_and_reports(tmp_path: Path) -> None:
    """``benchmarks/bench_large_check.py`` (run by hand at 90,198 links) at a small size: a
    clean check in a process of its own, measured, and the target judged not met (too few
    links to count)."""
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "bench_large_check.py"),
                          "--links", "300"], capture_output=True, text=True, timeout=300,
                         cwd=tmp_path)
    assert out.returncode == 1, out.stdout + out.stderr
    first, verdict = out.stdout.splitlines()
    assert first.startswith("300 links (0.1 MB), cold: exit 0, "), first
    assert first.endswith("last line: 1 file checked: 0 errors, 0 warnings"), first
    assert verdict == "target (90,198 links cold: 60 s, 1.5 GB): NOT met", verdict
