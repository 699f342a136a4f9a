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

The plans are `melfa.sim.plans`, their timing `melfa.sim.timing`, the Cartesian paths
`melfa.sim.paths`; this module decides which plan a move is, with which speed, and checks it.

Errors are those of `melfa.kin` (`Unreachable`, `JointLimitExceeded`,
`InterferenceLimitExceeded`) plus `IllegalMove` for impossible geometry.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from melfa.kin import (
    JOINT_LIMITS,
    JOINT_MAX_SPEED,
    MAX_RESULTANT_SPEED,
    Interference,
    InterferenceLimitExceeded,
    JointLimitExceeded,
    Joints,
    Pose,
    Unreachable,
    UnreachableReason,
    check_limits,
    configuration_of,
    ik,
    ik_batch,
    interference_violation,
    pose_mul,
    pose_to_matrix,
    unwrap_j6,
)
from melfa.kin.pose import FloatArray, matrix_to_pose, rotation_angle_deg
from melfa.protocol.jog import JogMode
from melfa.sim.paths import (
    Arc,
    IllegalMove,
    Line,
    Orientation,
    Path,
    ccw_angle,
    circle_through,
)
from melfa.sim.plans import Frames, JointPlan, MoveKind, PathPlan, Plan, SequencePlan
from melfa.sim.timing import Profile, Timing

__all__ = [
    "ACCEL_TIME_S",
    "ARCH_HEIGHT_MM",
    "SPD_DEFAULT",
    "JogMode",
    "Speeds",
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
    kind: MoveKind, start: Joints, path: Path, speeds: Speeds, frames: Frames
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


def _where(path: Path, s: float) -> str:
    p = path.positions(np.array([s]))[0]
    return f"({p[0]:.1f}, {p[1]:.1f}, {p[2]:.1f}) mm, {s * 100:.0f}% along the path"


def _check_table_limits(
    q: FloatArray, s: FloatArray, path: Path, interference: Interference
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
    path = Line(_pos(here), _pos(goal), Orientation((0.0, 1.0), (_rot(here), _rot(goal))))
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
    def __init__(self, kind: MoveKind, path: Path, speeds: Speeds, frames: Frames) -> None:
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
) -> Arc:
    u = p0 - centre
    r0 = float(np.linalg.norm(u))
    u = u / r0
    w = np.cross(normal, u)
    orient = Orientation(tuple(k for k, _ in keys), tuple(_rot(p) for _, p in keys))
    return Arc(centre, u, w, r0, r1, sweep, orient)


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
    centre, normal, radius = circle_through(p0, p1, p2)
    sweep = ccw_angle(centre, normal, p0, p2)
    f_via = ccw_angle(centre, normal, p0, p1) / sweep
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
    centre, normal, radius = circle_through(p0, pr, p2)
    normal = -normal  # the other way round: away from ref
    sweep = ccw_angle(centre, normal, p0, p2)
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
    sweep = ccw_angle(pc, normal, p0, p2)
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
    centre, normal, radius = circle_through(p0, p1, p2)
    sweep = 2.0 * math.pi
    f1 = ccw_angle(centre, normal, p0, p1) / sweep
    f2 = ccw_angle(centre, normal, p0, p2) / sweep
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
