"""A fixed connection turned round so that a hand of fingers is one tree in URDF and MJCF.

The notation guide's ``Hand`` and the held-out pincer instantiate an indexed part of fingers
whose ``link Root fixed to Palm`` makes each finger's root the palm's parent (Rule 1): the
palm had one parent per finger, so ``--urdf`` wrote one file per finger (``W-SDF-CUT``) and
``--mjcf`` welded the second finger by an equality constraint. A fixed connection carries no
motion, so the tree targets now write it from the palm (``cyphy/semantics/sdf/orientation.py``).

Oracles: ``check_urdf`` reads one tree rooted at the palm; Pinocchio places every visual of
the URDF, and MuJoCo every geom and centre of mass of the MJCF, where cyphy's elaboration
puts the RoboSim bodies (to 1e-9: the fingers are turned and tilted, the palm too, so a joint
origin not inverted correctly shows); MuJoCo (RK4, 0.1 ms) swings the fingers under gravity
as ``cyphy simulate --numeric`` does (1e-5 rad after 1 s, as test_simulate_compiled, with
simulate's tolerances tightened: the guide's short bones swing fast); a loop
closed through two moved links is still cut.
"""

from __future__ import annotations

import csv
import io
import json
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from cyphy import api
from cyphy.cli import main
from cyphy.model.poses import Pose

HERE = Path(__file__).resolve().parent
PINCER = HERE / "data" / "heldout" / "pincer"

#: The guide's Hand (docs/guide/index.md) with two fingers, each part copy turned and
#: tilted and the palm itself turned, so that the turned connections' poses are not
#: translations alone.
HAND = """\
package hand

import physmod::math::*
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor

pmodel Finger {
	local link Root {
		def {}
		local body Pad {
			def {
				box(length = 0.01m, width = 0.015m, height = 0.01m)
				inertial information { mass 0.01kg }
			}
		}
		jref Knuckle = Revolute {
			pose { x = 0 y = 0 z = 0.01m roll = 0 pitch = 0 yaw = 0 }
			instantiation AXIS = (|0, 1, 0|)
			flexibly connected to Bone
			aref Motor = SpeedControlMotor {
				relation Motor.T == Knuckle.tau
			}
		}
	}
	local link Bone {
		pose { x = 0 y = 0 z = 0.01m roll = 0 pitch = 0 yaw = 0 }
		def {}
		local body Shaft {
			pose { x = 0.03m y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
			def {
				box(length = 0.06m, width = 0.015m, height = 0.015m)
				inertial information { mass 0.05kg }
			}
		}
	}
}

pmodel Hand {
	local link Palm {
		pose { x = 0.01m y = -0.02m z = 0.1m roll = 0.2 pitch = -0.1 yaw = 0.5 }
		def {}
		local body Plate {
			def {
				box(length = 0.1m, width = 0.1m, height = 0.02m)
				inertial information { mass 0.5kg }
			}
		}
	}
	part Fingers = Finger {
		index i : [0,2)
		pose { x = 0.05m y = (0.04*(i - 1))m z = 0.01m roll = (0.3*i - 0.1) pitch = 0.2 yaw = (0.6*i - 0.3) }
		link Root fixed to Palm
	}
}
"""

#: The same hand with a bar that both bones are fixed to: the bar rides on two hinges, a
#: loop closed by moving joints that no turning makes a tree.
BAR = HAND.replace("""	part Fingers = Finger {""", """	local link Bar {
		pose { x = 0.1m y = 0 z = 0.05m roll = 0 pitch = 0 yaw = 0 }
		def {}
		local body Rod {
			def {
				box(length = 0.01m, width = 0.1m, height = 0.01m)
				inertial information { mass 0.02kg }
			}
		}
	}
	part Fingers = Finger {""").replace("""		link Root fixed to Palm
""", """		link Root fixed to Palm
		link Bone fixed to Bar
""")


def _hand(tmp_path: Path, text: str = HAND) -> Path:
    folder = tmp_path / "hand"
    folder.mkdir(exist_ok=True)
    (folder / "Hand.rsm").write_text(text)
    return folder


