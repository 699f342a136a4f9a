"""What the robot is doing, as one word every view shows the same way (the header, the
activity line, the jog pad, the 3D view, the desktop client, ROS).

Pure: computed from the polled state and the service's note of the motion it last started
(`Motion`), so a *Move to* is never reported as "running line 50" and a held jog key never
as "not moving".
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class Activity(enum.Enum):
    OFFLINE = "offline"
    """The robot link is down."""
    UPLOADING = "uploading"
    ALARM = "alarm"
    JOGGING = "jogging"
    MOVING_TO = "moving-to"
    """A *Move to* (or a step jog, an executed statement) is moving the arm."""
    RUNNING = "running"
    PAUSED = "paused"
    """The program was stopped mid-way: *Run* continues, *Reset program* starts over."""
    MOVING = "moving"
    """The arm moves and melfa did not start it (the pendant, another program)."""
    IDLE = "idle"


class MotionKind(enum.Enum):
    RUN = "run"
    MOVE_TO = "move_to"
    STEP = "step"
    EXEC = "exec"


@dataclass(frozen=True)
class Motion:
    """The motion the service last started, and what to call it (``P1``, ``X+``)."""

    kind: MotionKind
    label: str = ""


@dataclass(frozen=True)
class Facts:
    """The polled facts `activity_of` needs (from `StateSnapshot`)."""

    connected: bool
    busy: str | None = None
    alarm: bool = False
    jogging: bool = False
    running: bool | None = None
    program_running: bool | None = None
    paused: bool | None = None
    moving: bool | None = None
    line: int | None = None


def activity_of(facts: Facts, motion: Motion | None) -> tuple[Activity, str]:
    """The activity and its detail (the target, the line).

    >>> activity_of(Facts(True, running=True, program_running=False),
    ...             Motion(MotionKind.MOVE_TO, "P1"))
    (<Activity.MOVING_TO: 'moving-to'>, 'P1')
    >>> activity_of(Facts(True, running=True, program_running=True, line=30), None)
    (<Activity.RUNNING: 'running'>, 'line 30')
    """
    if not facts.connected:
        return Activity.OFFLINE, ""
    if facts.busy:
        return Activity.UPLOADING, ""
    if facts.alarm:
        return Activity.ALARM, ""
    if facts.jogging:
        return Activity.JOGGING, motion.label if motion and motion.kind is MotionKind.STEP else ""
    moving = bool(facts.running) or bool(facts.moving)
    if facts.program_running or (facts.running and motion and motion.kind is MotionKind.RUN):
        return Activity.RUNNING, f"line {facts.line}" if facts.line else ""
    if moving and motion is not None and motion.kind is not MotionKind.RUN:
        return Activity.MOVING_TO, motion.label
    if facts.paused:
        return Activity.PAUSED, f"line {facts.line}" if facts.line else ""
    if moving:
        return Activity.MOVING, ""
    return Activity.IDLE, ""


__all__ = ["Activity", "Facts", "Motion", "MotionKind", "activity_of"]
