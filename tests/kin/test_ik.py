"""Inverse kinematics: round trips for every configuration, refusals."""

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from melfa.kin import (
    HOME,
    JOINT_LIMITS,
    InterferenceLimitExceeded,
    JointLimitExceeded,
    Pose,
    Unreachable,
    configuration_of,
    fk,
    fk_matrix,
    ik,
    pose_distance,
    within_limits,
)

joint_vectors = st.tuples(*(st.floats(lo, hi, allow_nan=False) for lo, hi in JOINT_LIMITS))


def _well_conditioned(q: tuple[float, ...]) -> bool:
    """Away from the wrist, elbow and shoulder singularities, where IK is unique."""
    t = fk_matrix(q)
    wrist = t[:3, 3] - 85 * t[:3, 2]
    elbow = (q[2] - 17.6) % 180
    return abs(q[4]) > 1 and 1 < elbow < 179 and np.hypot(wrist[0], wrist[1]) > 1


@settings(max_examples=150)
@given(joint_vectors)
@example((0.0, 0.0, 0.125, 1.0, -2.0, 180.0))
def test_ik_inverts_fk_with_the_pose_flags(q: tuple[float, ...]) -> None:
    assume(within_limits(q) and _well_conditioned(q))
    p = fk(q)
    # A joint at exactly ±180° has two equal answers (J6 180 and -180 are one wrist pose).
    turns = [(a - b + 180) % 360 - 180 for a, b in zip(ik(p), q, strict=True)]
    assert turns == pytest.approx([0.0] * 6, abs=1e-6)


@settings(max_examples=60)
@given(joint_vectors, joint_vectors)
def test_ik_without_flags_reaches_the_pose(q: tuple[float, ...], start: tuple[float, ...]) -> None:
    assume(within_limits(q) and _well_conditioned(q))
    p = fk(q)
    q2 = ik(p, current=start, use_fl1=False, use_fl2=False)
    dist, angle = pose_distance(fk(q2), p)
    assert dist < 1e-6
    assert angle < 1e-6
    assert within_limits(q2)


def test_every_configuration_round_trips() -> None:
    seen = set()
    for q in [
        (10, 20, 100, 30, 40, 50),  # RAN
        (10, 20, 100, 30, -40, 50),  # RAF
        (10, 40, 0, 30, 40, 50),  # RBN
        (10, 40, 0, 30, -40, 50),  # RBF
        (10, -80, 130, 30, 40, 50),  # LAN
        (10, -80, 130, 30, -40, 50),  # LAF
        (10, -40, 10, 30, 40, 50),  # LBN
        (10, -40, 10, 30, -40, 50),  # LBF
    ]:
        p = fk(q)
        seen.add(p.fl1)
        assert ik(p) == pytest.approx(q, abs=1e-6), p
    assert seen == set(range(8))


def test_flags_choose_the_branch() -> None:
    p = fk((10, 20, 100, 30, 40, 50))
    flipped = ik(p.with_flags(6))
    assert flipped[4] == pytest.approx(-40)
    assert configuration_of(flipped).fl1 == 6
    assert pose_distance(fk(flipped), p)[0] < 1e-9


def test_fl2_selects_the_j6_turn() -> None:
    p = fk((0, 0, 90, 0, 90, 30))
    assert ik(p.with_flags(7, 0x00F00000))[5] == pytest.approx(-330)


def test_fl2_turn_outside_j6_range_is_a_joint_limit() -> None:
    p = fk((0, 0, 90, 0, 90, 30))
    with pytest.raises(JointLimitExceeded) as err:
        ik(p.with_flags(7, 0x00100000))
    assert err.value.joint == 6
    assert err.value.value == pytest.approx(390)


def test_nearest_j6_turn_without_fl2() -> None:
    p = fk((0, 0, 90, 0, 90, -170))
    q = ik(p, current=(0, 0, 90, 0, 90, 170), use_fl2=False)
    assert q[5] == pytest.approx(190)


def test_out_of_reach_raises_unreachable() -> None:
    with pytest.raises(Unreachable):
        ik(Pose(2000, 0, 500, 180, 0, 180))
    with pytest.raises(Unreachable):
        ik(Pose(2000, 0, 500, 180, 0, 180), use_fl1=False)


def test_target_needing_j5_beyond_range_raises_joint_limit() -> None:
    p = fk((0, 0, 90, 0, 130, 0))  # J5 = 130 is past its ±120 range
    with pytest.raises(JointLimitExceeded) as err:
        ik(p)
    assert err.value.joint == 5
    assert err.value.value == pytest.approx(130)


def test_interference_region_is_refused() -> None:
    q = (0, -60, 60, 0, 90, 0)  # |J1| <= 75, J2 < -45, J2 + J3 = 0 < 8
    with pytest.raises(InterferenceLimitExceeded):
        ik(fk(q))


def test_tool_and_base_round_trip() -> None:
    tool = Pose(10, -20, 120, 0, 30, 0)
    base = Pose(100, 50, -10, 0, 0, 45)
    q = (15, 25, 95, -20, 60, 70)
    assert ik(fk(q, tool, base), tool=tool, base=base) == pytest.approx(q, abs=1e-6)


def test_home_round_trips() -> None:
    assert ik(fk(HOME)) == pytest.approx(HOME, abs=1e-9)


def test_wrist_singularity_keeps_current_j4() -> None:
    q = ik(fk((0, 0, 90, 0, 0, 40)), current=(0, 0, 90, 25, 0, 0))
    assert q[3] == pytest.approx(25)
    assert q[5] == pytest.approx(15)
