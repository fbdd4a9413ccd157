"""Mass properties: solid formulas, combining bodies into a link, and the physical-tensor check."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cyphy.model.inertia import (
    Inertial,
    combine,
    entries,
    is_physical,
    solid_box,
    solid_cylinder,
    solid_sphere,
    tensor,
)
from cyphy.model.poses import Pose

UNIT_CUBE = solid_box(1.0, 1.0, 1.0, 1.0)  # 1/6 on the diagonal


def at(x: float, y: float, z: float, roll=0.0, pitch=0.0, yaw=0.0) -> Pose:
    return Pose.from_xyz_rpy(x, y, z, roll, pitch, yaw)


def assert_inertial_close(got: Inertial, want: Inertial, tol: float = 1e-9) -> None:
    assert got.mass == pytest.approx(want.mass, rel=tol)
    assert got.com.isclose(want.com, tol=tol)
    assert got.inertia == pytest.approx(want.inertia, abs=tol)


# --- solid formulas ------------------------------------------------------------------------


def test_solid_box() -> None:
    # m(w²+h²)/12, m(l²+h²)/12, m(l²+w²)/12 with m = 12, l,w,h = 1,2,3.
    assert solid_box(12.0, 1.0, 2.0, 3.0) == (13.0, 0.0, 0.0, 10.0, 0.0, 5.0)


def test_solid_cylinder_has_its_axis_along_z() -> None:
    # m(3r²+L²)/12 across, mr²/2 about the axis, with m = 12, r = 1, L = 2.
    assert solid_cylinder(12.0, 1.0, 2.0) == (7.0, 0.0, 0.0, 7.0, 0.0, 6.0)


def test_solid_sphere() -> None:
    # 2mr²/5 with m = 5, r = 2.
    assert solid_sphere(5.0, 2.0) == (8.0, 0.0, 0.0, 8.0, 0.0, 8.0)


def test_solid_formulas_are_physical() -> None:
    assert is_physical(solid_box(2.0, 0.1, 0.2, 0.3))
    assert is_physical(solid_cylinder(2.0, 0.05, 1.0))
    assert is_physical(solid_sphere(2.0, 0.05))


# --- tensor and entries --------------------------------------------------------------------


def test_tensor_and_entries_convert_both_ways() -> None:
    six = (1.0, 0.1, 0.2, 2.0, 0.3, 3.0)
    assert np.array_equal(tensor(six), [[1.0, 0.1, 0.2], [0.1, 2.0, 0.3], [0.2, 0.3, 3.0]])
    assert entries(tensor(six)) == six


# --- combine -------------------------------------------------------------------------------


def test_two_cubes_side_by_side() -> None:
    # Unit cubes of 1 kg centred at (±0.5, 0, 0): combined centre 0, offsets d = (±0.5, 0, 0).
    # Own tensors: 1/6 on each diagonal. Parallel axis m(|d|²E − d dᵀ) = diag(0, 0.25, 0.25).
    # ixx = 2·(1/6) = 1/3; iyy = izz = 2·(1/6 + 1/4) = 5/6; no products of inertia.
    # That is also the solid 2 × 1 × 1 box of 2 kg: 2(1+1)/12 = 1/3, 2(4+1)/12 = 5/6.
    combined = combine(
        [Inertial(1.0, at(-0.5, 0.0, 0.0), UNIT_CUBE), Inertial(1.0, at(0.5, 0.0, 0.0), UNIT_CUBE)]
    )
    assert combined.mass == 2.0
    assert combined.com == Pose.identity()
    assert combined.inertia == pytest.approx((1 / 3, 0.0, 0.0, 5 / 6, 0.0, 5 / 6), abs=1e-15)
    assert combined.inertia == pytest.approx(solid_box(2.0, 2.0, 1.0, 1.0), abs=1e-15)


def test_two_cubes_on_a_diagonal_have_a_product_of_inertia() -> None:
    # Unit cubes of 1 kg at (0,0,0) and (2,2,0): centre (1,1,0), d = ∓(1,1,0), |d|² = 2,
    # d dᵀ = [[1,1,0],[1,1,0],[0,0,0]], so each adds m(|d|²E − d dᵀ) = [[1,-1,0],[-1,1,0],[0,0,2]].
    # Sum: 2·that + 2·(1/6)E = [[7/3, -2, 0], [-2, 7/3, 0], [0, 0, 13/3]].
    combined = combine(
        [Inertial(1.0, at(0.0, 0.0, 0.0), UNIT_CUBE), Inertial(1.0, at(2.0, 2.0, 0.0), UNIT_CUBE)]
    )
    assert combined.com.isclose(at(1.0, 1.0, 0.0))
    assert combined.inertia == pytest.approx((7 / 3, -2.0, 0.0, 7 / 3, 0.0, 13 / 3), abs=1e-15)


def test_unequal_masses_weight_the_centre() -> None:
    # 3 kg at x = 0 and 1 kg at x = 4: centre x = 4/4 = 1.
    combined = combine(
        [Inertial(3.0, at(0.0, 0.0, 0.0), UNIT_CUBE), Inertial(1.0, at(4.0, 0.0, 0.0), UNIT_CUBE)]
    )
    assert combined.mass == 4.0
    assert combined.com.isclose(at(1.0, 0.0, 0.0))


def test_body_rotated_a_quarter_turn_about_z_swaps_ixx_and_iyy() -> None:
    box = Inertial(12.0, at(0.0, 0.0, 0.0, yaw=math.pi / 2), solid_box(12.0, 1.0, 2.0, 3.0))
    assert combine([box]).inertia == pytest.approx((10.0, 0.0, 0.0, 13.0, 0.0, 5.0), abs=1e-12)


def test_combine_of_one_part_equals_the_part() -> None:
    part = Inertial(2.5, at(0.3, -0.2, 0.7), (1.0, 0.1, -0.2, 2.0, 0.05, 2.5))
    assert_inertial_close(combine([part]), part)


def test_combine_of_one_rotated_part_is_equivalent() -> None:
    # Same mass and centre; the tensor turned into the frame's axes keeps its principal moments.
    part = Inertial(2.0, at(1.0, 2.0, 3.0, 0.3, -0.4, 1.2), solid_box(2.0, 0.1, 0.2, 0.3))
    combined = combine([part])
    assert combined.com.rotation == Pose.identity().rotation
    assert combined.com.position == pytest.approx(part.com.position, abs=1e-15)
    assert np.allclose(
        np.linalg.eigvalsh(tensor(combined.inertia)),
        np.linalg.eigvalsh(tensor(part.inertia)),
        rtol=0.0,
        atol=1e-15,
    )


@pytest.mark.parametrize(
    "parts",
    [[], [Inertial(0.0, Pose.identity(), UNIT_CUBE)], [Inertial(0.0, at(1, 0, 0), UNIT_CUBE)] * 2],
    ids=["no-parts", "massless", "two-massless"],
)
def test_combine_without_mass_raises(parts: list[Inertial]) -> None:
    with pytest.raises(ValueError, match="total mass"):
        combine(parts)


angles = st.floats(-math.pi, math.pi)
lengths = st.floats(0.01, 2.0)
bodies = st.builds(
    lambda mass, centre, rpy, size: Inertial(mass, at(*centre, *rpy), solid_box(mass, *size)),
    st.floats(0.1, 10.0),
    st.tuples(*[st.floats(-5.0, 5.0)] * 3),
    st.tuples(angles, angles, angles),
    st.tuples(lengths, lengths, lengths),
)


@given(st.data(), st.lists(bodies, min_size=1, max_size=5))
def test_combine_is_order_independent(data, parts: list[Inertial]) -> None:
    shuffled = data.draw(st.permutations(parts))
    assert_inertial_close(combine(shuffled), combine(parts), tol=1e-9)


@given(st.lists(bodies, min_size=1, max_size=5))
def test_combining_physical_bodies_is_physical(parts: list[Inertial]) -> None:
    assert is_physical(combine(parts).inertia)


@given(bodies, bodies, bodies)
def test_combine_is_associative(a: Inertial, b: Inertial, c: Inertial) -> None:
    # Combining a link's bodies in groups (as nested parts do) gives the same result.
    assert_inertial_close(combine([combine([a, b]), c]), combine([a, b, c]), tol=1e-9)


@given(bodies)
def test_one_part_is_the_same_body_as_its_two_halves(part: Inertial) -> None:
    # combine() takes a shortcut for a single part; halving it takes the general path.
    half = Inertial(part.mass / 2, part.com, tuple(v / 2 for v in part.inertia))
    assert_inertial_close(combine([part]), combine([half, half]), tol=1e-9)


# --- is_physical ---------------------------------------------------------------------------


def test_is_physical_accepts_a_flat_plate_at_the_triangle_equality() -> None:
    # A thin square plate in the xy plane: izz = ixx + iyy exactly, up to rounding.
    plate = solid_box(1.0, 0.3, 0.3, 1e-9)
    assert is_physical(plate)


@pytest.mark.parametrize(
    "inertia",
    [
        np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        (-1.0, 0.0, 0.0, 1.0, 0.0, 1.0),
        (1.0, 0.0, 0.0, 1.0, 0.0, 3.0),
        (1.0, 2.0, 0.0, 1.0, 0.0, 1.5),
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        np.eye(2),
    ],
    ids=["non-symmetric", "negative", "triangle", "indefinite", "zero", "wrong-shape"],
)
def test_is_physical_rejects(inertia) -> None:
    assert not is_physical(inertia)


def test_is_physical_takes_a_symmetric_tensor_too() -> None:
    assert is_physical(tensor(solid_box(1.0, 1.0, 2.0, 3.0)))


_MOMENT = st.one_of(st.floats(-1, 10, allow_nan=False, allow_infinity=False),
                    st.sampled_from([0.0, -0.0, 1.0, 2.0, 3.0, 1e-12]))  # values are finite


@settings(max_examples=300, deadline=None)
@given(_MOMENT, _MOMENT, _MOMENT)
def test_diagonal_shortcut_agrees_with_eigenvalues(ixx: float, iyy: float, izz: float) -> None:
    """Six entries with zero products take a shortcut (the moments are the diagonal); an
    array of the same entries goes through the eigenvalues: the answers agree."""
    entries = (ixx, 0.0, 0.0, iyy, 0.0, izz)
    assert is_physical(entries) == is_physical(np.array(entries))
    plate = (1.0, 0.0, 0.0, 2.0, 0.0, 3.0)  # A + B = C exactly: a flat plate, physical
    assert is_physical(plate) and is_physical(np.array(plate))
