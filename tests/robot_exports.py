"""Loading the URDF and MJCF exports in the real tools, and their mass matrices.

Every source of a mass matrix is a function ``(file, positions) → (joint names, M)`` over the
moving one-degree-of-freedom joints; :func:`compare` lines the matrices up by joint name,
so another source plugs in as one more entry of the dict. cyphy's own equations of motion
(:func:`cyphy_source`) are one: their qualified joint names become the exported names through
the export's name table (``<Model>.names.json``, exported name → qualified name), the table
the URDF and MJCF writers name joints by.

The bias forces ``h(q, q̇)`` (gravity, Coriolis, centrifugal) come the same way, as
``(joint names, h)``, with every tool's default gravity (−9.81 m/s² along z): the URDF's and the
MJCF's world is the model frame, as cyphy's.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

MassMatrix = tuple[list[str], np.ndarray]
Source = Callable[[Path, dict[str, float]], MassMatrix]
Bias = tuple[list[str], np.ndarray]
STANDARD_GRAVITY = np.array([0.0, 0.0, -9.81])


def check_urdf(path: Path) -> str:
    """``check_urdf``'s complaint about a file ('' when it accepts it)."""
    done = subprocess.run(["check_urdf", str(path)], capture_output=True, text=True)
    return "" if done.returncode == 0 else (done.stdout + done.stderr)[-500:]


def _pinocchio(urdf: Path, q: dict[str, float]) -> tuple[Any, list[str], np.ndarray]:
    """Pinocchio's model of the URDF, its one-degree-of-freedom joints' names and the
    configuration vector for the positions ``q`` (joint name → value)."""
    import pinocchio

    model = pinocchio.buildModelFromUrdf(str(urdf))
    names = [model.names[i] for i in range(1, model.njoints) if model.joints[i].nv == 1]
    config = pinocchio.neutral(model)
    for i in range(1, model.njoints):
        value, at = q.get(model.names[i], 0.0), model.joints[i].idx_q
        if model.joints[i].nq == 1:
            config[at] = value
        elif model.joints[i].nv == 1:  # unbounded (URDF continuous): (cos q, sin q)
            config[at:at + 2] = (np.cos(value), np.sin(value))
    return model, names, config


def pinocchio_mass(urdf: Path, q: dict[str, float]) -> MassMatrix:
    import pinocchio

    model, names, config = _pinocchio(urdf, q)
    data = model.createData()
    M = pinocchio.crba(model, data, config)
    M = np.triu(M) + np.triu(M, 1).T
    order = [model.joints[model.getJointId(n)].idx_v for n in names]
    return names, M[np.ix_(order, order)]


def pybullet_mass(urdf: Path, q: dict[str, float]) -> MassMatrix:
    import pybullet as p

    client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(urdf), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                          physicsClientId=client)
        names, positions = [], []
        for i in range(p.getNumJoints(body, physicsClientId=client)):
            info = p.getJointInfo(body, i, physicsClientId=client)
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                names.append(info[1].decode())
                positions.append(q.get(names[-1], 0.0))
        M = np.array(p.calculateMassMatrix(body, positions, physicsClientId=client))
        return names, M.reshape(len(names), len(names))
    finally:
        p.disconnect(client)


def mujoco_mass(mjcf: Path, q: dict[str, float]) -> MassMatrix:
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(mjcf))
    data = mujoco.MjData(model)
    names = []
    for j in range(model.njnt):
        if int(model.jnt_type[j]) in (int(mujoco.mjtJoint.mjJNT_HINGE),
                                      int(mujoco.mjtJoint.mjJNT_SLIDE)):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j)
            names.append(name)
            data.qpos[model.jnt_qposadr[j]] = q.get(name, 0.0)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    dofs = [model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n)]
            for n in names]
    return names, full[np.ix_(dofs, dofs)]


