"""Values and events of the service: who asks (`Actor`, defined in `melfa.service.actors`),
what the robot is doing (`StateSnapshot`) and what happened (the event dataclasses).

Every event is a frozen dataclass with a ``name``, the ``actor`` it concerns (None for the
service itself) and a UTC timestamp ``at`` (datasette's ``events.py`` habit). The web layer
serialises them with `event_to_dict`; it never invents events of its own.
"""

from __future__ import annotations

import datetime as dt
import enum
import ipaddress
from dataclasses import asdict, dataclass, field, fields
from typing import Any, ClassVar

from melfa.service.actors import SERVICE_ACTOR, Actor, Role
from melfa.service.slot import Slot
from melfa.vocab.activity import Activity
from melfa.vocab.commands import Command
from melfa.vocab.jog import JogEnd
from melfa.vocab.lease import LeaseReason
from melfa.vocab.link import LinkStatus
from melfa.vocab.robot_log import NoteKind


def utc_now() -> dt.datetime:
    """Now, timezone-aware UTC."""
    return dt.datetime.now(dt.UTC)


class JogFrame(enum.Enum):
    """Jog coordinate frames: tool (the thesis's requirement), base XYZ, joints."""

    TOOL = "tool"
    XYZ = "xyz"
    JOINT = "joint"


@dataclass(frozen=True)
class Alarm:
    """An active controller alarm with its text (``ERRORMES`` or melfa's table)."""

    number: int
    text: str
    step: int | None = None
    """The program's step when the alarm came while it ran (None: not a run-time error)."""
    line: int | None = None
    """That step's line in the loaded text (`Slot.line_of`), when melfa loaded it."""


@dataclass(frozen=True, kw_only=True)
class Event:
    """Base of every event: name, actor, UTC time."""

    NAME: ClassVar[str] = "event"
    actor: Actor | None = None
    at: dt.datetime = field(default_factory=utc_now)

    @property
    def name(self) -> str:
        return self.NAME


@dataclass(frozen=True, kw_only=True)
class StateSnapshot(Event):
    """Everything known about the robot at one moment. Fields are None until first read.

    ``pose_measured`` is False when the pose was computed from the joints (forward
    kinematics with the tool offset learned from the last PPOSF) rather than read.
    """

    NAME: ClassVar[str] = "state"
    seq: int = 0
    link: LinkStatus = LinkStatus.CONNECTING
    joints: tuple[float, ...] | None = None
    pose: tuple[float, ...] | None = None
    """X, Y, Z (mm), A, B, C (degrees)."""
    pose_measured: bool = False
    flags: tuple[int, int] | None = None
    servo: bool | None = None
    running: bool | None = None
    moving: bool | None = None
    program: str = ""
    line: int | None = None
    override: int | None = None
    speed: float | None = None
    """TCP end speed in mm/s from the last position reply."""
    alarm: Alarm | None = None
    hands: tuple[bool | None, ...] = ()
    """Hands 1…8: True open, False closed, None unknown."""
    busy: str | None = None
    """The long operation holding the line (``upload``), polling paused meanwhile."""
    jogging: bool = False
    lease_holder: str | None = None
    lease_since: dt.datetime | None = None
    """When the holder took the lease (UTC)."""
    lease_state: str | None = None
    """The holder's connection: ``connected``, ``no connection`` (REST only) or
    ``disconnected, robot moving`` (`melfa.vocab.lease.HolderState`)."""
    program_running: bool | None = None
    """The program runs (``running`` is the controller's RUN bit, also set by an EXEC move)."""
    paused: bool | None = None
    """The program was stopped mid-way (STOP without PROGRAM SELECT)."""
    activity: Activity = Activity.OFFLINE
    """What the robot does, the one word every view shows (`melfa.vocab.activity`)."""
    activity_detail: str = ""
    """The target of a move (``P1``) or the running line (``line 30``)."""
    slot: Slot | None = None
    """What melfa loaded into the controller's slot, by whom, when (`melfa.service.slot`:
    the one record of it, which the instructor's gate and the run recorder read too); None:
    nothing known (nothing loaded since the service started, a failed load, points onto a
    program not known, a delete)."""


