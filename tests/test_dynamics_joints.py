"""Ball (ZYX Euler angles) and universal joints, and the floating base, in the equations of
motion (cyphy.semantics.dynamics.rigid_body), checked against Pinocchio: its model is built here with
its own joints (``JointModelSphericalZYX``, ``JointModelUniversal``, ``JointModelTranslation``)
from the elaborated model's links, inertials and joints, never from cyphy's tree. Free bodies
are checked against the laws they obey (free fall, conservation of momentum and energy)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cyphy.diagnostics import Span
from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.model.poses import Pose
from cyphy.semantics.dynamics import motion
from cyphy.semantics.dynamics import rigid_body as dynamics
from cyphy.semantics.dynamics import tree_numbers as tree_module
from test_dynamics import _inertial, _pose  # the random links of the one-coordinate trees

pin = pytest.importorskip("pinocchio")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
_SPAN = Span.unknown()


def _elaborated(path: Path) -> ElaboratedModel:
    from cyphy.api import ElaborateOptions, elaborate

    result = elaborate([path], ElaborateOptions())
    assert result.model is not None, result.report.diagnostics
    return result.model


def _tensor(e):
    ixx, ixy, ixz, iyy, iyz, izz = e
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _se3(pose: Pose):
    return pin.SE3(np.array(pose.rotation), np.array(pose.position))


def _axis(joint: Joint, name: str) -> np.ndarray:
    value = joint.axis if name == "AXIS" else joint.device.port(name).value \
        if joint.device is not None else None
    if value is None:  # built in the test: the axes are on the joint
        value = getattr(joint, "test_axes")[name]
    axis = np.asarray(value, dtype=float).reshape(3)
    return axis / np.linalg.norm(axis)


# ----------------------------------------------------------------------------- Pinocchio

def pinocchio_model(model: ElaboratedModel, order: tuple[str, ...], floating: bool):
    """Pinocchio's model of the elaborated model, joints in ``order`` (cyphy's joint names, a
    floating base first under its root link's name): each joint at its own frame (child link
    pose ∘ joint pose); a floating base as a translation along the world axes then ZYX Euler
    angles about world-parallel axes at the root link's origin (a massless body between)."""
    kinds = {"Revolute": "revolute", "Prismatic": "prismatic", "Universal": "universal",
             "Spherical": "spherical"}
    joint_of_child = {j.child.name: j for j in model.joints}
    fixed_parent = {f.child.name: f.parent.name for f in model.fixed}

    def owner(link: str) -> str:
        """The joint (or root link) that moves ``link``."""
        while link not in joint_of_child and link in fixed_parent:
            link = fixed_parent[link]
        return joint_of_child[link].name if link in joint_of_child else link

    links = {link.name: link for link in model.links}
    frames = {j.name: j.child.pose.compose(j.pose) for j in model.joints}
    by_name = {j.name: j for j in model.joints}
    robot = pin.Model()
    ids: dict[str, int] = {}
    for name in order:
        if name in links:  # a floating root: translation, then the Euler angles
            assert floating
            at = Pose.at(links[name].pose.position)
            frames[name] = at
            mid = robot.addJoint(0, pin.JointModelTranslation(), pin.SE3.Identity(),
                                 f"{name}_translation")
            ids[name] = robot.addJoint(mid, pin.JointModelSphericalZYX(), _se3(at), name)
            continue
        joint = by_name[name]
        parent = owner(joint.parent.name)
        parent_id = ids.get(parent, 0)
        parent_frame = frames[parent] if parent in ids else Pose.identity()
        placement = frames[name].relative_to(parent_frame)
        kind = kinds[joint.definition]
        if kind == "revolute":
            jm = pin.JointModelRevoluteUnaligned(_axis(joint, "AXIS"))
        elif kind == "prismatic":
            jm = pin.JointModelPrismaticUnaligned(_axis(joint, "AXIS"))
        elif kind == "universal":
            jm = pin.JointModelUniversal(_axis(joint, "AXIS1"), _axis(joint, "AXIS2"))
        else:
            jm = pin.JointModelSphericalZYX()
        ids[name] = robot.addJoint(parent_id, jm, _se3(placement), name)
    for link in model.links:
        moved_by = owner(link.name)
        if moved_by not in ids:
            continue  # fixed to the world
        inertial = link.inertial
        rotation = np.array(inertial.com.rotation)
        inertia = rotation @ _tensor(inertial.inertia) @ rotation.T
        com_in_link = Pose(inertial.com.position, ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
        in_joint = link.pose.relative_to(frames[moved_by])
        robot.appendBodyToJoint(ids[moved_by], pin.Inertia(inertial.mass, np.zeros(3), inertia),
                                _se3(in_joint.compose(com_in_link)))
    return robot


def pinocchio_joint_space(model: ElaboratedModel, tree: dynamics.KinematicTree, q, qd,
                          floating: bool = False):
    robot = pinocchio_model(model, tree.names, floating)
    data = robot.createData()
    q, qd = np.asarray(q, float), np.asarray(qd, float)
    assert robot.nq == robot.nv == tree.dof
    # What Pinocchio's v is for these joints: the time derivative of q (its integrate is a
    # plain sum for ZYX angles, translations, revolute and universal joints), as cyphy's.
    step = 1e-7 * qd
    assert np.allclose(pin.integrate(robot, q, step), q + step, rtol=0, atol=1e-15)
    m = pin.crba(robot, data, q)
    m = np.triu(m) + np.triu(m, 1).T
    h = pin.rnea(robot, data, q, qd, np.zeros(tree.dof))
    return m, h, robot


def _close(a, b, rel=1e-9):
    # a floor of 1e-3: bias forces that cancel to 0 come out as ±1e-15 (float noise of
    # terms of order 1)
    scale = max(np.abs(b).max(), 1e-3)
    assert np.abs(np.asarray(a, float) - b).max() <= rel * scale, (a, b)


def _random_state(tree: dynamics.KinematicTree, rng):
    """Coordinates and rates, pitches of ZYX angles kept 0.3 rad away from ±π/2."""
    q, qd = rng.uniform(-2.5, 2.5, tree.dof), rng.uniform(-3, 3, tree.dof)
    for joint, start in zip(tree.joints, tree.offsets):
        if joint.kind in dynamics.EULER:
            q[start + joint.dof - 2] = rng.uniform(-1.2, 1.2)
    return q, qd


def _check(model: ElaboratedModel, floating: bool, seed: int, samples: int = 3) -> None:
    tree = dynamics.kinematic_tree(model, floating_base=floating)
    rng = np.random.default_rng(seed)
    for _ in range(samples):
        q, qd = _random_state(tree, rng)
        m, h, _ = dynamics.joint_space(tree, q, qd)
        m_ref, h_ref, robot = pinocchio_joint_space(model, tree, q, qd, floating)
        _close(m, m_ref)
        _close(h, h_ref)
        tau = rng.uniform(-2, 2, tree.dof)
        qdd = dynamics.forward_dynamics(tree, q, qd, tau)
        _close(qdd, pin.aba(robot, robot.createData(), q, qd, tau), rel=1e-8)
        _close(dynamics.inverse_dynamics(tree, q, qd, qdd), tau, rel=1e-8)


# ----------------------------------------------------------------------------- models

MULTI = """
import physmod::math::*
import physmod::joints::*

pmodel Multi {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
        jref Shoulder = Spherical {
            pose { x = 0.1 y = 0 z = 0 roll = 0.2 pitch = 0.1 yaw = 0.3 }
            flexibly connected to Upper
        }
    }
    local link Upper {
        pose { x = 0 y = 0 z = -0.1 roll = 0.1 pitch = 0 yaw = 0 }
        def { inertial information { mass 0.5 inertia matrix { ixx 0.01 ixy 0.001 ixz 0 iyy 0.02 iyz 0 izz 0.015 } pose { x = 0 y = 0.02 z = -0.2 roll = 0 pitch = 0 yaw = 0 } } }
        jref Wrist = Universal {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0.3 yaw = 0 }
            instantiation AXIS1 = (|1, 0, 0|)
            instantiation AXIS2 = (|0, 1, 0|)
            flexibly connected to Hand
        }
    }
    local link Hand {
        pose { x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0.4 }
        def { inertial information { mass 0.2 inertia matrix { ixx 0.002 ixy 0 ixz 0 iyy 0.003 iyz 0 izz 0.001 } pose { x = 0.01 y = 0 z = -0.05 roll = 0 pitch = 0 yaw = 0 } } }
    }
}
"""

PENDULUM = """
import physmod::math::*
import physmod::joints::*

pmodel P {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Wrist = Universal {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS1 = (|1, 0, 0|)
            instantiation AXIS2 = (|0, 1, 0|)
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 2.0 inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.02 iyz 0 izz 0.03 } } }
    }
}
"""

FREE = """
pmodel Free {
    local link Body {
        pose { x = 0 y = 0 z = 1 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 2.0 inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.2 iyz 0 izz 0.3 } pose { x = 0.05 y = -0.02 z = 0.03 roll = 0.3 pitch = 0.2 yaw = 0.1 } } }
    }
}
"""


@pytest.fixture(scope="module")
def multi(tmp_path_factory) -> ElaboratedModel:
    folder = tmp_path_factory.mktemp("multi")
    (folder / "m.rsm").write_text(MULTI)
    return _elaborated(folder)


def _write(tmp_path: Path, text: str) -> Path:
    (tmp_path / "m.rsm").write_text(text)
    return tmp_path


# ----------------------------------------------------------------------------- Pinocchio checks

@pytest.mark.parametrize("floating", [False, True])
def test_ball_and_universal_joints_agree_with_pinocchio(multi, floating: bool) -> None:
    tree = dynamics.kinematic_tree(multi, floating_base=floating)
    kinds = [j.kind for j in tree.joints]
    assert kinds == (["floating"] if floating else []) + ["spherical", "universal"]
    assert tree.dof == (6 if floating else 0) + 5
    _check(multi, floating, 16, samples=5)


@pytest.mark.parametrize("folder", ["manipulator", "dcmotor", "marxbot"])
def test_examples_with_a_floating_base_agree_with_pinocchio(folder: str) -> None:
    model = _elaborated(EXAMPLES / folder)
    tree = dynamics.kinematic_tree(model, floating_base=True)
    assert tree.joints[0].kind == "floating"
    _check(model, True, 3)


def test_coordinates_are_named_as_solve_names_components(multi) -> None:
    tree = dynamics.kinematic_tree(multi, floating_base=True)
    assert tree.coordinates("theta") == (
        "Base_x", "Base_y", "Base_z", "Base_yaw", "Base_pitch", "Base_roll",
        "Shoulder_theta_1", "Shoulder_theta_2", "Shoulder_theta_3",
        "Wrist_theta_1", "Wrist_theta_2")
    assert tree.coordinates("v")[:6] == ("Base_vx", "Base_vy", "Base_vz", "Base_vyaw",
                                         "Base_vpitch", "Base_vroll")
    assert tree.coordinates("tau") == ("Shoulder_tau_1", "Shoulder_tau_2", "Shoulder_tau_3",
                                       "Wrist_tau_1", "Wrist_tau_2")


def _unit(draw) -> np.ndarray:
    axis = np.array([draw(st.floats(-1, 1)) for _ in range(3)])
    return axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 0.1 else np.array([0, 0, 1.0])


@st.composite
def mixed_trees(draw) -> ElaboratedModel:
    """A root and 1 to 7 more links, each joined to an earlier link by a revolute, prismatic,
    universal or ball joint with random axes and poses, or (sometimes) rigidly fixed to it."""
    n = draw(st.integers(1, 7))
    model = ElaboratedModel("R", None)  # type: ignore[arg-type]
    model.links.append(Link(("R", "L0"), _SPAN, pose=_pose(draw), inertial=_inertial(draw)))
    for k in range(1, n + 1):
        link = Link(("R", f"L{k}"), _SPAN, pose=_pose(draw), inertial=_inertial(draw))
        parent = model.links[draw(st.integers(0, k - 1))]
        model.links.append(link)
        if k > 1 and draw(st.integers(0, 5)) == 0:
            model.fixed.append(FixedJoint(("R", f"F{k}"), _SPAN, parent=parent, child=link))
            continue
        kind = draw(st.sampled_from(["Revolute", "Prismatic", "Universal", "Spherical"]))
        frame = _pose(draw)
        first, second = _unit(draw), _unit(draw)  # any two axes that are not parallel
        if np.linalg.norm(np.cross(first, second)) < 0.1:
            second = np.cross(first, [1.0, 0, 0] if abs(first[0]) < 0.9 else [0, 1.0, 0])
            second = second / np.linalg.norm(second)
        joint = Joint(("R", parent.qname[-1], f"J{k}"), _SPAN, parent=parent, child=link,
                      pose=frame.relative_to(link.pose), local_pose=frame.relative_to(
                          parent.pose), axis=first if kind in ("Revolute", "Prismatic")
                      else None, definition=kind)
        joint.test_axes = {"AXIS1": first, "AXIS2": second}  # type: ignore[attr-defined]
        model.joints.append(joint)
    return model


@pytest.fixture(autouse=True)
def _axes_from_the_test(monkeypatch) -> None:
    """Joints built in the test carry their universal axes beside the joint (they have no
    device): cyphy reads them as it reads an annotation's ``axis``/``axis2``."""
    original = tree_module._axis

    def axis(joint, constant, annotation):
        given = getattr(joint, "test_axes", None)
        if given is not None and constant in given:
            return np.asarray(given[constant], float) / np.linalg.norm(given[constant])
        return original(joint, constant, annotation)

    monkeypatch.setattr(tree_module, "_axis", axis)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(mixed_trees(), st.booleans(), st.integers(0, 2**32 - 1))
def test_random_mixed_trees_agree_with_pinocchio(model: ElaboratedModel, floating: bool,
                                                 seed: int) -> None:
    _check(model, floating, seed, samples=2)


# ----------------------------------------------------------------------------- model equations

BALL = """
import physmod::math::*
import physmod::joints::*

pmodel P {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Shoulder = Spherical {
            pose { x = 0.1 y = 0 z = 0 roll = 0.2 pitch = 0.1 yaw = 0.3 }
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0 y = 0 z = -0.5 roll = 0.1 pitch = 0 yaw = 0 }
        def { inertial information { mass 2.0 inertia matrix { ixx 0.01 ixy 0.001 ixz 0 iyy 0.02 iyz 0 izz 0.015 } pose { x = 0.01 y = 0.02 z = -0.1 roll = 0 pitch = 0 yaw = 0 } } }
    }
}
"""


@pytest.mark.parametrize("text, port", [(BALL, "Shoulder_tau"), (PENDULUM, "Wrist_tau")],
                         ids=["ball", "universal"])
def test_motion_equations_of_vector_ports_agree_with_pinocchio(tmp_path: Path, text: str,
                                                               port: str) -> None:
    """The equations written into the model (``Shoulder_tau[k] == …``), evaluated at random
    states, give Pinocchio's inverse dynamics."""
    from cyphy import expr as ex

    model = _elaborated(_write(tmp_path, text))
    equations = motion.motion_equations(model)
    tree = dynamics.kinematic_tree(model)
    left = [e.left for e, _ in equations]
    assert all(isinstance(item, ex.Index) for item in left)
    assert [(item.base.text, item.args[0].text) for item in left] == [
        (port, str(k)) for k in range(1, tree.dof + 1)]
    rng = np.random.default_rng(5)
    for _ in range(3):
        q, qd = _random_state(tree, rng)
        qdd = rng.uniform(-2, 2, tree.dof)
        _, _, robot = pinocchio_joint_space(model, tree, q, qd)
        expected = pin.rnea(robot, robot.createData(), q, qd, qdd)
        values = {}
        for variable, row in (("theta", q), ("v", qd), ("a", qdd)):
            values.update(zip(tree.coordinates(variable), row))
        _close([_evaluate(e.right, values) for e, _ in equations], expected)


def test_a_ball_joint_among_others_is_not_written_out(multi) -> None:
    with pytest.raises(dynamics.DynamicsError, match="Shoulder of 3 coordinates") as raised:
        motion.motion_equations(multi)
    assert "cyphy simulate" in raised.value.hint
    assert not motion.written_out(dynamics.kinematic_tree(multi))


def _evaluate(node, values: dict[str, float]) -> float:
    """An equation's right-hand side at a state (``x[k]`` is the component ``x_k``)."""
    import math

    from cyphy import expr as ex

    if isinstance(node, ex.Num):
        return float(node.text)
    if isinstance(node, ex.Name):
        return values[node.text]
    if isinstance(node, ex.Index):
        return values[f"{node.base.text}_{node.args[0].text}"]
    if isinstance(node, ex.UnaryOp) and node.op == "-":
        return -_evaluate(node.operand, values)
    if isinstance(node, ex.Call):
        return {"sin": math.sin, "cos": math.cos}[node.func.text](
            _evaluate(node.args[0], values))
    assert isinstance(node, ex.BinOp), node
    a, b = _evaluate(node.left, values), _evaluate(node.right, values)
    return {"+": a + b, "-": a - b, "*": a * b, "/": a / b if b else math.nan,
            "^": a ** b if node.op == "^" else 0.0}[node.op]


def test_solve_gives_a_universal_joint_explicit_odes(tmp_path: Path, capsys) -> None:
    folder = _write(tmp_path, PENDULUM)
    out = _solve_json(folder, capsys)
    assert {"Wrist_theta_1", "Wrist_theta_2", "Wrist_v_1", "Wrist_v_2"} == set(out["states"])
    # the efforts, and the parent twist that only the joint device's outputs read
    assert {"Wrist_tau_1", "Wrist_tau_2"} <= set(out["inputs"])
    assert all(n.startswith(("Wrist_pV_", "Wrist_pA_")) for n in out["inputs"]
               if not n.startswith("Wrist_tau_"))
    assert out["outputs"]["Wrist_a_2"] == "Wrist_qdd_2"
    _check_solve_against_aba(_elaborated(folder), out, False, 11)


# ----------------------------------------------------------------------------- free bodies

def test_free_fall_and_constant_twist(tmp_path: Path, capsys) -> None:
    from cyphy.cli import main

    folder = _write(tmp_path, FREE.replace("pose { x = 0.05 y = -0.02 z = 0.03 roll = 0.3 "
                                           "pitch = 0.2 yaw = 0.1 }", ""))
    start = ["--init", "Body_vx=0.4", "--init", "Body_vy=-0.3", "--init", "Body_vz=1.5",
             "--init", "Body_vyaw=0.7"]  # spinning about z, a principal axis at the origin
    for gravity, g in (("0,0,0", 0.0), ("0,0,-9.81", -9.81)):
        assert main(["simulate", str(folder), "--floating-base", "--gravity", gravity,
                     "--t-end", "2", "--samples", "21", "--method", "DOP853", "--rtol",
                     "1e-11", "--atol", "1e-12", "--format", "json", *start]) == 0
        out = json.loads(capsys.readouterr().out)
        t, c = np.array(out["t"]), {k: np.array(v) for k, v in out["columns"].items()}
        assert np.abs(c["Body_x"] - 0.4 * t).max() < 1e-9
        assert np.abs(c["Body_y"] + 0.3 * t).max() < 1e-9
        assert np.abs(c["Body_z"] - (1.5 * t + 0.5 * g * t**2)).max() < 1e-9
        assert np.abs(c["Body_vz"] - (1.5 + g * t)).max() < 1e-9
        assert np.abs(c["Body_yaw"] - 0.7 * t).max() < 1e-9  # the twist stays constant
        for name in ("Body_vx", "Body_vy", "Body_vyaw"):
            assert np.ptp(c[name]) < 1e-9
        for name in ("Body_pitch", "Body_roll", "Body_vpitch", "Body_vroll"):
            assert np.abs(c[name]).max() < 1e-9


def test_spinning_free_body_conserves_momentum_and_energy(tmp_path: Path, capsys) -> None:
    """A body spinning about no principal axis, its centre of mass off the link origin and
    its inertia turned: it tumbles, yet its momentum, angular momentum about the centre of
    mass and kinetic energy stay (computed here from the Euler angles with SciPy)."""
    from scipy.spatial.transform import Rotation

    from cyphy.cli import main

    folder = _write(tmp_path, FREE)
    assert main(["simulate", str(folder), "--floating-base", "--gravity", "0,0,0",
                 "--t-end", "2", "--samples", "41", "--method", "DOP853", "--rtol", "1e-11",
                 "--atol", "1e-12", "--format", "json", "--init", "Body_vyaw=0.8",
                 "--init", "Body_vpitch=-0.5", "--init", "Body_vroll=1.1",
                 "--init", "Body_vx=0.2"]) == 0
    out = json.loads(capsys.readouterr().out)
    c = {k: np.array(v) for k, v in out["columns"].items()}
    com_pose = Pose.from_xyz_rpy(0.05, -0.02, 0.03, 0.3, 0.2, 0.1)
    com, turn = np.array(com_pose.position), np.array(com_pose.rotation)
    inertia = turn @ np.diag([0.1, 0.2, 0.3]) @ turn.T  # about the centre, link axes
    mass = 2.0
    momenta, spins, energies = [], [], []
    for k in range(len(out["t"])):
        yaw, pitch, roll = (c[f"Body_{n}"][k] for n in ("yaw", "pitch", "roll"))
        rates = [c[f"Body_v{n}"][k] for n in ("yaw", "pitch", "roll")]
        rz = Rotation.from_euler("z", yaw).as_matrix()
        ry = Rotation.from_euler("y", pitch).as_matrix()
        r = Rotation.from_euler("ZYX", [yaw, pitch, roll]).as_matrix()
        omega = rates[0] * np.array([0, 0, 1.0]) + rates[1] * (rz @ [0, 1.0, 0]) + \
            rates[2] * (rz @ ry @ [1.0, 0, 0])  # world frame
        velocity = np.array([c[f"Body_v{n}"][k] for n in "xyz"]) + np.cross(omega, r @ com)
        world_inertia = r @ inertia @ r.T
        momenta.append(mass * velocity)
        spins.append(world_inertia @ omega)
        energies.append(0.5 * mass * velocity @ velocity + 0.5 * omega @ world_inertia @ omega)
    momenta, spins = np.array(momenta), np.array(spins)
    assert np.abs(momenta - momenta[0]).max() < 1e-7
    assert np.abs(spins - spins[0]).max() < 1e-7
    assert np.abs(np.array(energies) - energies[0]).max() < 1e-7
    assert np.ptp(c["Body_vroll"]) > 0.1  # it does tumble: the rates change


# ----------------------------------------------------------------------------- bad input

def test_ball_joint_at_a_singular_start_is_diagnosed(tmp_path: Path, capsys) -> None:
    from cyphy.cli import main

    folder = _write(tmp_path, MULTI)
    assert main(["simulate", str(folder), "--init", "Shoulder_theta_2=1.5707963267948966",
                 "--t-end", "0.1"]) == 1
    err = capsys.readouterr().err
    assert "E-DYNAMICS" in err and "ball joint Multi::Base::Shoulder" in err, err
    assert "m.rsm:8:9" in err and "hint:" in err and "Traceback" not in err
    tree = dynamics.kinematic_tree(_elaborated(folder))
    q = np.zeros(tree.dof)
    q[1] = -np.pi / 2
    with pytest.raises(dynamics.DynamicsError, match="pitch"):
        dynamics.forward_dynamics(tree, q, q, q)


def test_floating_base_at_a_singular_start_is_diagnosed(tmp_path: Path, capsys) -> None:
    from cyphy.cli import main

    folder = _write(tmp_path, FREE)
    assert main(["simulate", str(folder), "--floating-base", "--init",
                 "Body_pitch=-1.5707963267948966"]) == 1
    err = capsys.readouterr().err
    assert "E-DYNAMICS" in err and "floating base Free::Body" in err and "hint:" in err, err


def test_universal_joint_with_parallel_axes_is_diagnosed(tmp_path: Path, capsys) -> None:
    from cyphy.cli import main

    folder = _write(tmp_path, PENDULUM.replace("AXIS2 = (|0, 1, 0|)", "AXIS2 = (|2, 0, 0|)"))
    assert main(["solve", str(folder)]) == 1
    err = capsys.readouterr().err
    assert "E-DYNAMICS" in err and "parallel axes" in err and "hint:" in err, err


def test_solve_of_a_lone_floating_body(tmp_path: Path, capsys) -> None:
    """``solve --floating-base`` on a lone body: twelve states, no input, free fall along z,
    and the ODEs equal to Pinocchio's aba at random states."""
    folder = _write(tmp_path, FREE)
    out = _solve_json(folder, capsys, "--floating-base")
    model = _elaborated(folder)
    tree = dynamics.kinematic_tree(model, floating_base=True)
    assert set(out["states"]) == set(tree.coordinates("theta")) | set(tree.coordinates("v"))
    assert out["inputs"] == []
    _check_solve_against_aba(model, out, True, 2)


# ----------------------------------------------------------------------------- named definitions

CHAIN = """
import physmod::math::*
import physmod::joints::*

pmodel Chain {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } } }
        jref Hip = Revolute {
            pose { x = 0 y = 0.1 z = 0 roll = 0.1 pitch = 0 yaw = 0.2 }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Upper
        }
    }
    local link Upper {
        pose { x = 0 y = 0.1 z = -0.1 roll = 0.1 pitch = 0 yaw = 0 }
        def { inertial information { mass 0.5 inertia matrix { ixx 0.01 ixy 0.001 ixz 0 iyy 0.02 iyz 0 izz 0.015 } pose { x = 0 y = 0.02 z = -0.2 roll = 0 pitch = 0 yaw = 0 } } }
        jref Wrist = Universal {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0.3 yaw = 0 }
            instantiation AXIS1 = (|1, 0, 0|)
            instantiation AXIS2 = (|0, 1, 1|)
            flexibly connected to Mid
        }
    }
    local link Mid {
        pose { x = 0 y = 0.1 z = -0.5 roll = 0 pitch = 0 yaw = 0.4 }
        def { inertial information { mass 0.3 inertia matrix { ixx 0.004 ixy 0 ixz 0.0005 iyy 0.003 iyz 0 izz 0.002 } pose { x = 0.01 y = 0 z = -0.1 roll = 0 pitch = 0 yaw = 0 } } }
        jref Shoulder = Spherical {
            pose { x = 0.02 y = 0 z = 0.01 roll = 0.2 pitch = 0.1 yaw = 0.3 }
            flexibly connected to Hand
        }
    }
    local link Hand {
        pose { x = 0 y = 0.1 z = -0.8 roll = 0.3 pitch = 0 yaw = 0 }
        def { inertial information { mass 0.2 inertia matrix { ixx 0.002 ixy 0 ixz 0 iyy 0.003 iyz 0 izz 0.001 } pose { x = 0.01 y = 0.02 z = -0.05 roll = 0 pitch = 0 yaw = 0 } } }
    }
}
"""


def _solve_json(folder: Path, capsys, *options: str) -> dict:
    from cyphy.cli import main

    assert main(["solve", str(folder), "--format", "json", *options]) == 0
    return json.loads(capsys.readouterr().out)


def _definitions_at(out: dict, values: dict[str, float]) -> dict[str, float]:
    """Every definition of `solve`'s JSON in order, from ``values``: Python evaluates the
    printed text (not cyphy's code)."""
    scope = dict(values)
    for d in out["definitions"]:
        scope[d["name"]] = eval(d["value"], FUNCTIONS, scope)  # noqa: S307 - our own output
    return scope


def _piecewise(*pairs):
    """SymPy's ``Piecewise`` as `solve` prints it (a joint's limit stop): the first value
    whose condition holds."""
    return next(value for value, condition in pairs if condition)


FUNCTIONS = {"cos": math.cos, "sin": math.sin, "Piecewise": _piecewise, "True": True,
             "__builtins__": {}}


def _check_solve_against_aba(model: ElaboratedModel, out: dict, floating: bool, seed: int,
                             samples: int = 3, damping: dict[str, float] | None = None
                             ) -> None:
    """`solve`'s explicit ODEs (the joints' rates', evaluated from its JSON) at random states
    and inputs equal Pinocchio's aba (its own joints) at the joints' efforts these give (an
    input, or a motor's output definition) to 1e-8 relative; the positions' ODEs are the
    rates. ``damping`` (rate name → coefficient, as the model's annotations give it) and
    each bounded coordinate's limit stop (``<q>_stop``, which `solve` defines) add to the
    efforts Pinocchio is given."""
    tree = dynamics.kinematic_tree(model, floating_base=floating)
    theta, rates, efforts = (tree.coordinates(v) for v in ("theta", "v", "tau"))
    assert set(theta) | set(rates) <= set(out["states"])
    for position, rate in zip(theta, rates):
        assert out["odes"][position] == rate
    robot = pinocchio_model(model, tree.names, floating)
    rng = np.random.default_rng(seed)
    others = sorted(set(out["states"]) - set(theta) - set(rates)) + sorted(out["inputs"]) + \
        sorted(out["parameters"])  # constants without a value (a motor's), any value
    for _ in range(samples):
        q, qd = _random_state(tree, rng)
        values = dict(zip([*theta, *rates], [*q, *qd]))
        values.update(zip(others, rng.uniform(0.5, 2, len(others))))
        scope = _definitions_at(out, values)
        got = [eval(out["odes"][n], FUNCTIONS, scope) for n in rates]  # noqa: S307
        tau = np.zeros(tree.dof)
        tau[6 if floating else 0:] = [scope[n] for n in efforts]
        assert not efforts or np.abs(tau).max() > 0.1  # the efforts do act
        tau += [-(damping or {}).get(r, 0.0) * values[r] + scope.get(f"{q}_stop", 0.0)
                for q, r in zip(theta, rates)]
        _close(got, pin.aba(robot, robot.createData(), q, qd, tau), rel=1e-8)


def test_solve_of_a_revolute_universal_ball_chain_agrees_with_pinocchio(tmp_path: Path,
                                                                         capsys) -> None:
    folder = _write(tmp_path, CHAIN)
    model = _elaborated(folder)
    assert [j.kind for j in dynamics.kinematic_tree(model).joints] == [
        "revolute", "universal", "spherical"]
    out = _solve_json(folder, capsys)
    assert out["odes"]["Wrist_v_2"] == "Wrist_qdd_2"
    assert out["odes"]["Shoulder_v_3"] == "Shoulder_qdd_3"
    names = [d["name"] for d in out["definitions"]]
    assert len(names) == len(set(names)) and "Shoulder_Dinv_1_3" in names
    _check_solve_against_aba(model, out, False, 21)
    out = _solve_json(folder, capsys, "--floating-base")
    assert out["odes"]["Base_vz"] == "Base_qdd_3" and out["odes"]["Base_yaw"] == "Base_vyaw"
    _check_solve_against_aba(model, out, True, 22)


def test_solve_of_the_floating_manipulator_agrees_with_pinocchio(capsys) -> None:
    folder = EXAMPLES / "manipulator"
    out = _solve_json(folder, capsys, "--floating-base")
    # the joints' damping in Manipulator.rsm's annotations
    damping = {"Shoulder_v": 0.5, "Slide_v": 2.0, "Lift_v": 2.0}
    _check_solve_against_aba(_elaborated(folder), out, True, 23, damping=damping)


@settings(max_examples=10, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(mixed_trees(), st.booleans(), st.integers(0, 2**32 - 1))
def test_named_definitions_of_random_mixed_trees_agree_with_pinocchio(
        model: ElaboratedModel, floating: bool, seed: int) -> None:
    """The articulated-body definitions (the same code `solve` prints) of random trees of
    all joint kinds, with and without a floating base, against Pinocchio's aba."""
    import math

    from cyphy.semantics.dynamics.articulated import explicit_motion

    tree = dynamics.kinematic_tree(model, floating_base=floating)
    if not len(tree):
        return
    motion = explicit_motion(tree, lambda joint, port: dynamics.coordinate_names(joint, port))
    robot = pinocchio_model(model, tree.names, floating)
    rng = np.random.default_rng(seed)
    q, qd = _random_state(tree, rng)
    tau = rng.uniform(-2, 2, tree.dof)
    if floating:
        tau[:6] = 0.0
    scope = dict(zip([*tree.coordinates("theta"), *tree.coordinates("v"),
                      *tree.coordinates("tau")],
                     [*q, *qd, *tau[6 if floating else 0:]]))
    functions = {"cos": math.cos, "sin": math.sin, "__builtins__": {}}
    for d in motion.definitions:
        scope[d.name] = eval(d.value.text(), functions, scope)  # noqa: S307
    got = [scope[n] for _, names in motion.accelerations for n in names]
    _close(got, pin.aba(robot, robot.createData(), q, qd, tau), rel=1e-8)


MOTOR_CONSTANTS = ("J=0.01", "Kd=0", "Ke=0.05", "Ki=0.5", "Kp=2", "Kt=0.05", "L=0.01", "R=1",
                   "b=0.001")


def test_simulate_of_a_floating_manipulator_driven_by_motors_conserves_momentum(capsys) -> None:
    """The manipulator free in space (no gravity), its motors driving its joints: the whole
    model is simulated (motor states included), the joints move, the base reacts, and the
    total momentum and angular momentum about the centre of mass (Pinocchio's centroidal
    momentum of the simulated states) stay zero."""
    from cyphy.cli import main

    folder = EXAMPLES / "manipulator"
    constants = [x for c in MOTOR_CONSTANTS for x in ("--const", f"SpeedControlMotor::{c}")]
    assert main(["simulate", str(folder), "--floating-base", "--gravity", "0,0,0",
                 "--t-end", "1", "--samples", "11", "--method", "DOP853", "--rtol", "1e-10",
                 "--atol", "1e-12", "--input", "ShoulderMotor_das=2", "--input",
                 "SlideMotor_das=1", "--input", "LiftMotor_das=-1", "--format", "json",
                 *constants]) == 0
    out = json.loads(capsys.readouterr().out)
    c = {k: np.array(v) for k, v in out["columns"].items()}
    assert np.abs(c["ShoulderMotor_i"]).max() > 1.0  # the motors are simulated, and drive
    # (the shoulder's damping, 0.5 N·m·s/rad, and the limit stops slow the joints)
    assert np.abs(c["Shoulder_v"]).max() > 0.1 and np.abs(c["Stand_vyaw"]).max() > 0.1
    model = _elaborated(folder)
    tree = dynamics.kinematic_tree(model, floating_base=True)
    robot = pinocchio_model(model, tree.names, True)
    data = robot.createData()
    for k in range(len(out["t"])):
        q = np.array([c[n][k] for n in tree.coordinates("theta")])
        qd = np.array([c[n][k] for n in tree.coordinates("v")])
        momentum = pin.computeCentroidalMomentum(robot, data, q, qd)
        assert np.abs(momentum.vector).max() < 1e-7, (k, momentum.vector)
