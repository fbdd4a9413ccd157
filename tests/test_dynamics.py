"""Equations of motion of the kinematic tree (cyphy.semantics.dynamics.rigid_body), checked against
independent derivations: Pinocchio, its model built here with its own API from the elaborated
model's links, inertials and joints (never from cyphy's tree), and SymPy's Lagrange method."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cyphy.semantics.dynamics.closed_form import inline_definitions
from cyphy.diagnostics import Span
from cyphy.model.elements import ElaboratedModel, FixedJoint, Joint, Link
from cyphy.model.inertia import Inertial
from cyphy.model.poses import Pose
from cyphy.semantics.dynamics import rigid_body as dynamics

pin = pytest.importorskip("pinocchio")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _elaborated(folder: str) -> ElaboratedModel:
    from cyphy.api import ElaborateOptions, elaborate

    result = elaborate([EXAMPLES / folder], ElaborateOptions())
    assert result.model is not None
    return result.model


# ----------------------------------------------------------------------------- Pinocchio

def _se3(pose: Pose) -> "pin.SE3":
    return pin.SE3(np.array(pose.rotation), np.array(pose.position))


def pinocchio_model(model: ElaboratedModel, order: tuple[str, ...]):
    """Pinocchio's model of the elaborated model: one Pinocchio joint per moving joint, its
    frame the joint's own frame (child link pose ∘ joint pose), each link's inertial appended
    to the joint that moves it (links joined by fixed connections follow their parent)."""
    owner: dict[str, str | None] = {link.name: None for link in model.links}
    joint_of_child = {j.child.name: j for j in model.joints}
    fixed_parent = {f.child.name: f.parent.name for f in model.fixed}

    def moving_joint(link: str) -> Joint | None:
        while link not in joint_of_child and link in fixed_parent:
            link = fixed_parent[link]
        return joint_of_child.get(link)

    for name in owner:
        j = moving_joint(name)
        owner[name] = j.name if j else None
    frames = {j.name: j.child.pose.compose(j.pose) for j in model.joints}
    by_name = {j.name: j for j in model.joints}
    robot = pin.Model()
    ids: dict[str, int] = {}
    for name in order:
        joint = by_name[name]
        parent = moving_joint(joint.parent.name)
        parent_id = ids[parent.name] if parent else 0
        parent_frame = frames[parent.name] if parent else Pose.identity()
        placement = frames[name].relative_to(parent_frame)
        axis = np.asarray(joint.axis, dtype=float)
        axis = axis / np.linalg.norm(axis)
        kind = dynamics.joint_kind(joint)
        jm = pin.JointModelRevoluteUnaligned(axis) if kind == "revolute" else \
            pin.JointModelPrismaticUnaligned(axis)
        ids[name] = robot.addJoint(parent_id, jm, _se3(placement), name)
    for link in model.links:
        if owner[link.name] is None:
            continue
        frame = frames[owner[link.name]]
        inertial = link.inertial
        rotation = np.array(inertial.com.rotation)
        inertia = rotation @ _tensor(inertial.inertia) @ rotation.T
        com_in_link = Pose(inertial.com.position, ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
        in_joint = link.pose.relative_to(frame)
        robot.appendBodyToJoint(ids[owner[link.name]],
                                pin.Inertia(inertial.mass, np.zeros(3), inertia),
                                _se3(in_joint.compose(com_in_link)))
    return robot


def _tensor(e):
    ixx, ixy, ixz, iyy, iyz, izz = e
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _pinocchio_joint_space(model: ElaboratedModel, names, q, qd):
    robot = pinocchio_model(model, names)
    data = robot.createData()
    m = pin.crba(robot, data, np.asarray(q, float))
    m = np.triu(m) + np.triu(m, 1).T
    h = pin.rnea(robot, data, np.asarray(q, float), np.asarray(qd, float), np.zeros(len(q)))
    assert tuple(robot.names[1:]) == tuple(names)
    return m, h


def _close(a, b, rel=1e-9):
    """Within ``rel`` of the largest reference entry; an all-zero reference (a wheel on a
    horizontal axis has no bias force) within rounding (1e-13 absolute: the terms that
    cancel are of the order of g, and Hypothesis found a sum of them rounding to 1.26e-15)."""
    scale = max(np.abs(b).max(), 1e-4)
    assert np.abs(np.asarray(a, float) - b).max() <= rel * scale, (a, b)


@pytest.mark.parametrize("folder", ["manipulator", "dcmotor", "marxbot"])
def test_examples_agree_with_pinocchio(folder: str) -> None:
    model = _elaborated(folder)
    tree = dynamics.kinematic_tree(model)
    assert set(tree.names) == {j.name for j in model.joints}
    rng = np.random.default_rng(16)
    for _ in range(5):
        q, qd = rng.uniform(-2, 2, len(tree)), rng.uniform(-3, 3, len(tree))
        m, h, names = dynamics.joint_space(model, q, qd)
        m_ref, h_ref = _pinocchio_joint_space(model, names, q, qd)
        _close(m, m_ref)
        _close(h, h_ref)
        tau = rng.uniform(-1, 1, len(tree))
        _close(dynamics.forward_dynamics(tree, q, qd, tau),
               pin.aba(pinocchio_model(model, names), pinocchio_model(model, names).createData(),
                       q, qd, tau), rel=1e-8)


def test_dcmotor_shaft_inertia_is_the_flywheel_about_its_axis() -> None:
    m, h, names = dynamics.joint_space(_elaborated("dcmotor"), [0.3], [2.0])
    assert names == ("DCMotorBase::Bench::Shaft",)
    assert m[0, 0] == pytest.approx(0.001, rel=1e-12)  # izz of the flywheel, on the axis
    assert h[0] == pytest.approx(0.0, abs=1e-15)  # vertical axis: gravity does no work


def test_joint_order_is_depth_first_in_model_order() -> None:
    tree = dynamics.kinematic_tree(_elaborated("manipulator"))
    assert tree.names == ("Manipulator::Stand::Shoulder", "Manipulator::Arm::Slide",
                          "Manipulator::Forearm::Lift")
    assert [j.parent for j in tree.joints] == [-1, 0, 1]


# ----------------------------------------------------------------------------- random trees

_SPAN = Span.unknown()


def _pose(draw) -> Pose:
    xyz = [draw(st.floats(-1, 1)) for _ in range(3)]
    rpy = [draw(st.floats(-np.pi, np.pi)) for _ in range(3)]
    return Pose.from_xyz_rpy(*xyz, *rpy)


def _inertial(draw) -> Inertial:
    a, b = draw(st.floats(0.01, 1.0)), draw(st.floats(0.01, 1.0))
    c = draw(st.floats(max(abs(a - b), 0.005), a + b))  # the triangle inequality
    return Inertial(draw(st.floats(0.1, 5.0)), _pose(draw), (a, 0.0, 0.0, b, 0.0, c))


@st.composite
def random_trees(draw) -> ElaboratedModel:
    """A fixed root and 1 to 8 moving links, each joined to an earlier link by a revolute or
    prismatic joint with a random axis and pose, or (sometimes) rigidly fixed to it."""
    n = draw(st.integers(1, 8))
    model = ElaboratedModel("R", None)  # type: ignore[arg-type]
    root = Link(("R", "L0"), _SPAN, pose=_pose(draw), inertial=_inertial(draw))
    model.links.append(root)
    for k in range(1, n + 1):
        link = Link(("R", f"L{k}"), _SPAN, pose=_pose(draw), inertial=_inertial(draw))
        parent = model.links[draw(st.integers(0, k - 1))]
        model.links.append(link)
        if k > 1 and draw(st.integers(0, 5)) == 0:
            model.fixed.append(FixedJoint(("R", f"F{k}"), _SPAN, parent=parent, child=link))
            continue
        axis = np.array([draw(st.floats(-1, 1)) for _ in range(3)])
        if np.linalg.norm(axis) < 0.1:
            axis = np.array([0.0, 0.0, 1.0])
        frame = _pose(draw)  # the joint frame in the model frame
        kind = draw(st.sampled_from(["Revolute", "Prismatic"]))
        model.joints.append(Joint(("R", parent.qname[-1], f"J{k}"), _SPAN, parent=parent,
                                  child=link, pose=frame.relative_to(link.pose),
                                  local_pose=frame.relative_to(parent.pose), axis=axis,
                                  definition=kind))
    return model


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_trees(), st.integers(0, 2**32 - 1))
def test_random_trees_agree_with_pinocchio(model: ElaboratedModel, seed: int) -> None:
    tree = dynamics.kinematic_tree(model)
    if not len(tree):
        return
    rng = np.random.default_rng(seed)
    q, qd = rng.uniform(-3, 3, len(tree)), rng.uniform(-3, 3, len(tree))
    m, h, names = dynamics.joint_space(tree, q, qd)
    m_ref, h_ref = _pinocchio_joint_space(model, names, q, qd)
    _close(m, m_ref)
    _close(h, h_ref)
    tau = rng.uniform(-5, 5, len(tree))
    qdd = dynamics.forward_dynamics(tree, q, qd, tau)
    _close(m @ qdd + h, tau, rel=1e-8)
    _close(dynamics.inverse_dynamics(tree, q, qd, qdd), tau, rel=1e-8)


# ----------------------------------------------------------------------------- Lagrange (SymPy)

def lagrange_joint_space(model: ElaboratedModel, names, q, qd):
    """``M`` and ``h`` from Lagrange's equations (``sympy.physics.mechanics``) of the model,
    each link a rigid body on the frame of the joint that moves it (no fixed connections)."""
    import sympy
    from sympy.physics import mechanics as me

    by_name = {j.name: j for j in model.joints}
    parent_joint = {j.child.name: j for j in model.joints}
    frames = {j.name: j.child.pose.compose(j.pose) for j in model.joints}
    coords = me.dynamicsymbols(f"q0:{len(names)}")
    world = me.ReferenceFrame("N")
    origin = me.Point("O")
    origin.set_vel(world, 0)
    frame_of, point_of, bodies = {}, {}, []
    for k, name in enumerate(names):
        joint = by_name[name]
        parent = parent_joint.get(joint.parent.name)
        parent_frame = frame_of[parent.name] if parent else world
        parent_point = point_of[parent.name] if parent else origin
        placement = frames[name].relative_to(frames[parent.name] if parent else Pose.identity())
        fixed = parent_frame.orientnew(f"P{k}", "DCM",
                                       sympy.Matrix(placement.rotation))
        axis = np.asarray(joint.axis, float) / np.linalg.norm(joint.axis)
        axis_vec = sum((sympy.nsimplify(0) + float(a)) * u for a, u in zip(axis, fixed))
        at = parent_point.locatenew(f"J{k}", sum(float(c) * u for c, u in zip(
            placement.position, parent_frame)))
        if dynamics.joint_kind(joint) == "revolute":
            frame = fixed.orientnew(f"B{k}", "Axis", (coords[k], axis_vec))
            point = at
        else:
            frame = fixed
            point = at.locatenew(f"S{k}", coords[k] * axis_vec)
        point.set_vel(frame, 0)
        frame.set_ang_vel(world, frame.ang_vel_in(world))
        frame_of[name], point_of[name] = frame, point
        link = joint.child
        com = link.pose.relative_to(frames[name]).compose(link.inertial.com)
        rotation = np.array(com.rotation)
        tensor = rotation @ _tensor(link.inertial.inertia) @ rotation.T
        centre = point.locatenew(f"C{k}", sum(float(c) * u for c, u in zip(com.position,
                                                                             frame)))
        centre.v2pt_theory(point, world, frame)
        dyadic = me.inertia(frame, *(float(tensor[i, j]) for i, j in
                                     [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)]))
        body = me.RigidBody(f"L{k}", centre, frame, float(link.inertial.mass),
                            (dyadic, centre))
        body.potential_energy = float(link.inertial.mass) * 9.81 * centre.pos_from(
            origin).dot(world.z)
        bodies.append(body)
    for k in range(len(names)):
        point_of[names[k]].vel(world)
    lagrangian = me.Lagrangian(world, *bodies)
    method = me.LagrangesMethod(lagrangian, coords)
    method.form_lagranges_equations()
    speeds = [sympy.diff(c, me.dynamicsymbols._t) for c in coords]
    values = {**dict(zip(speeds, qd)), **dict(zip(coords, q))}
    m = np.array(method.mass_matrix.xreplace(values).evalf(), dtype=float)
    h = -np.array(method.forcing.xreplace(values).evalf(), dtype=float).reshape(-1)
    return m, h


def test_manipulator_agrees_with_lagrange() -> None:
    model = _elaborated("manipulator")
    rng = np.random.default_rng(7)
    q, qd = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
    m, h, names = dynamics.joint_space(model, q, qd)
    m_ref, h_ref = lagrange_joint_space(model, names, q, qd)
    _close(m, m_ref)
    _close(h, h_ref)


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_trees(), st.integers(0, 2**32 - 1))
def test_small_random_trees_agree_with_lagrange(model: ElaboratedModel, seed: int) -> None:
    # One joint: SymPy's Lagrange method on two random frames takes minutes (measured); the
    # manipulator's three-joint chain is checked above.
    model.joints[:], model.fixed[:] = model.joints[:1], []
    kept = {model.links[0].name} | {j.child.name for j in model.joints}
    model.links[:] = [link for link in model.links if link.name in kept]
    for joint in model.joints:
        if joint.parent.name not in kept:
            joint.parent = model.links[0]
            joint.local_pose = joint.child.pose.compose(joint.pose).relative_to(
                model.links[0].pose)
    rng = np.random.default_rng(seed)
    tree = dynamics.kinematic_tree(model)
    q, qd = rng.uniform(-3, 3, len(tree)), rng.uniform(-3, 3, len(tree))
    m, h, names = dynamics.joint_space(tree, q, qd)
    m_ref, h_ref = lagrange_joint_space(model, names, q, qd)
    _close(m, m_ref)
    _close(h, h_ref)


# ----------------------------------------------------------------------------- double pendulum

def double_pendulum(m1=1.0, m2=0.5, l1=1.0, l2=0.7) -> ElaboratedModel:
    """Two point masses on massless rods hanging from hinges about −y (the angle grows
    towards +x), the textbook double pendulum."""
    model = ElaboratedModel("P", None)  # type: ignore[arg-type]
    zero = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    base = Link(("P", "Base"), _SPAN, pose=Pose.identity(),
                inertial=Inertial(1.0, Pose.identity(), (1, 0, 0, 1, 0, 1)))
    upper = Link(("P", "Upper"), _SPAN, pose=Pose.identity(),
                 inertial=Inertial(m1, Pose.at((0, 0, -l1)), zero))
    lower = Link(("P", "Lower"), _SPAN, pose=Pose.at((0, 0, -l1)),
                 inertial=Inertial(m2, Pose.at((0, 0, -l2)), zero))
    model.links += [base, upper, lower]
    for name, parent, child in [("Hip", base, upper), ("Knee", upper, lower)]:
        model.joints.append(Joint(("P", parent.qname[-1], name), _SPAN, parent=parent,
                                  child=child, pose=Pose.identity(),
                                  local_pose=child.pose.relative_to(parent.pose),
                                  axis=np.array([0.0, -1.0, 0.0]), definition="Revolute"))
    return model


def test_double_pendulum_matches_the_textbook_equations() -> None:
    from scipy.integrate import solve_ivp

    m1, m2, l1, l2, g = 1.0, 0.5, 1.0, 0.7, 9.81
    tree = dynamics.kinematic_tree(double_pendulum(m1, m2, l1, l2))

    def ours(_t, x):
        return np.concatenate([x[2:], dynamics.forward_dynamics(tree, x[:2], x[2:],
                                                                np.zeros(2))])

    def textbook(_t, x):  # absolute angles from the downward vertical
        a, b, wa, wb = x
        d = a - b
        den = 2 * m1 + m2 - m2 * np.cos(2 * d)
        aa = (-g * (2 * m1 + m2) * np.sin(a) - m2 * g * np.sin(a - 2 * b)
              - 2 * np.sin(d) * m2 * (wb**2 * l2 + wa**2 * l1 * np.cos(d))) / (l1 * den)
        bb = (2 * np.sin(d) * (wa**2 * l1 * (m1 + m2) + g * (m1 + m2) * np.cos(a)
                               + wb**2 * l2 * m2 * np.cos(d))) / (l2 * den)
        return [wa, wb, aa, bb]

    start = np.array([1.2, -0.4, 0.0, 0.5])  # relative angles: hip, knee
    times = np.linspace(0, 2, 41)
    mine = solve_ivp(ours, (0, 2), start, t_eval=times, method="DOP853", rtol=1e-12,
                     atol=1e-12)
    absolute = [start[0], start[0] + start[1], start[2], start[2] + start[3]]
    ref = solve_ivp(textbook, (0, 2), absolute, t_eval=times, method="DOP853", rtol=1e-12,
                    atol=1e-12)
    assert np.abs(mine.y[0] - ref.y[0]).max() < 1e-6
    assert np.abs(mine.y[0] + mine.y[1] - ref.y[1]).max() < 1e-6
    assert np.abs(ref.y[0]).max() > 0.5  # it really swings


# ----------------------------------------------------------------------------- cyphy solve

def test_solve_dcmotor_shaft_follows_the_motor_torque(capsys) -> None:
    import json

    import sympy

    from cyphy import api
    from cyphy.cli import main

    assert main(["solve", str(EXAMPLES / "dcmotor"), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"Shaft_theta", "Shaft_v"} <= set(out["states"])
    result = api.solve([EXAMPLES / "dcmotor"], api.SolveOptions(closed_form=False))
    reduced = result.reduced
    inline_definitions(reduced, result.system)
    # Shaft_v' = Motor_T / J with J the flywheel's izz (0.001 kg m², on the axis)
    difference = reduced.rhs["Shaft_v"] - reduced.outputs["Motor_T"] / sympy.Float(0.001)
    assert sympy.expand(difference).xreplace(
        {f: 0 for f in sympy.expand(difference).atoms(sympy.Float) if abs(f) < 1e-9}) == 0
    assert reduced.rhs["Shaft_v"].has(sympy.Symbol("Motor_i", real=True))


def test_solve_marxbot_exits_0() -> None:
    from cyphy.cli import main

    assert main(["solve", str(EXAMPLES / "marxbot"), "--model", "marXbotBase"]) == 0


def test_undriven_joint_effort_is_an_input(tmp_path: Path) -> None:
    from cyphy import api

    (tmp_path / "p.rsm").write_text(PENDULUM)
    result = api.solve([tmp_path], api.SolveOptions(closed_form=False))
    reduced = result.reduced
    # the effort, and the parent twist the joint device's outputs (fV, fA) read: every name
    # solve prints is defined; the ODEs read the effort only
    assert "Hinge_tau" in reduced.inputs and not reduced.obstacles
    assert all(n.startswith(("Hinge_pV_", "Hinge_pA_")) for n in reduced.inputs
               if n != "Hinge_tau")
    assert {str(s) for e in reduced.rhs.values() for s in e.free_symbols} & \
        set(reduced.inputs) <= {"Hinge_tau"}
    inline_definitions(reduced, result.system)
    import sympy

    theta, tau = sympy.Symbol("Hinge_theta", real=True), sympy.Symbol("Hinge_tau", real=True)
    # a point-like bob of 2 kg at 0.5 m below a hinge about y (izz-type moment 0.01):
    # J = 0.01 + 2 * 0.25 = 0.51, gravity torque -2 * 9.81 * 0.5 * sin(theta)
    expected = (tau - 2 * 9.81 * 0.5 * sympy.sin(theta)) / 0.51
    values = {theta: 0.7, tau: 0.3, sympy.Symbol("Hinge_v", real=True): 1.1}
    assert float(reduced.rhs["Hinge_v"].subs(values)) == pytest.approx(
        float(expected.subs(values)), rel=1e-12)


PENDULUM = """
import physmod::math::*
import physmod::joints::Revolute

