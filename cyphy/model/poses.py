"""Rigid poses of links, bodies, sensors and joints (sdf.md decision 4, sdf-robotool.md §3).

A RoboSim pose ``(x, y, z, roll, pitch, yaw)`` is a rigid transform ``T = [R p; 0 1]`` with
``R = Rz(yaw)·Ry(pitch)·Rx(roll)``: SDF's fixed-axis convention, which SciPy spells ``"xyz"``
(lower case = extrinsic). Nested poses compose outer first, ``T = T_outer · … · T_inner``, so the
innermost pose is applied first; a child pose in its parent's frame is ``parent.compose(child)``.

The rotation is stored as a 3x3 matrix, not a quaternion: composition is then plain matrix
arithmetic, ``isclose`` compares what SDF means entry by entry, and a matrix has no double cover
(``q`` and ``-q`` are the same rotation) to trip up equality.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

from cyphy.records import record

Vector3 = tuple[float, float, float]
Matrix3 = tuple[Vector3, Vector3, Vector3]
XyzRpy = tuple[float, float, float, float, float, float]

NOISE = 1e-12
"""Float noise that ``clean`` and the angle normalisation absorb: far below the 1e-6 m / 1e-6 rad
that the conformance comparison tolerates, far above the ~1e-16 error of one operation."""

_ORTHONORMAL_TOL = 1e-6
"""How far from a proper rotation a stored matrix may drift (many compositions add rounding)."""


def clean(value: float) -> float:
    """``value`` with float noise removed, for printing.

    A value within ``NOISE`` of an integer (zero included) becomes that integer as a float, and
    ``-0.0`` becomes ``0.0``, so a computed ``2.9999999999999996`` or ``-1.2e-16`` prints as an
    exact input would (``3.0``, ``0.0``). Other values, and non-finite ones, are returned as given.
    """
    if not math.isfinite(value):
        return value
    nearest = round(value)
    return float(nearest) if abs(value - nearest) <= NOISE else value


def _half_open_angle(angle: float) -> float:
    """``angle`` (already in [−π, π]) moved into (−π, π].

    SciPy wraps angles into [−π, π), so a yaw of π comes back as −π; anything within ``NOISE`` of
    −π is reported as π so that a half turn prints the same whichever way it was computed.
    """
    return math.pi if angle <= -math.pi + NOISE else angle


@record
class Pose:
    """A rigid transform: ``position`` in metres and ``rotation`` as a row-major 3x3 matrix.

    Immutable so that one pose can be shared by every element that refers to it; equality is
    exact (use ``isclose`` for computed poses).
    """

    position: Vector3
    rotation: Matrix3

    def __post_init__(self) -> None:
        # Normalise to tuples of plain floats so that lists or NumPy arrays passed in cannot be
        # mutated later and equal poses compare equal whatever type built them.
        position = _floats(self.position)
        rotation = [_floats(row) for row in _listed(self.rotation)]
        if len(position) != 3 or len(rotation) != 3 or any(len(row) != 3 for row in rotation):
            raise ValueError("a pose needs a 3-vector position and a 3x3 rotation matrix")
        if not _is_rotation(rotation):
            raise ValueError("the rotation of a pose must be orthonormal with determinant +1")
        object.__setattr__(self, "position", tuple(position))
        object.__setattr__(self, "rotation", tuple(tuple(row) for row in rotation))

    @classmethod
    def identity(cls) -> Pose:
        """The pose of a frame in itself (the default when a RoboSim element gives no pose)."""
        return cls.at((0.0, 0.0, 0.0))

    @classmethod
    def at(cls, position: Sequence[float]) -> Pose:
        """The pose at ``position`` with no rotation (a centre of mass in the frame's axes)."""
        x, y, z = (float(v) for v in position)
        return cls._trusted((x, y, z), ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))

    @classmethod
    def from_xyz_rpy(
        cls, x: float, y: float, z: float, roll: float, pitch: float, yaw: float
    ) -> Pose:
        """The pose written ``x y z roll pitch yaw`` in RoboSim and SDF.

        ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``: roll about the fixed x axis first, then pitch about
        fixed y, then yaw about fixed z (SciPy ``"xyz"``; equivalently intrinsic ``"ZYX"``).
        """
        # The product written out: SciPy's from_euler gives the same matrix (a test checks)
        # but costs 0.1 ms a call, and a model builds a pose per element.
        cr, sr = math.cos(roll), math.sin(roll)
        cp, sp = math.cos(pitch), math.sin(pitch)
        cy, sy = math.cos(yaw), math.sin(yaw)
        rotation = (
            (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr),
        )
        return cls._trusted((float(x), float(y), float(z)), rotation)

    @classmethod
    def _trusted(cls, position: Vector3, rotation: Matrix3) -> Pose:
        """A pose from values this module computed itself (floats, a proper rotation): the
        validation in ``__post_init__`` costs more than building the pose."""
        pose = object.__new__(cls)
        object.__setattr__(pose, "position", position)
        object.__setattr__(pose, "rotation", rotation)
        return pose

    def compose(self, inner: Pose) -> Pose:
        """``self ∘ inner`` (``T_self · T_inner``): ``inner`` is expressed in ``self``'s frame.

        The result expresses ``inner``'s frame in the frame ``self`` is expressed in, which is how
        a part's pose carries the poses of its links into the model frame.
        """
        r, q = self.rotation, inner.rotation
        p, v = self.position, inner.position
        # Written out, not as generators: a tuple built from a generator keeps room for ten
        # items (120 bytes, not 64), and every elaborated link keeps several poses.
        (r0, r1, r2), (q0, q1, q2) = r, q
        position = (r0[0] * v[0] + r0[1] * v[1] + r0[2] * v[2] + p[0],
                    r1[0] * v[0] + r1[1] * v[1] + r1[2] * v[2] + p[1],
                    r2[0] * v[0] + r2[1] * v[1] + r2[2] * v[2] + p[2])
        rotation = tuple([(ri[0] * q0[0] + ri[1] * q1[0] + ri[2] * q2[0],
                           ri[0] * q0[1] + ri[1] * q1[1] + ri[2] * q2[1],
                           ri[0] * q0[2] + ri[1] * q1[2] + ri[2] * q2[2]) for ri in (r0, r1, r2)])
        return Pose._trusted(position, rotation)  # type: ignore[arg-type]

    def __matmul__(self, inner: Pose) -> Pose:
        """``self @ inner`` is ``self.compose(inner)``, reading like the matrix product."""
        return self.compose(inner)

    def inverse(self) -> Pose:
        """The pose of the outer frame in this one: ``[Rᵀ  −Rᵀp]``.

        ``Rᵀp`` is summed as BLAS's ``dgemv`` sums a transposed product (from +0.0, left to
        right, no fused multiply-add), which NumPy computed here before: the same bits, so
        that every pose printed stays as it was, now on every processor (OpenBLAS's kernel
        for one with fused multiply-adds can differ in the last place)."""
        (r0, r1, r2), (p0, p1, p2) = self.rotation, self.position
        position = (-(0.0 + r0[0] * p0 + r1[0] * p1 + r2[0] * p2),
                    -(0.0 + r0[1] * p0 + r1[1] * p1 + r2[1] * p2),
                    -(0.0 + r0[2] * p0 + r1[2] * p1 + r2[2] * p2))
        return Pose._trusted(position, tuple(zip(r0, r1, r2)))  # type: ignore[arg-type]

    def relative_to(self, frame: Pose) -> Pose:
        """This pose expressed in ``frame`` (both given in the same outer frame).

        This is how a joint pose is re-expressed relative to its child link (SDF 1.6);
        ``frame.compose(p).relative_to(frame)`` gives back ``p``.
        """
        return frame.inverse().compose(self)

    def to_xyz_rpy(self) -> XyzRpy:
        """``(x, y, z, roll, pitch, yaw)`` with roll, yaw in (−π, π] and pitch in [−π/2, π/2].

        Angles come from SciPy's ``as_euler("xyz")``. At gimbal lock (|pitch| within SciPy's
        1e-7 rad of π/2) roll and yaw turn about the same axis and only their difference
        (pitch = π/2) or sum (pitch = −π/2) is determined: then **yaw = 0** and roll carries it,
        as RoboTool does (sdf-robotool.md §3). Inside that band the angles reproduce the
        rotation to twice the distance of pitch from ±π/2 (at most 2e-7 rad), within the 1e-6 rad
        that the conformance check allows. Values are not passed through ``clean``: that is the
        printer's choice.
        """
        from scipy.spatial.transform import Rotation  # lazy: SciPy, for the LSP and `show`

        roll, pitch, yaw = Rotation.from_matrix(self._rotation_array()).as_euler(
            "xyz", suppress_warnings=True
        )
        return (
            *self.position,
            _half_open_angle(float(roll)),
            float(pitch),
            _half_open_angle(float(yaw)),
        )

    def apply(self, point: Sequence[float]) -> Vector3:
        """``point`` (given in this pose's frame) expressed in the outer frame: ``R·point + p``."""
        import numpy as np  # lazy: for the drawings of ``cyphy view``, which use NumPy anyway

        moved = self._rotation_array() @ np.asarray(point, dtype=float)
        x, y, z = (moved + self._position_array()).tolist()
        return (x, y, z)

    def matrix(self) -> Any:
        """The 4x4 homogeneous NumPy matrix ``[R p; 0 1]`` (a fresh array the caller may
        modify)."""
        import numpy as np  # lazy: the dynamics compute with it; the SDF path never asks

        result = np.eye(4)
        result[:3, :3] = self._rotation_array()
        result[:3, 3] = self._position_array()
        return result

    def isclose(self, other: Pose, tol: float = 1e-9) -> bool:
        """Positions and rotation matrices equal entry by entry within ``tol``.

        Comparing matrices rather than Euler angles keeps poses near gimbal lock comparable: there
        two nearly equal rotations can have angles that differ by 2π (sdf-robotool.md §3.2).
        """
        mine = (*self.position, *(x for row in self.rotation for x in row))
        theirs = (*other.position, *(x for row in other.rotation for x in row))
        return all(abs(a - b) <= tol for a, b in zip(mine, theirs))

    def _position_array(self) -> Any:
        import numpy as np  # lazy: for SciPy's and NumPy's callers only

        return np.array(self.position)

    def _rotation_array(self) -> Any:
        import numpy as np  # lazy: for SciPy's and NumPy's callers only

        return np.array(self.rotation)


def _listed(values: Any) -> list[Any]:
    """A list of ``values`` (a sequence, or a NumPy array or Array, through ``tolist``)."""
    return values.tolist() if hasattr(values, "tolist") else list(values)


def _floats(values: Any) -> list[float]:
    try:
        return [float(v) for v in _listed(values)]
    except TypeError:
        raise ValueError("a pose needs a 3-vector position and a 3x3 rotation matrix") from None


def _is_rotation(m: list[list[float]]) -> bool:
    """Orthonormal with determinant +1, within the drift that repeated composition causes.

    Plain arithmetic on the nine entries: ``np.allclose`` costs more than the composition it
    guards, and every elaborated element builds poses."""
    for i in range(3):
        for j in range(i, 3):
            dot = m[i][0] * m[j][0] + m[i][1] * m[j][1] + m[i][2] * m[j][2]
            if abs(dot - (1.0 if i == j else 0.0)) > _ORTHONORMAL_TOL:
                return False
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
           - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    return det > 0.0
