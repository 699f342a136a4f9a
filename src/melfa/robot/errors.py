"""Robot-level failures. Link failures stay `melfa.link.LinkError`; garbled replies stay
`melfa.protocol.RemoteProtocolError`; a controller "no" is a `ControllerError`."""

from __future__ import annotations

EXEC_PREFIX = "EXEC"


class RobotError(Exception):
    """Base of the robot client's own errors."""


def statement_of(command: str) -> str:
    """What the user asked for: an ``EXEC`` command shows as its statement.

    >>> statement_of("EXECMOV P1"), statement_of("SRVON")
    ('MOV P1', 'SRVON')
    """
    if command.upper().startswith(EXEC_PREFIX):
        return command[len(EXEC_PREFIX) :]
    return command


def describe(number: int, message: str) -> str:
    """The error as a person reads it, with its number exactly once.

    >>> describe(2600, "L2600 Position data exceeds the limit")
    'L2600 Position data exceeds the limit'
    >>> describe(9050, "user error")
    'error 9050: user error'
    """
    if f"{number:04d}" in message or str(number) in message.split():
        return message
    return f"error {number:04d}: {message}" if message else f"error {number:04d}"


class ControllerError(RobotError):
    """The controller refused: ``QeR<number>``. ``message`` is the controller's own text
    (``ERRORMES``) when it could be read, else melfa's table. ``command`` is what was sent
    (``EXECMOV P1``); ``alarm`` is true when the reply said an alarm is active (``Qer``).

    >>> str(ControllerError(2600, "L2600 Position data exceeds the limit", command="EXECMOV P9"))
    'the controller refused `MOV P9`: L2600 Position data exceeds the limit'
    """

    def __init__(
        self,
        number: int,
        message: str,
        *,
        command: str = "",
        alarm: bool = False,
        code: str | None = None,
    ) -> None:
        self.number = number
        self.message = message
        self.command = command
        self.alarm = alarm
        self.code = code or f"{number:04d}"
        """The number as the controller sent it: ``6020`` or ``602000000``."""
        what = f" `{statement_of(command)}`" if command else ""
        super().__init__(f"the controller refused{what}: {self.detail}")

    @property
    def detail(self) -> str:
        """``L2600 Position data exceeds the limit`` (number once, level letter if known)."""
        return describe(self.number, self.message)

    @property
    def statement(self) -> str:
        """The refused command as the user wrote it (no ``EXEC`` prefix)."""
        return statement_of(self.command)


class UploadRefused(ControllerError):
    """An upload line the controller refused, mapped back to the source text.

    ``line`` is the 1-based line in the text the caller passed as ``source`` (``program``
    or ``points``), ``column`` the controller's character position (1-based) within that
    line, ``text`` the line as sent.
    """

    def __init__(
        self,
        number: int,
        message: str,
        *,
        line: int,
        column: int,
        text: str,
        alarm: bool = False,
        source: str = "program",
    ) -> None:
        super().__init__(number, message, command="EMDAT", alarm=alarm)
        self.line = line
        self.column = column
        self.text = text
        self.source = source
        self.args = (
            f"the controller refused {source} line {line}, column {column}: {self.detail}"
            f"\n    {text}",
        )


class Stopped(RobotError):
    """The operation was interrupted because `Robot.stop` was called meanwhile."""
