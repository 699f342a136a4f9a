"""ros/melfa_ros/launch/melfa.launch with roslaunch: robot_description is the URDF, the
node comes up, and robot_state_publisher with it (TF on by default), as `rosnode` and
`rostopic` show (ROS_PACKAGE_PATH pointing at ros/, nothing to build; scripts/ros-env
installs what the package declares)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path
from typing import Any

import pytest

from tests.ros.rospy_tests.conftest import end_group
from tests.ros.rospy_tests.helpers import wait_for

rospy: Any = pytest.importorskip("rospy", reason="ROS 1 runs under scripts/ros-env only")

ROOT = Path(__file__).resolve().parents[3]


def test_the_launch_file_starts_the_node_with_its_description(
    ros_master: str, tmp_path: Path
) -> None:
    env = dict(os.environ)
    env["ROS_PACKAGE_PATH"] = f"{ROOT / 'ros'}:{env.get('ROS_PACKAGE_PATH', '')}".rstrip(":")
    log = (tmp_path / "roslaunch.log").open("wb")
    launch = subprocess.Popen(
        ["roslaunch", "melfa_ros", "melfa.launch", "mode:=thesis", "--wait"],
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    try:
        try:
            rospy.wait_for_service("/melfa/state", timeout=90)
        except rospy.ROSException:
            pytest.fail(
                "roslaunch did not start the node:\n" + (tmp_path / "roslaunch.log").read_text()
            )
        description = rospy.get_param("/robot_description")
        assert '<robot name="rv6s">' in description and 'name="joint_6"' in description

        def listed(tool: str, what: str) -> bool:
            done = subprocess.run(
                [tool, "list"], env=env, capture_output=True, text=True, timeout=60, check=False
            )
            return what in done.stdout.split()

        assert wait_for(lambda: listed("rosnode", "/robot_state_publisher"), 60), (
            tmp_path / "roslaunch.log"
        ).read_text()
        assert wait_for(lambda: listed("rostopic", "/tf"), 60)  # TF, with no rsp:=true asked
    finally:
        end_group(launch)
        log.close()
