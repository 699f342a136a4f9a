"""Forward kinematics against the check values of rv6s.md §4.1."""

import numpy as np
import pytest

from melfa.kin import HOME, Pose, fk, fk_matrix, structure_flags


@pytest.mark.parametrize(
    ("joints", "xyz"),
    [
        ((0, 0, 90, 0, 0, 0), (485, 0, 730)),
        ((0, 0, 90, 0, 90, 0), (400, 0, 645)),
        ((0, 0, 0, 0, 0, 0), (-15, 0, 1030)),
    ],
)
def test_flange_position_check_values(joints: tuple[float, ...], xyz: tuple[float, ...]) -> None:
    assert fk_matrix(joints)[:3, 3] == pytest.approx(xyz, abs=1e-9)


def test_tool_z_points_along_x_with_forearm_horizontal() -> None:
    assert fk_matrix((0, 0, 90, 0, 0, 0))[:3, 2] == pytest.approx((1, 0, 0), abs=1e-12)


def test_hand_down_home_is_180_0_180_with_default_flags() -> None:
    p = fk(HOME)
    assert fk_matrix(HOME)[:3, :3] == pytest.approx(np.diag([-1.0, 1.0, -1.0]), abs=1e-12)
    assert (p.x, p.y, p.z) == pytest.approx((400, 0, 645))
    assert abs(p.a) == pytest.approx(180)
    assert p.b == pytest.approx(0, abs=1e-9)
    assert abs(p.c) == pytest.approx(180)
    assert (p.fl1, p.fl2) == (7, 0)


def test_zero_pose_points_up_with_identity_rotation() -> None:
    assert fk_matrix((0, 0, 0, 0, 0, 0))[:3, :3] == pytest.approx(np.eye(3), abs=1e-12)


def test_j1_rotates_the_flange_about_the_vertical_axis() -> None:
    p = fk((90, 0, 90, 0, 90, 0))
    assert (p.x, p.y, p.z) == pytest.approx((0, 400, 645), abs=1e-9)


def test_tool_offsets_the_tcp_along_the_flange_z_axis() -> None:
    p = fk(HOME, tool=Pose(0, 0, 100, 0, 0, 0))
    assert (p.x, p.y, p.z) == pytest.approx((400, 0, 545), abs=1e-9)


def test_base_shifts_the_world_frame() -> None:
    p = fk(HOME, base=Pose(1000, 0, 0, 0, 0, 90))
    assert (p.x, p.y, p.z) == pytest.approx((1000, 400, 645), abs=1e-9)


@pytest.mark.parametrize(
    ("joints", "fl1"),
    [
        ((0, 0, 90, 0, 90, 0), 7),  # R A N
        ((0, 0, 90, 0, -90, 0), 6),  # R A F: J5 < 0 flips
        ((0, 0, 10, 0, 90, 0), 5),  # R B N: elbow past the J2-J3 line
        ((0, -80, 130, 0, 90, 0), 3),  # L A N: wrist behind the J1 axis
    ],
)
def test_structure_flags(joints: tuple[float, ...], fl1: int) -> None:
    assert structure_flags(joints)[0] == fl1


def test_fl2_counts_j6_turns() -> None:
    assert structure_flags((0, 0, 90, 0, 90, 200))[1] == 0x00100000
    assert structure_flags((0, 0, 90, 0, 90, -200))[1] == 0x00F00000
    assert structure_flags((0, 0, 90, 0, 90, 180))[1] == 0
