"""Joint ranges, interference limits, FL2 helpers."""

import pytest

from melfa.kin import (
    HOME,
    Configuration,
    Interference,
    InterferenceLimitExceeded,
    JointLimitExceeded,
    check_limits,
    fl2_get,
    fl2_set,
    turns_for_angle,
    within_limits,
)


@pytest.mark.parametrize(
    ("joints", "joint"),
    [
        ((171, 0, 90, 0, 90, 0), 1),
        ((0, -93, 90, 0, 90, 0), 2),
        ((0, 0, 167, 0, 90, 0), 3),
        ((0, 0, 90, -161, 90, 0), 4),
        ((0, 0, 90, 0, 121, 0), 5),
        ((0, 0, 90, 0, 90, 361), 6),
    ],
)
def test_each_joint_range(joints: tuple[float, ...], joint: int) -> None:
    with pytest.raises(JointLimitExceeded) as err:
        check_limits(joints)
    assert err.value.joint == joint
    assert err.value.value == joints[joint - 1]


def test_limits_are_inclusive() -> None:
    check_limits((170, 0, 90, 160, 120, 360))
    check_limits((-170, 0, 90, -160, -120, -360))


@pytest.mark.parametrize(
    "joints",
    [
        (0, 0, -105, 0, 90, 0),  # -45<=J2<15: J2 + 2 J3 = -210
        (0, -60, 60, 0, 90, 0),  # |J1|<=75, J2<-45: J2 + J3 = 0
        (80, -60, 10, 0, 90, 0),  # |J1|>75, J2<-45: J2 + J3 = -50
        (0, 125, -50, 0, 90, 0),  # J2 >= 123: J3 = -50
    ],
)
def test_trusted_interference_rows(joints: tuple[float, ...]) -> None:
    with pytest.raises(InterferenceLimitExceeded):
        check_limits(joints)
    check_limits(joints, Interference.NONE)


def test_garbled_rows_only_with_all() -> None:
    q = (120, 0, 90, 0, 90, 0)  # J1 > 95 needs J2 >= 110 in the garbled row
    check_limits(q)
    assert not within_limits(q, Interference.ALL)
    with pytest.raises(InterferenceLimitExceeded):
        check_limits(q, Interference.ALL)


def test_home_is_within_all_limits() -> None:
    assert within_limits(HOME, Interference.ALL)


def test_fl1_letters_and_bits() -> None:
    assert Configuration.from_fl1(7).letters == "RAN"
    assert Configuration.from_fl1(0).letters == "LBF"
    assert all(Configuration.from_fl1(v).fl1 == v for v in range(8))


def test_fl2_nibbles() -> None:
    assert fl2_get(15728640, 6) == -1  # [TRACE S10] PPOSF flags 6,15728640
    assert fl2_set(0, 6, 1) == 1048576
    assert fl2_get(fl2_set(fl2_set(0, 1, -2), 6, 3), 1) == -2
    with pytest.raises(ValueError, match="outside"):
        fl2_set(0, 6, 8)


@pytest.mark.parametrize(
    ("angle", "turns"), [(0, 0), (180, 0), (-180, 0), (180.5, 1), (540, 1), (541, 2), (-541, -2)]
)
def test_turns_for_angle(angle: float, turns: int) -> None:
    assert turns_for_angle(angle) == turns
