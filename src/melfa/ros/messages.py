"""Robot state as ROS messages, without ROS: plain values any middleware can copy.

The rospy node, a future rclpy node and the rosbridge endpoint all turn a service
`StateSnapshot` into the same things:

- the thesis's strings (appendix 9.1): ``tool_pose`` "(x,y,z,roll,pitch,yaw)" and
  ``joint_state`` "(j1,j2,j3,j4,j5,j6)", in metres and radians as the thesis's node sent
  them (the same text `melfa.service.ThesisMessages` publishes on request);
- `JointStateData` for ``sensor_msgs/JointState``: joints ``joint_1`` … ``joint_6`` in
  radians (REP 103 units);
- `PoseData` for ``geometry_msgs/PoseStamped``: the tool pose in metres with the A/B/C
  angles as a quaternion. MELFA's A/B/C are fixed-axis X, Y, Z rotations, R = Rz(C)·Ry(B)·Rx(A)
  [GUESS rv6s.md §5, `melfa.kin.pose.ABC_ORDER`], which is exactly ROS's roll/pitch/yaw.

Pure: no I/O, no clock (the snapshot's own time stamps the messages).
"""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Sequence
from dataclasses import dataclass

from melfa.service import StateSnapshot
from melfa.service.thesis import format_tuple

JOINT_STATE_NAMES = tuple(f"joint_{i}" for i in range(1, 7))
"""Joint names in ``sensor_msgs/JointState`` (URDF-style, as ROS-Industrial names them)."""

BASE_FRAME = "base"
"""Frame of the tool pose: the controller's base coordinates (ROS-Industrial's ``base``
frame, REP-I0004), in metres."""


@dataclass(frozen=True)
class Stamp:
    """A ROS time: whole seconds and nanoseconds since the Unix epoch."""

    secs: int
    nsecs: int

    @classmethod
    def of(cls, when: dt.datetime) -> Stamp:
        """The stamp of an aware datetime (exact to the microsecond).

        >>> Stamp.of(dt.datetime(1970, 1, 1, 0, 0, 1, 500000, tzinfo=dt.UTC))
        Stamp(secs=1, nsecs=500000000)
        """
        delta = when - dt.datetime(1970, 1, 1, tzinfo=dt.UTC)
        micros = (delta.days * 86_400 + delta.seconds) * 1_000_000 + delta.microseconds
        secs, rest = divmod(micros, 1_000_000)
        return cls(secs, rest * 1000)

    def to_sec(self) -> float:
        return self.secs + self.nsecs / 1e9


@dataclass(frozen=True)
class JointStateData:
    """A ``sensor_msgs/JointState`` (positions only: the controller reports no velocity)."""

    seq: int
    stamp: Stamp
    name: tuple[str, ...]
    position: tuple[float, ...]
    """Radians."""


@dataclass(frozen=True)
class PoseData:
    """A ``geometry_msgs/PoseStamped``: position in metres, orientation as a quaternion."""

    seq: int
    stamp: Stamp
    frame_id: str
    position: tuple[float, float, float]
    orientation: tuple[float, float, float, float]
    """x, y, z, w."""


def quaternion_from_abc(a: float, b: float, c: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of R = Rz(C)·Ry(B)·Rx(A), angles in degrees (roll A, pitch B, yaw C).

    >>> [round(v, 6) for v in quaternion_from_abc(0, 0, 90)]
    [0.0, 0.0, 0.707107, 0.707107]
    >>> [round(v, 6) for v in quaternion_from_abc(180, 0, 0)]
    [1.0, 0.0, 0.0, 0.0]
    """
    hr, hp, hy = (math.radians(v) / 2 for v in (a, b, c))
    cr, sr = math.cos(hr), math.sin(hr)
    cp, sp = math.cos(hp), math.sin(hp)
    cy, sy = math.cos(hy), math.sin(hy)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def format_tool_pose(pose: Sequence[float], *, si_units: bool = True) -> str:
    """The thesis's ``tool_pose`` text from X, Y, Z (mm), A, B, C (°).

    >>> format_tool_pose((400.0, -1e-30, 600.0, 180.0, -0.0, 90.0))
    '(0.4,0,0.6,3.14159,0,1.5708)'
    """
    values = tuple(float(v) for v in pose[:6])
    if si_units:
        values = (*(v / 1000 for v in values[:3]), *(math.radians(v) for v in values[3:]))
    return format_tuple(_clean(values))


def format_joint_state(joints: Sequence[float], *, si_units: bool = True) -> str:
    """The thesis's ``joint_state`` text from J1…J6 (°).

    >>> format_joint_state((0, 0, 90, 0, 90, 0))
    '(0,0,1.5708,0,1.5708,0)'
    """
    values = tuple(float(v) for v in joints[:6])
    if si_units:
        values = tuple(math.radians(v) for v in values)
    return format_tuple(_clean(values))


def _clean(values: tuple[float, ...]) -> tuple[float, ...]:
    """Rounding noise (1e-33, -0) printed as 0."""
    return tuple(0.0 if abs(v) < 1e-12 else v for v in values)


def joint_state(snapshot: StateSnapshot) -> JointStateData | None:
    """The snapshot's joints as a JointState (None until the joints were first read)."""
    if snapshot.joints is None or len(snapshot.joints) < 6:
        return None
    return JointStateData(
        seq=snapshot.seq,
        stamp=Stamp.of(snapshot.at),
        name=JOINT_STATE_NAMES,
        position=tuple(math.radians(v) for v in snapshot.joints[:6]),
    )


def tool_pose(snapshot: StateSnapshot, frame_id: str = BASE_FRAME) -> PoseData | None:
    """The snapshot's tool pose as a PoseStamped (None until it was first known)."""
    if snapshot.pose is None or len(snapshot.pose) < 6:
        return None
    x, y, z, a, b, c = snapshot.pose[:6]
    return PoseData(
        seq=snapshot.seq,
        stamp=Stamp.of(snapshot.at),
        frame_id=frame_id,
        position=(x / 1000, y / 1000, z / 1000),
        orientation=quaternion_from_abc(a, b, c),
    )


@dataclass(frozen=True)
class StreamMessages:
    """Everything one snapshot publishes (each part None when unknown yet)."""

    joint_states: JointStateData | None
    tool_pose_stamped: PoseData | None
    joint_state_text: str | None
    tool_pose_text: str | None

    @classmethod
    def of(cls, snapshot: StateSnapshot, frame_id: str = BASE_FRAME) -> StreamMessages:
        joints = snapshot.joints if snapshot.joints and len(snapshot.joints) >= 6 else None
        pose = snapshot.pose if snapshot.pose and len(snapshot.pose) >= 6 else None
        return cls(
            joint_states=joint_state(snapshot),
            tool_pose_stamped=tool_pose(snapshot, frame_id),
            joint_state_text=format_joint_state(joints) if joints else None,
            tool_pose_text=format_tool_pose(pose) if pose else None,
        )


__all__ = [
    "BASE_FRAME",
    "JOINT_STATE_NAMES",
    "JointStateData",
    "PoseData",
    "Stamp",
    "StreamMessages",
    "format_joint_state",
    "format_tool_pose",
    "joint_state",
    "quaternion_from_abc",
    "tool_pose",
]
