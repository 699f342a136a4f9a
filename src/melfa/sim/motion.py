"""Motion planning for the simulated RV-6S: pure, no clock (times are seconds from a plan's start).

A *plan* is built once, checked up front (the controller refuses a move before it starts
where it can), then sampled at any time ``t``: ``plan.sample(t) -> Joints``. Every plan has
``duration``, ``start_joints`` and ``end_joints``; ``plan.stopped(t)`` gives the decelerating
stop from ``t`` (time origin moved to ``t``).

Moves (melfa-basic-iv.md §4.1–4.2):

- `plan_joint` (MOV): every joint from its maximum speed × (OP override × OVRD × JOVRD),
  all synchronised to the slowest.
- `plan_linear` (MVS), `plan_linear_offset` (``MVS , d``): straight TCP path at SPD × (OP
  override × OVRD), orientation by slerp, never faster than the joints allow.
- `plan_arc` (MVR), `plan_arc_ref` (MVR2), `plan_arc_centre` (MVR3), `plan_circle` (MVC):
  arcs, preceded by a linear move to the arc start when the arm is elsewhere [S1].
- `plan_arch` (MVA): lift, traverse, lower.
- `close` (``MOV P1, -50``): the target shifted along its own tool Z (`approach_pose`).
- `jog_step`: one integration step of continuous JOG motion (the arm keeps the jog state).

Errors are those of `melfa.kin` (`Unreachable`, `JointLimitExceeded`,
`InterferenceLimitExceeded`) plus `IllegalMove` for impossible geometry.
"""

from __future__ import annotations

import enum
import math
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from melfa.kin import (
    DEFAULT_INTERFERENCE,
    JOINT_LIMITS,
    JOINT_MAX_SPEED,
    MAX_RESULTANT_SPEED,
    Configuration,
    Interference,
    InterferenceLimitExceeded,
    JointLimitExceeded,
    Joints,
    KinematicsError,
    Pose,
    Unreachable,
    UnreachableReason,
    check_limits,
    configuration_of,
    fk,
    fk_matrix,
    ik,
    ik_batch,
    interference_violation,
    pose_mul,
    pose_to_matrix,
    unwrap_j6,
)
from melfa.kin.pose import FloatArray, invert_transform, matrix_to_pose, rotation_angle_deg

__all__ = [
    "ACCEL_TIME_S",
    "ARCH_HEIGHT_MM",
    "SPD_DEFAULT",
    "ArcPlan",
    "Frames",
    "IllegalMove",
    "JogMode",
    "JointPlan",
    "MoveKind",
    "PathPlan",
    "Plan",
    "Profile",
    "SequencePlan",
    "Speeds",
    "Timing",
    "approach_pose",
    "jog_step",
    "plan_arc",
    "plan_arc_centre",
    "plan_arc_ref",
    "plan_arch",
    "plan_circle",
    "plan_joint",
    "plan_linear",
    "plan_linear_offset",
]

# --- tunables ([GUESS] unless marked; the controller's real values are parameters) --------

ACCEL_TIME_S = 0.2
"""[GUESS] time to reach full speed (and to stop from it) at ACCEL 100 %."""
SPD_DEFAULT = 10000.0
"""[GUESS] SPD after reset (M_NSPD); in effect "as fast as the arm goes" (9300 mm/s max)."""
ROT_SPEED_DEG_S = 180.0
"""[GUESS] orientation speed of linear/circular moves at 100 % (pure re-orientations)."""
ARCH_HEIGHT_MM = 50.0
"""[GUESS] MVA lift/lower height when no DEF ARCH shape is given."""
PATH_STEP_MM = 2.0
"""Path-check sample spacing along the TCP path (mm)."""
PATH_STEP_DEG = 1.0
"""Path-check sample spacing of the orientation (deg)."""
PATH_MIN_SAMPLES = 8
PATH_MAX_SAMPLES = 2000
SINGULAR_JUMP_DEG = 30.0
"""A joint moving more than this between two path samples means a singularity crossing."""
AT_START_MM = 0.01
AT_START_DEG = 0.01
"""Closer than this to an arc's start point counts as "already there"."""
MVS_REQUIRES_SAME_FL1 = True
"""[DOC S1 MVS] start and end structure flags of a linear move must match."""


class IllegalMove(KinematicsError):
    """The move's geometry is impossible (collinear arc points, flags changing in MVS, ...)."""


class Profile(enum.Enum):
    """Velocity profile shape in the acceleration and deceleration ramps."""

    TRAPEZOID = "trapezoid"
    SMOOTH = "smooth"
    """Cosine ramps (no step in acceleration); same durations as the trapezoid."""


class MoveKind(enum.Enum):
    JOINT = "MOV"
    LINEAR = "MVS"
    ARC = "MVR"
    CIRCLE = "MVC"
    ARCH = "MVA"
    SEQUENCE = "sequence"
    STOP = "stop"


