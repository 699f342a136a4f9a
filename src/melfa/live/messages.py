"""The messages of ``/api/ws`` (docs/api.md "WebSocket"), one pydantic model each.

Server → client: `ServerMessage`, a union discriminated by ``type`` (an ``ack`` by its
``op`` as well). Client → server: `ClientMessage`, discriminated by ``type``. The server
sends only what `ServerMessage` validates, and acts only on what `ClientMessage`
validates; `tests/web/test_ws_schema.py` holds both to the committed schema.

Reading is lenient where a newer peer may add to a message (extra fields are ignored);
the schema says which fields there are (``additionalProperties: false`` on what the
server sends).
"""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter

from melfa.protocol.advice import Fix
from melfa.protocol.limits import HANDS
from melfa.vocab.activity import Activity
from melfa.vocab.commands import Command
from melfa.vocab.jog import JogEnd
from melfa.vocab.lease import LeaseReason
from melfa.vocab.link import LinkStatus
from melfa.vocab.queue import EntryState, QueueStep, TurnEnd
from melfa.vocab.refusals import Refusal

PROTOCOL_VERSION = 1

JogFrameName = Literal["tool", "xyz", "joint"]
RequestId = int | str | None
"""A client message's ``id``, echoed in its ``ack``/``error``/``pong`` (any JSON scalar)."""


class _Sent(BaseModel):
    """What the server sends: its fields, no others (in the schema); read leniently."""

    model_config = ConfigDict(extra="ignore", json_schema_extra={"additionalProperties": False})


class ActorOut(_Sent):
    """Who: a user and their role (``observer``, ``student``, ``instructor``)."""

    user: str
    role: str


class TargetRef(_Sent):
    id: str = Field(description="`lab` (the lab's robot) or `mine` (your own simulator).")
    kind: str = Field(description="`lab` (shared, leased) or `private` (yours alone).")
    label: str


class AlarmOut(_Sent):
    number: int
    text: str
    """The controller's own text."""
    code: str = ""
    """``L2000``: level letter and number, as the manual lists it."""
    message: str = ""
    """What happened and what to do, in a student's words (`melfa.protocol.advice`)."""
    fix: Fix | None = None
    """The one action that fixes it (``reset-alarm``, ``servo-on-retry``…), if any."""
    fix_label: str | None = None
    step: int | None = None
    """The program's step when the alarm came while it ran (None: not a run-time error)."""
    line: int | None = None
    """That step's line in the text loaded (the slot's step map), when melfa loaded it."""
    own: bool = False
    """The program raised it itself (its ``ERROR`` statement: 9000–9299)."""


class SlotOut(_Sent):
    """What melfa loaded into the controller's slot (`melfa.service.slot.Slot`)."""

    user: str = Field(description="Who loaded it.")
    at: datetime = Field(description="When the load finished (UTC).")
    fingerprint: str = Field(
        description="The program and points as sent; `run`'s `expect` names it."
    )
    workspace_id: int | None = None
    workspace: str = Field("", description="The workspace it came from, by name.")


class AdviceOut(_Sent):
    """A controller error in the student's words (`melfa.protocol.advice.Advice`)."""

    code: str
    message: str
    fix: Fix | None = None
    fix_label: str | None = None


class StateOut(_Sent):
    """The service's latest `StateSnapshot` (also the WebSocket ``state`` message)."""

    seq: int
    at: datetime
    link: LinkStatus
    joints: list[float] | None
    pose: list[float] | None
    pose_measured: bool
    flags: list[int] | None
    servo: bool | None
    running: bool | None
    moving: bool | None
    program: str
    line: int | None
    override: int | None
    speed: float | None
    alarm: AlarmOut | None
    hands: list[bool | None]
    busy: str | None
    jogging: bool
    lease_holder: str | None
    lease_since: datetime | None = None
    lease_state: str | None = Field(
        None, description="connected, no connection (REST only), disconnected, robot moving"
    )
    program_running: bool | None = None
    paused: bool | None = None
    activity: Activity = Activity.OFFLINE
    """The one word every view shows (`melfa.vocab.activity`)."""
    activity_detail: str = ""
    slot: SlotOut | None = None
    """Whose program the controller's slot holds (None: nothing known)."""


# --- server → client -----------------------------------------------------------------------


class Hello(_Sent):
    """The first message: who you are to the server, and the target's link."""

    type: Literal["hello"] = "hello"
    protocol: int = PROTOCOL_VERSION
    user: str
    role: str
    robot_role: str
    session: str
    robot: str
    target: TargetRef
    link: LinkStatus
    lease_holder: ActorOut | None
    snapshot_hz: float
    jog_override_ceiling: int
    stopped_when_you_left: datetime | None = Field(
        None,
        description="When your run or move on this robot was stopped because every "
        "connection of yours had closed (a reload, a closed tab); sent once.",
    )


class StateMessage(StateOut):
    type: Literal["state"] = "state"


