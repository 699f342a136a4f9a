"""The ROS face of the robot, named once: topics, services, parameters and their types.

The rospy node (`melfa.ros.node`), the rosbridge endpoint (`melfa.ros.rosbridge`) and a
future rclpy node offer exactly these. Names follow the thesis where it named them
(``execute_instruction``, ``tool_pose``, ``joint_state``) and ROS conventions elsewhere
(``joint_states`` for robot_state_publisher, services private to the node: ``/melfa/run``).

Loads use ``std_srvs/Trigger`` with the text in a parameter (``/melfa/program``,
``/melfa/points``) because Debian's ROS cannot build custom service types (no catkin
message generation) and every ROS tool already knows Trigger; over rosbridge the same
services also take the texts as arguments (``{"program": …, "points": …}``)::

    rosparam set --textfile pick.mb4 /melfa/program
    rosservice call /melfa/load_program
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from melfa.protocol import OVERRIDE_PERCENT, span_text

NODE_NAME = "melfa"
"""Default node name; services and parameters live under it (``/melfa/...``)."""


class Direction(enum.Enum):
    IN = "subscribed"
    """Clients publish, the robot listens."""
    OUT = "published"
    """The robot publishes."""


@dataclass(frozen=True)
class TopicSpec:
    name: str
    """Relative name (``/name`` in the root namespace)."""
    type: str
    direction: Direction
    doc: str


@dataclass(frozen=True)
class ServiceSpec:
    name: str
    """Private name: ``/<node>/<name>``."""
    type: str
    doc: str
    param: str | None = None
    """The private parameter holding the text a load service sends."""


STRING = "std_msgs/String"
JOINT_STATE = "sensor_msgs/JointState"
POSE_STAMPED = "geometry_msgs/PoseStamped"
TRIGGER = "std_srvs/Trigger"
SET_BOOL = "std_srvs/SetBool"

EXECUTE_INSTRUCTION = "execute_instruction"
TOOL_POSE = "tool_pose"
JOINT_STATE_TEXT = "joint_state"
JOINT_STATES = "joint_states"
TOOL_POSE_STAMPED = "tool_pose_stamped"
EXECUTE_ERROR = "execute_error"

TOPICS: tuple[TopicSpec, ...] = (
    TopicSpec(
        EXECUTE_INSTRUCTION,
        STRING,
        Direction.IN,
        "the thesis's control messages (appendix 9.1), e.g. ---MOV TOOL +X---",
    ),
    TopicSpec(
        TOOL_POSE,
        STRING,
        Direction.OUT,
        '"(x,y,z,roll,pitch,yaw)" in m and rad (thesis mode: x,y,z,roll,pitch,yaw on request)',
    ),
    TopicSpec(
        JOINT_STATE_TEXT,
        STRING,
        Direction.OUT,
        '"(j1,j2,j3,j4,j5,j6)" in rad (thesis mode: j1,…,j6 on request)',
    ),
    TopicSpec(JOINT_STATES, JOINT_STATE, Direction.OUT, "joint_1…joint_6 in rad"),
    TopicSpec(TOOL_POSE_STAMPED, POSE_STAMPED, Direction.OUT, "tool pose in the base frame"),
    TopicSpec(EXECUTE_ERROR, STRING, Direction.OUT, "why a control message or move failed"),
)

LOAD_PROGRAM = "load_program"
LOAD_POINTS = "load_points"
LOAD_PROJECT = "load_project"
RUN = "run"
STOP = "stop"
DELETE = "delete"
SERVO = "servo"
RESET = "reset"
OVERRIDE = "override"
STATE = "state"

PROGRAM_PARAM = "program"
POINTS_PARAM = "points"
OVERRIDE_PARAM = "override"
MODE_PARAM = "mode"
"""``~mode``: ``melfa`` (default) or ``thesis`` (`melfa.service.thesis.THESIS`)."""

SERVICES: tuple[ServiceSpec, ...] = (
    ServiceSpec(
        LOAD_PROGRAM,
        TRIGGER,
        "upload the program text in ~program (or the file named by ~program_file)",
        PROGRAM_PARAM,
    ),
    ServiceSpec(
        LOAD_POINTS,
        TRIGGER,
        "upload the points (.POS text) in ~points (or the file named by ~points_file)",
        POINTS_PARAM,
    ),
    ServiceSpec(
        LOAD_PROJECT,
        TRIGGER,
        "upload ~program and ~points in one session (nothing half saved)",
        PROGRAM_PARAM,
    ),
    ServiceSpec(RUN, TRIGGER, "run the loaded program"),
    ServiceSpec(STOP, TRIGGER, "stop now (overtakes everything queued)"),
    ServiceSpec(DELETE, TRIGGER, "delete the program and its points"),
    ServiceSpec(SERVO, SET_BOOL, "servo on (data: true) or off"),
    ServiceSpec(RESET, TRIGGER, "reset the controller's alarm (after a refused move)"),
    ServiceSpec(
        OVERRIDE,
        TRIGGER,
        f"set the override to ~override percent ({span_text(OVERRIDE_PERCENT)})",
        OVERRIDE_PARAM,
    ),
    ServiceSpec(STATE, TRIGGER, "the state in one line: link, servo, program, alarm, lease"),
)

TOPIC_BY_NAME = {t.name: t for t in TOPICS}
SERVICE_BY_NAME = {s.name: s for s in SERVICES}

__all__ = [
    "EXECUTE_ERROR",
    "EXECUTE_INSTRUCTION",
    "JOINT_STATES",
    "JOINT_STATE_TEXT",
    "MODE_PARAM",
    "NODE_NAME",
    "OVERRIDE",
    "OVERRIDE_PARAM",
    "RESET",
    "SERVICES",
    "SERVICE_BY_NAME",
    "STATE",
    "TOOL_POSE",
    "TOOL_POSE_STAMPED",
    "TOPICS",
    "TOPIC_BY_NAME",
    "Direction",
    "ServiceSpec",
    "TopicSpec",
]
