"""``cyphy show --format dot|svg``: the kinematic graph, read back by Graphviz itself."""

from __future__ import annotations

import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

from conftest import EXAMPLES
from cyphy.cli import main


def _graph(text: str) -> tuple[dict[str, str], list[tuple[str, str, str, str]]]:
    """Graphviz's reading of a DOT text: node → label, and (tail, head, label, style)."""
    done = subprocess.run(["dot", "-Tjson"], input=text, capture_output=True, text=True,
                          check=True)
    graph = json.loads(done.stdout)
    objects = graph.get("objects", [])
    labels = {o["name"]: o["label"] for o in objects}
    names = [o["name"] for o in objects]
    edges = [(labels[names[e["tail"]]], labels[names[e["head"]]], e.get("label", ""),
              e.get("style", "")) for e in graph.get("edges", [])]
    return labels, edges


def test_marxbot_dot(capsys) -> None:
    assert main(["show", str(EXAMPLES / "marxbot"), "--format", "dot"]) == 0
    text = capsys.readouterr().out
    labels, edges = _graph(text)
    assert sorted(labels.values()) == ["Core", "LTreel::Track", "LTreel::Wheel",
                                       "RTreel::Track", "RTreel::Wheel"]
    assert sorted(edges) == [
        ("Core", "LTreel::Track", "fixed", "dashed"),
        ("Core", "LTreel::Wheel", "LHinge\\n(Revolute)", ""),
        ("Core", "RTreel::Track", "fixed", "dashed"),
        ("Core", "RTreel::Wheel", "RHinge\\n(Revolute)", "")]
    assert main(["show", str(EXAMPLES / "marxbot"), "--format", "dot"]) == 0
    assert capsys.readouterr().out == text  # byte-identical


def test_manipulator_svg(capsys) -> None:
    assert main(["show", str(EXAMPLES / "manipulator"), "--format", "svg"]) == 0
    root = ET.fromstring(capsys.readouterr().out)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    texts = [t.text for t in root.iter("{http://www.w3.org/2000/svg}text")]
    for name in ("Stand", "Arm", "Forearm", "Gripper", "Shoulder", "Slide", "Lift",
                 "(Prismatic)"):
        assert name in texts


def test_unconnected_joints_and_fixed_connections(tmp_path: Path, capsys) -> None:
    model = tmp_path / "Q.rsm"
    model.write_text("""\
import physmod::joints::Revolute
pmodel Q {
  local link A {
    def { inertial information { mass 1.0 } }
    jref Loose = Revolute { }
  }
  local link B { def { inertial information { mass 1.0 } } fixed to A }
}
""")
    assert main(["show", str(model), "--format", "dot"]) == 0
    labels, edges = _graph(capsys.readouterr().out)
    assert ("A", "", "Loose\\n(unconnected)", "dotted") in edges
    assert ("B", "A", "fixed", "dashed") in edges  # from the link that says `fixed to`


def test_svg_without_graphviz_is_a_clear_error(monkeypatch, capsys) -> None:
    import shutil

    monkeypatch.setattr(shutil, "which", lambda name: None)
    assert main(["show", str(EXAMPLES / "dcmotor"), "--format", "svg"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "needs Graphviz's `dot` on PATH" in captured.err