class _Event(_Sent):
    """A service event: who it concerns (None: the service itself) and when (UTC)."""

    actor: ActorOut | None = None
    at: datetime


class PartOut(_Sent):
    """Where one part of the simulated cell is (docs/simulator.md): the centre of its
    bottom face (mm), its heading about the vertical (degrees), whether the gripper holds
    it and what it stands on (``table``, a fixture, a conveyor or another part)."""

    name: str
    position: list[float]
    rz: float
    held: bool
    on: str | None = None


class DebugMessage(_Event):
    """The debugger's state, on the socket of your simulator (docs/debugger.md)."""

    type: Literal["debug"] = "debug"
    session: int
    seq: int
    status: dict[str, Any]
    joints: list[float] | None = None
    pose: list[float] | None = None
    variables: list[dict[str, Any]] | None = None
    parts: list[PartOut] | None = None
    """The cell's parts as the run moves them (absent when the cell has none)."""
    ended: bool = False


class LinkMessage(_Event):
    type: Literal["link"] = "link"
    status: LinkStatus
    detail: str = ""


class ProgressMessage(_Event):
    type: Literal["progress"] = "progress"
    command_id: int
    command: Command
    label: str
    """The command in the student's words."""
    sent: int
    total: int


class CommandResultMessage(_Event):
    type: Literal["result"] = "result"
    command_id: int
    command: Command
    label: str
    ok: bool
    error: str = ""
    """What happened, in the student's words (never the request sent, nor a class name)."""
    error_number: int | None = None
    advice: AdviceOut | None = None


class LeaseMessage(_Event):
    type: Literal["lease"] = "lease"
    holder: ActorOut | None
    previous: ActorOut | None
    reason: LeaseReason
    """Why (a client shows `LeaseReason.words`)."""
    since: datetime | None = None
    holder_state: str | None = None
    command: Command | None = None
    """The command that took a free lease (a client names it by `Command.label`)."""


class JogMessage(_Event):
    """A hold-to-move jog began or ended: an end says why (``end``: a client shows
    `JogEnd.words`), who caused it (``by``) and a refusal's text (``detail``)."""

    type: Literal["jog"] = "jog"
    active: bool
    frame: JogFrameName | None = None
    axis: int | None = None
    direction: int | None = None
    end: JogEnd | None = None
    by: str | None = None
    detail: str = ""


class QueueStepOut(_Sent):
    """One transition of the queue (a client shows `QueueStep.words`)."""

    kind: QueueStep
    user: str | None = None
    by: str | None = None
    position: int | None = None
    seconds: float | None = None


class QueueEntryOut(_Sent):
    """A student waiting for the shared robot."""

    user: str
    position: int
    """1-based place in the line."""
    state: EntryState
    estimate: datetime
    """When their turn should start (pre-flight cycle times and the turn length)."""
    cycle_s: float | None = None
    """The queued text's pre-flight cycle time (simulated seconds)."""
    stale: bool = False
    """Their workspace's text changed since they queued it."""
    away: bool = False
    """No connection open: the place is kept for the grace time."""
    missed: int = 0
    offer_ends: datetime | None = None
    """While the arm is offered to them: the end of the claim window."""
    gate: Refusal | None = None
    """What the instructor's gate would say to the queued text now: ``cell-changed`` (the
    lab's cell was edited since it passed: it must pass pre-flight again before the turn),
    ``simulation-required`` (the gate was switched on since); null: it would load."""


class QueueTurnOut(_Sent):
    """Who is at the arm."""

    user: str
    started: datetime
    ends: datetime
    warned: bool
    """The turn ends soon (they were told)."""
    ending: bool
    """Time is up: the program finishes, nothing new starts."""
    away: bool
    held: bool
    """An instructor holds the arm; the turn's time left is kept."""
    left_s: float
    ready: bool
    """Attended mode: the supervisor said the arm is ready for the next run."""
    run_waiting: bool
    """Attended mode: a run waits for the supervisor's *Arm ready*."""


class QueueOut(_Sent):
    """The queue of a shared robot (also ``GET /api/queue``)."""

    target: str
    now: datetime
    """The server's time when this was sent (countdowns run from it)."""
    active: bool
    """Someone waits or is at the arm: only the queue gives the lease."""
    paused: bool
    attended: bool
    turn: QueueTurnOut | None
    entries: list[QueueEntryOut]
    claim_s: float
    turn_s: float
    at_turn_end: TurnEnd


class QueueMessage(QueueOut):
    """The queue changed (``steps``: what happened), or its state on connecting (no steps)."""

    type: Literal["queue"] = "queue"
    steps: list[QueueStepOut] = Field(default_factory=list)


class _Ack(_Sent):
    type: Literal["ack"] = "ack"
    id: RequestId = None


class JogStartAck(_Ack):
    op: Literal["jog_start"] = "jog_start"
    method: Literal["jog", "step"]
    """``step`` when the controller has no JOG command and the jog moves in steps."""