def pinocchio_bias(urdf: Path, q: dict[str, float], qd: dict[str, float],
                   gravity: Sequence[float] = STANDARD_GRAVITY) -> Bias:
    """``h(q, q̇)`` = Pinocchio's ``rnea(model, data, q, v, 0)``, ``gravity`` in the URDF's
    world frame (the root link's)."""
    import pinocchio

    model, names, config = _pinocchio(urdf, q)
    model.gravity.linear = np.asarray(gravity, dtype=float)
    velocity = np.zeros(model.nv)
    for n in names:
        velocity[model.joints[model.getJointId(n)].idx_v] = qd.get(n, 0.0)
    h = pinocchio.rnea(model, model.createData(), config, velocity, np.zeros(model.nv))
    return names, np.array([h[model.joints[model.getJointId(n)].idx_v] for n in names])


def pybullet_bias(urdf: Path, q: dict[str, float], qd: dict[str, float],
                  gravity: Sequence[float] = STANDARD_GRAVITY) -> Bias:
    """``h(q, q̇)`` = PyBullet's ``calculateInverseDynamics`` at zero acceleration (fixed
    base, the file's inertias), ``gravity`` in the URDF's world frame."""
    import pybullet as p

    client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(urdf), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                          physicsClientId=client)
        # PyBullet's inverse dynamics has the root link's inertial frame for world:
        # gravity is turned into it.
        turn = p.getDynamicsInfo(body, -1, physicsClientId=client)[4]
        rotation = np.array(p.getMatrixFromQuaternion(turn)).reshape(3, 3)
        p.setGravity(*(rotation.T @ np.asarray(gravity, dtype=float)).tolist(),
                     physicsClientId=client)
        names = []
        for i in range(p.getNumJoints(body, physicsClientId=client)):
            info = p.getJointInfo(body, i, physicsClientId=client)
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                names.append(info[1].decode())
        h = p.calculateInverseDynamics(body, [q.get(n, 0.0) for n in names],
                                       [qd.get(n, 0.0) for n in names], [0.0] * len(names),
                                       physicsClientId=client)
        return names, np.array(h)
    finally:
        p.disconnect(client)


def mujoco_bias(mjcf: Path, q: dict[str, float], qd: dict[str, float]) -> Bias:
    """``h(q, q̇)`` = MuJoCo's ``qfrc_bias`` (gravity, Coriolis and centrifugal forces; the
    model's own gravity, −9.81 m/s² along the model's z)."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(mjcf))
    data = mujoco.MjData(model)
    names, dofs = [], []
    for j in range(model.njnt):
        if int(model.jnt_type[j]) in (int(mujoco.mjtJoint.mjJNT_HINGE),
                                      int(mujoco.mjtJoint.mjJNT_SLIDE)):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j)
            names.append(name)
            dofs.append(int(model.jnt_dofadr[j]))
            data.qpos[model.jnt_qposadr[j]] = q.get(name, 0.0)
            data.qvel[model.jnt_dofadr[j]] = qd.get(name, 0.0)
    mujoco.mj_forward(model, data)
    return names, data.qfrc_bias[dofs].copy()


def random_states(rng: np.random.Generator, joints: int, count: int
                  ) -> list[tuple[list[float], list[float]]]:
    """``count`` states (positions in [-2, 2], velocities in [-3, 3]) of ``joints`` joints."""
    return [(rng.uniform(-2, 2, joints).tolist(), rng.uniform(-3, 3, joints).tolist())
            for _ in range(count)]


def random_trees() -> Any:
    """Hypothesis: ``(link specs, parents)`` of chains and trees of 2-8 links, for
    ``test_mjcf._tree_model`` (a root at a random pose, revolute and prismatic joints with
    random axes and poses, random masses, centres of mass and rotated inertias)."""
    from hypothesis import strategies as st

    from test_mjcf import links

    return st.lists(links, min_size=2, max_size=8).flatmap(
        lambda specs: st.tuples(st.just(specs), st.tuples(
            *[st.integers(0, i) for i in range(len(specs) - 1)])))


def names_table(path: Path) -> dict[str, str]:
    """The export's name table: exported (URDF, MJCF) name → qualified RoboSim name."""
    return json.loads(path.read_text())


