"""The rospy (ROS 1) node: `RosCore` bound to rospy topics, services and parameters.

Imported only when running under ROS (Debian's ``/usr/bin/python3`` with its rospy; see
``scripts/ros-env``): rospy and the message modules are loaded with `importlib` inside
`run_node`, so this module imports anywhere and mypy sees them as ``Any``.

Threads: rospy calls back from its own threads; the `RobotService` runs on an asyncio loop
in a `ServiceThread`; callbacks hand it coroutines with ``asyncio.run_coroutine_threadsafe``.
Publishing (from the loop thread) is thread-safe in rospy.

A ROS 2 node would do the same with rclpy: a `RosOutput` over rclpy publishers, a
`ParamSource` over declared parameters, and the same `RosCore` calls.
"""

from __future__ import annotations

import importlib
import logging
from collections.abc import Sequence
from typing import Any

from melfa.ros import interface as ri
from melfa.ros.core import RosCore
from melfa.ros.messages import BASE_FRAME, JointStateData, PoseData
from melfa.ros.runtime import ServiceThread
from melfa.ros.urdf import rv6s_urdf
from melfa.service import RobotService, ServiceConfig
from melfa.service.thesis import dialect_named

SERVICE_TIMEOUT_S = 600.0
"""Longest a ROS service call waits for the robot (an upload at 9600 baud takes minutes)."""


def ros_available() -> bool:
    """True when rospy and the message packages import in this interpreter."""
    try:
        for name in ("rospy", "std_msgs.msg", "sensor_msgs.msg", "geometry_msgs.msg"):
            importlib.import_module(name)
        importlib.import_module("std_srvs.srv")
    except ImportError:
        return False
    return True


class RospyOutput:
    """`RosOutput` over rospy publishers (relative names: remappable, namespaced)."""

    def __init__(self, rospy: Any) -> None:
        self.rospy = rospy
        std = importlib.import_module("std_msgs.msg")
        sensor = importlib.import_module("sensor_msgs.msg")
        geometry = importlib.import_module("geometry_msgs.msg")
        self._string = std.String
        self._joint_state = sensor.JointState
        self._pose_stamped = geometry.PoseStamped
        self._texts = {
            name: rospy.Publisher(name, std.String, queue_size=10)
            for name in (ri.TOOL_POSE, ri.JOINT_STATE_TEXT, ri.EXECUTE_ERROR)
        }
        self._joints = rospy.Publisher(ri.JOINT_STATES, sensor.JointState, queue_size=10)
        self._pose = rospy.Publisher(ri.TOOL_POSE_STAMPED, geometry.PoseStamped, queue_size=10)

    def joint_states(self, message: JointStateData) -> None:
        msg = self._joint_state()
        msg.header.stamp = self.rospy.Time(message.stamp.secs, message.stamp.nsecs)
        msg.name = list(message.name)
        msg.position = list(message.position)
        self._joints.publish(msg)

    def tool_pose_stamped(self, message: PoseData) -> None:
        msg = self._pose_stamped()
        msg.header.stamp = self.rospy.Time(message.stamp.secs, message.stamp.nsecs)
        msg.header.frame_id = message.frame_id
        p, q = msg.pose.position, msg.pose.orientation
        p.x, p.y, p.z = message.position
        q.x, q.y, q.z, q.w = message.orientation
        self._pose.publish(msg)

    def text(self, topic: str, text: str) -> None:
        publisher = self._texts.get(topic)
        if publisher is None:
            publisher = self._texts[topic] = self.rospy.Publisher(
                topic, self._string, queue_size=10
            )
        publisher.publish(self._string(data=text))

    def log(self, level: int, text: str) -> None:
        if level >= logging.ERROR:
            self.rospy.logerr(text)
        elif level >= logging.WARNING:
            self.rospy.logwarn(text)
        else:
            self.rospy.loginfo(text)


class RospyParams:
    """`ParamSource` over the node's private parameters (``~program`` …)."""

    def __init__(self, rospy: Any) -> None:
        self.rospy = rospy

    def get(self, name: str) -> object | None:
        value: object | None = self.rospy.get_param(f"~{name}", None)
        return value


def run_node(
    robot: str = "sim",
    *,
    node_name: str = ri.NODE_NAME,
    max_rate_hz: float | None = None,
    frame_id: str = BASE_FRAME,
    mode: str = "melfa",
    description: bool = True,
    argv: Sequence[str] = (),
    config: ServiceConfig | None = None,
) -> None:
    """Run the node until ROS shuts it down (Ctrl-C, ``rosnode kill``, master gone).

    ``argv`` carries ROS remappings (``joint_states:=/arm/joint_states``, ``__ns:=arm``).
    """
    rospy: Any = importlib.import_module("rospy")
    srv = importlib.import_module("std_srvs.srv")

    rospy.init_node(node_name, argv=["melfa-ros", *argv])
    rate = rospy.get_param("~max_rate", max_rate_hz)
    frame = rospy.get_param("~frame_id", frame_id)
    dialect = dialect_named(str(rospy.get_param(f"~{ri.MODE_PARAM}", mode)))
    if description and not rospy.has_param("robot_description"):
        rospy.set_param("robot_description", rv6s_urdf())
    output = RospyOutput(rospy)
    runtime = ServiceThread(
        lambda: RobotService.from_spec(robot, config=config),
        output,
        RospyParams(rospy),
        frame_id=frame,
        max_rate_hz=float(rate) if rate else None,
        dialect=dialect,
    )
    core = runtime.start()
    rospy.on_shutdown(runtime.close)
    _wire(rospy, srv, runtime, core)
    rospy.loginfo(
        f"melfa: robot {robot!r} ready ({dialect.name} mode); send control messages on "
        "/execute_instruction"
    )
    rospy.spin()
    runtime.close()


def _wire(rospy: Any, srv: Any, runtime: ServiceThread, core: RosCore) -> None:
    std = importlib.import_module("std_msgs.msg")

    def instruction(msg: Any) -> None:
        runtime.submit(core.put_instruction(str(msg.data)))

    rospy.Subscriber(ri.EXECUTE_INSTRUCTION, std.String, instruction, queue_size=100)

    for spec in ri.SERVICES:
        if spec.type == ri.TRIGGER:
            rospy.Service(f"~{spec.name}", srv.Trigger, _trigger(srv, runtime, core, spec.name))
        else:
            rospy.Service(f"~{spec.name}", srv.SetBool, _set_bool(srv, runtime, core, spec.name))


def _trigger(srv: Any, runtime: ServiceThread, core: RosCore, name: str) -> Any:
    def handle(_request: Any) -> Any:
        reply = runtime.submit(core.call(name)).result(SERVICE_TIMEOUT_S)
        return srv.TriggerResponse(success=reply.success, message=reply.message)

    return handle


def _set_bool(srv: Any, runtime: ServiceThread, core: RosCore, name: str) -> Any:
    def handle(request: Any) -> Any:
        reply = runtime.submit(core.call(name, bool(request.data))).result(SERVICE_TIMEOUT_S)
        return srv.SetBoolResponse(success=reply.success, message=reply.message)

    return handle


__all__ = ["RospyOutput", "RospyParams", "ros_available", "run_node"]