@dataclass(frozen=True, kw_only=True)
class LinkStatusChanged(Event):
    """The link went up, down, or is being reopened."""

    NAME: ClassVar[str] = "link"
    status: LinkStatus
    detail: str = ""


@dataclass(frozen=True, kw_only=True)
class CommandResult(Event):
    """A command finished: ``ok`` only after the controller answered. ``error_number`` is
    the controller's error number when it refused."""

    NAME: ClassVar[str] = "result"
    command_id: int
    command: Command
    ok: bool
    error: str = ""
    error_number: int | None = None


@dataclass(frozen=True, kw_only=True)
class UploadProgress(Event):
    """Bytes of an upload sent so far, out of ``total``."""

    NAME: ClassVar[str] = "progress"
    command_id: int
    command: Command
    sent: int
    total: int


@dataclass(frozen=True, kw_only=True)
class LeaseChanged(Event):
    """The operator lease moved: ``holder`` None means free. ``actor`` caused it."""

    NAME: ClassVar[str] = "lease"
    holder: Actor | None
    previous: Actor | None
    reason: LeaseReason
    since: dt.datetime | None = None
    holder_state: str | None = None
    """As `StateSnapshot.lease_state`."""
    command: Command | None = None
    """The command that took a free lease (``reason``: `LeaseReason.TAKEN_BY_COMMAND`)."""


@dataclass(frozen=True, kw_only=True)
class JogChanged(Event):
    """A hold-to-move jog began or ended; an end says why (``end``, `JogEnd`), who caused
    it when a person did (``by``: STOP, take-over) and the controller's text of a refusal
    (``detail``)."""

    NAME: ClassVar[str] = "jog"
    active: bool
    frame: JogFrame | None = None
    axis: int | None = None
    direction: int | None = None
    end: JogEnd | None = None
    by: str | None = None
    detail: str = ""


@dataclass(frozen=True, kw_only=True)
class AuditEvent(Event):
    """Who asked for what that can move or change the robot, and what came of it.

    One command gives two entries with the same ``command_id``: ``result="accepted"`` when
    it is queued (or ``"refused: …"`` when the service turns it down), then ``"ok"`` or
    ``"failed: …"`` when the controller's reply arrives.
    """

    NAME: ClassVar[str] = "audit"
    command_id: int
    command: Command
    detail: str = ""
    result: str = "accepted"
    moves: bool = True


@dataclass(frozen=True, kw_only=True)
class RobotNote(Event):
    """Something that happened to the robot that no command asked for (control changed
    hands, an alarm came or went, the link went down or up), for the audit log and so the
    robot's log (`melfa.vocab.robot_log`). Its facts are codes and names, never words."""

    NAME: ClassVar[str] = "note"
    kind: NoteKind
    facts: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, kw_only=True)
class ThesisOutput(Event):
    """A string the thesis's Execute Node would publish on a ROS topic (``tool_pose``,
    ``joint_state``)."""

    NAME: ClassVar[str] = "thesis"
    topic: str
    text: str


def event_to_dict(event: Event) -> dict[str, Any]:
    """JSON-ready dict: enums as values, datetimes as ISO 8601, ``name`` included."""

    def plain(value: Any) -> Any:
        if isinstance(value, enum.Enum):
            return value.value
        if isinstance(value, dt.datetime):
            return value.isoformat()
        if isinstance(value, ipaddress.IPv4Address | ipaddress.IPv6Address):
            return str(value)
        if isinstance(value, dict):
            return {k: plain(v) for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [plain(v) for v in value]
        return value

    out: dict[str, Any] = {"name": event.name}
    raw = asdict(event)
    for f in fields(event):
        out[f.name] = plain(raw[f.name])
    return out


__all__ = [
    "SERVICE_ACTOR",
    "Actor",
    "Alarm",
    "AuditEvent",
    "CommandResult",
    "Event",
    "JogChanged",
    "JogFrame",
    "LeaseChanged",
    "LinkStatus",
    "LinkStatusChanged",
    "Role",
    "StateSnapshot",
    "ThesisOutput",
    "UploadProgress",
    "event_to_dict",
    "utc_now",
]
