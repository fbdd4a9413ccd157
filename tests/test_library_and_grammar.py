"""The grammar is conflict-free, the shipped library parses and resolves, and our examples
pass `cyphy check`."""

from __future__ import annotations

from pathlib import Path

import pytest

from cyphy import api
from cyphy.lang import ast
from cyphy.lang.parser import contains_lark_objects, grammar, parse_text
from cyphy.lang.workspace import library_files
from conftest import EXAMPLES


def test_grammar_builds_in_strict_mode() -> None:
    """strict=True rejects shift/reduce conflicts and terminal collisions."""
    grammar.cache_clear()
    try:
        assert grammar(strict=True) is not None
    finally:
        grammar.cache_clear()


@pytest.mark.parametrize("path", library_files(), ids=lambda p: p.name)
def test_library_file_parses_cleanly(path: Path) -> None:
    result = parse_text(path.read_text(encoding="utf-8"), str(path))
    assert result.diagnostics == ()
    assert result.file is not None and result.file.package[0] == "physmod"
    assert not contains_lark_objects(result.file)


def test_library_resolves_with_no_diagnostics() -> None:
    result = api.check(library_files())
    assert result.report.diagnostics == []


def _library_member(package: tuple[str, ...], name: str) -> object:
    result = api.check(library_files(), api.CheckOptions(syntax_only=True))
    return result.workspace.packages[package].members[name][0]


def test_library_has_the_elements_the_corpus_uses() -> None:
    revolute = _library_member(("physmod", "joints"), "Revolute")
    assert isinstance(revolute, ast.Definition) and revolute.kind is ast.BlockKind.JOINT
    ports = {d.name: d.kind for d in revolute.members if isinstance(d, ast.VarDecl)}
    assert ports["tau"] is ast.DeclKind.INPUT and ports["AXIS"] is ast.DeclKind.CONST
    assert {"theta", "v", "a"} <= set(ports)
    motor = _library_member(("physmod", "actuators"), "SpeedControlMotor")
    ports = {d.name: d.kind for d in motor.members if isinstance(d, ast.VarDecl)}
    assert ports["das"] is ast.DeclKind.INPUT and ports["T"] is ast.DeclKind.OUTPUT
    assert {"b", "Ke", "Kt", "R", "L", "Kp", "Ki", "Kd"} <= {
        n for n, k in ports.items() if k is ast.DeclKind.CONST}
    ir = _library_member(("physmod", "sensors"), "IR")
    ports = {d.name: d.kind for d in ir.members if isinstance(d, ast.VarDecl)}
    assert ports["distance"] is ast.DeclKind.INPUT and ports["voltage"] is ast.DeclKind.OUTPUT
    axis = _library_member(("physmod", "sdf", "annotations"), "Axis")
    assert {p.name for p in axis.params} >= {"xyz", "initial_position", "dynamics", "limit"}


def test_marxbot_example_passes_check() -> None:
    result = api.check([EXAMPLES / "marxbot"])
    assert result.report.diagnostics == []
    assert len(result.workspace.targets) == 5


def test_marxbot_example_has_24_indexed_proximity_sensors() -> None:
    result = api.check([EXAMPLES / "marxbot"], api.CheckOptions(syntax_only=True))
    base = next(f for p, f in result.workspace.files.items() if p.endswith("marXbotBase.rsm"))
    pmodel = next(i for i in base.items if isinstance(i, ast.PModel))
    core = next(b for b in pmodel.blocks if b.name == "Core")
    proximity = next(b for b in core.blocks if b.name == "Proximity")
    assert proximity.kind is ast.BlockKind.SENSOR and proximity.ref == ("IR",)
    index = proximity.index
    assert (index.var, index.lower.text, index.upper.text, index.closed) == ("j", "0", "24",
                                                                             False)
    hinges = [b for b in core.blocks if b.kind is ast.BlockKind.JOINT]
    assert sorted(h.name for h in hinges) == ["LHinge", "RHinge"]
    assert all(any(a.kind is ast.BlockKind.ACTUATOR for a in h.blocks) for h in hinges)
    assert sorted(p.name for p in pmodel.parts) == ["LTreel", "RTreel"]