pmodel P {
    local link Base {
        def { inertial information { mass 1.0 inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 } } }
        jref Hinge = Revolute {
            pose { x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
            instantiation AXIS = (|0, 1, 0|)
            flexibly connected to Bob
        }
    }
    local link Bob {
        pose { x = 0 y = 0 z = -0.5 roll = 0 pitch = 0 yaw = 0 }
        def { inertial information { mass 2.0 inertia matrix { ixx 0.01 ixy 0 ixz 0 iyy 0.01 iyz 0 izz 0.01 } } }
    }
}
"""


def test_show_lists_the_motion_per_body(capsys) -> None:
    import json

    from cyphy.cli import main

    assert main(["show", str(EXAMPLES / "manipulator"), "--format", "json"]) == 0
    motion = json.loads(capsys.readouterr().out)["motion"]
    assert [b["joint"].split("::")[-1] for b in motion] == ["Shoulder", "Slide", "Lift"]
    assert [b["mass"] for b in motion] == [0.8, 0.4, pytest.approx(0.21)]
    assert motion[2]["links"] == ["Manipulator::Gripper"] and motion[2]["parent"].endswith(
        "Slide")
    assert motion[2]["screw"] == [0, 0, 0, 0, 0, -1]
    # the gripper: a 0.15 kg palm at 0 and two 0.03 kg fingers 0.04 m below
    assert motion[2]["com"][2] == pytest.approx(-2 * 0.03 * 0.04 / 0.21)
    assert "Lift_tau == transpose(Lift_A) * Lift_F" in motion[2]["equations"]


# ----------------------------------------------------------------------------- bad trees

_LINK = """
    local link {name} {{
        pose {{ x = 0 y = 0 z = {z} roll = 0 pitch = 0 yaw = 0 }}
        def {{ {inertial} }}
        {inside}
    }}"""
_INERTIAL = ("inertial information { mass 1.0 inertia matrix "
             "{ ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 } }")
_JOINT = """
        jref {name} = Revolute {{
            pose {{ x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
            instantiation AXIS = {axis}
            flexibly connected to {child}
        }}"""


def _bad_model(tmp_path: Path, links: str) -> Path:
    (tmp_path / "m.rsm").write_text("import physmod::math::*\nimport physmod::joints::Revolute"
                                    "\npmodel M {" + links + "\n}\n")
    return tmp_path


@pytest.mark.parametrize("case, code, message", [
    # A zero axis is refused by the value checks (V6) before the dynamics see it.
    ("zero-axis", "V6", "zero"),
    ("no-inertia", "E-DYNAMICS", "has no mass properties"),
    ("loop", "E-DYNAMICS", "closes a kinematic loop"),
])
def test_bad_trees_are_diagnosed(tmp_path: Path, capsys, case: str, code: str,
                                 message: str) -> None:
    from cyphy.cli import main

    axis = "(|0, 0, 0|)" if case == "zero-axis" else "(|0, 0, 1|)"
    child = "" if case == "no-inertia" else _INERTIAL
    joints = _JOINT.format(name="J", axis=axis, child="B")
    if case == "loop":
        joints += _JOINT.format(name="K", axis=axis, child="B")
    links = _LINK.format(name="A", z=0, inertial=_INERTIAL, inside=joints) + \
        _LINK.format(name="B", z=0.5, inertial=child, inside="")
    folder = _bad_model(tmp_path, links)
    assert main(["solve", str(folder)]) == 1
    err = capsys.readouterr().err
    assert code in err and message in err, err
    assert "m.rsm:" in err and "hint:" in err and "Traceback" not in err


def test_a_singular_mass_matrix_is_diagnosed_at_its_joint() -> None:
    # Point masses on both hinges' axis: nothing resists turning the hip. The value checks (V1)
    # refuse such an inertia in a model file; the dynamics still guard models built otherwise.
    model = double_pendulum()
    model.links[1].inertial = Inertial(1.0, Pose.identity(), (0, 0, 0, 0, 0, 0))
    model.links[2].inertial = Inertial(1.0, Pose.at((0, 0, 1.0)), (0, 0, 0, 0, 0, 0))
    model.links[2].pose = Pose.identity()
    model.joints[1].local_pose = Pose.identity()
    tree = dynamics.kinematic_tree(model)
    with pytest.raises(dynamics.DynamicsError, match="mass matrix is singular at joint P::Base::Hip"):
        dynamics.forward_dynamics(tree, [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])


def test_gravity_option(tmp_path: Path, capsys) -> None:
    import json

    from cyphy.cli import main

    (tmp_path / "p.rsm").write_text(PENDULUM)
    assert main(["solve", str(tmp_path), "--gravity", "0,0,0", "--format", "json"]) == 0
    odes = json.dumps(json.loads(capsys.readouterr().out))
    assert "sin" not in odes  # no gravity: nothing depends on the angle
    with pytest.raises(SystemExit) as usage:
        main(["solve", str(tmp_path), "--gravity", "0,0"])
    assert usage.value.code == 2 and "three numbers" in capsys.readouterr().err
    m, h, _ = dynamics.joint_space(double_pendulum(), [0.3, 0.2], [0.0, 0.0],
                                   gravity=(0.0, 0.0, -1.62))
    m2, h2, _ = dynamics.joint_space(double_pendulum(), [0.3, 0.2], [0.0, 0.0])
    _close(h * 9.81 / 1.62, h2)
