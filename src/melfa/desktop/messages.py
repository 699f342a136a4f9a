"""Typed values of what the server sends (docs/api.md), parsed from JSON. Pure, no Qt.

The WebSocket ``state`` message and `GET /api/robot/state` share one shape; ``link``,
``result``, ``progress`` and ``hello`` are the events the client shows. Unknown message
types parse to None so a newer server does not break an older client.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from melfa.protocol.advice import Fix, error_code

JOINT_NAMES = ("J1", "J2", "J3", "J4", "J5", "J6")
POSE_NAMES = ("X", "Y", "Z", "A", "B", "C")


class LinkStatus(enum.Enum):
    """The robot link as the server sees it (the ``link`` message's ``status``)."""

    CONNECTING = "connecting"
    CONNECTED = "connected"
    RECONNECTING = "reconnecting"
    LOST = "lost"
    CLOSED = "closed"
    UNKNOWN = "unknown"

    @classmethod
    def parse(cls, value: object) -> LinkStatus:
        """
        >>> LinkStatus.parse("connected"), LinkStatus.parse("bogus")
        (<LinkStatus.CONNECTED: 'connected'>, <LinkStatus.UNKNOWN: 'unknown'>)
        """
        try:
            return cls(value)
        except ValueError:
            return cls.UNKNOWN


@dataclass(frozen=True)
class Alarm:
    """The controller's error: ``message`` is the student's sentence (`melfa.protocol.advice`),
    ``code`` the manual's (``L2000``), ``fix`` the one action that clears it, if any."""

    number: int
    text: str
    code: str = ""
    message: str = ""
    fix: Fix | None = None

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Alarm:
        """
        >>> a = Alarm.from_json({"number": 2000, "text": "Servo off", "code": "L2000",
        ...                      "message": "The servo is off.", "fix": "servo-on-retry"})
        >>> a.said, a.fix
        ('L2000 The servo is off.', <Fix.SERVO_ON_RETRY: 'servo-on-retry'>)
        """
        number = _opt_int(data.get("number")) or 0
        return cls(
            number=number,
            text=str(data.get("text") or ""),
            code=str(data.get("code") or error_code(number)),
            message=str(data.get("message") or data.get("text") or ""),
            fix=parse_fix(data.get("fix")),
        )

    @property
    def said(self) -> str:
        """The code and the sentence, as every view shows an alarm."""
        return f"{self.code} {self.message}".strip()


def parse_fix(value: object) -> Fix | None:
    """The server's ``fix`` word (`melfa.protocol.advice.Fix`), or None (unknown: no button)."""
    try:
        return Fix(value)
    except ValueError:
        return None


def _opt_time(value: object) -> datetime | None:
    """
    >>> _opt_time("2026-11-24T09:02:00+00:00").minute, _opt_time("soon"), _opt_time(None)
    (2, None, None)
    """
    if not isinstance(value, str):
        return None
    try:
        return datetime.fromisoformat(value)
    except ValueError:
        return None


def _six(value: object) -> tuple[float, ...] | None:
    if not isinstance(value, list | tuple) or not value:
        return None
    try:
        return tuple(float(v) for v in value)
    except (TypeError, ValueError):
        return None


def _opt_bool(value: object) -> bool | None:
    return value if isinstance(value, bool) else None


def _opt_int(value: object) -> int | None:
    return value if isinstance(value, int) and not isinstance(value, bool) else None


@dataclass(frozen=True)
class RobotState:
    """A state snapshot: pose is X, Y, Z (mm), A, B, C (deg); joints J1…J6 (deg)."""

    seq: int
    link: LinkStatus
    joints: tuple[float, ...] | None
    pose: tuple[float, ...] | None
    flags: tuple[int, ...] | None
    servo: bool | None
    running: bool | None
    moving: bool | None
    program: str
    line: int | None
    override: int | None
    alarm: Alarm | None
    busy: str | None
    lease_holder: str | None
    activity: str = ""
    """The service's one word for what the robot does (`idle`, `jogging`, `running`, …)."""
    activity_detail: str = ""
    jogging: bool = False
    lease_state: str | None = None
    lease_since: datetime | None = None

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> RobotState:
        """
        >>> s = RobotState.from_json({"seq": 3, "link": "connected", "pose": [1, 2, 3, 4, 5, 6],
        ...                           "running": True, "line": 40, "program": "1.MB4"})
        >>> s.pose, s.running, s.line, s.joints
        ((1.0, 2.0, 3.0, 4.0, 5.0, 6.0), True, 40, None)
        """
        alarm = data.get("alarm")
        flags = data.get("flags")
        return cls(
            seq=_opt_int(data.get("seq")) or 0,
            link=LinkStatus.parse(data.get("link")),
            joints=_six(data.get("joints")),
            pose=_six(data.get("pose")),
            flags=tuple(int(f) for f in flags) if isinstance(flags, list) else None,
            servo=_opt_bool(data.get("servo")),
            running=_opt_bool(data.get("running")),
            moving=_opt_bool(data.get("moving")),
            program=str(data.get("program") or ""),
            line=_opt_int(data.get("line")),
            override=_opt_int(data.get("override")),
            alarm=Alarm.from_json(alarm) if isinstance(alarm, Mapping) else None,
            busy=data.get("busy") if isinstance(data.get("busy"), str) else None,
            lease_holder=(
                data.get("lease_holder") if isinstance(data.get("lease_holder"), str) else None
            ),
            activity=str(data.get("activity") or ""),
            activity_detail=str(data.get("activity_detail") or ""),
            jogging=data.get("jogging") is True,
            lease_state=(
                data.get("lease_state") if isinstance(data.get("lease_state"), str) else None
            ),
            lease_since=_opt_time(data.get("lease_since")),
        )


@dataclass(frozen=True)
class Hello:
    """The first message on the socket: who we are to the server."""

    user: str
    role: str
    robot: str
    link: LinkStatus


@dataclass(frozen=True)
class LinkChanged:
    status: LinkStatus
    detail: str


@dataclass(frozen=True)
class CommandFinished:
    """A ``result`` message: any client's command finished (``actor`` may be someone else).
    ``error`` is already in the student's words (docs/api.md "Student-facing errors")."""

    command: str
    ok: bool
    error: str
    error_number: int | None
    actor: str | None


@dataclass(frozen=True)
class JogChanged:
    """A ``jog`` message: a hold-to-move jog began or ended, and why it ended."""

    actor: str | None
    active: bool
    reason: str


@dataclass(frozen=True)
class Acked:
    """An ``ack``: the server did what the message with ``id`` asked. ``jogging`` is False
    when a heartbeat found the jog already ended."""

    id: int | None
    op: str
    jogging: bool | None


@dataclass(frozen=True)
class Refused:
    """An ``error`` reply to a client message: the API's one error shape."""

    id: int | None
    code: str
    message: str
    fix: Fix | None


@dataclass(frozen=True)
class UploadProgress:
    """Bytes sent of an upload's total; ``actor`` is who uploads (None: the service)."""

    command: str
    sent: int
    total: int
    actor: str | None = None


LiveMessage = (
    Hello
    | RobotState
    | LinkChanged
    | CommandFinished
    | UploadProgress
    | JogChanged
    | Acked
    | Refused
)


def _actor(value: object) -> str | None:
    if isinstance(value, Mapping):
        return str(value.get("user"))
    return None


def parse_message(data: object) -> LiveMessage | None:
    """The typed message, or None for types this client does not show.

    >>> parse_message({"type": "link", "status": "lost", "detail": "no reply"})
    LinkChanged(status=<LinkStatus.LOST: 'lost'>, detail='no reply')
    >>> parse_message({"type": "pong", "id": 1}) is None
    True
    """
    if not isinstance(data, Mapping):
        return None
    kind = data.get("type")
    if kind == "state":
        return RobotState.from_json(data)
    if kind == "link":
        return LinkChanged(LinkStatus.parse(data.get("status")), str(data.get("detail") or ""))
    if kind == "result":
        return CommandFinished(
            command=str(data.get("command") or ""),
            ok=bool(data.get("ok")),
            error=str(data.get("error") or ""),
            error_number=_opt_int(data.get("error_number")),
            actor=_actor(data.get("actor")),
        )
    if kind == "progress":
        return UploadProgress(
            command=str(data.get("command") or ""),
            sent=_opt_int(data.get("sent")) or 0,
            total=_opt_int(data.get("total")) or 0,
            actor=_actor(data.get("actor")),
        )
    if kind == "jog":
        return JogChanged(
            actor=_actor(data.get("actor")),
            active=data.get("active") is True,
            reason=str(data.get("reason") or ""),
        )
    if kind == "ack":
        jogging = data.get("jogging")
        return Acked(_opt_int(data.get("id")), str(data.get("op") or ""), _opt_bool(jogging))
    if kind == "error":
        error = data.get("error")
        error = error if isinstance(error, Mapping) else {}
        detail = error.get("detail")
        return Refused(
            id=_opt_int(data.get("id")),
            code=str(error.get("code") or ""),
            message=str(error.get("message") or "the server refused"),
            fix=parse_fix(detail.get("fix")) if isinstance(detail, Mapping) else None,
        )
    if kind == "hello":
        return Hello(
            user=str(data.get("user") or ""),
            role=str(data.get("role") or ""),
            robot=str(data.get("robot") or ""),
            link=LinkStatus.parse(data.get("link")),
        )
    return None


__all__ = [
    "JOINT_NAMES",
    "POSE_NAMES",
    "Acked",
    "Alarm",
    "CommandFinished",
    "Hello",
    "JogChanged",
    "LinkChanged",
    "LinkStatus",
    "LiveMessage",
    "Refused",
    "RobotState",
    "UploadProgress",
    "parse_fix",
    "parse_message",
]