@dataclass(frozen=True, slots=True)
class Speeds:
    """Speed settings, percentages as 1..100 and SPD in mm/s (melfa-basic-iv.md §4.2).

    Effective joint speed = OP override × OVRD × JOVRD; linear = OP override × OVRD × SPD
    [DOC S1 OVRD, JOVRD].
    """

    op_override: float = 100.0
    ovrd: float = 100.0
    jovrd: float = 100.0
    spd: float = SPD_DEFAULT
    accel: float = 100.0
    decel: float = 100.0
    profile: Profile = Profile.TRAPEZOID

    @property
    def joint_factor(self) -> float:
        """Fraction of each joint's maximum speed used by joint interpolation."""
        return self.op_override * self.ovrd * self.jovrd / 1e6

    @property
    def path_factor(self) -> float:
        """Fraction of the joints' maximum speeds available to linear/circular moves."""
        return self.op_override * self.ovrd / 1e4

    @property
    def linear_speed(self) -> float:
        """TCP speed of linear/circular moves, mm/s."""
        return min(self.spd, MAX_RESULTANT_SPEED) * self.path_factor

    @property
    def accel_time(self) -> float:
        return ACCEL_TIME_S * 100.0 / self.accel

    @property
    def decel_time(self) -> float:
        return ACCEL_TIME_S * 100.0 / self.decel


@dataclass(frozen=True, slots=True)
class Frames:
    """The active TOOL and BASE (None = identity) and which interference rows apply."""

    tool: Pose | None = None
    base: Pose | None = None
    interference: Interference = DEFAULT_INTERFERENCE

    def pose(self, joints: Sequence[float]) -> Pose:
        """TCP pose (with flags) of a joint vector."""
        return fk(joints, self.tool, self.base)

    def tcp_matrix(self, joints: Sequence[float]) -> FloatArray:
        return fk_matrix(joints, self.tool, self.base)

    def to_flange(self, tcp: FloatArray) -> FloatArray:
        """World TCP transforms (N, 4, 4) -> robot-base flange transforms."""
        out = tcp
        if self.base is not None:
            out = invert_transform(pose_to_matrix(self.base)) @ out
        if self.tool is not None:
            out = out @ invert_transform(pose_to_matrix(self.tool))
        return out


# --- timing -----------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Timing:
    """Path parameter s(t) in [0, 1]: ramp up over `t_acc`, cruise, ramp down over `t_dec`.

    `cruise_time` is what the move would take at full rate with infinite acceleration;
    with room to cruise, ``duration = cruise_time + (t_acc + t_dec) / 2``.
    """

    cruise_time: float
    t_acc: float
    t_cruise: float
    t_dec: float
    peak_rate: float
    profile: Profile = Profile.TRAPEZOID

    @classmethod
    def build(
        cls, cruise_time: float, accel_time: float, decel_time: float, profile: Profile
    ) -> Timing:
        if cruise_time <= 0.0:
            return cls(0.0, 0.0, 0.0, 0.0, 0.0, profile)
        vmax = 1.0 / cruise_time
        if (accel_time + decel_time) / 2.0 <= cruise_time:
            t_cruise = cruise_time - (accel_time + decel_time) / 2.0
            return cls(cruise_time, accel_time, t_cruise, decel_time, vmax, profile)
        a, d = vmax / accel_time, vmax / decel_time
        vp = math.sqrt(2.0 / (1.0 / a + 1.0 / d))  # triangular: never reaches vmax
        return cls(cruise_time, vp / a, 0.0, vp / d, vp, profile)

    @property
    def duration(self) -> float:
        return self.t_acc + self.t_cruise + self.t_dec

    def _ramp(self, tau: float, length: float) -> tuple[float, float]:
        """(distance, rate) after `tau` of a ramp from 0 to peak over `length`."""
        vp = self.peak_rate
        if self.profile is Profile.SMOOTH:
            x = math.pi * tau / length
            return vp * (tau / 2.0 - length / (2.0 * math.pi) * math.sin(x)), vp * (
                1.0 - math.cos(x)
            ) / 2.0
        return 0.5 * vp * tau * tau / length, vp * tau / length

    def state(self, t: float) -> tuple[float, float]:
        """(s, ds/dt) at time t, clamped to the plan."""
        if self.duration <= 0.0 or t >= self.duration:
            return 1.0, 0.0
        if t <= 0.0:
            return 0.0, 0.0
        if t < self.t_acc:
            return self._ramp(t, self.t_acc)
        s_acc = 0.5 * self.peak_rate * self.t_acc
        if t < self.t_acc + self.t_cruise:
            return s_acc + self.peak_rate * (t - self.t_acc), self.peak_rate
        rest = self.duration - t
        d, v = self._ramp(rest, self.t_dec)
        return 1.0 - d, v

    def s(self, t: float) -> float:
        return self.state(t)[0]

    @property
    def decel_rate(self) -> float:
        """ds/dt² used for stops (the plan's own deceleration)."""
        return self.peak_rate / self.t_dec if self.t_dec > 0 else math.inf