def _gen(folder: Path, target: str, out: Path, model: str,
         capsys: pytest.CaptureFixture[str]) -> str:
    """``cyphy gen`` (exit 0), the names of what it wrote and its standard error."""
    capsys.readouterr()
    assert main(["gen", str(folder), target, "--model", model, "-o", str(out)]) == 0
    return capsys.readouterr().err


def _body_poses(folder: Path, model: str) -> dict[str, Pose]:
    """cyphy's elaborated pose of every RoboSim body in the model frame, by the link's
    qualified name and the body's own name."""
    elaborated = api.elaborate([folder], api.ElaborateOptions(model)).model
    assert elaborated is not None
    return {f"{link.name}::{body.qname[-1]}": (link.pose or Pose.identity())
            .compose(body.pose or Pose.identity())
            for link in elaborated.links for body in link.bodies}


def _by_shape(poses: dict[str, Pose], names: dict[str, str]) -> dict[str, Pose]:
    """The qualified body poses keyed by the exported shape name: the exported link name
    (from ``<Model>.names.json``) and the body's own name."""
    link_of = {qualified: exported for exported, qualified in names.items()}
    out = {}
    for qualified, pose in poses.items():
        link, body = qualified.rsplit("::", 1)
        out[f"{link_of[link]}__{body}"] = pose
    return out


def _close(a: Pose, position: np.ndarray, rotation: np.ndarray) -> bool:
    return bool(np.abs(np.asarray(a.position) - position).max() < 1e-9
                and np.abs(np.asarray(a.rotation) - rotation).max() < 1e-9)


CASES = [(PINCER, "PincerBase"), (None, "Hand")]


@pytest.mark.parametrize("folder, model", CASES, ids=["pincer", "hand"])
def test_one_urdf_tree_rooted_at_the_palm_with_the_model_s_poses(
        folder: Path | None, model: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    pin = pytest.importorskip("pinocchio")
    folder = folder or _hand(tmp_path)
    out = tmp_path / "urdf"
    err = _gen(folder, "--urdf", out, model, capsys)
    assert "W-SDF-CUT" not in err and "W-SDF-TREE" not in err
    assert sorted(p.name for p in out.iterdir()) == [f"{model}.names.json", f"{model}.urdf"]
    urdf = out / f"{model}.urdf"
    names = json.loads((out / f"{model}.names.json").read_text())
    if shutil.which("check_urdf"):
        said = subprocess.run(["check_urdf", str(urdf)], capture_output=True, text=True)
        assert said.returncode == 0, said.stderr
        assert said.stdout.split("---------------\n")[-1] == (  # one tree, from the palm
            "root Link: Palm has 2 child(ren)\n"
            "    child(1):  Fingers_0__Root\n        child(1):  Fingers_0__Bone\n"
            "    child(2):  Fingers_1__Root\n        child(1):  Fingers_1__Bone\n")
    robot = ET.parse(urdf).getroot()
    fixed = {j.get("name"): (j.find("parent").get("link"), j.find("child").get("link"))
             for j in robot.iter("joint") if j.get("type") == "fixed"}
    assert fixed == {f"Fingers_{i}__Root__fixed__Palm": ("Palm", f"Fingers_{i}__Root")
                     for i in range(2)}
    assert all(j.find("axis") is None for j in robot.iter("joint") if j.get("type") == "fixed")
    assert urdf.read_text().count(", turned round: the parent is its target") == 2
    # Pinocchio places every visual of the URDF; cyphy's elaboration every body.
    pmodel = pin.buildModelFromUrdf(str(urdf))
    geometry = pin.buildGeomFromUrdf(pmodel, str(urdf), pin.GeometryType.VISUAL)
    data, gdata = pmodel.createData(), geometry.createData()
    pin.updateGeometryPlacements(pmodel, data, geometry, gdata, pin.neutral(pmodel))
    visuals = {link.get("name"): [v.get("name").removesuffix("_visual")
                                  for v in link.findall("visual")]
               for link in robot.iter("link")}
    want = _by_shape(_body_poses(folder, model), names)
    placed = {}
    for k, obj in enumerate(geometry.geometryObjects):
        link, _, n = obj.name.rpartition("_")
        placed[visuals[link][int(n)]] = gdata.oMg[k]
    assert sorted(placed) == sorted(want) and len(want) == 5
    for shape, pose in want.items():
        assert _close(pose, placed[shape].translation, placed[shape].rotation), shape


@pytest.mark.parametrize("folder, model", CASES, ids=["pincer", "hand"])
def test_one_mjcf_body_tree_without_equality_and_mujoco_s_poses(
        folder: Path | None, model: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    mujoco = pytest.importorskip("mujoco")
    folder = folder or _hand(tmp_path)
    out = tmp_path / "mjcf"
    err = _gen(folder, "--mjcf", out, model, capsys)
    assert "W-SDF-CUT" not in err
    xml = ET.parse(out / f"{model}.xml").getroot()
    assert xml.find("equality") is None
    (palm,) = xml.find("worldbody").findall("body")  # one tree, the palm at its root
    assert palm.get("name") == "Palm"
    assert sorted(b.get("name") for b in palm.findall("body")) == \
        ["Fingers_0__Root", "Fingers_1__Root"]
    m = mujoco.MjModel.from_xml_path(str(out / f"{model}.xml"))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    assert m.neq == 0 and m.nq == 2
    names = json.loads((out / f"{model}.names.json").read_text())
    want = _by_shape(_body_poses(folder, model), names)
    for shape, pose in want.items():
        k = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, shape)
        assert k >= 0, shape
        assert _close(pose, d.geom_xpos[k], d.geom_xmat[k].reshape(3, 3)), shape
    # each link's centre of mass where cyphy's elaboration has it
    elaborated = api.elaborate([folder], api.ElaborateOptions(model)).model
    exported = {q: e for e, q in names.items()}
    for link in elaborated.links:
        k = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, exported[link.name])
        com = link.pose.compose(link.inertial.com).position
        assert np.abs(d.xipos[k] - np.asarray(com)).max() < 1e-9, link.name


