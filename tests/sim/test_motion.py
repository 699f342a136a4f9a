"""Motion planning: timing from joint speeds and overrides, paths, arcs, refusals."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.kin import (
    HOME,
    JOINT_MAX_SPEED,
    JointLimitExceeded,
    Joints,
    KinematicsError,
    Pose,
    Unreachable,
    fk,
    fk_matrix,
    pose_distance,
)
from melfa.sim.motion import (
    ACCEL_TIME_S,
    JogMode,
    Speeds,
    approach_pose,
    jog_step,
    plan_arc,
    plan_arc_centre,
    plan_arc_ref,
    plan_arch,
    plan_circle,
    plan_joint,
    plan_linear,
    plan_linear_offset,
)
from melfa.sim.paths import IllegalMove
from melfa.sim.plans import Frames, PathPlan, Plan, SequencePlan
from melfa.sim.timing import Profile, Timing

HOME_POSE = fk(HOME)  # (400, 0, 645, 180, 0, 180)


def at(x: float, y: float, z: float) -> Pose:
    """A hand-down pose (same orientation as home)."""
    return Pose(x, y, z, HOME_POSE.a, HOME_POSE.b, HOME_POSE.c)


def tcp(plan_joints: Joints) -> np.ndarray:
    return fk_matrix(plan_joints)[:3, 3]


# --- timing ---------------------------------------------------------------------------


@pytest.mark.parametrize("profile", list(Profile))
def test_timing_is_monotonic_from_0_to_1(profile: Profile) -> None:
    for cruise in (0.05, 1.0):
        tm = Timing.build(cruise, 0.2, 0.3, profile)
        ts = np.linspace(0, tm.duration, 101)
        s = [tm.s(t) for t in ts]
        assert s[0] == 0.0
        assert s[-1] == pytest.approx(1.0)
        assert all(b >= a - 1e-12 for a, b in itertools.pairwise(s))


def test_trapezoid_duration_adds_half_the_ramps() -> None:
    tm = Timing.build(1.0, 0.2, 0.4, Profile.TRAPEZOID)
    assert tm.duration == pytest.approx(1.3)
    assert tm.s(0.2) == pytest.approx(0.1)  # half the ramp time at full rate


def test_short_move_never_reaches_full_rate() -> None:
    tm = Timing.build(0.05, 0.2, 0.2, Profile.TRAPEZOID)
    assert tm.t_cruise == 0.0
    assert tm.peak_rate < 1 / 0.05
    assert tm.s(tm.duration / 2) == pytest.approx(0.5)


def test_smooth_and_trapezoid_take_the_same_time() -> None:
    a = Timing.build(0.7, 0.2, 0.2, Profile.TRAPEZOID)
    b = Timing.build(0.7, 0.2, 0.2, Profile.SMOOTH)
    assert a.duration == pytest.approx(b.duration)
    assert a.s(0.1) != pytest.approx(b.s(0.1))


# --- joint moves ------------------------------------------------------------------------


def test_mov_time_follows_the_slowest_joint() -> None:
    target = Joints(80.2, 10, 90, 0, 90, 0)  # J1 needs 0.2 s at 401 deg/s, J2 0.031 s
    plan = plan_joint(HOME, target, Speeds())
    assert plan.timing.cruise_time == pytest.approx(80.2 / JOINT_MAX_SPEED[0])
    assert plan.duration == pytest.approx(80.2 / 401 + ACCEL_TIME_S)
    mid = plan.sample(plan.duration / 2)
    # every joint is at the same fraction of its travel: synchronised
    assert mid.j1 / 80.2 == pytest.approx(mid.j2 / 10)
    assert plan.sample(plan.duration) == target


def test_overrides_multiply_and_halving_doubles_the_time() -> None:
    target = Joints(0, 0, 90, 0, 90, 300)  # J6 is the slowest
    full = plan_joint(HOME, target, Speeds()).timing.cruise_time
    assert full == pytest.approx(300 / 660)
    for speeds in (Speeds(ovrd=50), Speeds(jovrd=50), Speeds(op_override=50)):
        assert plan_joint(HOME, target, speeds).timing.cruise_time == pytest.approx(2 * full)
    quarter = Speeds(op_override=50, ovrd=50)
    assert plan_joint(HOME, target, quarter).timing.cruise_time == pytest.approx(4 * full)


def test_accel_percent_stretches_the_ramps() -> None:
    target = Joints(0, 0, 90, 0, 90, 300)  # cruise 0.45 s leaves room for 0.4 s ramps
    fast = plan_joint(HOME, target, Speeds())
    slow = plan_joint(HOME, target, Speeds(accel=50, decel=50))
    assert slow.duration - fast.duration == pytest.approx(ACCEL_TIME_S)


def test_mov_to_a_pose_uses_its_flags() -> None:
    target = fk((20, 10, 100, 30, 40, 30))
    plan = plan_joint(HOME, target, Speeds())
    assert plan.end_joints == pytest.approx((20, 10, 100, 30, 40, 30), abs=1e-6)
    flipped = plan_joint(HOME, target.with_flags(6), Speeds())
    assert flipped.end_joints.j5 == pytest.approx(-40)


def test_mov_close_distance_offsets_along_tool_z() -> None:
    target = at(400, 100, 400)
    plan = plan_joint(HOME, target, Speeds(), close=-50)
    assert tcp(plan.end_joints) == pytest.approx((400, 100, 450), abs=1e-6)  # hand down: up


def test_mov_to_joints_outside_range_is_refused() -> None:
    with pytest.raises(JointLimitExceeded) as err:
        plan_joint(HOME, Joints(0, 0, 90, 0, 125, 0), Speeds())
    assert err.value.joint == 5


def test_zero_move_takes_no_time() -> None:
    assert plan_joint(HOME, HOME, Speeds()).duration == 0.0


# --- linear moves -------------------------------------------------------------------------


def _distance_to_line(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    d = (b - a) / np.linalg.norm(b - a)
    v = p - a
    return float(np.linalg.norm(v - (v @ d) * d))


def test_mvs_keeps_the_tcp_on_the_straight_line() -> None:
    goal = at(300, 250, 450)
    plan = plan_linear(HOME, goal, Speeds(spd=200))
    a, b = np.array(HOME_POSE.xyz), np.array(goal.xyz)
    for t in np.linspace(0, plan.duration, 37):
        q = plan.sample(float(t))
        assert _distance_to_line(tcp(q), a, b) < 1e-6
        assert pose_distance(fk(q), goal)[1] < 1e-6  # orientation held
    assert tcp(plan.end_joints) == pytest.approx(b, abs=1e-6)


def test_mvs_time_is_length_over_speed() -> None:
    goal = at(400, 200, 645)
    plan = plan_linear(HOME, goal, Speeds(spd=100))
    assert plan.timing.cruise_time == pytest.approx(2.0)
    half = plan_linear(HOME, goal, Speeds(spd=100, ovrd=50))
    assert half.timing.cruise_time == pytest.approx(4.0)


def test_mvs_interpolates_orientation() -> None:
    goal = Pose(400, 0, 645, 180, 0, 120)  # turn C by 60 degrees in place
    plan = plan_linear(HOME, goal, Speeds())
    mid = fk(plan.at_s(0.5))
    assert mid.xyz == pytest.approx(HOME_POSE.xyz, abs=1e-6)
    assert pose_distance(mid, Pose(400, 0, 645, 180, 0, 150))[1] < 1e-6


def test_mvs_is_slowed_by_joint_speeds() -> None:
    goal = at(400, 300, 645)
    plan = plan_linear(HOME, goal, Speeds(spd=9000))
    q = plan.table_q
    dt = np.diff(plan.table_s) * plan.timing.cruise_time
    rates = np.abs(np.diff(q, axis=0)) / dt[:, None]
    assert np.all(rates <= np.asarray(JOINT_MAX_SPEED) * (1 + 1e-9))
    assert plan.timing.cruise_time > 300 / 9000


def test_mvs_out_of_reach_is_refused_up_front() -> None:
    with pytest.raises(Unreachable):
        plan_linear(HOME, at(400, 0, 1500), Speeds())


def test_mvs_path_through_a_joint_limit_names_the_joint() -> None:
    start = Joints(0, 0, 90, 0, 90, 350)
    goal = fk(start)
    turned = Pose(goal.x, goal.y, goal.z, goal.a, goal.b, goal.c - 30, goal.fl1, goal.fl2)
    with pytest.raises(JointLimitExceeded) as err:
        plan_linear(start, turned, Speeds())
    assert err.value.joint == 6


def test_mvs_refuses_a_change_of_structure_flag() -> None:
    with pytest.raises(IllegalMove, match="FL1"):
        plan_linear(HOME, at(400, 100, 600).with_flags(6), Speeds())


def test_mvs_offset_moves_along_tool_z() -> None:
    plan = plan_linear_offset(HOME, 50, Speeds())
    assert tcp(plan.end_joints) == pytest.approx((400, 0, 595), abs=1e-6)  # hand down: +Z is down
    assert fk(plan.end_joints).xyz == pytest.approx(approach_pose(HOME_POSE, 50).xyz, abs=1e-6)


def test_mvs_with_tool_moves_the_tcp_straight() -> None:
    frames = Frames(tool=Pose(0, 0, 100, 0, 0, 0))
    here = frames.pose(HOME)
    goal = Pose(here.x + 100, here.y - 100, here.z, here.a, here.b, here.c)
    plan = plan_linear(HOME, goal, Speeds(), frames)
    a, b = np.array(here.xyz), np.array(goal.xyz)
    for s in np.linspace(0, 1, 11):
        p = np.array(frames.pose(plan.at_s(float(s))).xyz)
        assert _distance_to_line(p, a, b) < 1e-6


def test_crossing_the_shoulder_is_refused() -> None:
    with pytest.raises(KinematicsError):
        plan_linear(HOME, at(-300, 0, 645), Speeds())


# --- arcs -----------------------------------------------------------------------------------


def _samples(plan: Plan, n: int = 200) -> list[np.ndarray]:
    return [tcp(plan.sample(float(t))) for t in np.linspace(0, plan.duration, n)]


def test_mvc_goes_round_and_returns_to_start() -> None:
    start, v1, v2 = at(400, 0, 500), at(450, 50, 500), at(500, 0, 500)
    plan = plan_circle(HOME, start, v1, v2, Speeds(spd=200))
    assert isinstance(plan, SequencePlan)  # approach to the start first
    circle = plan.parts[-1]
    assert isinstance(circle, PathPlan)
    assert tcp(circle.start_joints) == pytest.approx(start.xyz, abs=1e-6)
    assert tcp(circle.end_joints) == pytest.approx(start.xyz, abs=1e-6)
    centre = np.array([450, 0, 500])
    pts = [tcp(circle.sample(float(t))) for t in np.linspace(0, circle.duration, 50)]
    assert all(abs(np.linalg.norm(p - centre) - 50) < 1e-6 for p in pts)
    assert max(p[1] for p in pts) == pytest.approx(50, abs=0.5)  # went through y = +50
    assert min(p[1] for p in pts) == pytest.approx(-50, abs=0.5)  # and round the far side
    assert circle.timing.cruise_time == pytest.approx(2 * math.pi * 50 / 200)


def test_mvr_passes_the_via_point() -> None:
    start = HOME_POSE
    via, end = at(450, 50, 645), at(500, 0, 645)
    plan = plan_arc(HOME, start, via, end, Speeds(spd=100))
    pts = _samples(plan, 400)
    assert min(np.linalg.norm(p - np.array(via.xyz)) for p in pts) < 0.5
    assert pts[-1] == pytest.approx(end.xyz, abs=1e-6)
    assert all(p[1] >= -1e-6 for p in pts)  # the half through via, not the other half


def test_mvr2_avoids_the_reference_point() -> None:
    ref, end = at(450, 50, 645), at(500, 0, 645)
    plan = plan_arc_ref(HOME, HOME_POSE, end, ref, Speeds(spd=100))
    pts = _samples(plan)
    assert all(p[1] <= 1e-6 for p in pts)  # went round the y < 0 side
    assert min(p[1] for p in pts) == pytest.approx(-50, abs=0.5)
    assert pts[-1] == pytest.approx(end.xyz, abs=1e-6)


def test_mvr3_keeps_the_radius_about_the_centre() -> None:
    centre, end = at(450, 0, 645), at(450, 50, 645)
    plan = plan_arc_centre(HOME, HOME_POSE, end, centre, Speeds(spd=100))
    for p in _samples(plan, 50):
        assert np.linalg.norm(p - np.array(centre.xyz)) == pytest.approx(50, abs=1e-6)
    assert tcp(plan.end_joints) == pytest.approx(end.xyz, abs=1e-6)
    assert isinstance(plan, PathPlan)  # already at the start: no approach move
    assert plan.timing.cruise_time == pytest.approx(math.pi / 2 * 50 / 100)


def test_collinear_arc_points_are_illegal() -> None:
    with pytest.raises(IllegalMove):
        plan_arc(HOME, HOME_POSE, at(450, 0, 645), at(500, 0, 645), Speeds())
    with pytest.raises(IllegalMove):
        plan_arc_centre(HOME, HOME_POSE, at(500, 0, 645), at(450, 0, 645), Speeds())


def test_mva_lifts_traverses_and_lowers() -> None:
    goal = at(400, 200, 600)
    plan = plan_arch(HOME, goal, Speeds(), height=80)
    pts = _samples(plan, 300)
    assert max(p[2] for p in pts) == pytest.approx(645 + 80, abs=0.5)
    assert pts[-1] == pytest.approx(goal.xyz, abs=1e-6)
    lift, _traverse, lower = plan.parts
    assert tcp(lift.end_joints) == pytest.approx((400, 0, 725), abs=1e-6)
    assert tcp(lower.start_joints) == pytest.approx((400, 200, 680), abs=1e-6)


# --- stops and jog ----------------------------------------------------------------------------


def test_stop_decelerates_and_ends_short_of_the_target() -> None:
    target = Joints(150, 0, 90, 0, 90, 0)
    plan = plan_joint(HOME, target, Speeds())
    t = plan.duration / 2
    stop = plan.stopped(t)
    assert stop.start_joints == pytest.approx(plan.sample(t))
    assert 0 < stop.duration <= ACCEL_TIME_S + 1e-9
    assert plan.sample(t).j1 < stop.end_joints.j1 < 150
    assert stop.sample(stop.duration + 1) == stop.end_joints


def test_joint_jog_moves_at_jog_speed_and_stops_at_the_limit() -> None:
    q = jog_step(HOME, JogMode.JOINT, (1, 0, 0, 0, 0, -1), 0.1, 100)
    assert q.j1 == pytest.approx(0.1 * 401 * 0.1)
    assert q.j6 == pytest.approx(-0.1 * 660 * 0.1)
    edge = jog_step(Joints(169.9, 0, 90, 0, 90, 0), JogMode.JOINT, (1,), 1.0, 100)
    assert edge.j1 == 170


def test_xyz_jog_moves_the_tcp_along_world_x() -> None:
    q = jog_step(HOME, JogMode.XYZ, (1, 0, 0, 0, 0, 0), 0.1, 50)
    assert tcp(q) == pytest.approx((400 + 250 * 0.5 * 0.1, 0, 645), abs=1e-6)


def test_tool_jog_moves_along_tool_z() -> None:
    q = jog_step(HOME, JogMode.TOOL, (0, 0, 1, 0, 0, 0), 0.1, 100)
    assert tcp(q) == pytest.approx((400, 0, 645 - 25), abs=1e-6)  # hand down: tool Z is down


@settings(max_examples=30)
@given(
    st.tuples(st.floats(-60, 60), st.floats(-20, 40), st.floats(60, 120), st.floats(-90, 90)),
    st.tuples(*(st.floats(-150, 150) for _ in range(3))),
)
def test_mvs_samples_lie_on_the_line_whenever_the_move_is_accepted(
    q: tuple[float, float, float, float], offset: tuple[float, float, float]
) -> None:
    start = Joints(q[0], q[1], q[2], q[3], 60, 0)
    here = fk(start)
    goal = Pose(
        here.x + offset[0],
        here.y + offset[1],
        here.z + offset[2],
        here.a,
        here.b,
        here.c,
        here.fl1,
        here.fl2,
    )
    try:
        plan = plan_linear(start, goal, Speeds(spd=500))
    except KinematicsError:
        return  # refused up front: nothing moved
    a, b = np.array(here.xyz), np.array(goal.xyz)
    assert plan.start_joints == pytest.approx(start, abs=1e-6)
    for t in np.linspace(0, plan.duration, 9):
        p = tcp(plan.sample(float(t)))
        if np.linalg.norm(b - a) > 1e-6:
            assert _distance_to_line(p, a, b) < 1e-6
    assert tcp(plan.end_joints) == pytest.approx(b, abs=1e-6)


def test_sample_many_gives_what_sample_gives_at_each_time() -> None:
    """The batched sampling pre-flight reads (one IK call per path) against `sample`."""
    a = Pose(400, -150, 300, 180, 0, 180)
    b = Pose(420, 150, 380, 180, 0, 150)
    start = plan_joint(HOME, a, Speeds()).end_joints
    plans: list[Plan] = [
        plan_joint(HOME, b, Speeds()),
        plan_linear(start, b, Speeds()),
        plan_arch(start, b, Speeds()),
    ]
    plans.append(plans[1].stopped(plans[1].duration / 3))
    for plan in plans:
        ts = np.linspace(-0.1, plan.duration + 0.1, 37)
        many = plan.sample_many(ts)
        one = np.array([tuple(plan.sample(float(t))) for t in ts])
        assert many.shape == (37, 6)
        assert many == pytest.approx(one, abs=1e-9), type(plan).__name__