def cyphy_joint_space(model: Any, table: dict[str, str], q: dict[str, float],
                      qd: dict[str, float]) -> tuple[list[str], np.ndarray, np.ndarray]:
    """cyphy's ``joint_space`` of the elaborated ``model`` in the exported joint names
    (through the export's name ``table``): ``(names, M(q), h(q, q̇))``, the positions and
    velocities keyed by exported name (0 when not given)."""
    from cyphy.semantics.dynamics import rigid_body as dynamics

    exported = {qualified: name for name, qualified in table.items()}
    tree = dynamics.kinematic_tree(model)
    names = [exported[n] for n in tree.names]
    M, h, _ = dynamics.joint_space(tree, [q.get(n, 0.0) for n in names],
                                   [qd.get(n, 0.0) for n in names])
    return names, np.asarray(M, dtype=float), np.asarray(h, dtype=float)


def cyphy_source(model: Any) -> Source:
    """cyphy's mass matrix of the elaborated ``model`` as a source: its file is the
    export's name table."""
    def source(table: Path, q: dict[str, float]) -> MassMatrix:
        names, M, _ = cyphy_joint_space(model, names_table(table), q, {})
        return names, M

    return source


def compare(values: dict[str, MassMatrix], floor: float = 0.0) -> float:
    """The largest relative difference between any source's matrix (or vector: bias forces)
    and the first's, in the first's joint order (every source must name the same joints),
    relative to the first's largest entry, or to ``floor`` when that is larger (bias forces
    that vanish, a wheel on a vertical axis, are measured against a force scale)."""
    (first, (names, reference)), *others = values.items()
    scale = max(float(np.abs(reference).max()), floor, 1e-300)
    worst = 0.0
    for source, (their_names, value) in others:
        assert sorted(their_names) == sorted(names), (first, names, source, their_names)
        order = [their_names.index(n) for n in names]
        lined_up = value[np.ix_(order, order)] if value.ndim == 2 else value[order]
        worst = max(worst, float(np.abs(lined_up - reference).max()) / scale)
    return worst


def _drake(path: Path, q: dict[str, float], qd: dict[str, float]
           ) -> tuple[Any, Any, list[str], list[int]]:
    """Drake's plant of an SDF or URDF file (its own parser: the file's inertias, joint poses
    and axes), the model frame welded to the world (cyphy's root is fixed in the model frame),
    at the positions ``q`` and velocities ``qd``: ``(plant, context, one-degree-of-freedom
    joint names, their velocity indices)``. Drake's default gravity is −9.81 m/s² along z."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)
    (instance,) = Parser(plant).AddModels(str(path))
    if plant.HasFrameNamed("__model__", instance):  # SDF: the links' poses are in it
        root = plant.GetFrameByName("__model__", instance)
    else:  # URDF: the root link's frame is the model frame
        children = {plant.get_joint(j).child_body().index()
                    for j in plant.GetJointIndices(instance)}
        (first,) = [b for b in plant.GetBodyIndices(instance) if b not in children]
        root = plant.get_body(first).body_frame()
    plant.WeldFrames(plant.world_frame(), root)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    names, dofs = [], []
    positions, velocities = plant.GetPositions(context), plant.GetVelocities(context)
    for index in plant.GetJointIndices(instance):
        joint = plant.get_joint(index)
        if joint.num_velocities() == 1:
            names.append(joint.name())
            dofs.append(joint.velocity_start())
            positions[joint.position_start()] = q.get(joint.name(), 0.0)
            velocities[joint.velocity_start()] = qd.get(joint.name(), 0.0)
    plant.SetPositions(context, positions)
    plant.SetVelocities(context, velocities)
    return plant, context, names, dofs


def drake_mass(path: Path, q: dict[str, float]) -> MassMatrix:
    """Drake's ``CalcMassMatrix`` of the SDF or URDF ``path``."""
    plant, context, names, dofs = _drake(path, q, {})
    return names, plant.CalcMassMatrix(context)[np.ix_(dofs, dofs)]


def drake_bias(path: Path, q: dict[str, float], qd: dict[str, float]) -> Bias:
    """``h(q, q̇)`` = Drake's ``CalcBiasTerm`` (Coriolis, centrifugal: ``C(q, v) v``) minus
    ``CalcGravityGeneralizedForces`` (Drake's inverse dynamics leaves gravity out)."""
    plant, context, names, dofs = _drake(path, q, qd)
    h = plant.CalcBiasTerm(context) - plant.CalcGravityGeneralizedForces(context)
    return names, np.asarray(h)[dofs]