@dataclass(frozen=True, slots=True)
class _StopTiming:
    """Constant deceleration from (s0, v0) to rest."""

    s0: float
    v0: float
    decel: float

    @property
    def duration(self) -> float:
        return self.v0 / self.decel if self.decel < math.inf and self.v0 > 0 else 0.0

    def s(self, t: float) -> float:
        t = min(max(t, 0.0), self.duration)
        return min(1.0, self.s0 + self.v0 * t - 0.5 * self.decel * t * t)


# --- plans ------------------------------------------------------------------------------


class Plan(ABC):
    """A planned motion sampled at t seconds from its start (clamped to [0, duration])."""

    kind: MoveKind
    start_joints: Joints
    end_joints: Joints

    @property
    @abstractmethod
    def duration(self) -> float: ...

    @abstractmethod
    def sample(self, t: float) -> Joints:
        """Joints (deg) at t seconds after the plan started."""

    @abstractmethod
    def stopped(self, t: float) -> Plan:
        """The decelerating stop begun at t: a new plan whose time 0 is t."""


class _PathLike(Plan):
    """Plans moving along one geometric parameter s in [0, 1]."""

    timing: Timing

    @property
    def duration(self) -> float:
        return self.timing.duration

    @abstractmethod
    def at_s(self, s: float) -> Joints: ...

    def sample(self, t: float) -> Joints:
        if t >= self.timing.duration:
            return self.end_joints
        return self.at_s(self.timing.s(t))

    def stopped(self, t: float) -> Plan:
        s0, v0 = self.timing.state(t)
        return _StoppingPlan(self, _StopTiming(s0, v0, self.timing.decel_rate))


class _StoppingPlan(Plan):
    kind = MoveKind.STOP

    def __init__(self, base: _PathLike, timing: _StopTiming) -> None:
        self.base = base
        self.timing = timing
        self.start_joints = base.at_s(timing.s0)
        self.end_joints = base.at_s(timing.s(timing.duration))

    @property
    def duration(self) -> float:
        return self.timing.duration

    def sample(self, t: float) -> Joints:
        return self.end_joints if t >= self.duration else self.base.at_s(self.timing.s(t))

    def stopped(self, t: float) -> Plan:
        s = self.timing.s(t)
        v = max(0.0, self.timing.v0 - self.timing.decel * t)
        return _StoppingPlan(self.base, _StopTiming(s, v, self.timing.decel))


class JointPlan(_PathLike):
    """Joint interpolation: every joint moves proportionally, synchronised to the slowest."""

    kind = MoveKind.JOINT

    def __init__(self, start: Joints, end: Joints, timing: Timing) -> None:
        self.start_joints = start
        self.end_joints = end
        self.timing = timing
        self._q0 = np.asarray(start, dtype=float)
        self._dq = np.asarray(end, dtype=float) - self._q0

    def at_s(self, s: float) -> Joints:
        return Joints.of(self._q0 + s * self._dq)


class PathPlan(_PathLike):
    """A Cartesian path (line or arc) with joints from IK at each sample."""

    def __init__(
        self,
        kind: MoveKind,
        path: _Path,
        frames: Frames,
        config: Configuration,
        table_s: FloatArray,
        table_q: FloatArray,
        timing: Timing,
    ) -> None:
        self.kind = kind
        self.path = path
        self.frames = frames
        self.config = config
        self.table_s = table_s
        self.table_q = table_q
        self.timing = timing
        self.start_joints = Joints.of(table_q[0])
        self.end_joints = Joints.of(table_q[-1])

    def at_s(self, s: float) -> Joints:
        if s <= 0.0:
            return self.start_joints
        if s >= 1.0:
            return self.end_joints
        near = np.array([np.interp(s, self.table_s, self.table_q[:, j]) for j in range(6)])
        flange = self.frames.to_flange(self.path.at(np.array([s])))
        q = ik_batch(flange, self.config, near[0], near[3])[0]
        if np.isnan(q[0]):  # cannot happen on a checked path; fall back to the table
            return Joints.of(near)
        q[5] = unwrap_j6(q[5:6], float(near[5]))[0]
        return Joints.of(q)

    def tcp_pose(self, s: float) -> Pose:
        """The TCP pose on the path at parameter s (for tests and the 3D view)."""
        return matrix_to_pose(self.path.at(np.array([s]))[0])


ArcPlan = PathPlan


