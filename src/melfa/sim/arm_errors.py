"""The simulated arm's refusals: `ArmError`s carrying the controller's error numbers.

The numbers are the controller's (protocol.md §2.3):

| class | number | when |
|---|---|---|
| `ServoOff` | L2000 | a move or jog with the servo off |
| `JogRefused` | L2030 | a jog the arm cannot take (moving, unsupported mode) |
| `JointLimitError` | H2160 | a target or path sample outside a joint range or interference limit |
| `OutOfRange` | L2600 | no IK solution: out of reach, or a path through a singularity [GUESS] |
| `IllegalPosition` | L2800 | impossible geometry: collinear arc points, FL1 change in MVS [GUESS] |
| `ArmBusy` | L5640 | a new move while one is running (the busy reply S6/S7 rely on) |

[GUESS] L2600 ("position data exceeds the limit") rather than H2180-H2193 (X/Y/Z data exceeds
the limit) for unreachable targets: the latter read like the XYZ operating-range check.
"""

from __future__ import annotations

from melfa.kin import InterferenceLimitExceeded, JointLimitExceeded, KinematicsError, Unreachable
from melfa.protocol.error_table import (
    BUSY,
    ILLEGAL_POSITION_DATA,
    JOG_REFUSED,
    JOINT_LIMIT,
    POSITION_LIMIT,
    SERVO_OFF,
    ErrorLevel,
    error_code,
)
from melfa.sim.paths import IllegalMove

ERR_SERVO_OFF = SERVO_OFF
ERR_JOG_REFUSED = JOG_REFUSED
ERR_JOINT_LIMIT = JOINT_LIMIT
ERR_OUT_OF_RANGE = POSITION_LIMIT
ERR_ILLEGAL_POSITION = ILLEGAL_POSITION_DATA
ERR_BUSY = BUSY


class ArmError(Exception):
    """A refusal by the (simulated) controller, with its error number and level."""

    number: int = 0
    level: ErrorLevel = ErrorLevel.LOW

    def __init__(self, message: str, number: int | None = None) -> None:
        if number is not None:
            self.number = number
        self.message = message
        super().__init__(f"{self.code}: {message}")

    @property
    def code(self) -> str:
        """Number with its level letter, as the error list writes it: "H2160"."""
        return error_code(self.number, self.level)


class ServoOff(ArmError):
    number = ERR_SERVO_OFF


class JogRefused(ArmError):
    number = ERR_JOG_REFUSED


class JointLimitError(ArmError):
    """`joint` is 1-based, or None for an interference limit (several joints together)."""

    number = ERR_JOINT_LIMIT
    level = ErrorLevel.HIGH

    def __init__(self, message: str, joint: int | None = None, value: float | None = None) -> None:
        self.joint = joint
        self.value = value
        super().__init__(message)


class OutOfRange(ArmError):
    number = ERR_OUT_OF_RANGE


class IllegalPosition(ArmError):
    number = ERR_ILLEGAL_POSITION


class ArmBusy(ArmError):
    number = ERR_BUSY


def from_kinematics(exc: KinematicsError) -> ArmError:
    """The controller error for a kinematics refusal."""
    if isinstance(exc, JointLimitExceeded):
        return JointLimitError(str(exc), exc.joint, exc.value)
    if isinstance(exc, InterferenceLimitExceeded):
        return JointLimitError(str(exc))
    if isinstance(exc, Unreachable):
        return OutOfRange(str(exc))
    if isinstance(exc, IllegalMove):
        return IllegalPosition(str(exc))
    return OutOfRange(str(exc))
