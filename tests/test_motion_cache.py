"""The persistent cache of equations of motion (``cyphy/semantics/dynamics/motion_cache.py``):
a warm run gives the very files a cold one gave without importing SymPy; a change to any
number the equations depend on is a miss that derives the new equations (checked against
Pinocchio's inverse dynamics, an independent derivation); anything odd about an entry falls
back to deriving."""

from __future__ import annotations

import math
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES, ROOT
from cyphy import disk_cache
from cyphy.semantics.dynamics import motion, motion_cache
from cyphy.semantics.dynamics import rigid_body as dynamics
from cyphy.semantics.dynamics.errors import DynamicsError

ARM = """
import physmod::math::*
import physmod::joints::*
import physmod::sdf::annotations::*

pmodel Arm {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
        jref Shoulder = Revolute {
            annotation Revolute { axis = Axis { xyz = (|0, 0, 1|) dynamics = Dynamics { damping = 0.5 } } }
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|0, 0, 1|)
            flexibly connected to Upper
        }
    }
    local link Upper {
        pose { x = 0.1 y = 0 z = 0 roll = 0 pitch = 0.2 yaw = 0 }
        def { inertial information { mass 0.5 inertia matrix { ixx 0.01 ixy 0.001 ixz 0 iyy 0.02 iyz 0 izz 0.015 } pose { x = 0 y = 0.02 z = -0.2 roll = 0 pitch = 0 yaw = 0 } } }
        jref Elbow = Revolute {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Hand
        }
    }
    local link Hand {
        pose { x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0.4 }
        def { inertial information { mass 0.2 inertia matrix { ixx 0.002 ixy 0 ixz 0 iyy 0.003 iyz 0 izz 0.001 } pose { x = 0.01 y = 0 z = -0.05 roll = 0 pitch = 0 yaw = 0 } } }
    }
}
"""
GRAVITY = (0.0, 0.0, -9.81)
#: One number changed each: (text replaced, replacement, gravity, Shoulder's damping).
CHANGES = {
    "inertia": ("ixx 0.01 ixy 0.001", "ixx 0.013 ixy 0.001", GRAVITY, 0.5),
    "mass": ("mass 0.2", "mass 0.25", GRAVITY, 0.5),
    "link pose": ("x = 0 y = 0 z = -0.5", "x = 0 y = 0 z = -0.45", GRAVITY, 0.5),
    "joint axis": ("AXIS = (|0, 1, 0|)", "AXIS = (|1, 0, 0|)", GRAVITY, 0.5),
    "damping": ("damping = 0.5", "damping = 0.7", GRAVITY, 0.7),
    "gravity": ("", "", (0.0, 0.0, -1.62), 0.5),
}


@pytest.fixture
def derivations(monkeypatch: pytest.MonkeyPatch) -> list[object]:
    """The trees derived with SymPy (the misses), in order."""
    calls: list[object] = []
    real = motion._derive

    def counted(tree: dynamics.KinematicTree) -> list[tuple[object, int]]:
        calls.append(tree)
        return real(tree)

    monkeypatch.setattr(motion, "_derive", counted)
    return calls


def entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("motion-*/*.pickle"))


def elaborated(folder: Path, text: str):
    from cyphy.api import ElaborateOptions, elaborate

    folder.mkdir(parents=True, exist_ok=True)
    (folder / "arm.rsm").write_text(text)
    result = elaborate([folder], ElaborateOptions())
    assert result.model is not None, result.report.diagnostics
    return result.model


def run_gen(cache_dir: Path, out: Path, no_cache: bool = False) -> str:
    """``cyphy gen examples/marxbot --isabelle`` in a new process: its exit status and whether
    it imported SymPy."""
    script = ("import sys; from cyphy.cli import main; "
              f"code = main(['gen', {str(EXAMPLES / 'marxbot')!r}, '--isabelle', '-o', "
              f"{str(out)!r}, '-q']); print(code, 'sympy' in sys.modules)")
    env = {**os.environ, "CYPHY_CACHE_DIR": str(cache_dir), "PYTHONPATH": str(ROOT)}
    env.pop("CYPHY_NO_CACHE", None)
    if no_cache:
        env["CYPHY_NO_CACHE"] = "1"
    proc = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.splitlines()[-1]


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_a_warm_gen_isabelle_writes_the_same_files_without_sympy(tmp_path: Path) -> None:
    cyphy_cache = tmp_path / "cache"
    assert run_gen(cyphy_cache, tmp_path / "cold") == "0 True"
    assert len(entries(cyphy_cache)) == 1
    assert len(list(cyphy_cache.glob("jinja-*/*.jinja"))) == 3  # the theory's templates, compiled
    assert run_gen(cyphy_cache, tmp_path / "warm") == "0 False"  # SymPy never imported
    assert run_gen(cyphy_cache, tmp_path / "none", no_cache=True) == "0 True"
    cold = files(tmp_path / "cold")
    assert any(name.endswith("_CyPhyCircus.thy") for name in cold)
    assert "LHinge_tau" in cold["marXbotBase_CyPhyCircus.thy"].decode()  # the equations
    assert files(tmp_path / "warm") == cold
    assert files(tmp_path / "none") == cold