class SequencePlan(Plan):
    """Plans run one after the other (approach + arc, MVA's lift/traverse/lower)."""

    kind = MoveKind.SEQUENCE

    def __init__(self, parts: Sequence[Plan], kind: MoveKind = MoveKind.SEQUENCE) -> None:
        if not parts:
            raise ValueError("a sequence needs at least one plan")
        self.parts = tuple(parts)
        self.kind = kind
        self.start_joints = self.parts[0].start_joints
        self.end_joints = self.parts[-1].end_joints
        self._offsets = np.cumsum([0.0] + [p.duration for p in self.parts])

    @property
    def duration(self) -> float:
        return float(self._offsets[-1])

    def _locate(self, t: float) -> tuple[int, float]:
        i = int(np.searchsorted(self._offsets, t, side="right")) - 1
        i = min(max(i, 0), len(self.parts) - 1)
        return i, t - float(self._offsets[i])

    def sample(self, t: float) -> Joints:
        if t >= self.duration:
            return self.end_joints
        i, local = self._locate(t)
        return self.parts[i].sample(local)

    def stopped(self, t: float) -> Plan:
        i, local = self._locate(min(t, self.duration))
        return self.parts[i].stopped(local)


# --- geometry -----------------------------------------------------------------------------


def _log_rot(r: FloatArray) -> FloatArray:
    """Rotation vector (axis × angle, radians) of a rotation matrix."""
    cos = (float(np.trace(r)) - 1.0) / 2.0
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    sin = float(np.linalg.norm(v))
    angle = math.atan2(sin, cos)
    if sin > 1e-9:
        return np.asarray(v / sin * angle, dtype=float)
    if cos > 0:
        return np.zeros(3)
    # angle ≈ π: axis from the symmetric part
    m = (r + np.eye(3)) / 2.0
    k = int(np.argmax(np.diag(m)))
    axis = m[:, k] / math.sqrt(max(m[k, k], 1e-300))
    return np.asarray(axis / np.linalg.norm(axis) * math.pi, dtype=float)


def _exp_rot(rv: FloatArray) -> FloatArray:
    """Rotation matrices (N, 3, 3) from rotation vectors (N, 3) (Rodrigues)."""
    theta = np.linalg.norm(rv, axis=1)
    safe = np.where(theta > 1e-12, theta, 1.0)
    k = rv / safe[:, None]
    kx = np.zeros((rv.shape[0], 3, 3))
    kx[:, 0, 1], kx[:, 0, 2] = -k[:, 2], k[:, 1]
    kx[:, 1, 0], kx[:, 1, 2] = k[:, 2], -k[:, 0]
    kx[:, 2, 0], kx[:, 2, 1] = -k[:, 1], k[:, 0]
    s = np.sin(theta)[:, None, None]
    c = (1.0 - np.cos(theta))[:, None, None]
    return np.asarray(np.eye(3) + s * kx + c * (kx @ kx), dtype=float)


@dataclass(frozen=True)
class _Orientation:
    """Piecewise slerp through key rotations placed at path fractions `knots`."""

    knots: tuple[float, ...]
    rots: tuple[FloatArray, ...]
    steps: tuple[FloatArray, ...] = field(init=False)

    def __post_init__(self) -> None:
        steps = tuple(
            _log_rot(self.rots[i].T @ self.rots[i + 1]) for i in range(len(self.rots) - 1)
        )
        object.__setattr__(self, "steps", steps)

    @property
    def total_angle_deg(self) -> float:
        return math.degrees(sum(float(np.linalg.norm(s)) for s in self.steps))

    def at(self, s: FloatArray) -> FloatArray:
        out = np.empty((s.shape[0], 3, 3))
        seg = np.clip(np.searchsorted(self.knots, s, side="right") - 1, 0, len(self.steps) - 1)
        for i in np.unique(seg):
            rows = seg == i
            lo, hi = self.knots[i], self.knots[i + 1]
            f = np.clip((s[rows] - lo) / (hi - lo), 0.0, 1.0) if hi > lo else np.ones(rows.sum())
            out[rows] = self.rots[i] @ _exp_rot(f[:, None] * self.steps[i][None, :])
        return out


class _Path(ABC):
    orientation: _Orientation

    @property
    @abstractmethod
    def length(self) -> float:
        """TCP path length, mm."""

    @abstractmethod
    def positions(self, s: FloatArray) -> FloatArray: ...

    def at(self, s: FloatArray) -> FloatArray:
        """World TCP transforms (N, 4, 4) at path parameters s (N,)."""
        out = np.zeros((s.shape[0], 4, 4))
        out[:, :3, :3] = self.orientation.at(s)
        out[:, :3, 3] = self.positions(s)
        out[:, 3, 3] = 1.0
        return out