def _csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    data = np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def _run_mujoco(m, seconds: float, controls: dict[str, float] | None = None):  # type: ignore[no-untyped-def]
    """MuJoCo's data after ``seconds`` from rest: RK4 at 0.1 ms, contacts off, the motors
    held at ``controls`` (actuator name → value, default 0)."""
    import mujoco  # the callers skip without it

    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    m.opt.timestep = 1e-4
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    d = mujoco.MjData(m)
    for name, value in (controls or {}).items():
        d.ctrl[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, name)] = value
    for _ in range(round(seconds / m.opt.timestep)):
        mujoco.mj_step(m, d)
    return d


@pytest.mark.parametrize("folder, model", CASES, ids=["pincer", "hand"])
def test_the_fingers_swing_in_mujoco_as_simulate_numeric(
        folder: Path | None, model: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    """1 s from rest under gravity, the motors unpowered: each knuckle's angle in MuJoCo
    (RK4 at 0.1 ms, contacts off) on the one-tree MJCF agrees with ``simulate --numeric``
    to 1e-5 rad."""
    mujoco = pytest.importorskip("mujoco")
    folder = folder or _hand(tmp_path)
    capsys.readouterr()
    assert main(["simulate", str(folder), "--model", model, "--numeric", "--samples", "11",
                 "--rtol", "1e-10", "--atol", "1e-12"]) == 0
    ours = _csv(capsys.readouterr().out)
    _gen(folder, "--mjcf", tmp_path / "mjcf", model, capsys)
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "mjcf" / f"{model}.xml"))
    assert m.neq == 0
    d = _run_mujoco(m, 1.0)
    for i in range(2):
        joint = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"Fingers_{i}__Root__Knuckle")
        theirs = d.qpos[m.jnt_qposadr[joint]]
        assert abs(ours[f"Fingers{i}_Root_Knuckle_theta"][-1] - theirs) < 1e-5
        assert np.abs(ours[f"Fingers{i}_Root_Knuckle_theta"]).max() > 0.1  # it swung