def _pinocchio_efforts(model, gravity, damping: float, q, qd, qdd) -> np.ndarray:
    """Pinocchio's inverse dynamics of the model under ``gravity``, plus the Shoulder's
    damping (``τ = M·a + h + d·v``): a derivation that shares nothing with cyphy's."""
    pin = pytest.importorskip("pinocchio")
    from test_dynamics_joints import pinocchio_model

    tree = dynamics.kinematic_tree(model)
    robot = pinocchio_model(model, tree.names, False)
    robot.gravity = pin.Motion(np.array(gravity, dtype=float), np.zeros(3))
    tau = pin.rnea(robot, robot.createData(), q, qd, qdd)
    shoulder = list(tree.names).index("Arm::Base::Shoulder")
    tau[shoulder] += damping * qd[shoulder]
    return tau


def _evaluated(equations, model, q, qd, qdd) -> list[float]:
    from test_dynamics_joints import _evaluate

    tree = dynamics.kinematic_tree(model)
    values: dict[str, float] = {}
    for variable, row in (("theta", q), ("v", qd), ("a", qdd)):
        values.update(zip(tree.coordinates(variable), row))
    return [_evaluate(e.right, values) for e, _ in equations]


@pytest.mark.parametrize("change", sorted(CHANGES))
def test_a_changed_number_misses_and_gives_the_new_equations(
        change: str, tmp_path: Path, cyphy_cache: Path, derivations: list[object],
        monkeypatch: pytest.MonkeyPatch) -> None:
    old, new, gravity, damping = CHANGES[change]
    base_model = elaborated(tmp_path / "base", ARM)
    base = motion.motion_equations(base_model)
    assert len(derivations) == 1 and len(entries(cyphy_cache)) == 1
    assert old in ARM
    model = elaborated(tmp_path / "base", ARM.replace(old, new))  # the same file, changed
    changed = motion.motion_equations(model, gravity)
    assert len(derivations) == 2 and len(entries(cyphy_cache)) == 2  # a miss, stored
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    assert [e for e, _ in motion.motion_equations(model, gravity)] == \
        [e for e, _ in changed]
    monkeypatch.delenv("CYPHY_NO_CACHE")
    rng = np.random.default_rng(7)
    q, qd, qdd = (rng.uniform(-2, 2, 2) for _ in range(3))
    got = _evaluated(changed, model, q, qd, qdd)
    np.testing.assert_allclose(got, _pinocchio_efforts(model, gravity, damping, q, qd, qdd),
                               rtol=1e-9, atol=1e-12)
    before = _evaluated(base, base_model, q, qd, qdd)
    assert not np.allclose(got, before)  # the change matters to the equations
    calls = len(derivations)
    again = elaborated(tmp_path / "base", ARM)
    assert [e for e, _ in motion.motion_equations(again)] == [e for e, _ in base]
    assert len(derivations) == calls  # the first model again: a hit


def test_the_same_model_at_another_path_misses(tmp_path: Path, cyphy_cache: Path,
                                               derivations: list[object]) -> None:
    """Spans name the file: the equations of a copy point at the copy."""
    first = motion.motion_equations(elaborated(tmp_path / "a", ARM))
    second = motion.motion_equations(elaborated(tmp_path / "b", ARM))
    assert len(derivations) == 2
    assert {e.span.file for e, _ in first} == {str(tmp_path / "a" / "arm.rsm")}
    assert {e.span.file for e, _ in second} == {str(tmp_path / "b" / "arm.rsm")}


def test_a_corrupt_entry_is_derived_again_and_replaced(tmp_path: Path, cyphy_cache: Path,
                                                       derivations: list[object]) -> None:
    model = elaborated(tmp_path / "m", ARM)
    expected = [e for e, _ in motion.motion_equations(model)]
    (entry,) = entries(cyphy_cache)
    entry.write_bytes(b"not a pickle")
    entry.chmod(0o600)
    assert [e for e, _ in motion.motion_equations(model)] == expected
    assert len(derivations) == 2 and entry.read_bytes() != b"not a pickle"


