"""Robot-level failures. Link failures stay `melfa.link.LinkError`; garbled replies stay
`melfa.protocol.RemoteProtocolError`; a controller "no" is a `ControllerError`."""

from __future__ import annotations


class RobotError(Exception):
    """Base of the robot client's own errors."""


class ControllerError(RobotError):
    """The controller refused: ``QeR<number>``. ``message`` is the controller's own text
    (``ERRORMES``) when it could be read, else melfa's table."""

    def __init__(
        self, number: int, message: str, *, command: str = "", alarm: bool = False
    ) -> None:
        self.number = number
        self.message = message
        self.command = command
        self.alarm = alarm
        where = f" (to {command})" if command else ""
        super().__init__(f"controller refused{where}: error {number:04d} {message}")


class UploadRefused(ControllerError):
    """An upload line the controller refused, mapped back to the source text.

    ``line`` is the 1-based line in the text the caller passed, ``column`` the controller's
    character position (1-based) within that line, ``text`` the line as sent.
    """

    def __init__(
        self, number: int, message: str, *, line: int, column: int, text: str, alarm: bool = False
    ) -> None:
        super().__init__(number, message, command="EMDAT", alarm=alarm)
        self.line = line
        self.column = column
        self.text = text
        self.args = (
            f"controller refused line {line}, column {column}: error {number:04d} {message}"
            f"\n    {text}",
        )


class Stopped(RobotError):
    """The operation was interrupted because `Robot.stop` was called meanwhile."""