def test_a_loop_through_two_hinges_is_still_cut(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    """The bar fixed to both bones: the roots are turned to hang off the palm (one tree),
    the second bone's fixed connection to the bar closes a loop of moving joints, cut with
    W-SDF-CUT for URDF and welded for MuJoCo."""
    folder = _hand(tmp_path, BAR)
    err = _gen(folder, "--urdf", tmp_path / "urdf", "Hand", capsys)
    assert err.count("W-SDF-CUT") == 1
    assert "fixed connection from Hand::Fingers::1::Bone to Hand::Bar closes a kinematic " \
           "loop: it is left out for URDF" in err
    assert sorted(p.name for p in (tmp_path / "urdf").iterdir()) == \
        ["Hand.names.json", "Hand.urdf"]
    robot = ET.parse(tmp_path / "urdf" / "Hand.urdf").getroot()
    assert {(j.find("parent").get("link"), j.find("child").get("link"))
            for j in robot.iter("joint") if j.get("type") == "fixed"} == \
        {("Palm", "Fingers_0__Root"), ("Palm", "Fingers_1__Root"), ("Fingers_0__Bone", "Bar")}
    err = _gen(folder, "--mjcf", tmp_path / "mjcf", "Hand", capsys)
    assert err.count("W-SDF-CUT") == 1
    weld = ET.parse(tmp_path / "mjcf" / "Hand.xml").getroot().find("equality/weld")
    assert (weld.get("body1"), weld.get("body2")) == ("Fingers_1__Bone", "Bar")


def _zyx(rotation: np.ndarray) -> np.ndarray:
    """ZYX Euler angles (yaw, pitch, roll) of a rotation, away from pitch ±π/2."""
    return np.array([np.arctan2(rotation[1, 0], rotation[0, 0]), -np.arcsin(rotation[2, 0]),
                     np.arctan2(rotation[2, 1], rotation[2, 2])])


@pytest.mark.parametrize("folder, model", CASES, ids=["pincer", "hand"])
def test_the_free_hand_s_base_is_the_palm_in_simulate_and_in_mujoco(
        folder: Path | None, model: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    """``simulate --floating-base`` names and places the base at the palm, as ``--mjcf
    --mjcf-free-base`` gives the palm the free joint (the base used to be the last finger's
    root, ``Root_x``): 0.5 s of free fall from rest, constant torques on the knuckles
    swinging the fingers and turning the palm in reaction, the palm's displacement and ZYX
    angles and the knuckles agree with MuJoCo (RK4 at 0.1 ms, contacts off) to 1e-5."""
    mujoco = pytest.importorskip("mujoco")
    folder = folder or _hand(tmp_path)
    capsys.readouterr()
    torques = (0.002, -0.001)
    assert main(["simulate", str(folder), "--model", model, "--numeric", "--floating-base",
                 "--t-end", "0.5", "--samples", "6", "--rtol", "1e-10", "--atol", "1e-12",
                 *(f"--input=Fingers{i}_Root_Knuckle_tau={t}" for i, t in enumerate(torques))
                 ]) == 0
    ours = _csv(capsys.readouterr().out)
    capsys.readouterr()
    assert main(["gen", str(folder), "--mjcf", "--mjcf-free-base", "--model", model,
                 "-o", str(tmp_path / "free")]) == 0
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "free" / f"{model}.xml"))
    assert m.njnt == 3 and mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, 0) == "Palm__free"
    d = _run_mujoco(m, 0.5, {f"Fingers_{i}__Root__Knuckle__motor": torque
                             for i, torque in enumerate(torques)})
    rest = np.empty(9)
    mujoco.mju_quat2Mat(rest, m.qpos0[3:7])
    turned = np.empty(9)
    mujoco.mju_quat2Mat(turned, d.qpos[3:7])
    angles = _zyx(turned.reshape(3, 3) @ rest.reshape(3, 3).T)
    want = {"Palm_x": d.qpos[0] - m.qpos0[0], "Palm_y": d.qpos[1] - m.qpos0[1],
            "Palm_z": d.qpos[2] - m.qpos0[2], "Palm_yaw": angles[0], "Palm_pitch": angles[1],
            "Palm_roll": angles[2]}
    for i in range(2):
        joint = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"Fingers_{i}__Root__Knuckle")
        want[f"Fingers{i}_Root_Knuckle_theta"] = d.qpos[m.jnt_qposadr[joint]]
    for name, value in want.items():
        assert abs(ours[name][-1] - value) < 1e-5, (name, ours[name][-1], value)
    assert ours["Palm_z"][-1] < -1.0  # it fell
    assert abs(ours["Palm_pitch"][-1]) > 1e-3  # the palm turned in reaction
    assert abs(ours["Fingers0_Root_Knuckle_theta"][-1]) > 0.1  # and the fingers swung


