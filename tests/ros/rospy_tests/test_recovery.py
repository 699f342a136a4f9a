"""A fresh node in melfa's mode: a failed motion is reported on /execute_error and in the
node's log and is recoverable with the reset service; /joint_states keeps flowing during a
jog step; programs load by service from ~program_file (UTF-8 or Windows-1252) and from
`rosparam set --textfile`."""

from __future__ import annotations

import itertools
import math
import statistics
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.ros.rospy_tests.conftest import node_process
from tests.ros.rospy_tests.helpers import Inbox, instruction_publisher, trigger, wait_for

rospy: Any = pytest.importorskip("rospy", reason="ROS 1 runs under scripts/ros-env only")
std_msgs: Any = pytest.importorskip("std_msgs.msg")
sensor_msgs: Any = pytest.importorskip("sensor_msgs.msg")
geometry_msgs: Any = pytest.importorskip("geometry_msgs.msg")
rosgraph_msgs: Any = pytest.importorskip("rosgraph_msgs.msg")

PROGRAM_1252 = (
    "10 ' Piràmide: comentaris en català, desats per un editor de Windows\r\n"
    "20 SERVO ON\r\n30 MOV P1 ' cap al punt\r\n40 END\r\n"
)
POINTS = "DEF POS P1=(400.00,-100.00,600.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture
def node(ros_master: str, tmp_path: Path) -> Iterator[Path]:
    with node_process(tmp_path) as log:
        yield log


def send(pub: Any, *texts: str) -> None:
    for text in texts:
        pub.publish(std_msgs.String(data=text))


def test_a_failed_motion_is_reported_and_recoverable_with_reset(node: Path) -> None:
    pub = instruction_publisher()
    errors = Inbox("/execute_error", std_msgs.String)
    log = Inbox("/rosout", rosgraph_msgs.Log)
    poses = Inbox("/tool_pose_stamped", geometry_msgs.PoseStamped)
    try:
        assert wait_for(lambda: poses.last() is not None)
        # The first step: a move sent with the servo off (a statement leaves the
        # servo alone) fails with L2000 and leaves an alarm.
        send(pub, "---SINGLE INSTRUCTION---", "MVS P_CURR+(0,0,10,0,0,0)")
        assert wait_for(lambda: errors.last() is not None)
        reason = errors.last().data
        assert wait_for(lambda: "alarm" in trigger("state").message)

        def logged() -> bool:
            return any(
                m.name == "/melfa" and m.level >= rosgraph_msgs.Log.ERROR and reason in m.msg
                for m in log.snapshot()
            )

        assert wait_for(logged), [(m.name, m.msg) for m in log.snapshot()][-5:]

        reset = trigger("reset")
        assert (reset.success, reset.message) == (True, "alarm reset")
        assert wait_for(lambda: "no alarm" in trigger("state").message)
        z = poses.last().pose.position.z
        send(pub, "---MOV TOOL -Z---")  # tool Z points down: the arm goes up one step
        assert wait_for(lambda: poses.last().pose.position.z > z + 0.0099)
    finally:
        errors.close()
        log.close()
        poses.close()


def test_joint_states_keep_flowing_during_a_jog_step(node: Path) -> None:
    pub = instruction_publisher()
    joints = Inbox("/joint_states", sensor_msgs.JointState)
    try:
        assert wait_for(lambda: len(joints.snapshot()) >= 50)
        rest = [m.header.stamp.to_sec() for m in joints.snapshot()[-50:]]
        poll = statistics.median(b - a for a, b in itertools.pairwise(rest))
        first = joints.last().position
        send(pub, "---MOV TOOL +X---")
        assert wait_for(lambda: joints.last().position != first)
        time.sleep(0.5)
        changed = [m for m in joints.snapshot() if m.position != first]
        assert wait_for(lambda: joints.snapshot()[-1].position == joints.snapshot()[-20].position)
        moving = [m for m in joints.snapshot() if m.header.stamp >= changed[0].header.stamp]
        stamps = [m.header.stamp.to_sec() for m in moving]
        end = next(i for i, m in enumerate(moving) if i > 0 and m.position == moving[-1].position)
        during = stamps[: end + 1]
        gaps = [b - a for a, b in itertools.pairwise(during)]
        between = {tuple(m.position) for m in moving[:end]}
        print(
            f"jog step: {len(during)} joint states ({len(between)} positions on the way) over "
            f"{during[-1] - during[0]:.3f} s, longest gap {max(gaps) * 1000:.1f} ms; at rest "
            f"one every {poll * 1000:.1f} ms"
        )
        # A step that held the line would show the arm only before and after it.
        assert len(between) >= 3
    finally:
        joints.close()


def test_program_loading_by_file_in_windows_1252_and_by_textfile(
    node: Path, tmp_path: Path
) -> None:
    program = tmp_path / "piramide.mb4"
    program.write_bytes(PROGRAM_1252.encode("cp1252"))
    points = tmp_path / "piramide.pos"
    points.write_text(POINTS, encoding="utf-8")
    for name in ("/melfa/program", "/melfa/points"):
        if rospy.has_param(name):
            rospy.delete_param(name)
    rospy.set_param("/melfa/program_file", str(program))
    rospy.set_param("/melfa/points_file", str(points))
    poses = Inbox("/tool_pose_stamped", geometry_msgs.PoseStamped)
    try:
        loaded = trigger("load_project")
        assert loaded.success is True, loaded.message
        assert "program and points loaded" in loaded.message
        assert trigger("run").success is True

        def at_p1() -> bool:
            p = poses.last().pose.position
            return math.dist((p.x, p.y, p.z), (0.4, -0.1, 0.6)) < 1e-3

        assert wait_for(at_p1, timeout=60)

        # The documented recipe: rosparam set --textfile (keeps lines and ' comments).
        text = tmp_path / "utf8.mb4"
        text.write_text("10 ' Comentari: l'àrea\n20 SERVO ON\n30 END\n", encoding="utf-8")
        subprocess.run(
            ["rosparam", "set", "--textfile", str(text), "/melfa/program"],
            check=True,
            timeout=60,
            capture_output=True,
        )
        assert rospy.get_param("/melfa/program").count("\n") == 3
        again = trigger("load_program")
        assert again.success is True, again.message
    finally:
        poses.close()
        for name in ("/melfa/program_file", "/melfa/points_file", "/melfa/program"):
            if rospy.has_param(name):
                rospy.delete_param(name)


def test_a_program_with_errors_is_refused_by_the_services_policy(node: Path) -> None:
    """The ROS 1 node is a door like any other: check-before-upload is the service's, so a
    program with errors is refused before anything is sent, in the same words REST,
    rosbridge and the thesis's messages use."""
    from melfa.lang.plan import plan_upload
    from melfa.service.policy import plan_refusal

    broken = "10 MOV P1\n20 GOTO 99\n"
    rospy.set_param("/melfa/program", broken)
    try:
        reply = trigger("load_program")
        expected = plan_refusal(plan_upload(broken))
        assert expected is not None
        assert (reply.success, reply.message) == (False, str(expected))
        assert "Fix it in the editor, then load again." in reply.message
    finally:
        rospy.delete_param("/melfa/program")
