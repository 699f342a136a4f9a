"""melfa.ros: the robot on ROS — a ROS 1 node and a rosbridge-compatible endpoint.

- `melfa.ros.interface`: the topics, services and parameters, named once.
- `melfa.ros.messages`: snapshots → the thesis's strings, JointState and PoseStamped values
  (pure; no ROS needed).
- `melfa.ros.core.RosCore`: what a node does with a `RobotService`, whatever the client
  library: ordered control messages through `ThesisMessages`, services, state streaming.
- `melfa.ros.node`: the rospy binding (imports rospy lazily; run it with
  ``scripts/ros-env melfa ros``). A ROS 2 (rclpy) binding would sit beside it.
- `melfa.ros.rosbridge`: the rosbridge v2 protocol over a FastAPI WebSocket, no ROS needed.
"""

from melfa.ros.core import ParamSource, RosCore, RosOutput, ServiceReply
from melfa.ros.interface import SERVICES, TOPICS, ServiceSpec, TopicSpec
from melfa.ros.messages import (
    JointStateData,
    PoseData,
    StreamMessages,
    format_joint_state,
    format_tool_pose,
    quaternion_from_abc,
)

__all__ = [
    "SERVICES",
    "TOPICS",
    "JointStateData",
    "ParamSource",
    "PoseData",
    "RosCore",
    "RosOutput",
    "ServiceReply",
    "ServiceSpec",
    "StreamMessages",
    "TopicSpec",
    "format_joint_state",
    "format_tool_pose",
    "quaternion_from_abc",
]
