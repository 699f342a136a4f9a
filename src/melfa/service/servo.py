"""The servo before a move: the one rule every frontend (IDE, desktop, ROS) shares.

The controller starts with its servo off, and a move sent then is refused with L2000 and
leaves an alarm that blocks the next *Run*. So before a command that moves the arm the
service reads ``STATE`` and, when the servo is off, does what the caller chose:

- `ServoPolicy.TURN_ON`: the operator asked to move, so switch the servo on first (one
  ``SRVON``, audited as its own ``servo`` entry naming the move it was for);
- `ServoPolicy.ASK`: send nothing and raise `ServoOff` (a `ControllerError` numbered
  2000, like the controller's own refusal) so the frontend can ask once and retry with
  ``TURN_ON``;
- `ServoPolicy.LEAVE`: no check; the controller refuses a move itself (statements that
  may not move, such as ``M1=5``, and callers that did not choose).

A stale L2000 alarm (left by a move refused earlier) is reset before ``SRVON``: it says
only that the servo was off, which is being fixed.
"""

from __future__ import annotations

import enum

from melfa.protocol import error_text
from melfa.protocol.answers import RunStatus, Status
from melfa.protocol.error_table import SERVO_OFF
from melfa.robot import ControllerError, Robot


class ServoPolicy(enum.Enum):
    """What a moving command does when it finds the servo off."""

    TURN_ON = "turn-on"
    ASK = "ask"
    LEAVE = "leave"


class ServoOff(ControllerError):
    """The servo is off and the caller did not ask to switch it on: nothing was sent.
    Numbered 2000 like the controller's refusal, so one error text serves both."""

    def __init__(self, command: str = "") -> None:
        super().__init__(SERVO_OFF, error_text(SERVO_OFF), command=command)


def servo_is_on(status: Status) -> bool:
    """The servo bit of a ``STATE`` answer's status field."""
    return RunStatus.SERVO_ON in status.run


def ensure_servo(robot: Robot, policy: ServoPolicy, command: str = "") -> bool:
    """Worker side: apply ``policy`` before a move. Returns True when it switched the
    servo on (the caller audits that), False when nothing was needed."""
    if policy is ServoPolicy.LEAVE:
        return False
    status = robot.state().status  # STATE: every firmware answers it (DSTATE not all)
    if servo_is_on(status):
        return False
    if policy is ServoPolicy.ASK:
        raise ServoOff(command)
    if status.error == SERVO_OFF:
        robot.reset_alarm()
    robot.servo(True)
    return True


__all__ = ["ServoOff", "ServoPolicy", "ensure_servo", "servo_is_on"]