class _Line(_Path):
    def __init__(self, p0: FloatArray, p1: FloatArray, orientation: _Orientation) -> None:
        self.p0, self.p1, self.orientation = p0, p1, orientation

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.p1 - self.p0))

    def positions(self, s: FloatArray) -> FloatArray:
        return np.asarray(self.p0 + s[:, None] * (self.p1 - self.p0), dtype=float)


class _Arc(_Path):
    """Arc about `centre` in the plane (u, w), angle `sweep` (rad), radius r0 -> r1."""

    def __init__(
        self,
        centre: FloatArray,
        u: FloatArray,
        w: FloatArray,
        r0: float,
        r1: float,
        sweep: float,
        orientation: _Orientation,
    ) -> None:
        self.centre, self.u, self.w = centre, u, w
        self.r0, self.r1, self.sweep = r0, r1, sweep
        self.orientation = orientation

    @property
    def length(self) -> float:
        return (self.r0 + self.r1) / 2.0 * abs(self.sweep)

    def positions(self, s: FloatArray) -> FloatArray:
        ang = s * self.sweep
        r = self.r0 + s * (self.r1 - self.r0)
        return np.asarray(
            self.centre
            + r[:, None] * (np.cos(ang)[:, None] * self.u + np.sin(ang)[:, None] * self.w),
            dtype=float,
        )

    def fraction_of(self, point: FloatArray) -> float:
        """Path fraction at which the arc passes the direction of `point`."""
        d = point - self.centre
        ang = math.atan2(float(d @ self.w), float(d @ self.u)) % (2.0 * math.pi)
        return ang / self.sweep if self.sweep else 0.0


def _circle_through(
    p0: FloatArray, p1: FloatArray, p2: FloatArray
) -> tuple[FloatArray, FloatArray, float]:
    """(centre, unit normal, radius) of the circle through three points; normal makes
    p0 -> p1 -> p2 counter-clockwise."""
    a, b = p1 - p0, p2 - p0
    n = np.cross(a, b)
    nn = float(n @ n)
    if nn < 1e-9 * max(float(a @ a) * float(b @ b), 1e-12) or nn < 1e-12:
        raise IllegalMove("arc points are collinear or coincide: no circle through them")
    centre = p0 + (float(a @ a) * np.cross(b, n) + float(b @ b) * np.cross(n, a)) / (2.0 * nn)
    return centre, n / math.sqrt(nn), float(np.linalg.norm(p0 - centre))


def _ccw_angle(centre: FloatArray, normal: FloatArray, p0: FloatArray, p: FloatArray) -> float:
    """Angle (0, 2π] from p0 to p about `normal`."""
    u = p0 - centre
    u = u / np.linalg.norm(u)
    w = np.cross(normal, u)
    d = p - centre
    ang = math.atan2(float(d @ w), float(d @ u)) % (2.0 * math.pi)
    return ang if ang > 1e-12 else 2.0 * math.pi


# --- planning ---------------------------------------------------------------------------


def approach_pose(target: Pose, close: float) -> Pose:
    """``MOV P, d`` / ``MVS P, d``: the target moved `close` mm along its own tool Z
    (negative = retract for the default tool on a vertical arm [S4 p.55])."""
    return pose_mul(target, Pose(0.0, 0.0, close, 0.0, 0.0, 0.0))


def _target_pose(target: Pose | Joints, frames: Frames, close: float | None) -> Pose:
    pose = frames.pose(target) if isinstance(target, Joints) else target
    return approach_pose(pose, close) if close else pose


def plan_joint(
    start: Joints,
    target: Pose | Joints,
    speeds: Speeds,
    frames: Frames | None = None,
    *,
    close: float | None = None,
    shortcut: bool = False,
) -> JointPlan:
    """MOV: joint-interpolated move to a pose (configuration from its FL1, J6 turn from
    its FL2, or the nearest J6 turn when `shortcut`, TYPE 0) or to joints.

    Raises `Unreachable`, `JointLimitExceeded`, `InterferenceLimitExceeded`.
    """
    frames = frames or Frames()
    if isinstance(target, Joints) and not close:
        end = Joints.of(target)
        check_limits(end, frames.interference)
    else:
        pose = _target_pose(target, frames, close)
        end = ik(
            pose,
            start,
            frames.tool,
            frames.base,
            use_fl2=not shortcut,
            interference=frames.interference,
        )
    return JointPlan(start, end, _joint_timing(start, end, speeds))


def _joint_timing(start: Joints, end: Joints, speeds: Speeds) -> Timing:
    dq = np.abs(np.asarray(end) - np.asarray(start))
    cruise = float(np.max(dq / (np.asarray(JOINT_MAX_SPEED) * speeds.joint_factor)))
    if cruise < 1e-9:
        cruise = 0.0
    return Timing.build(cruise, speeds.accel_time, speeds.decel_time, speeds.profile)


