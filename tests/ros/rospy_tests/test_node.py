"""The `melfa ros` node on a real ROS master, driven with rospy publishers, subscribers
and service proxies, as the thesis's tests drove its Execute Node with rostopic."""

from __future__ import annotations

import math
from typing import Any

import pytest

from melfa.robot import RobotSettings
from tests.ros.rospy_tests.helpers import (
    Inbox,
    instruction_publisher,
    position,
    trigger,
    wait_for,
)

rospy: Any = pytest.importorskip("rospy", reason="ROS 1 runs under scripts/ros-env only")
std_msgs: Any = pytest.importorskip("std_msgs.msg")
sensor_msgs: Any = pytest.importorskip("sensor_msgs.msg")
geometry_msgs: Any = pytest.importorskip("geometry_msgs.msg")
std_srvs: Any = pytest.importorskip("std_srvs.srv")

pytestmark = pytest.mark.usefixtures("melfa_node")

STEP_M = RobotSettings().jog_step_mm / 1000
PROGRAM = "10 SERVO ON\n20 MOV P1\n30 END\n"
POINTS = "DEF POS P1=(400.00,-100.00,600.00,180.00,0.00,180.00)(7,0)\n"
RATE_WINDOW_S = 1.5
"""Joint-state rate is counted over this much of the node's (the controller's) time."""
MIN_RATE_HZ = 10.0
"""A generous floor: the in-process virtual controller streams ~100 states/s, a real
9600-baud line ~3–5."""


def tool_x_axis(pose: Any) -> tuple[float, float, float]:
    q = pose.pose.orientation
    x, y, z, w = q.x, q.y, q.z, q.w
    return (1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w))


def test_thesis_control_messages_move_the_tool_by_one_step() -> None:
    poses = Inbox("/tool_pose_stamped", geometry_msgs.PoseStamped)
    texts = Inbox("/tool_pose", std_msgs.String)
    try:
        assert wait_for(lambda: poses.last() is not None and texts.last() is not None)
        start = poses.last()
        assert start.header.frame_id == "base"
        pub = instruction_publisher()
        for text in ("---SINGLE INSTRUCTION---", "SERVO ON", "---MOV TOOL +X---"):
            pub.publish(std_msgs.String(data=text))
        axis = tool_x_axis(start)
        expected = [p + STEP_M * a for p, a in zip(position(start), axis, strict=True)]
        assert wait_for(lambda: math.dist(position(poses.last()), expected) < 1e-4), (
            position(start),
            expected,
            position(poses.last()),
        )

        def text_agrees() -> bool:
            values = [float(v) for v in texts.last().data.strip("()").split(",")]
            return len(values) == 6 and math.dist(values[:3], expected) < 1e-4

        assert wait_for(text_agrees), texts.last()
    finally:
        poses.close()
        texts.close()


def test_a_message_out_of_place_is_reported_on_execute_error() -> None:
    errors = Inbox("/execute_error", std_msgs.String)
    try:
        assert wait_for(lambda: errors.subscriber.get_num_connections() >= 1)
        instruction_publisher().publish(std_msgs.String(data="10 MOV P1"))
        assert wait_for(lambda: errors.last() is not None)
        assert "not a control message" in errors.last().data
    finally:
        errors.close()


def test_services_load_program_and_points_and_run_it() -> None:
    if rospy.has_param("/melfa/program"):
        rospy.delete_param("/melfa/program")
    missing = trigger("load_program")
    assert missing.success is False and "~program" in missing.message

    poses = Inbox("/tool_pose_stamped", geometry_msgs.PoseStamped)
    try:
        rospy.set_param("/melfa/program", PROGRAM)
        rospy.set_param("/melfa/points", POINTS)
        loaded = trigger("load_program")
        assert loaded.success is True and "program loaded" in loaded.message, loaded
        assert trigger("load_points").success is True
        servo = rospy.ServiceProxy("/melfa/servo", std_srvs.SetBool)(True)
        assert (servo.success, servo.message) == (True, "servo on")
        assert trigger("run").success is True
        assert wait_for(
            lambda: (
                poses.last() is not None
                and math.dist(position(poses.last()), (0.4, -0.1, 0.6)) < 1e-3
            )
        ), poses.last()
        stopped = trigger("stop")
        assert (stopped.success, stopped.message) == (True, "stopped")
    finally:
        poses.close()


def test_joint_states_stream_at_the_service_rate() -> None:
    joints = Inbox("/joint_states", sensor_msgs.JointState)
    try:
        assert wait_for(lambda: len(joints.snapshot()) >= 1)
        first = joints.last()
        assert list(first.name) == [f"joint_{i}" for i in range(1, 7)]
        assert len(first.position) == 6
        assert all(abs(v) <= 2 * math.pi for v in first.position)  # radians, not degrees
        t0 = first.header.stamp.to_sec()

        def window_done() -> bool:
            last = joints.last()
            return last.header.stamp.to_sec() >= t0 + RATE_WINDOW_S

        assert wait_for(window_done)
        stamps = [m.header.stamp.to_sec() for m in joints.snapshot()]
        in_window = [s for s in stamps if t0 <= s < t0 + RATE_WINDOW_S]
        rate = len(in_window) / RATE_WINDOW_S
        print(f"joint_states: {rate:.1f} messages/s over {RATE_WINDOW_S} s of node time")
        assert rate >= MIN_RATE_HZ
        assert stamps == sorted(stamps)
    finally:
        joints.close()
