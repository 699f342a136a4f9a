"""Typed values of what the server sends (docs/api.md), parsed from JSON. Pure, no Qt.

The WebSocket ``state`` message and `GET /api/robot/state` share one shape; ``link``,
``result``, ``progress`` and ``hello`` are the events the client shows. Unknown message
types parse to None so a newer server does not break an older client.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

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
    number: int
    text: str


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
            alarm=(
                Alarm(int(alarm.get("number", 0)), str(alarm.get("text", "")))
                if isinstance(alarm, Mapping)
                else None
            ),
            busy=data.get("busy") if isinstance(data.get("busy"), str) else None,
            lease_holder=(
                data.get("lease_holder") if isinstance(data.get("lease_holder"), str) else None
            ),
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
    """A ``result`` message: any client's command finished (``actor`` may be someone else)."""

    command: str
    ok: bool
    error: str
    error_number: int | None
    actor: str | None


@dataclass(frozen=True)
class UploadProgress:
    command: str
    sent: int
    total: int


LiveMessage = Hello | RobotState | LinkChanged | CommandFinished | UploadProgress


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
    "Alarm",
    "CommandFinished",
    "Hello",
    "LinkChanged",
    "LinkStatus",
    "LiveMessage",
    "RobotState",
    "UploadProgress",
    "parse_message",
]
