"""A/B/C angles and position arithmetic (melfa-basic-iv.md §7)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.kin import (
    Pose,
    abc_to_matrix,
    matrix_to_abc,
    pose_add,
    pose_distance,
    pose_div,
    pose_inv,
    pose_mul,
    pose_sub,
    pose_to_matrix,
    wrap_deg,
)

angles = st.floats(-180, 180, allow_nan=False)
coords = st.floats(-1000, 1000, allow_nan=False)
poses = st.builds(Pose, coords, coords, coords, angles, angles, angles)


def _close(p: Pose, q: Pose) -> bool:
    d, ang = pose_distance(p, q)
    return d < 1e-6 and ang < 1e-6


def test_abc_order_is_rz_ry_rx() -> None:
    a, b, c = 10.0, 20.0, 30.0

    def rx(t: float) -> np.ndarray:
        t = math.radians(t)
        return np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])

    def ry(t: float) -> np.ndarray:
        t = math.radians(t)
        return np.array([[math.cos(t), 0, math.sin(t)], [0, 1, 0], [-math.sin(t), 0, math.cos(t)]])

    def rz(t: float) -> np.ndarray:
        t = math.radians(t)
        return np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])

    assert abc_to_matrix(a, b, c) == pytest.approx(rz(c) @ ry(b) @ rx(a))


@given(angles, st.floats(-89.9, 89.9), angles)
def test_matrix_to_abc_round_trips(a: float, b: float, c: float) -> None:
    a2, b2, c2 = matrix_to_abc(abc_to_matrix(a, b, c))
    assert abc_to_matrix(a2, b2, c2) == pytest.approx(abc_to_matrix(a, b, c), abs=1e-9)
    assert b2 == pytest.approx(b, abs=1e-6)


def test_gimbal_lock_still_gives_the_same_rotation() -> None:
    r = abc_to_matrix(30, 90, 10)
    assert abc_to_matrix(*matrix_to_abc(r)) == pytest.approx(r, abs=1e-9)


def test_mul_moves_along_the_tool_axes() -> None:
    hand_down = Pose(400, 0, 645, 180, 0, 180)
    up = pose_mul(hand_down, Pose(0, 0, -50, 0, 0, 0))
    assert up.xyz == pytest.approx((400, 0, 695))
    assert (up.fl1, up.fl2) == (7, 0)


@given(poses, poses)
def test_div_undoes_mul(p1: Pose, p2: Pose) -> None:
    assert _close(pose_div(pose_mul(p1, p2), p2), p1)


@given(poses)
def test_inverse_times_pose_is_identity(p: Pose) -> None:
    ident = pose_to_matrix(pose_mul(pose_inv(p), p))
    assert ident == pytest.approx(np.eye(4), abs=1e-9)
    assert _close(pose_inv(pose_inv(p)), p)


@given(poses, poses)
def test_add_and_sub_are_elementwise_inverses(p1: Pose, p2: Pose) -> None:
    s = pose_sub(pose_add(p1, p2), p2)
    assert (s.x, s.y, s.z, s.a, s.b, s.c) == pytest.approx(
        (p1.x, p1.y, p1.z, p1.a, p1.b, p1.c), abs=1e-9
    )


def test_add_keeps_left_flags_and_extra_axes() -> None:
    r = pose_add(Pose(1, 2, 3, 0, 0, 170, fl1=6, fl2=5, l1=1.0), Pose(0, 0, 0, 0, 0, 20))
    assert r.c == 190
    assert (r.fl1, r.fl2, r.l1, r.l2) == (6, 5, 1.0, None)


def test_str_is_the_controller_form() -> None:
    assert str(Pose(400.126, 0, 644.62, 180, 0, 180)) == (
        "(+400.13,+0.00,+644.62,+180.00,+0.00,+180.00)(7,0)"
    )


@given(st.floats(-1e4, 1e4, allow_nan=False))
def test_wrap_deg_range(x: float) -> None:
    w = wrap_deg(x)
    assert -180 < w <= 180
    assert math.isclose(math.cos(math.radians(w)), math.cos(math.radians(x)), abs_tol=1e-9)