def _check_path(
    kind: MoveKind, start: Joints, path: _Path, speeds: Speeds, frames: Frames
) -> PathPlan:
    """Sample the whole path, solve IK in one vectorised call, refuse at the first bad sample,
    and time it: TCP speed, orientation speed and every joint's speed limit."""
    length = path.length
    angle = path.orientation.total_angle_deg
    n = int(
        min(
            PATH_MAX_SAMPLES,
            max(
                PATH_MIN_SAMPLES, math.ceil(length / PATH_STEP_MM), math.ceil(angle / PATH_STEP_DEG)
            ),
        )
    )
    s = np.linspace(0.0, 1.0, n + 1)
    config = configuration_of(start)
    flange = frames.to_flange(path.at(s))
    q = ik_batch(flange, config, start[0], start[3])
    bad = np.isnan(q[:, 0])
    if bad.any():
        i = int(np.argmax(bad))
        raise Unreachable(
            UnreachableReason.OUT_OF_REACH,
            f"the path leaves the arm's reach at {_where(path, s[i])}",
        )
    q[:, 5] = unwrap_j6(q[:, 5], start[5])
    _check_table_limits(q, s, path, frames.interference)
    steps = np.abs(np.diff(q, axis=0))
    if steps.size and float(steps.max()) > SINGULAR_JUMP_DEG:
        i = int(np.argmax(steps.max(axis=1)))
        raise Unreachable(
            UnreachableReason.SINGULAR, f"the path crosses a singularity near {_where(path, s[i])}"
        )
    cruise = 0.0
    if speeds.linear_speed > 0:
        cruise = length / speeds.linear_speed
    cruise = max(cruise, angle / (ROT_SPEED_DEG_S * speeds.path_factor))
    if steps.size:
        ds = np.diff(s)
        per_joint = steps / (np.asarray(JOINT_MAX_SPEED) * speeds.path_factor)
        cruise = max(cruise, float(np.max(per_joint.max(axis=1) / ds)))
    if length < 1e-9 and angle < 1e-9:
        cruise = 0.0
    timing = Timing.build(cruise, speeds.accel_time, speeds.decel_time, speeds.profile)
    return PathPlan(kind, path, frames, config, s, q, timing)


def _where(path: _Path, s: float) -> str:
    p = path.positions(np.array([s]))[0]
    return f"({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm, {s * 100:.0f}% along the path"


def _check_table_limits(
    q: FloatArray, s: FloatArray, path: _Path, interference: Interference
) -> None:
    lo = np.array([lim[0] for lim in JOINT_LIMITS]) - 1e-6
    hi = np.array([lim[1] for lim in JOINT_LIMITS]) + 1e-6
    out = (q < lo) | (q > hi)
    if out.any():
        i = int(np.argmax(out.any(axis=1)))
        j = int(np.argmax(out[i]))
        raise JointLimitExceeded(j + 1, float(q[i, j]), JOINT_LIMITS[j])
    if interference is Interference.NONE:
        return
    for row in q:
        rule = interference_violation(row.tolist(), interference)
        if rule is not None:
            raise InterferenceLimitExceeded(rule.text, tuple(float(v) for v in row))


def _rot(p: Pose) -> FloatArray:
    return pose_to_matrix(p)[:3, :3]


def _pos(p: Pose) -> FloatArray:
    return np.array(p.xyz, dtype=float)


def plan_linear(
    start: Joints,
    target: Pose | Joints,
    speeds: Speeds,
    frames: Frames | None = None,
    *,
    close: float | None = None,
) -> PathPlan:
    """MVS: straight TCP line, orientation by slerp, configuration kept from the start.

    Raises `IllegalMove` when the target's FL1 differs from the start's [DOC S1 MVS], and the
    `melfa.kin` errors at the first bad sample.
    """
    frames = frames or Frames()
    goal = _target_pose(target, frames, close)
    here = frames.pose(start)
    if MVS_REQUIRES_SAME_FL1 and isinstance(target, Pose) and goal.fl1 != here.fl1:
        raise IllegalMove(
            f"linear move changes the structure flag FL1 from {here.fl1} to {goal.fl1}"
        )
    path = _Line(_pos(here), _pos(goal), _Orientation((0.0, 1.0), (_rot(here), _rot(goal))))
    return _check_path(MoveKind.LINEAR, start, path, speeds, frames)


def plan_linear_offset(
    start: Joints, distance: float, speeds: Speeds, frames: Frames | None = None
) -> PathPlan:
    """``MVS , d``: from the current pose `distance` mm along the tool Z axis."""
    frames = frames or Frames()
    goal = approach_pose(frames.pose(start), distance)
    return plan_linear(start, goal, speeds, frames)


