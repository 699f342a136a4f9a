"""The thesis's own backend tests (chapter 7.1) on a fresh `melfa ros --mode thesis` node,
as written: programs and points sent as control messages and loaded into the controller,
every movement command sent with `rostopic pub -1` (the servo on while jogging, off when a
non-movement message follows); and recovery, state during a jog step, program loading."""

from __future__ import annotations

import math
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

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
STEP_MM = 20.0
"""The thesis's jog increment (TOOL_INCREMENT = 0.02 m)."""


@pytest.fixture
def fresh(ros_master: str, tmp_path: Path) -> Iterator[Path]:
    """A fresh thesis-mode node for each test (its log file)."""
    with node_process(tmp_path, "--mode", "thesis") as log:
        yield log


def send(pub: Any, *texts: str) -> None:
    for text in texts:
        pub.publish(std_msgs.String(data=text))


def state() -> str:
    return str(trigger("state").message)


def pose_mm(pub: Any, answers: Inbox) -> list[float]:
    """The pose the thesis's way: REQUEST TOOL POSE, answer "x,y,z,r,p,y" (m, rad). Asked
    again if no answer comes: the first message to a just-started node can be lost while
    rospy still holds the previous node's connection."""
    assert wait_for(lambda: answers.subscriber.get_num_connections() >= 1)
    for _ in range(10):
        count = len(answers.snapshot())
        send(pub, "---REQUEST TOOL POSE---")
        if wait_for(lambda: len(answers.snapshot()) > count, timeout=3):  # noqa: B023
            break
    else:
        raise AssertionError("no answer on /tool_pose")
    text = answers.last().data
    assert not text.startswith("(")
    values = [float(v) for v in text.split(",")]
    return [v * 1000 for v in values[:3]] + [math.degrees(v) for v in values[3:]]


def numbered(path: Path) -> list[str]:
    """The file's lines numbered 10, 20, … (as the thesis's page sent them)."""
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]
    return [
        line if line[:1].isdigit() else f"{10 * (i + 1)} {line}" for i, line in enumerate(lines)
    ]


def test_7_1_1_to_3_programs_and_points_are_loaded_and_run(fresh: Path) -> None:
    pub = instruction_publisher()
    errors = Inbox("/execute_error", std_msgs.String)
    answers = Inbox("/tool_pose", std_msgs.String)
    try:
        # 7.1.2: a long program with the thesis's Catalan comments, in many messages.
        send(pub, "---LOAD PROGRAM BEGIN---", *numbered(EXAMPLES / "pyramid.MB4"))
        send(pub, "---LOAD PROGRAM END---")
        # 7.1.1 and 7.1.3: the short program and its points, then run it.
        send(pub, "---DELETE---", "---LOAD PROGRAM BEGIN---")
        send(pub, *numbered(EXAMPLES / "thesis_test.MB4"), "---LOAD PROGRAM END---")
        points = (EXAMPLES / "thesis_test.POS").read_text(encoding="utf-8").splitlines()
        send(pub, "---LOAD POINTS BEGIN---", *points, "---LOAD POINTS END---")
        send(pub, "---RUN PROGRAM---")
        pinic = (524.49, 80.98, 614.92)

        def at_pinic() -> bool:
            return math.dist(pose_mm(pub, answers)[:3], pinic) < 0.05

        assert wait_for(at_pinic, timeout=120), pose_mm(pub, answers)
        assert not errors.snapshot(), [m.data for m in errors.snapshot()]
        assert "no alarm" in state()
    finally:
        errors.close()
        answers.close()


def test_7_1_4_every_movement_command_with_rostopic(fresh: Path) -> None:
    pub = instruction_publisher()
    answers = Inbox("/tool_pose", std_msgs.String)
    poses = Inbox("/tool_pose_stamped", geometry_msgs.PoseStamped)
    errors = Inbox("/execute_error", std_msgs.String)
    try:
        start = pose_mm(pub, answers)
        assert "servo on" in state()  # the node switched it on when it connected
        target = list(start[:3])

        def arrived() -> bool:
            p = poses.last().pose.position
            return math.dist((p.x * 1000, p.y * 1000, p.z * 1000), target) < 0.05

        moves = [("+", "X"), ("-", "X"), ("+", "Y"), ("-", "Y"), ("+", "Z"), ("-", "Z")]
        for number, (sign, axis) in enumerate(moves):
            text = f"---MOV TOOL {sign}{axis}---"
            if number == 0:  # as written in the thesis
                command = ["rostopic", "pub", "-1", "/execute_instruction", "std_msgs/String"]
                subprocess.run([*command, "--", text], check=True, timeout=60, capture_output=True)
            else:
                send(pub, text)
            target["XYZ".index(axis)] += STEP_MM if sign == "+" else -STEP_MM
            assert wait_for(arrived), (text, target, poses.last().pose.position)
            assert "servo on" in state()  # the servo stays on while jogging
            time.sleep(0.5)  # the next press comes after this move ended (the thesis's rule)
        pose_mm(pub, answers)  # a non-movement message ends the jog session...
        assert wait_for(lambda: "servo off" in state())  # ...and the servo goes off
        # Open and close the actuator (the page's space bar).
        send(pub, "---SINGLE INSTRUCTION---", "HCLOSE 1", "---SINGLE INSTRUCTION---", "HOPEN 1")
        assert wait_for(lambda: "servo on" in state())
        time.sleep(0.5)
        assert not errors.snapshot(), [m.data for m in errors.snapshot()]
    finally:
        answers.close()
        poses.close()
        errors.close()
