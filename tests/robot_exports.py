"""Loading the URDF and MJCF exports in the real tools, and their mass matrices.

Every source of a mass matrix is a function ``(file, positions) → (joint names, M)`` over the
moving one-degree-of-freedom joints; :func:`compare` lines the matrices up by joint name,
so another source (cyphy's own equations of motion) plugs in as one more entry of the dict.
"""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Callable

import numpy as np

MassMatrix = tuple[list[str], np.ndarray]
Source = Callable[[Path, dict[str, float]], MassMatrix]


def check_urdf(path: Path) -> str:
    """``check_urdf``'s complaint about a file ('' when it accepts it)."""
    done = subprocess.run(["check_urdf", str(path)], capture_output=True, text=True)
    return "" if done.returncode == 0 else (done.stdout + done.stderr)[-500:]


def pinocchio_mass(urdf: Path, q: dict[str, float]) -> MassMatrix:
    import pinocchio

    model = pinocchio.buildModelFromUrdf(str(urdf))
    data = model.createData()
    names = [model.names[i] for i in range(1, model.njoints) if model.joints[i].nv == 1]
    config = pinocchio.neutral(model)
    for i in range(1, model.njoints):
        value, at = q.get(model.names[i], 0.0), model.joints[i].idx_q
        if model.joints[i].nq == 1:
            config[at] = value
        elif model.joints[i].nv == 1:  # unbounded (URDF continuous): (cos q, sin q)
            config[at:at + 2] = (np.cos(value), np.sin(value))
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


def compare(matrices: dict[str, MassMatrix]) -> float:
    """The largest relative difference between any source's matrix and the first's, in the
    first's joint order (every source must name the same joints)."""
    (first, (names, reference)), *others = matrices.items()
    scale = max(float(np.abs(reference).max()), 1e-300)
    worst = 0.0
    for source, (their_names, M) in others:
        assert sorted(their_names) == sorted(names), (first, names, source, their_names)
        order = [their_names.index(n) for n in names]
        worst = max(worst, float(np.abs(M[np.ix_(order, order)] - reference).max()) / scale)
    return worst
