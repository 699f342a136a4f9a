"""The robot client: one session with one CR2B-574 controller, synchronous.

`Robot` opens the session once, takes the operation rights when an operation needs them, and
offers typed operations (upload, run, stop, exec, jog, hand, servo, override, read joints/
pose/state, status with the active alarm, alarm reset). Refusals raise
`ControllerError(number, message)`; link failures raise `melfa.link.LinkError`; garbled
replies raise `melfa.protocol.RemoteProtocolError`. `stop` may be called from any thread,
even while another request is in flight.
"""

from melfa.robot.channel import Channel
from melfa.robot.client import Robot
from melfa.robot.edit import (
    Progress,
    SavedNotConfirmed,
    SaveOutcomeUnknown,
    UploadReport,
    VerifyFailed,
)
from melfa.robot.errors import ControllerError, RobotError, Stopped, UploadRefused
from melfa.robot.opener import open_robot_link
from melfa.robot.settings import HandMethod, JogMethod, RobotSettings
from melfa.robot.status import Alarm, ControllerStatus
from melfa.robot.upload import UploadPreparationError, sendable

__all__ = [
    "Alarm",
    "Channel",
    "ControllerError",
    "ControllerStatus",
    "HandMethod",
    "JogMethod",
    "Progress",
    "Robot",
    "RobotError",
    "RobotSettings",
    "SaveOutcomeUnknown",
    "SavedNotConfirmed",
    "Stopped",
    "UploadPreparationError",
    "UploadRefused",
    "UploadReport",
    "VerifyFailed",
    "open_robot_link",
    "sendable",
]
