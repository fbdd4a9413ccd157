"""Pose arithmetic: hand-computed transforms, the RPY convention, gimbal lock, the group laws."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy.model.poses import Pose, clean

PI = math.pi
HALF_PI = math.pi / 2

coordinates = st.floats(-10.0, 10.0)
angles = st.floats(-PI, PI)
any_angles = st.floats(-20.0, 20.0)
# Pitch kept 0.01 rad clear of ±π/2, where roll and yaw are not separately determined.
regular_pitches = st.floats(-HALF_PI + 0.01, HALF_PI - 0.01)
poses = st.builds(Pose.from_xyz_rpy, coordinates, coordinates, coordinates, angles, angles, angles)


def rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def cleaned(values: tuple[float, ...]) -> tuple[float, ...]:
    return tuple(clean(v) for v in values)


def pose(x=0.0, y=0.0, z=0.0, roll=0.0, pitch=0.0, yaw=0.0) -> Pose:
    return Pose.from_xyz_rpy(x, y, z, roll, pitch, yaw)


# --- clean ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (-0.0, 0.0),
        (1.2e-16, 0.0),
        (-1e-13, 0.0),
        (2.9999999999999996, 3.0),
        (-4.000000000000001, -4.0),
        (0.5, 0.5),
        (1.0 + 1e-9, 1.0 + 1e-9),
        (0.30000000000000004, 0.30000000000000004),
        (math.inf, math.inf),
    ],
)
def test_clean_snaps_only_noise_around_integers(value: float, expected: float) -> None:
    assert clean(value) == expected
    assert math.copysign(1.0, clean(value)) == math.copysign(1.0, expected)


def test_clean_returns_floats() -> None:
    assert type(clean(7)) is float


# --- construction and the RPY convention ---------------------------------------------------


def test_identity_leaves_points_alone() -> None:
    assert Pose.identity().apply((1.5, -2.0, 3.0)) == (1.5, -2.0, 3.0)
    assert np.array_equal(Pose.identity().matrix(), np.eye(4))


def test_yaw_quarter_turn_takes_x_to_y() -> None:
    assert cleaned(pose(yaw=HALF_PI).apply((1.0, 0.0, 0.0))) == (0.0, 1.0, 0.0)


def test_single_axis_quarter_turns() -> None:
    # Rx(π/2): y → z; Ry(π/2): z → x; Rz(π/2): x → y (right-handed, counter-clockwise).
    assert cleaned(pose(roll=HALF_PI).apply((0.0, 1.0, 0.0))) == (0.0, 0.0, 1.0)
    assert cleaned(pose(pitch=HALF_PI).apply((0.0, 0.0, 1.0))) == (1.0, 0.0, 0.0)
    assert cleaned(pose(yaw=HALF_PI).apply((0.0, 0.0, 5.0))) == (0.0, 0.0, 5.0)


def test_translation_is_applied_after_rotation() -> None:
    assert cleaned(pose(1.0, 2.0, 3.0, yaw=HALF_PI).apply((1.0, 0.0, 0.0))) == (1.0, 3.0, 3.0)


def test_rotation_is_rz_ry_rx_for_a_fixed_example() -> None:
    roll, pitch, yaw = 0.3, -0.7, 2.1
    expected = rz(yaw) @ ry(pitch) @ rx(roll)
    assert np.allclose(pose(roll=roll, pitch=pitch, yaw=yaw).rotation, expected, atol=1e-15)


@given(angles, angles, angles)
def test_rotation_is_rz_ry_rx(roll: float, pitch: float, yaw: float) -> None:
    expected = rz(yaw) @ ry(pitch) @ rx(roll)
    assert np.allclose(pose(roll=roll, pitch=pitch, yaw=yaw).rotation, expected, atol=1e-14)


def test_roll_then_pitch_then_yaw_by_hand() -> None:
    # Roll is applied first, so it is the innermost pose: T = T_yaw · T_pitch · T_roll.
    # T_pitch · T_roll: p = Ry(π/2)·(0,2,0) + (0,0,1) = (0,2,1)
    # T_yaw · (...):    p = Rz(π/2)·(0,2,1) + (1,0,0) = (-2,0,1) + (1,0,0) = (-1,0,1)
    # R = Rz(π/2)·Ry(π/2)·Rx(π/2); images of the axes: x → x → -z → -z, y → z → x → y,
    # z → -y → -y → x, so R = [[0,0,1],[0,1,0],[-1,0,0]] = Ry(π/2).
    # (1,2,3) ↦ R·(1,2,3) + p = (3,2,-1) + (-1,0,1) = (2,2,0).
    roll = pose(0.0, 2.0, 0.0, roll=HALF_PI)
    pitch = pose(0.0, 0.0, 1.0, pitch=HALF_PI)
    yaw = pose(1.0, 0.0, 0.0, yaw=HALF_PI)
    composed = yaw.compose(pitch).compose(roll)
    assert cleaned(composed.position) == (-1.0, 0.0, 1.0)
    assert tuple(cleaned(row) for row in composed.rotation) == (
        (0.0, 0.0, 1.0),
        (0.0, 1.0, 0.0),
        (-1.0, 0.0, 0.0),
    )
    assert cleaned(composed.apply((1.0, 2.0, 3.0))) == (2.0, 2.0, 0.0)
    assert composed.isclose(pose(-1.0, 0.0, 1.0, HALF_PI, HALF_PI, HALF_PI))
    # Gimbal lock: only roll - yaw = 0 is determined; yaw is reported as 0.
    assert cleaned(composed.to_xyz_rpy()) == (-1.0, 0.0, 1.0, 0.0, HALF_PI, 0.0)


def test_matmul_is_compose() -> None:
    outer, inner = pose(1.0, 2.0, 3.0, 0.1, 0.2, 0.3), pose(-1.0, 0.5, 2.0, 0.4, -0.5, 0.6)
    assert outer @ inner == outer.compose(inner)


def test_matrix_is_homogeneous() -> None:
    p = pose(1.0, 2.0, 3.0, 0.1, 0.2, 0.3)
    m = p.matrix()
    assert np.array_equal(m[:3, :3], np.array(p.rotation))
    assert np.array_equal(m[:3, 3], np.array(p.position))
    assert np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0])


def test_pose_is_immutable_and_normalised_to_float_tuples() -> None:
    p = Pose(np.array([1, 2, 3]), np.eye(3))
    assert p.position == (1.0, 2.0, 3.0) and type(p.position[0]) is float
    assert p.rotation == Pose.identity().rotation
    with pytest.raises(AttributeError):
        p.position = (0.0, 0.0, 0.0)  # type: ignore[misc]


@pytest.mark.parametrize(
    "rotation",
    [np.diag([1.0, 1.0, -1.0]), 2.0 * np.eye(3), np.ones((3, 3)), np.eye(2)],
    ids=["reflection", "scaled", "singular", "wrong-shape"],
)
def test_pose_rejects_matrices_that_are_not_rotations(rotation: np.ndarray) -> None:
    with pytest.raises(ValueError):
        Pose((0.0, 0.0, 0.0), rotation)


# --- back to xyz-rpy -------------------------------------------------------------------------


@given(coordinates, coordinates, coordinates, angles, regular_pitches, angles)
def test_to_xyz_rpy_round_trips(x, y, z, roll, pitch, yaw) -> None:
    got = pose(x, y, z, roll, pitch, yaw).to_xyz_rpy()
    assert got[:3] == (x, y, z)
    # Roll and yaw of ±π are the same rotation; compare angles on the circle.
    for want, have in zip((roll, pitch, yaw), got[3:]):
        assert abs(math.remainder(have - want, 2 * PI)) <= 1e-9


@given(coordinates, coordinates, coordinates, any_angles, any_angles, any_angles)
def test_to_xyz_rpy_ranges_and_same_rotation(x, y, z, roll, pitch, yaw) -> None:
    p = pose(x, y, z, roll, pitch, yaw)
    r, q, w = p.to_xyz_rpy()[3:]
    assert -PI < r <= PI and -PI < w <= PI and -HALF_PI <= q <= HALF_PI
    assert pose(x, y, z, r, q, w).isclose(p, tol=1e-6)  # 1e-6: the gimbal band, see below


@pytest.mark.parametrize(
    ("given_rpy", "expected_rpy"),
    [
        ((3 * HALF_PI, 0.0, 0.0), (-HALF_PI, 0.0, 0.0)),
        ((0.0, 0.0, -PI), (0.0, 0.0, PI)),
        ((0.0, 0.0, PI), (0.0, 0.0, PI)),
        ((-PI, 0.0, 0.0), (PI, 0.0, 0.0)),
        ((7.0, 0.0, 0.0), (7.0 - 2 * PI, 0.0, 0.0)),
        ((0.0, 0.0, 4.0), (0.0, 0.0, 4.0 - 2 * PI)),
        # Pitch past π/2 is the same rotation as pitch π - 2.0 with roll and yaw half a turn on.
        ((0.0, 2.0, 0.0), (PI, PI - 2.0, PI)),
        # Rz(π/2)·Rx(π) maps (x,y,z) to (y,x,-z): roll a half turn, reported as +π.
        ((PI, 0.0, HALF_PI), (PI, 0.0, HALF_PI)),
    ],
)
def test_angles_are_normalised(given_rpy, expected_rpy) -> None:
    got = pose(1.0, 2.0, 3.0, *given_rpy).to_xyz_rpy()
    assert got[:3] == (1.0, 2.0, 3.0)
    assert got[3:] == pytest.approx(expected_rpy, abs=1e-12)


@given(angles, angles)
def test_gimbal_lock_reports_yaw_zero(roll: float, yaw: float) -> None:
    # Pitch +π/2: R depends on roll - yaw only; pitch -π/2: on roll + yaw only.
    for sign, combined in ((1.0, roll - yaw), (-1.0, roll + yaw)):
        p = pose(roll=roll, pitch=sign * HALF_PI, yaw=yaw)
        r, q, w = p.to_xyz_rpy()[3:]
        assert w == 0.0
        assert q == pytest.approx(sign * HALF_PI, abs=1e-12)
        assert abs(math.remainder(r - combined, 2 * PI)) <= 1e-9
        assert pose(roll=r, pitch=q, yaw=w).isclose(p)


def test_gimbal_lock_of_a_yawed_sensor_matches_robotool() -> None:
    # sdf-robotool.md §3: yaw ψ at pitch π/2 prints as roll -ψ, pitch π/2, yaw 0.
    r, q, w = pose(pitch=HALF_PI, yaw=5 * PI / 4).to_xyz_rpy()[3:]
    assert (r, q, w) == pytest.approx((3 * PI / 4, HALF_PI, 0.0), abs=1e-12)


@given(angles, angles, st.floats(0.0, 1e-7), st.sampled_from([1.0, -1.0]))
def test_near_gimbal_lock_error_is_bounded(roll, yaw, distance, sign) -> None:
    # SciPy treats pitch within 1e-7 rad of ±π/2 as locked; the error is at most 2·distance.
    p = pose(roll=roll, pitch=sign * (HALF_PI - distance), yaw=yaw)
    assert pose(*p.to_xyz_rpy()).isclose(p, tol=2.5e-7)


# --- group laws ----------------------------------------------------------------------------


@given(poses)
def test_compose_with_inverse_is_identity(p: Pose) -> None:
    assert p.compose(p.inverse()).isclose(Pose.identity())
    assert p.inverse().compose(p).isclose(Pose.identity())


@given(poses, poses, poses)
def test_compose_is_associative(a: Pose, b: Pose, c: Pose) -> None:
    assert a.compose(b).compose(c).isclose(a.compose(b.compose(c)))


@given(poses, poses)
def test_relative_to_undoes_compose(parent: Pose, child: Pose) -> None:
    assert parent.compose(child).relative_to(parent).isclose(child)


@given(poses, poses)
def test_compose_is_the_matrix_product(a: Pose, b: Pose) -> None:
    assert np.allclose(a.compose(b).matrix(), a.matrix() @ b.matrix(), rtol=0.0, atol=1e-12)


@given(poses, st.tuples(coordinates, coordinates, coordinates))
def test_apply_agrees_with_matrix_and_inverse(p: Pose, point) -> None:
    moved = p.apply(point)
    assert np.allclose(moved, (p.matrix() @ [*point, 1.0])[:3], rtol=0.0, atol=1e-12)
    assert np.allclose(p.inverse().apply(moved), point, rtol=0.0, atol=1e-12)


def test_isclose_uses_the_tolerance() -> None:
    p = pose(1.0, 2.0, 3.0, 0.1, 0.2, 0.3)
    assert p.isclose(pose(1.0 + 1e-10, 2.0, 3.0, 0.1, 0.2, 0.3))
    assert not p.isclose(pose(1.0 + 1e-8, 2.0, 3.0, 0.1, 0.2, 0.3))
    assert not p.isclose(pose(1.0, 2.0, 3.0, 0.1, 0.2, 0.3 + 1e-8))
    assert p.isclose(pose(1.0, 2.0, 3.0, 0.1, 0.2, 0.3 + 1e-8), tol=1e-7)


@settings(max_examples=200, deadline=None)
@given(st.floats(-7, 7), st.floats(-7, 7), st.floats(-7, 7))
def test_from_xyz_rpy_equals_scipy_from_euler(roll: float, pitch: float, yaw: float) -> None:
    from scipy.spatial.transform import Rotation

    expected = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix()
    assert np.allclose(Pose.from_xyz_rpy(0, 0, 0, roll, pitch, yaw).rotation, expected,
                       atol=1e-12)
