"""The pure-Python vectors and matrices of constant values (``cyphy.model.array``) against
NumPy, the library they replaced on the start-up path: the same shapes, indexing and entries,
and, for every operation computed without NumPy, the same bits (outputs print with ``repr``,
so one ulp would show)."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cyphy.expr import Expr
from cyphy.lang.parser import parse_text
from cyphy.model.array import Array
from cyphy.model.evaluate import evaluate
from cyphy.model.inertia import Inertial, combine
from cyphy.model.poses import Pose
from cyphy.model.values import from_env

FINITE = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
ANGLE = st.floats(min_value=-4.0, max_value=4.0, allow_nan=False)


def _bits(values: object) -> list[str]:
    return [float(x).hex() for x in np.asarray(values, dtype=float).ravel()]


def test_an_array_reads_like_the_numpy_array_it_stands_for() -> None:
    rows = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]
    value, array = Array.of(rows), np.array(rows)
    assert value.shape == array.shape and value.ndim == 2 and value.size == 6 and len(value) == 2
    assert value.tolist() == array.tolist() and value.T.tolist() == array.T.tolist()
    assert value[1, 2] == array[1, 2] and value[-1, 0] == array[-1, 0]
    assert value[1].tolist() == array[1].tolist() and value[:, 1].tolist() == array[:, 1].tolist()
    assert value[:1, 1:].tolist() == array[:1, 1:].tolist()
    assert [row.tolist() for row in value] == [row.tolist() for row in array]
    vector = Array.of([7.0, 8.0, 9.0])
    assert vector.shape == (3,) and list(vector) == [7.0, 8.0, 9.0]
    assert vector[1:].tolist() == [8.0, 9.0]
    converted = np.asarray(value)
    assert converted.dtype == np.float64 and converted.tolist() == rows
    assert not converted.flags.writeable
    with pytest.raises(IndexError):
        vector[3]


def test_an_array_is_an_immutable_hashable_value() -> None:
    value = Array.of([[1, 2], [3, 4]])
    assert value == Array.of([[1.0, 2.0], [3.0, 4.0]]) and value != Array.of([1, 2, 3, 4])
    assert hash(value) == hash(Array.of([[1.0, 2.0], [3.0, 4.0]]))
    assert pickle.loads(pickle.dumps(value)) == value
    with pytest.raises(AttributeError):
        value.shape = (4,)  # type: ignore[misc]
    with pytest.raises(ValueError):
        Array.of([[1, 2], [3]])
    with pytest.raises(ValueError):
        Array.of([1, "x"])


def test_numpy_values_given_in_env_become_arrays_and_python_scalars() -> None:
    assert from_env("b", np.True_) is True
    assert from_env("i", np.int64(3)) == 3 and type(from_env("i", np.int64(3))) is int
    value = from_env("v", np.array([1, 2, 3]))
    assert isinstance(value, Array) and value.tolist() == [1.0, 2.0, 3.0]
    with pytest.raises(ValueError):
        from_env("s", np.array(["a"]))


@settings(max_examples=200, deadline=None)
@given(st.lists(FINITE, min_size=3, max_size=3), st.lists(FINITE, min_size=3, max_size=3),
       FINITE.filter(lambda x: abs(x) >= 1e-3))
def test_entry_wise_arithmetic_has_numpy_s_bits(a: list[float], b: list[float],
                                                k: float) -> None:
    env = {"a": np.array(a), "b": np.array(b), "k": k}
    for source, expected in (("a + b", env["a"] + env["b"]), ("a - b", env["a"] - env["b"]),
                             ("k * a", k * env["a"]), ("a * k", env["a"] * k),
                             ("a / k", env["a"] / k), ("-a", -env["a"]),
                             ("(a)cm", env["a"] * 0.01),
                             ("cross(a, b)", np.cross(env["a"], env["b"]))):
        expr = _parse(source)
        assert _bits(evaluate(expr, env)) == _bits(expected), source


@settings(max_examples=300, deadline=None)
@given(st.tuples(FINITE, FINITE, FINITE), ANGLE, ANGLE, ANGLE,
       st.sampled_from([0.0, -0.0, 1.0]))
@example((0.0, 1.0, 3.0), 1.0, 0.0, 0.0, 0.0)  # OpenBLAS's fused kernel: 1 ulp off (docstring)
def test_the_inverse_of_a_pose_has_numpy_s_bits(p: tuple[float, float, float], roll: float,
                                                pitch: float, yaw: float, zero: float) -> None:
    """``Pose.inverse`` sums ``Rᵀp`` without NumPy, as BLAS's ``dgemv`` without fused
    multiply-adds does (from +0.0, left to right; signed zeros too): the oracle is NumPy's
    element-wise products and sums in that order, each rounded as IEEE 754 rounds it. The
    matrix product ``rotation.T @ position`` itself is not the oracle for the bits: OpenBLAS
    chooses its kernel by processor, and on one with fused multiply-adds (an AMD EPYC, in CI)
    it differs in the last place (``-0x1.884896f340b56p+1`` against the correctly rounded
    ``…b55p+1`` for the pose (0, 1, 3, roll 1)); it is held to a few units there."""
    for pose in (Pose.from_xyz_rpy(*p, roll, pitch, yaw),
                 Pose.from_xyz_rpy(zero * p[0], -0.0, p[2], 0.0, 0.0, 0.0)):
        rotation, position = np.array(pose.rotation), np.array(pose.position)
        products = rotation.T * position  # row i: R[0][i] p0, R[1][i] p1, R[2][i] p2
        expected = -(((0.0 + products[:, 0]) + products[:, 1]) + products[:, 2])
        assert _bits(pose.inverse().position) == _bits(expected)
        blas = -(rotation.T @ position)
        scale = np.abs(rotation.T) @ np.abs(position)  # the sum's error bound grows with it
        # each sum of three products is within 3 units of 2**-53 of the exact one (Higham),
        # so the two within 6, and a margin for the bound computed in floating point
        assert np.all(np.abs(np.array(pose.inverse().position) - blas) <= 8e-16 * scale)
        assert pose.inverse().rotation == tuple(map(tuple, rotation.T.tolist()))


@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=1e-3, max_value=1e3), st.tuples(FINITE, FINITE, FINITE),
       st.lists(st.floats(min_value=-10.0, max_value=10.0), min_size=6, max_size=6))
def test_one_body_in_the_frame_s_axes_combines_with_numpy_s_bits(
        mass: float, centre: tuple[float, float, float], inertia: list[float]) -> None:
    """The shortcut of ``combine`` (no ``R I Rᵀ`` for the identity) against the product."""
    inertia[1] = -0.0 if inertia[1] < 0 else inertia[1]  # a negative zero among the entries
    part = Inertial(mass, Pose.at(centre), tuple(inertia))  # type: ignore[arg-type]
    combined = combine([part])
    r = np.eye(3)
    ixx, ixy, ixz, iyy, iyz, izz = inertia
    product = r @ np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]) @ r.T
    expected = [product[0, 0], product[0, 1], product[0, 2], product[1, 1], product[1, 2],
                product[2, 2]]
    assert _bits(combined.inertia) == _bits(expected)
    assert combined.mass == mass and combined.com.position == tuple(map(float, centre))


def test_matrix_products_are_numpy_s() -> None:
    """A product of two arrays is left to NumPy (its fused multiply-adds round differently
    from a Python loop): the evaluator's result is NumPy's, bit for bit."""
    rng = np.random.default_rng(7)
    m, v = rng.normal(size=(3, 3)), rng.normal(size=3)
    assert _bits(evaluate(_parse("m * v"), {"m": m, "v": v})) == _bits(m @ v)
    assert _bits(evaluate(_parse("m * m"), {"m": m})) == _bits(m @ m)
    assert math.isclose(evaluate(_parse("det(m)"), {"m": m}), float(np.linalg.det(m)))


def _parse(source: str) -> Expr:
    result = parse_text(f"const value: real = {source}", "<test>")
    assert result.file is not None and not result.diagnostics
    expr = result.file.items[0].value  # type: ignore[union-attr]
    assert expr is not None
    return expr