def _with_approach(
    start: Joints, arc_start: Pose, speeds: Speeds, frames: Frames, build: _ArcBuilder
) -> Plan:
    here = frames.pose(start)
    d = math.dist(here.xyz, arc_start.xyz)
    ang = rotation_angle_deg(_rot(here), _rot(arc_start))
    if d <= AT_START_MM and ang <= AT_START_DEG:
        return build(start)
    approach = plan_linear(start, arc_start, speeds, frames)
    arc = build(approach.end_joints)
    return SequencePlan((approach, arc), kind=arc.kind)


class _ArcBuilder:
    def __init__(self, kind: MoveKind, path: _Path, speeds: Speeds, frames: Frames) -> None:
        self.kind, self.path, self.speeds, self.frames = kind, path, speeds, frames

    def __call__(self, start: Joints) -> PathPlan:
        return _check_path(self.kind, start, self.path, self.speeds, self.frames)


def _arc_path(
    centre: FloatArray,
    normal: FloatArray,
    p0: FloatArray,
    r1: float,
    sweep: float,
    keys: Sequence[tuple[float, Pose]],
) -> _Arc:
    u = p0 - centre
    r0 = float(np.linalg.norm(u))
    u = u / r0
    w = np.cross(normal, u)
    orient = _Orientation(tuple(k for k, _ in keys), tuple(_rot(p) for _, p in keys))
    return _Arc(centre, u, w, r0, r1, sweep, orient)


def plan_arc(
    start_joints: Joints,
    start: Pose,
    via: Pose,
    end: Pose,
    speeds: Speeds,
    frames: Frames | None = None,
) -> Plan:
    """MVR start, via, end: the arc from `start` through `via` to `end`; orientation
    interpolated start -> via -> end."""
    frames = frames or Frames()
    p0, p1, p2 = _pos(start), _pos(via), _pos(end)
    centre, normal, radius = _circle_through(p0, p1, p2)
    sweep = _ccw_angle(centre, normal, p0, p2)
    f_via = _ccw_angle(centre, normal, p0, p1) / sweep
    path = _arc_path(centre, normal, p0, radius, sweep, ((0.0, start), (f_via, via), (1.0, end)))
    return _with_approach(
        start_joints, start, speeds, frames, _ArcBuilder(MoveKind.ARC, path, speeds, frames)
    )


def plan_arc_ref(
    start_joints: Joints,
    start: Pose,
    end: Pose,
    ref: Pose,
    speeds: Speeds,
    frames: Frames | None = None,
) -> Plan:
    """MVR2 start, end, ref: the arc of the circle through the three points that goes from
    `start` to `end` *without* passing `ref`."""
    frames = frames or Frames()
    p0, p2, pr = _pos(start), _pos(end), _pos(ref)
    centre, normal, radius = _circle_through(p0, pr, p2)
    normal = -normal  # the other way round: away from ref
    sweep = _ccw_angle(centre, normal, p0, p2)
    path = _arc_path(centre, normal, p0, radius, sweep, ((0.0, start), (1.0, end)))
    return _with_approach(
        start_joints, start, speeds, frames, _ArcBuilder(MoveKind.ARC, path, speeds, frames)
    )


def plan_arc_centre(
    start_joints: Joints,
    start: Pose,
    end: Pose,
    centre: Pose,
    speeds: Speeds,
    frames: Frames | None = None,
) -> Plan:
    """MVR3 start, end, centre: the short arc (0 < angle < 180°) about `centre`. If the end
    is at a different radius, the radius changes evenly along the arc."""
    frames = frames or Frames()
    p0, p2, pc = _pos(start), _pos(end), _pos(centre)
    a, b = p0 - pc, p2 - pc
    n = np.cross(a, b)
    if float(np.linalg.norm(a)) < 1e-6 or float(np.linalg.norm(b)) < 1e-6:
        raise IllegalMove("MVR3: the start or end point is the centre")
    if float(np.linalg.norm(n)) < 1e-9 * float(np.linalg.norm(a) * np.linalg.norm(b)):
        raise IllegalMove("MVR3: start, end and centre are collinear (arc angle 0 or 180°)")
    normal = n / np.linalg.norm(n)
    sweep = _ccw_angle(pc, normal, p0, p2)
    path = _arc_path(pc, normal, p0, float(np.linalg.norm(b)), sweep, ((0.0, start), (1.0, end)))
    return _with_approach(
        start_joints, start, speeds, frames, _ArcBuilder(MoveKind.ARC, path, speeds, frames)
    )