@st.composite
def _graphs(draw: st.DrawFn) -> tuple[int, list[tuple[str, int, int]]]:
    """A number of links and connections between them: ``("joint" | "fixed", parent,
    child)``, any graph (second parents, cycles, loops through the world)."""
    n = draw(st.integers(2, 6))
    pairs = st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)).filter(lambda p: p[0] != p[1])
    edges = draw(st.lists(st.tuples(st.sampled_from(("joint", "fixed")), pairs), max_size=8))
    return n, [(kind, a, b) for kind, (a, b) in edges]


def _text(n: int, edges: list[tuple[str, int, int]]) -> str:
    links = []
    for i in range(n):
        inside = []
        for k, (kind, a, b) in enumerate(edges):
            if a != i:
                continue
            inside.append(f"local joint J{k} {{ def {{ annotation Revolute {{ axis = Axis {{ "
                          f"xyz = (|0,0,1|) }} }} }} flexibly connected to L{b} }}"
                          if kind == "joint" else f"fixed to L{b}")
        links.append(f"local link L{i} {{ def {{ inertial information {{ mass 1 }} }} "
                     + " ".join(inside) + " }")
    return ("package g\nimport physmod::sdf::annotations::*\nimport physmod::math::*\n"
            "pmodel G {\n" + "\n".join(links) + "\n}\n")


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(_graphs())
def test_the_tree_shape_of_any_graph(tmp_path: Path, graph) -> None:  # type: ignore[no-untyped-def]
    """On any graph of joints and fixed connections, checked with NetworkX: what is kept,
    fixed connections turned, is a forest (one parent at most, no cycle); no joint is turned;
    every tree's root is in a body no joint moves; and every connection cut is one a tree
    cannot hold (a joint into a link or rigid body that already has a parent, or that closes
    a cycle; a fixed connection whose ends are already joined or whose two rigid bodies are
    both moved by joints), so nothing is cut that turning could have kept."""
    import networkx as nx

    from cyphy.model.elements import FixedJoint
    from cyphy.semantics.sdf.orientation import tree_shape

    n, edges = graph
    folder = Path(tempfile.mkdtemp(dir=tmp_path))  # one per example
    (folder / "G.rsm").write_text(_text(n, edges))
    model = api.elaborate([folder], api.ElaborateOptions("G")).model
    assume(model is not None)  # a model with errors (the same fixed connection twice)
    shape = tree_shape(model)
    cut = {id(c) for c in shape.cuts}
    connections = [c for c in [*model.joints, *model.fixed]]
    assert len(connections) == len(edges)
    kept = nx.MultiDiGraph()
    kept.add_nodes_from(link.name for link in model.links)
    for c in connections:
        if id(c) not in cut:
            parent, child = shape.ends(c)
            kept.add_edge(parent.name, child.name, moving=not isinstance(c, FixedJoint))
    assert nx.is_forest(nx.Graph(kept)) and kept.number_of_edges() == nx.Graph(kept).number_of_edges()
    assert all(kept.in_degree(node) <= 1 for node in kept.nodes)
    assert not {id(c) for c in model.joints} & shape.turned
    rigid = nx.Graph()
    rigid.add_nodes_from(kept.nodes)
    rigid.add_edges_from((a, b) for a, b, moving in kept.edges(data="moving") if not moving)
    body = {name: k for k, names in enumerate(nx.connected_components(rigid)) for name in names}
    moved = {body[b] for _, b, moving in kept.edges(data="moving") if moving}
    for node in kept.nodes:
        if kept.in_degree(node) == 0:
            assert body[node] not in moved, node  # a root stands on the world
    joined = nx.Graph(kept)
    for c in shape.cuts:
        a, b = c.parent.name, c.child.name
        if isinstance(c, FixedJoint):
            assert nx.has_path(joined, a, b) or (body[a] in moved and body[b] in moved), c.name
        else:
            assert nx.has_path(joined, a, b) or body[b] in moved, c.name
