"""Forward and closed-form inverse kinematics of the RV-6S (rv6s.md §4, §6).

IK is analytic (no iteration): the wrist is spherical, so the wrist centre (P-point, 85 mm
behind the flange) fixes J1–J3 (planar two-link with the 85 mm shoulder offset and the
100 mm elbow offset folded into one 330 mm link), and the rest of the orientation fixes
J4–J6 as a Z-Y-Z Euler triple. The array functions (`fk_batch`, `ik_batch`) work on many
samples at once so path checks stay cheap.

TOOL and BASE: the TCP transform is ``BASE · flange · TOOL`` (BASE is the robot base frame
as seen from the world frame).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from melfa.kin.errors import (
    LimitExceeded,
    Unreachable,
    UnreachableReason,
)
from melfa.kin.flags import (
    ALL_CONFIGURATIONS,
    Configuration,
    fl2_from_joints,
    fl2_get,
)
from melfa.kin.model import (
    BASE_HEIGHT,
    DEFAULT_INTERFERENCE,
    DH,
    ELBOW_OFFSET,
    FLANGE,
    FOREARM,
    JOINT_LIMITS,
    JOINT_MAX_SPEED,
    SHOULDER_OFFSET,
    UPPER_ARM,
    Interference,
    check_limits,
)
from melfa.kin.pose import (
    FloatArray,
    Joints,
    Pose,
    invert_transform,
    matrix_to_pose,
    pose_to_matrix,
)

_FORE = math.hypot(ELBOW_OFFSET, FOREARM)  # J3 axis to wrist centre, ≈330.5 mm
_PHI = math.atan2(FOREARM, ELBOW_OFFSET)  # angle of that line in the forearm, ≈72.4°
_ALPHA = tuple(math.radians(r.alpha) for r in DH)
_OFFSET = np.radians([r.offset for r in DH])
_WRIST_EPS = 1e-9  # sin(J5) below this counts as the wrist singularity
_SHOULDER_EPS = 1e-6  # wrist centre this close (mm) to the J1 axis: J1 is free

MAX_REACH = UPPER_ARM + _FORE
"""Shoulder (J2) to wrist-centre reach, mm (the documented 696 mm is from J1's axis)."""


def _as_batch(q: FloatArray) -> FloatArray:
    arr = np.asarray(q, dtype=float)
    return arr.reshape(1, 6) if arr.ndim == 1 else arr


def fk_batch(joints: Sequence[float] | FloatArray) -> FloatArray:
    """Flange transforms (N, 4, 4) for joint rows (N, 6) in degrees."""
    return frames_batch(joints)[:, -1]


def frames_batch(joints: Sequence[float] | FloatArray) -> FloatArray:
    """Every DH frame (N, 7, 4, 4) for joint rows (N, 6) in degrees: frame 0 is the base,
    frame i is after joint i (its origin on joint i+1's axis), frame 6 the flange."""
    q = _as_batch(np.asarray(joints, dtype=float))
    theta = np.radians(q) + _OFFSET
    n = q.shape[0]
    frames = np.empty((n, len(DH) + 1, 4, 4))
    out = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    frames[:, 0] = out
    for i, row in enumerate(DH):
        ct, st = np.cos(theta[:, i]), np.sin(theta[:, i])
        ca, sa = math.cos(_ALPHA[i]), math.sin(_ALPHA[i])
        t = np.zeros((n, 4, 4))
        t[:, 0, 0] = ct
        t[:, 0, 1] = -st * ca
        t[:, 0, 2] = st * sa
        t[:, 0, 3] = row.a * ct
        t[:, 1, 0] = st
        t[:, 1, 1] = ct * ca
        t[:, 1, 2] = -ct * sa
        t[:, 1, 3] = row.a * st
        t[:, 2, 1] = sa
        t[:, 2, 2] = ca
        t[:, 2, 3] = row.d
        t[:, 3, 3] = 1.0
        out = out @ t
        frames[:, i + 1] = out
    return frames


def _fk_single(joints: Sequence[float]) -> FloatArray:
    """`fk_batch` for one joint vector, without the per-row array overhead (hot path)."""
    t = np.eye(4)
    for q, row, alpha, off in zip(joints, DH, _ALPHA, _OFFSET, strict=True):
        th = math.radians(float(q)) + float(off)
        ct, st = math.cos(th), math.sin(th)
        ca, sa = math.cos(alpha), math.sin(alpha)
        t = t @ np.array(
            [
                [ct, -st * ca, st * sa, row.a * ct],
                [st, ct * ca, -ct * sa, row.a * st],
                [0.0, sa, ca, row.d],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
    return t


def fk_matrix(
    joints: Sequence[float], tool: Pose | None = None, base: Pose | None = None
) -> FloatArray:
    """4×4 TCP transform (flange when no tool) in the world frame (robot base when no base)."""
    t = _fk_single(joints)
    if tool is not None:
        t = t @ pose_to_matrix(tool)
    if base is not None:
        t = pose_to_matrix(base) @ t
    return t


def fk(joints: Sequence[float], tool: Pose | None = None, base: Pose | None = None) -> Pose:
    """Forward kinematics: joints (deg) -> TCP pose (mm, deg) with FL1/FL2 from the joints.

    >>> str(fk((0, 0, 90, 0, 90, 0)))
    '(+400.00,+0.00,+645.00,+180.00,+0.00,+180.00)(7,0)'
    """
    fl1, fl2 = structure_flags(joints)
    return matrix_to_pose(fk_matrix(joints, tool, base), fl1, fl2)


def configuration_of(joints: Sequence[float]) -> Configuration:
    """Right/Left, Above/Below, Non-flip/Flip of a joint vector (rv6s.md §6).

    Right: the wrist centre lies on the arm's side of the J1 axis. Above: the wrist centre is
    above the line J2–J3 (elbow up). Non-flip: J5 >= 0 (CODE S12 uses J5 > 0; at J5 = 0 the
    wrist is singular and both are the same pose).
    """
    th2 = math.radians(joints[1]) + _OFFSET[1]
    beta = math.radians(joints[2]) + _OFFSET[2] + _PHI
    radial = SHOULDER_OFFSET + UPPER_ARM * math.cos(th2) + _FORE * math.cos(th2 + beta)
    return Configuration(
        right=radial >= 0.0, above=math.sin(beta) >= 0.0, nonflip=float(joints[4]) >= 0.0
    )


def structure_flags(joints: Sequence[float]) -> tuple[int, int]:
    """(FL1, FL2) of a joint vector, as PPOSF would show them.

    >>> structure_flags((0, 0, 90, 0, 90, 0)), structure_flags((0, 0, 90, 0, -30, 200))
    ((7, 0), (6, 1048576))
    """
    return configuration_of(joints).fl1, fl2_from_joints(joints)


def flange_target(pose: Pose, tool: Pose | None = None, base: Pose | None = None) -> FloatArray:
    """The flange transform (robot base frame) that puts the TCP at `pose`."""
    t = pose_to_matrix(pose)
    if base is not None:
        t = invert_transform(pose_to_matrix(base)) @ t
    if tool is not None:
        t = t @ invert_transform(pose_to_matrix(tool))
    return t


def ik_batch(
    transforms: FloatArray,
    config: Configuration,
    j1_fallback: FloatArray | float = 0.0,
    j4_fallback: FloatArray | float = 0.0,
) -> FloatArray:
    """Closed-form IK of one configuration for flange transforms (N, 4, 4) -> joints (N, 6).

    J6 comes back in (-180, 180]; rows with no solution (out of reach) are NaN. Limits are not
    checked. At the shoulder singularity (wrist centre on the J1 axis) J1 takes `j1_fallback`;
    at the wrist singularity (J5 = 0) J4 takes `j4_fallback` (degrees, scalar or per row).
    """
    t = np.asarray(transforms, dtype=float).reshape(-1, 4, 4)
    n = t.shape[0]
    rot = t[:, :3, :3]
    wrist = t[:, :3, 3] - FLANGE * rot[:, :, 2]
    xw, yw, zw = wrist[:, 0], wrist[:, 1], wrist[:, 2]

    hyp = np.hypot(xw, yw)
    j1_fb = np.radians(np.broadcast_to(np.asarray(j1_fallback, dtype=float), (n,)))
    if config.right:
        th1 = np.where(hyp > _SHOULDER_EPS, np.arctan2(yw, xw), j1_fb)
        rho = hyp
    else:
        th1 = np.where(hyp > _SHOULDER_EPS, np.arctan2(-yw, -xw), j1_fb)
        rho = -hyp
    u = rho - SHOULDER_OFFSET
    v = BASE_HEIGHT - zw  # frame-1 y axis points down
    cos_beta = (u * u + v * v - UPPER_ARM**2 - _FORE**2) / (2.0 * UPPER_ARM * _FORE)
    reachable = np.abs(cos_beta) <= 1.0 + 1e-9
    beta = np.arccos(np.clip(cos_beta, -1.0, 1.0))
    if not config.above:
        beta = -beta
    th2 = np.arctan2(v, u) - np.arctan2(_FORE * np.sin(beta), UPPER_ARM + _FORE * np.cos(beta))
    th3 = beta - _PHI

    # Orientation of frame 3, then R36 = Rz(θ4)·Ry(-θ5)·Rz(θ6).
    c1, s1 = np.cos(th1), np.sin(th1)
    c23, s23 = np.cos(th2 + th3), np.sin(th2 + th3)
    r03 = np.empty((n, 3, 3))
    # Rz(θ1)·Rx(-90)·Rz(θ2+θ3)·Rx(-90), expanded.
    r03[:, 0, 0] = c1 * c23
    r03[:, 0, 1] = s1
    r03[:, 0, 2] = -c1 * s23
    r03[:, 1, 0] = s1 * c23
    r03[:, 1, 1] = -c1
    r03[:, 1, 2] = -s1 * s23
    r03[:, 2, 0] = -s23
    r03[:, 2, 1] = 0.0
    r03[:, 2, 2] = -c23
    r36 = np.transpose(r03, (0, 2, 1)) @ rot
    r13, r23, r33 = r36[:, 0, 2], r36[:, 1, 2], r36[:, 2, 2]
    r31, r32 = r36[:, 2, 0], r36[:, 2, 1]
    s5 = np.hypot(r13, r23)
    th5 = np.arctan2(s5, r33)
    sign = 1.0 if config.nonflip else -1.0
    th5 = sign * th5
    th4 = np.arctan2(-sign * r23, -sign * r13)
    th6 = np.arctan2(-sign * r32, sign * r31)
    singular = s5 < _WRIST_EPS
    if np.any(singular):
        j4_fb = np.radians(np.broadcast_to(np.asarray(j4_fallback, dtype=float), (n,)))
        total = np.arctan2(r36[:, 1, 0], r36[:, 0, 0])  # θ4 + θ6 when θ5 = 0
        th4 = np.where(singular, j4_fb, th4)
        th6 = np.where(singular, total - j4_fb, th6)

    q = np.degrees(np.stack([th1, th2, th3, th4, th5, th6], axis=1) - _OFFSET)
    q = _wrap(q)
    q[~reachable] = np.nan
    return q


def _wrap(q: FloatArray) -> FloatArray:
    """Wrap degrees to (-180, 180]."""
    w = np.mod(q + 180.0, 360.0)
    w = np.where(w == 0.0, 360.0, w)
    return w - 180.0


def unwrap_j6(j6: FloatArray, reference: float) -> FloatArray:
    """Make a J6 sequence continuous and start at the turn nearest `reference` (degrees)."""
    seq = np.unwrap(np.asarray(j6, dtype=float), period=360.0)
    if seq.size == 0:
        return seq
    return np.asarray(seq + 360.0 * np.round((reference - seq[0]) / 360.0), dtype=float)


def _move_cost(q: FloatArray, current: FloatArray) -> float:
    """Time-like distance: slowest joint's travel time at full speed, then total travel."""
    d = np.abs(q - current)
    return float(np.max(d / np.asarray(JOINT_MAX_SPEED)) + 1e-6 * np.sum(d))


def ik(
    pose: Pose,
    current: Sequence[float] | None = None,
    tool: Pose | None = None,
    base: Pose | None = None,
    *,
    use_fl1: bool = True,
    use_fl2: bool = True,
    interference: Interference = DEFAULT_INTERFERENCE,
) -> Joints:
    """Inverse kinematics: TCP pose (mm, deg) -> joints (deg).

    With `use_fl1` the arm configuration is the pose's FL1; otherwise the solution nearest
    to `current` (in joint-time) among all eight. With `use_fl2` J6's turn is the pose's FL2
    J6 nibble; otherwise the turn nearest to `current` J6. Singular joints (J1 on the shoulder
    singularity, J4 at J5 = 0) keep their `current` values.

    Raises `Unreachable` (no solution) or `JointLimitExceeded` / `InterferenceLimitExceeded`
    (solution outside the operating range; with `use_fl1` the flags' solution is the only one).

    >>> [round(q, 6) for q in ik(fk((10, 20, 100, 30, 40, 50)))]
    [10.0, 20.0, 100.0, 30.0, 40.0, 50.0]
    """
    cur = np.asarray(current if current is not None else (0.0,) * 6, dtype=float)
    target = flange_target(pose, tool, base)
    configs = [Configuration.from_fl1(pose.fl1)] if use_fl1 else list(ALL_CONFIGURATIONS)
    best: FloatArray | None = None
    best_cost = math.inf
    first_error: LimitExceeded | None = None
    for cfg in configs:
        q = ik_batch(target, cfg, cur[0], cur[3])[0]
        if np.isnan(q[0]):
            continue
        for cand in _j6_candidates(q, pose.fl2, cur[5], use_fl2):
            try:
                check_limits(cand.tolist(), interference)
            except LimitExceeded as exc:
                first_error = first_error or exc
                continue
            cost = _move_cost(cand, cur)
            if cost < best_cost:
                best, best_cost = cand, cost
    if best is None:
        if first_error is not None:
            raise first_error
        raise Unreachable(UnreachableReason.OUT_OF_REACH, f"no arm configuration reaches {pose}")
    return Joints.of(best)


def _j6_candidates(q: FloatArray, fl2: int, current_j6: float, use_fl2: bool) -> list[FloatArray]:
    lo, hi = JOINT_LIMITS[5]
    if use_fl2:
        out = q.copy()
        out[5] = q[5] + 360.0 * fl2_get(fl2, 6)
        return [out]
    cands = []
    for k in (-1, 0, 1):
        c = q.copy()
        c[5] = q[5] + 360.0 * k
        if lo <= c[5] <= hi:
            cands.append(c)
    cands.sort(key=lambda c: abs(c[5] - current_j6))
    return cands[:1] if cands else [q]
