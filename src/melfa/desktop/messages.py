"""What the server sends, read into the live protocol's own models (`melfa.live.messages`:
the models the server builds, so there is one declaration of every message). Pure, no Qt.

A message this client does not know (a newer server) reads as None, and the feed goes on.
"""

from __future__ import annotations

from collections.abc import Mapping

from pydantic import ValidationError

from melfa.live.messages import (
    SERVER,
    ActorOut,
    AlarmOut,
    CommandResultMessage,
    ErrorMessage,
    Hello,
    JogHeartbeatAck,
    JogMessage,
    LinkMessage,
    ProgressMessage,
    QueueMessage,
    StateMessage,
    StateOut,
)
from melfa.protocol.advice import Fix

LiveMessage = (
    Hello
    | StateMessage
    | LinkMessage
    | CommandResultMessage
    | ProgressMessage
    | JogMessage
    | JogHeartbeatAck
    | ErrorMessage
    | QueueMessage
)
"""The messages this client acts on (the rest of `melfa.live.messages.ServerMessage` it
reads and lets pass)."""


def parse_message(data: object) -> LiveMessage | None:
    """The typed message, or None for one this client does not act on (or cannot read).

    >>> parse_message({"type": "link", "status": "lost", "detail": "no reply",
    ...                "at": "2026-11-24T09:02:00Z"}).status
    <LinkStatus.LOST: 'lost'>
    >>> parse_message({"type": "pong", "id": 1}) is None, parse_message({"type": "new"})
    (True, None)
    """
    try:
        message = SERVER.validate_python(data)
    except ValidationError:
        return None
    return message if isinstance(message, LiveMessage) else None


def read_state(data: object) -> StateOut:
    """`GET /api/robot/state`'s reply (the ``state`` message's model without its type)."""
    return StateOut.model_validate(data)


def alarm_said(alarm: AlarmOut) -> str:
    """The code and the sentence, as every view shows an alarm.

    >>> alarm_said(AlarmOut(number=2000, text="Servo off", code="L2000",
    ...                     message="The servo is off."))
    'L2000 The servo is off.'
    """
    return f"{alarm.code} {alarm.message or alarm.text}".strip()


def actor_name(actor: ActorOut | None) -> str | None:
    """Whose event it is (None: the service itself)."""
    return None if actor is None else actor.user


def error_fix(message: ErrorMessage) -> Fix | None:
    """The one-click fix of a refused client message (``error.detail.fix``), if any."""
    detail = message.error.detail
    return parse_fix(detail.get("fix")) if isinstance(detail, Mapping) else None


FIXES_OFFERED = frozenset({Fix.SERVO_ON_RETRY, Fix.RESET_ALARM, Fix.LOAD_PROJECT, Fix.STOP})
"""The one-click fixes this client can do (`presenter.Presenter.apply_fix`; adding a point
needs the IDE's points editor). Every part of the client that shows a fix's button (a
notice, the alarm's row) asks `offered_fix`."""


def offered_fix(fix: Fix | None) -> Fix | None:
    """``fix`` when this client can do it (`FIXES_OFFERED`), else None: no button.

    >>> offered_fix(Fix.RESET_ALARM), offered_fix(None)
    (<Fix.RESET_ALARM: 'reset-alarm'>, None)
    """
    return fix if fix in FIXES_OFFERED else None


def parse_fix(value: object) -> Fix | None:
    """The server's ``fix`` word (`melfa.protocol.advice.Fix`), or None (unknown: no button)."""
    try:
        return Fix(value)
    except ValueError:
        return None


__all__ = [
    "FIXES_OFFERED",
    "LiveMessage",
    "actor_name",
    "alarm_said",
    "error_fix",
    "offered_fix",
    "parse_fix",
    "parse_message",
    "read_state",
]
