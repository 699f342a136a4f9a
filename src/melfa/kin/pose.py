"""Poses, joint vectors, A/B/C angles and position arithmetic (controller units: mm, degrees).

The A/B/C convention is fixed-axis XYZ: **R = Rz(C)·Ry(B)·Rx(A)** [CODE S6, DERIVED rv6s.md §5;
the composition order is a GUESS to verify on the robot, see `ABC_ORDER`].

Position arithmetic follows melfa-basic-iv.md §7:

- `pose_mul(p1, p2)`: ``P1 * P2``, P2 applied in P1's tool frame (T1·T2);
- `pose_div(p1, p2)`: ``P1 / P2`` = T1·T2⁻¹;
- `pose_add` / `pose_sub`: ``P1 + P2`` / ``P1 - P2``, element-wise in world coordinates, angles
  included;
- `pose_inv(p)`: ``INV(P)``, the inverse transform.

Results keep the flags (FL1, FL2) of the left operand, like the controller does for
``P_CURR * P2``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

ABC_ORDER = "Rz(C)·Ry(B)·Rx(A)"
"""[GUESS rv6s.md §5] composition order of A/B/C; fixed-axis X, then Y, then Z."""

DEFAULT_FL1 = 7
"""Right/Above/Non-flip, the default for vertical arms [DOC S2 p.146]."""
DEFAULT_FL2 = 0


class Joints(NamedTuple):
    """Six joint angles J1..J6 in degrees (the controller's JPOSF units)."""

    j1: float
    j2: float
    j3: float
    j4: float
    j5: float
    j6: float

    @classmethod
    def of(cls, values: Iterable[float]) -> Joints:
        """Build from any 6-element iterable (list, tuple, numpy array)."""
        vals = [float(v) for v in values]
        if len(vals) != 6:
            raise ValueError(f"need 6 joint values, got {len(vals)}")
        return cls(*vals)

    def array(self) -> FloatArray:
        return np.array(self, dtype=float)


@dataclass(frozen=True, slots=True)
class Pose:
    """An XYZ position: mm and degrees, with structure flags (FL1, FL2).

    `l1`/`l2` are the optional additional axes (mm or degrees); the RV-6S has none, but the
    language carries them.
    """

    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0
    fl1: int = DEFAULT_FL1
    fl2: int = DEFAULT_FL2
    l1: float | None = None
    l2: float | None = None

    @property
    def xyz(self) -> tuple[float, float, float]:
        return (self.x, self.y, self.z)

    @property
    def abc(self) -> tuple[float, float, float]:
        return (self.a, self.b, self.c)

    def with_flags(self, fl1: int, fl2: int | None = None) -> Pose:
        return replace(self, fl1=fl1, fl2=self.fl2 if fl2 is None else fl2)

    def matrix(self) -> FloatArray:
        """The 4×4 homogeneous transform of this pose."""
        return pose_to_matrix(self)

    def __str__(self) -> str:
        """The controller's text form: ``(+400.00,+0.00,+645.00,+180.00,+0.00,+180.00)(7,0)``."""
        vals = ",".join(_fmt(v) for v in (self.x, self.y, self.z, self.a, self.b, self.c))
        return f"({vals})({self.fl1},{self.fl2})"


def _fmt(v: float) -> str:
    return f"{round(v, 2) + 0.0:+.2f}"  # + 0.0 turns -0.0 into 0.0


IDENTITY_POSE = Pose(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def wrap_deg(angle: float) -> float:
    """Wrap an angle to (-180, 180] degrees.

    >>> wrap_deg(190.0), wrap_deg(-180.0), wrap_deg(540.0)
    (-170.0, 180.0, 180.0)
    """
    w = math.fmod(angle + 180.0, 360.0)
    if w <= 0.0:
        w += 360.0
    return w - 180.0


def abc_to_matrix(a: float, b: float, c: float) -> FloatArray:
    """Rotation matrix for A/B/C in degrees: R = Rz(C)·Ry(B)·Rx(A)."""
    ca, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
    cb, sb = math.cos(math.radians(b)), math.sin(math.radians(b))
    cc, sc = math.cos(math.radians(c)), math.sin(math.radians(c))
    return np.array(
        [
            [cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa],
            [sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa],
            [-sb, cb * sa, cb * ca],
        ]
    )


def matrix_to_abc(r: npt.ArrayLike) -> tuple[float, float, float]:
    """A/B/C in degrees from a rotation matrix; B in [-90, 90], A and C in (-180, 180].

    At B = ±90° (gimbal lock) A is set to 0 and the whole rotation goes into C.

    >>> [round(v, 6) + 0.0 for v in matrix_to_abc(np.diag([-1.0, 1.0, -1.0]))]
    [180.0, 0.0, 180.0]
    """
    m = np.asarray(r, dtype=float)
    cb = math.hypot(m[0, 0], m[1, 0])
    b = math.atan2(-m[2, 0], cb)
    if cb > 1e-9:
        a = math.atan2(m[2, 1], m[2, 2])
        c = math.atan2(m[1, 0], m[0, 0])
    else:  # gimbal lock: only A - C (B = +90) or A + C (B = -90) is defined
        a = 0.0
        c = math.atan2(-m[0, 1], m[1, 1])
    return (
        wrap_deg(math.degrees(a)),
        math.degrees(b),
        wrap_deg(math.degrees(c)),
    )


def pose_to_matrix(p: Pose) -> FloatArray:
    """4×4 transform of a pose (flags ignored)."""
    t = np.eye(4)
    t[:3, :3] = abc_to_matrix(p.a, p.b, p.c)
    t[:3, 3] = (p.x, p.y, p.z)
    return t


def matrix_to_pose(
    t: npt.ArrayLike,
    fl1: int = DEFAULT_FL1,
    fl2: int = DEFAULT_FL2,
    l1: float | None = None,
    l2: float | None = None,
) -> Pose:
    """Pose from a 4×4 transform, with the given flags."""
    m = np.asarray(t, dtype=float)
    a, b, c = matrix_to_abc(m[:3, :3])
    return Pose(
        float(m[0, 3]), float(m[1, 3]), float(m[2, 3]), a, b, c, fl1=fl1, fl2=fl2, l1=l1, l2=l2
    )


def invert_transform(t: FloatArray) -> FloatArray:
    """Inverse of a rigid 4×4 transform (cheaper and exacter than np.linalg.inv)."""
    inv = np.eye(4)
    rt = t[:3, :3].T
    inv[:3, :3] = rt
    inv[:3, 3] = -rt @ t[:3, 3]
    return inv


def pose_mul(p1: Pose, p2: Pose) -> Pose:
    """``P1 * P2``: P2 taken in P1's tool frame (T1·T2); flags from P1.

    >>> str(pose_mul(Pose(400, 0, 645, 180, 0, 180), Pose(0, 0, -50, 0, 0, 0)))
    '(+400.00,+0.00,+695.00,+180.00,+0.00,+180.00)(7,0)'
    """
    return matrix_to_pose(
        pose_to_matrix(p1) @ pose_to_matrix(p2), p1.fl1, p1.fl2, *_add_extra(p1, p2, 1.0)
    )


def pose_div(p1: Pose, p2: Pose) -> Pose:
    """``P1 / P2``: the inverse of `pose_mul` (T1·T2⁻¹); flags from P1."""
    return matrix_to_pose(
        pose_to_matrix(p1) @ invert_transform(pose_to_matrix(p2)),
        p1.fl1,
        p1.fl2,
        *_add_extra(p1, p2, -1.0),
    )


def pose_inv(p: Pose) -> Pose:
    """``INV(P)``: the inverse transform; flags from P."""
    return matrix_to_pose(invert_transform(pose_to_matrix(p)), p.fl1, p.fl2, p.l1, p.l2)


def pose_add(p1: Pose, p2: Pose) -> Pose:
    """``P1 + P2``: element-wise in world coordinates, A/B/C included (not wrapped); flags from P1.

    >>> str(pose_add(Pose(1, 2, 3, 10, 20, 30), Pose(1, 1, 1, 1, 1, 1)))
    '(+2.00,+3.00,+4.00,+11.00,+21.00,+31.00)(7,0)'
    """
    return _elementwise(p1, p2, 1.0)


def pose_sub(p1: Pose, p2: Pose) -> Pose:
    """``P1 - P2``: element-wise in world coordinates; flags from P1."""
    return _elementwise(p1, p2, -1.0)


def _elementwise(p1: Pose, p2: Pose, sign: float) -> Pose:
    l1, l2 = _add_extra(p1, p2, sign)
    return Pose(
        p1.x + sign * p2.x,
        p1.y + sign * p2.y,
        p1.z + sign * p2.z,
        p1.a + sign * p2.a,
        p1.b + sign * p2.b,
        p1.c + sign * p2.c,
        fl1=p1.fl1,
        fl2=p1.fl2,
        l1=l1,
        l2=l2,
    )


def _add_extra(p1: Pose, p2: Pose, sign: float) -> tuple[float | None, float | None]:
    """Additional axes L1/L2 add element-wise; missing on the right counts as 0."""

    def one(u: float | None, v: float | None) -> float | None:
        if u is None:
            return None
        return u + sign * (v or 0.0)

    return one(p1.l1, p2.l1), one(p1.l2, p2.l2)


def rotation_angle_deg(r0: FloatArray, r1: FloatArray) -> float:
    """Angle in degrees of the rotation taking r0 to r1 (0..180)."""
    r = r0.T @ r1
    cos = (float(np.trace(r)) - 1.0) / 2.0
    sin = math.hypot(r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]) / 2.0
    return math.degrees(math.atan2(sin, cos))  # atan2 stays exact near 0, unlike acos


def pose_distance(p1: Pose, p2: Pose) -> tuple[float, float]:
    """(position distance in mm, orientation distance in degrees) between two poses."""
    d = math.dist(p1.xyz, p2.xyz)
    return d, rotation_angle_deg(abc_to_matrix(*p1.abc), abc_to_matrix(*p2.abc))