def test_an_entry_of_other_contents_is_a_miss(tmp_path: Path, cyphy_cache: Path,
                                              derivations: list[object]) -> None:
    """The right header over a pickle that is not this tree's equations (a list of other
    things, a joint index past the tree)."""
    model = elaborated(tmp_path / "m", ARM)
    expected = [e for e, _ in motion.motion_equations(model)]
    (entry,) = entries(cyphy_cache)
    header = motion_cache.key(dynamics.kinematic_tree(model))
    assert header is not None and entry.read_bytes().startswith(header)
    first = pickle.loads(entry.read_bytes()[len(header):])
    for other in ({"a": 1}, [(first[0][0], 2)], [("x", 0)]):
        entry.write_bytes(header + pickle.dumps(other))
        entry.chmod(0o600)
        assert [e for e, _ in motion.motion_equations(model)] == expected
    assert len(derivations) == 4


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_an_entry_others_may_write_is_not_unpickled(tmp_path: Path, cyphy_cache: Path,
                                                    derivations: list[object],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    model = elaborated(tmp_path / "m", ARM)
    expected = [e for e, _ in motion.motion_equations(model)]
    (entry,) = entries(cyphy_cache)
    entry.chmod(0o666)
    loads: list[object] = []
    monkeypatch.setattr(disk_cache.pickle, "load", lambda f: loads.append(f))
    assert [e for e, _ in motion.motion_equations(model)] == expected
    assert loads == [] and len(derivations) == 2


def test_an_entry_another_user_owns_is_not_unpickled(tmp_path: Path, cyphy_cache: Path,
                                                     derivations: list[object],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    model = elaborated(tmp_path / "m", ARM)
    expected = [e for e, _ in motion.motion_equations(model)]
    monkeypatch.setattr(os, "getuid", lambda: os.stat(entries(cyphy_cache)[0]).st_uid + 1)
    assert [e for e, _ in motion.motion_equations(model)] == expected
    assert len(derivations) == 2


def test_errors_are_not_stored(tmp_path: Path, cyphy_cache: Path,
                               monkeypatch: pytest.MonkeyPatch) -> None:
    model = elaborated(tmp_path / "m", ARM)

    def fails(tree: dynamics.KinematicTree) -> list[tuple[object, int]]:
        raise DynamicsError("no", model.joints[0].span, "")

    monkeypatch.setattr(motion, "_derive", fails)
    with pytest.raises(DynamicsError):
        motion.motion_equations(model)
    assert entries(cyphy_cache) == []


def test_no_cache_writes_nothing(tmp_path: Path, cyphy_cache: Path,
                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYPHY_NO_CACHE", "1")
    assert motion.motion_equations(elaborated(tmp_path / "m", ARM))
    assert not cyphy_cache.exists()


def test_a_value_the_key_cannot_encode_is_derived_not_stored(
        tmp_path: Path, cyphy_cache: Path, derivations: list[object],
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Never keyed on less: an input of a kind the encoder does not know leaves the cache out."""
    model = elaborated(tmp_path / "m", ARM)
    model.joints[0].index["odd"] = object()  # type: ignore[assignment]
    assert motion_cache.key(dynamics.kinematic_tree(model)) is None
    motion.motion_equations(model)
    motion.motion_equations(model)
    assert len(derivations) == 2 and entries(cyphy_cache) == []


def _perturbed(value: object) -> object:
    import dataclasses

    from cyphy.model.elements import Link
    from cyphy.model.poses import Pose

    if isinstance(value, np.ndarray):
        return value + 1e-12
    if isinstance(value, Pose):  # the last bit of one coordinate
        x, y, z = value.position
        return dataclasses.replace(value, position=(math.nextafter(x, math.inf), y, z))
    if isinstance(value, tuple) and value and isinstance(value[0], Link):
        first = value[0]  # a body's links: the first one's mass
        inertial = dataclasses.replace(first.inertial, mass=first.inertial.mass * 1.5)
        return (dataclasses.replace(first, inertial=inertial), *value[1:])
    if isinstance(value, bool):
        return not value
    if isinstance(value, (int, float)):
        return value + 1
    if isinstance(value, str):
        return value + "x"
    if isinstance(value, tuple):
        return (*value, np.ones(3) if value and isinstance(value[0], np.ndarray) else "x")
    raise AssertionError(f"no perturbation of {type(value).__name__}")


def test_every_input_of_the_derivation_changes_the_key(tmp_path: Path) -> None:
    """Each field of each tree joint (the encoder walks the fields: one added later is keyed
    on too), and what the derivation reads from the joint's element (its span, annotation,
    AXIS, definition and device ports), changes the key when it changes; so do gravity and
    the floating base."""
    import dataclasses

    from cyphy.model.elements import Device

    model = elaborated(tmp_path / "m", ARM)
    tree = dynamics.kinematic_tree(model)
    base = motion_cache.key(tree)
    assert base is not None and motion_cache.key(dynamics.kinematic_tree(model)) == base

    def key_with(k: int, joint: object) -> bytes | None:
        joints = list(tree.joints)
        joints[k] = joint  # type: ignore[call-overload]
        return motion_cache.key(dataclasses.replace(tree, joints=tuple(joints)))

    seen = set()
    for k, joint in enumerate(tree.joints):
        for f in dataclasses.fields(joint):
            if f.name != "element":
                changed = key_with(k, dataclasses.replace(
                    joint, **{f.name: _perturbed(getattr(joint, f.name))}))
                assert changed not in (None, base), f.name
                seen.add(changed)
        first = joint.links[0]  # the body's links are read field by field, not walked
        for what, link in {
                "link pose": dataclasses.replace(first, pose=_perturbed(first.pose)),
                "link span": dataclasses.replace(first, span=dataclasses.replace(
                    first.span, line=first.span.line + 1)),
                "link qname": dataclasses.replace(first, qname=(*first.qname, "x"))}.items():
            changed = key_with(k, dataclasses.replace(joint, links=(link, *joint.links[1:])))
            assert changed not in (None, base), what
            seen.add(changed)
        element = joint.element
        device = element.device
        port = device.port("theta")
        variants = {
            "span": dataclasses.replace(element, span=dataclasses.replace(
                element.span, end_column=element.span.end_column + 1)),
            "qname": dataclasses.replace(element, qname=(*element.qname, "x")),
            "axis": dataclasses.replace(element, axis=np.array([1.0, 0.0, 0.0])),
            "definition": dataclasses.replace(element, definition="Prismatic"),
            "annotation": dataclasses.replace(element, annotation=None),
            "device prefix": dataclasses.replace(element, device=Device(
                device.prefix + "x", device.ports, ())),
            "port": dataclasses.replace(element, device=Device(device.prefix, tuple(
                dataclasses.replace(p, mangled=p.mangled + "x") if p is port else p
                for p in device.ports), ())),
        }
        if k == 0:  # the Shoulder's damping is annotated; the Elbow has no annotation
            assert element.annotation is not None
        for what, other in variants.items():
            changed = key_with(k, dataclasses.replace(joint, element=other))
            assert changed not in (None, base), what
            seen.add(changed)
    assert motion_cache.key(dynamics.kinematic_tree(model, (0.0, 0.0, -1.62))) != base
    assert motion_cache.key(dynamics.kinematic_tree(model, floating_base=True)) != base
    assert len(seen) > 20


def test_without_its_sources_nothing_is_cached(tmp_path: Path, cyphy_cache: Path,
                                               derivations: list[object],
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """An installation without the modules the fingerprint reads could not tell a changed
    cyphy from the one that wrote an entry: it derives every time."""
    monkeypatch.setattr(motion_cache, "_SOURCES", (*motion_cache._SOURCES, "absent/*.py"))
    motion_cache.fingerprint.cache_clear()
    try:
        model = elaborated(tmp_path / "m", ARM)
        motion.motion_equations(model)
        motion.motion_equations(model)
        assert len(derivations) == 2 and entries(cyphy_cache) == []
    finally:
        monkeypatch.undo()
        motion_cache.fingerprint.cache_clear()


_LOOP = """            flexibly connected to Hand
        }
        jref Wrist = Revolute {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|1, 0, 0|)
            flexibly connected to Hand
        }"""
_UPPER_INERTIAL = ("inertial information { mass 0.5 inertia matrix { ixx 0.01 ixy 0.001 ixz 0 "
                   "iyy 0.02 iyz 0 izz 0.015 } pose { x = 0 y = 0.02 z = -0.2 roll = 0 "
                   "pitch = 0 yaw = 0 } }")


@pytest.mark.parametrize("case, message", [
    ("no mass", "link Arm::Upper has no mass properties"),
    ("loop", "closes a kinematic loop"),
    ("no mass and a loop", "closes a kinematic loop"),
])
def test_a_bad_tree_is_reported_as_the_tree_with_numbers_reports_it(
        tmp_path: Path, cyphy_cache: Path, case: str, message: str) -> None:
    """The cache is looked up with the tree built without its numbers (no NumPy); a tree
    whose numbers fail, or that has a loop, still gets the error the tree built with its
    numbers raises, the first one it finds (a second parent joint is seen before any
    number), and nothing is stored."""
    text = ARM
    if "mass" in case:  # the Upper arm, moved by the first joint, loses its inertial
        text = text.replace(_UPPER_INERTIAL, "")
    if "loop" in case:  # the Hand gets a second parent joint, after the Elbow's
        text = text.replace("            flexibly connected to Hand\n        }", _LOOP)
    assert text != ARM
    model = elaborated(tmp_path / "m", text)
    with pytest.raises(DynamicsError) as eager:
        dynamics.kinematic_tree(model)
    with pytest.raises(DynamicsError) as lazy:
        motion.motion_equations(model)
    assert message in eager.value.message
    assert (lazy.value.message, lazy.value.span) == (eager.value.message, eager.value.span)
    assert entries(cyphy_cache) == []