def plan_circle(
    start_joints: Joints,
    start: Pose,
    via1: Pose,
    via2: Pose,
    speeds: Speeds,
    frames: Frames | None = None,
) -> Plan:
    """MVC start, via1, via2: the full circle start -> via1 -> via2 -> start."""
    frames = frames or Frames()
    p0, p1, p2 = _pos(start), _pos(via1), _pos(via2)
    centre, normal, radius = _circle_through(p0, p1, p2)
    sweep = 2.0 * math.pi
    f1 = _ccw_angle(centre, normal, p0, p1) / sweep
    f2 = _ccw_angle(centre, normal, p0, p2) / sweep
    keys = ((0.0, start), (f1, via1), (f2, via2), (1.0, start))
    path = _arc_path(centre, normal, p0, radius, sweep, keys)
    return _with_approach(
        start_joints, start, speeds, frames, _ArcBuilder(MoveKind.CIRCLE, path, speeds, frames)
    )


def plan_arch(
    start: Joints,
    target: Pose | Joints,
    speeds: Speeds,
    frames: Frames | None = None,
    *,
    height: float = ARCH_HEIGHT_MM,
) -> SequencePlan:
    """MVA: lift `height` mm (world +Z), joint-interpolated traverse to above the target,
    lower onto it. [GUESS] shape; the controller's comes from DEF ARCH."""
    frames = frames or Frames()
    goal = _target_pose(target, frames, None)
    here = frames.pose(start)
    up = Pose(0.0, 0.0, height, 0.0, 0.0, 0.0)
    lift = plan_linear(start, _shift(here, up), speeds, frames)
    above = _shift(goal, up)
    traverse = plan_joint(lift.end_joints, above, speeds, frames)
    lower = plan_linear(traverse.end_joints, goal, speeds, frames)
    return SequencePlan((lift, traverse, lower), kind=MoveKind.ARCH)


def _shift(p: Pose, d: Pose) -> Pose:
    return replace(p, x=p.x + d.x, y=p.y + d.y, z=p.z + d.z)


# --- jog ------------------------------------------------------------------------------------


class JogMode(enum.Enum):
    """JOG command modes [DOC S1 §5.2.59]; value = the protocol's mode number."""

    JOINT = 0
    XYZ = 1
    TOOL = 2
    XYZ3 = 4
    CYLINDRICAL = 5


JOG_JOINT_FRACTION = 0.1
"""[GUESS] joint jog at 100 % OP override runs at this fraction of each joint's max speed."""
JOG_LINEAR_MM_S = 250.0
"""[GUESS] XYZ/tool jog TCP speed at 100 % OP override (the usual T/B safety ceiling)."""
JOG_ROT_DEG_S = 40.0
"""[GUESS] A/B/C jog speed at 100 % OP override."""


def jog_step(
    joints: Joints,
    mode: JogMode,
    directions: Sequence[int],
    dt: float,
    op_override: float,
    frames: Frames | None = None,
) -> Joints:
    """Joints after jogging `dt` seconds from `joints` (directions -1/0/+1 per axis).

    Joint jog stops each joint at its range end. XYZ/TOOL jog keeps the configuration and
    raises the `melfa.kin` errors when the step leaves the operating range; the caller
    stops there. XYZ3 and CYLINDRICAL are not simulated (`ValueError`).
    """
    frames = frames or Frames()
    dirs = np.zeros(6)
    dirs[: min(6, len(directions))] = np.sign(np.asarray(directions[:6], dtype=float))
    k = op_override / 100.0
    if mode is JogMode.JOINT:
        q = np.asarray(joints) + dirs * np.asarray(JOINT_MAX_SPEED) * JOG_JOINT_FRACTION * k * dt
        lo = np.array([lim[0] for lim in JOINT_LIMITS])
        hi = np.array([lim[1] for lim in JOINT_LIMITS])
        return Joints.of(np.clip(q, lo, hi))
    if mode not in (JogMode.XYZ, JogMode.TOOL):
        raise ValueError(f"jog mode {mode.name} is not simulated")
    here = frames.pose(joints)
    dp = dirs[:3] * JOG_LINEAR_MM_S * k * dt
    da = dirs[3:] * JOG_ROT_DEG_S * k * dt
    if mode is JogMode.XYZ:
        t = pose_to_matrix(here)
        t[:3, 3] += dp
        # A/B/C jog turns about the world axes, keeping the TCP in place.
        rot = pose_to_matrix(Pose(0.0, 0.0, 0.0, float(da[0]), float(da[1]), float(da[2])))[:3, :3]
        t[:3, :3] = rot @ t[:3, :3]
        goal = matrix_to_pose(t, here.fl1, here.fl2)
    else:
        x, y, z = (float(v) for v in dp)
        a, b, c = (float(v) for v in da)
        delta = Pose(x, y, z, a, b, c)
        goal = pose_mul(here, delta)
    return ik(
        goal,
        joints,
        frames.tool,
        frames.base,
        use_fl2=False,
        interference=frames.interference,
    )
