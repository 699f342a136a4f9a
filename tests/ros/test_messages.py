"""Snapshots → ROS message values: units, names, the quaternion of A/B/C, the thesis's
strings."""

from __future__ import annotations

import datetime as dt
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.kin.pose import abc_to_matrix
from melfa.ros.messages import (
    JOINT_STATE_NAMES,
    Stamp,
    StreamMessages,
    format_joint_state,
    format_tool_pose,
    quaternion_from_abc,
)
from melfa.service import StateSnapshot
from melfa.service.thesis import format_tuple

angles = st.floats(-180, 180, allow_nan=False)


def matrix_of(q: tuple[float, float, float, float]) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


@settings(max_examples=200, deadline=None)
@given(angles, angles, angles)
def test_the_quaternion_is_kins_abc_rotation(a: float, b: float, c: float) -> None:
    q = quaternion_from_abc(a, b, c)
    assert math.fsum(v * v for v in q) == pytest.approx(1.0)
    np.testing.assert_allclose(matrix_of(q), abc_to_matrix(a, b, c), atol=1e-9)


def test_a_snapshot_becomes_joint_states_pose_and_the_thesis_strings() -> None:
    at = dt.datetime(2024, 5, 1, 12, 0, 0, 250000, tzinfo=dt.UTC)
    snapshot = StateSnapshot(
        seq=7,
        at=at,
        joints=(10.0, -20.0, 90.0, 0.0, 45.0, 180.0),
        pose=(400.0, -50.0, 600.0, 180.0, 0.0, 90.0),
    )
    out = StreamMessages.of(snapshot, "world")
    js, pose = out.joint_states, out.tool_pose_stamped
    assert js is not None and pose is not None
    assert js.name == JOINT_STATE_NAMES == tuple(f"joint_{i}" for i in range(1, 7))
    assert js.position == pytest.approx([math.radians(v) for v in snapshot.joints or ()])
    assert js.stamp == pose.stamp == Stamp(int(at.timestamp()), 250_000_000)
    assert js.seq == pose.seq == 7
    assert pose.frame_id == "world"
    assert pose.position == pytest.approx((0.4, -0.05, 0.6))
    assert pose.orientation == pytest.approx(quaternion_from_abc(180, 0, 90))
    assert out.joint_state_text == format_tuple(tuple(js.position))
    assert out.tool_pose_text == "(0.4,-0.05,0.6,3.14159,0,1.5708)"


def test_nothing_is_published_before_the_first_read() -> None:
    out = StreamMessages.of(StateSnapshot())
    assert out == StreamMessages(None, None, None, None)


def test_thesis_strings_in_controller_units_on_request() -> None:
    assert format_joint_state((0, 0, 90, 0, 90, 0), si_units=False) == "(0,0,90,0,90,0)"
    assert format_tool_pose((1, 2, 3, 4, 5, 6, 7, 0), si_units=False) == "(1,2,3,4,5,6)"