class JogHeartbeatAck(_Ack):
    """Only when a heartbeat found the jog already ended."""

    op: Literal["jog_heartbeat"] = "jog_heartbeat"
    jogging: Literal[False] = False


class JogReleaseAck(_Ack):
    op: Literal["jog_release"] = "jog_release"


class HandToggleAck(_Ack):
    op: Literal["hand_toggle"] = "hand_toggle"
    hand: int
    open: bool


class StopAck(_Ack):
    op: Literal["stop"] = "stop"


Ack = Annotated[
    JogStartAck | JogHeartbeatAck | JogReleaseAck | HandToggleAck | StopAck,
    Field(discriminator="op"),
]


class ErrorBody(_Sent):
    """The API's one error shape (docs/api.md "Error shape")."""

    code: str
    message: str
    status: int
    where: dict[str, Any] | None = None
    detail: dict[str, Any] | None = None


class ErrorMessage(_Sent):
    """A client message failed (``id`` is its id, None when it could not be read)."""

    type: Literal["error"] = "error"
    id: RequestId = None
    error: ErrorBody


class Pong(_Sent):
    type: Literal["pong"] = "pong"
    id: RequestId = None


ServerMessage = Annotated[
    Hello
    | StateMessage
    | DebugMessage
    | LinkMessage
    | ProgressMessage
    | CommandResultMessage
    | LeaseMessage
    | JogMessage
    | QueueMessage
    | Ack
    | ErrorMessage
    | Pong,
    Field(discriminator="type"),
]
"""Everything the server sends on ``/api/ws``."""

SERVER = TypeAdapter[ServerMessage](ServerMessage)


def parse_server(data: object) -> Any:
    """A server message as its model (raises `pydantic.ValidationError` if it is none).

    >>> parse_server({"type": "pong", "id": 7})
    Pong(type='pong', id=7)
    """
    return SERVER.validate_python(data)


# --- client → server -----------------------------------------------------------------------


class _Asked(BaseModel):
    """What a client sends: unknown fields are ignored (an older server reads a newer
    client), ``id`` is echoed in the reply."""

    model_config = ConfigDict(extra="ignore")
    id: RequestId = None


class Ping(_Asked):
    type: Literal["ping"] = "ping"


class JogStart(_Asked):
    """Start hold-to-move (needs the lease). ``axis`` is 0–5 or a name (``J1``, ``X``…),
    ``direction`` 1, -1, ``+`` or ``-``; the service checks both."""

    type: Literal["jog_start"] = "jog_start"
    frame: JogFrameName = "joint"
    axis: Annotated[int, Field(strict=True)] | str
    direction: Annotated[int, Field(strict=True)] | str
    servo_on: bool = False


class JogHeartbeat(_Asked):
    type: Literal["jog_heartbeat"] = "jog_heartbeat"


class JogRelease(_Asked):
    type: Literal["jog_release"] = "jog_release"


class HandToggle(_Asked):
    type: Literal["hand_toggle"] = "hand_toggle"
    hand: Annotated[int, Field(strict=True, ge=HANDS.start, le=HANDS[-1])] = 1


class Stop(_Asked):
    type: Literal["stop"] = "stop"


ClientMessage = Annotated[
    Ping | JogStart | JogHeartbeat | JogRelease | HandToggle | Stop,
    Field(discriminator="type"),
]
"""Everything the server accepts on ``/api/ws``."""

CLIENT = TypeAdapter[ClientMessage](ClientMessage)

CLIENT_TYPES = frozenset(
    model.model_fields["type"].default
    for model in (Ping, JogStart, JogHeartbeat, JogRelease, HandToggle, Stop)
)


def parse_client(data: object) -> Ping | JogStart | JogHeartbeat | JogRelease | HandToggle | Stop:
    """A client message as its model (raises `pydantic.ValidationError` if it is none).

    >>> parse_client({"type": "hand_toggle", "hand": 2, "id": 5})
    HandToggle(id=5, type='hand_toggle', hand=2)
    """
    return CLIENT.validate_python(data)


__all__ = [
    "CLIENT",
    "CLIENT_TYPES",
    "PROTOCOL_VERSION",
    "SERVER",
    "Ack",
    "ActorOut",
    "AdviceOut",
    "AlarmOut",
    "ClientMessage",
    "CommandResultMessage",
    "DebugMessage",
    "ErrorBody",
    "ErrorMessage",
    "HandToggle",
    "HandToggleAck",
    "Hello",
    "JogHeartbeat",
    "JogHeartbeatAck",
    "JogMessage",
    "JogRelease",
    "JogReleaseAck",
    "JogStart",
    "JogStartAck",
    "LeaseMessage",
    "LinkMessage",
    "Ping",
    "Pong",
    "ProgressMessage",
    "ServerMessage",
    "StateMessage",
    "StateOut",
    "Stop",
    "StopAck",
    "TargetRef",
    "parse_client",
    "parse_server",
]
