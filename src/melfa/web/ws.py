"""`/api/ws`: one WebSocket per browser tab for live state, events and the jog dead-man, of
one target (``/api/ws?target=mine`` for the user's private simulator; the lab robot
by default).

Every message is a model of `melfa.live.messages` (the schema is ``docs/ws-schema.json``):
the server sends `ServerMessage`s (``state`` throttled per socket to
`WebSettings.snapshot_hz`, newest wins) and acts on `ClientMessage`s, read here into their
models before anything is done. docs/api.md has every field.

Each socket has its own subscription (the service's bus never waits for a reader) and its
own `Outbox` and sender task: nothing that reads or handles a message ever waits for the
browser to read, so a slow reader only delays itself and its STOP is still read at once.
Snapshots waiting to go out are merged (the newest wins); a socket whose answers pile up
beyond `OUTBOX_LENGTH` is closed. A binary frame is answered with an error. When a socket
closes, a jog it started is released; when the user's last connection closes, the service
ends their jog and lease (a move in progress keeps its owner, see `melfa.service.lease`).
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import json
import logging
import re
import time
from collections import deque
from typing import Any

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import ValidationError

from melfa.live.messages import (
    CLIENT_TYPES,
    CommandResultMessage,
    DebugMessage,
    ErrorBody,
    ErrorMessage,
    HandToggle,
    HandToggleAck,
    Hello,
    JogHeartbeat,
    JogHeartbeatAck,
    JogMessage,
    JogRelease,
    JogReleaseAck,
    JogStart,
    JogStartAck,
    LeaseMessage,
    LinkMessage,
    Ping,
    Pong,
    ProgressMessage,
    RequestId,
    ServerMessage,
    StateMessage,
    Stop,
    StopAck,
    TargetRef,
    parse_client,
)
from melfa.protocol.advice import advice_for
from melfa.protocol.limits import HANDS, span_text
from melfa.service import (
    Actor,
    AuditEvent,
    CommandResult,
    Event,
    JogChanged,
    LeaseChanged,
    LinkStatusChanged,
    ServiceClosed,
    ServoPolicy,
    StateSnapshot,
    Subscription,
    UploadProgress,
    event_to_dict,
)
from melfa.service.debugging import DebugUpdate
from melfa.service.queue_keeper import QueueChanged
from melfa.store import is_access_token
from melfa.vocab.commands import command_label
from melfa.web.config import SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.convert import actor_dict, actor_out, state_dict, target_dict
from melfa.web.deps import actor_of, find_session, peer_of
from melfa.web.errors import ApiError, from_robot
from melfa.web.guard import MessageGate, TooManySockets
from melfa.web.limits import origin_allowed as same_site
from melfa.web.queues import message_of_change, queue_message
from melfa.web.targets import LAB, Target, UnknownTarget

router = APIRouter()
_log = logging.getLogger("melfa.web.ws")

POLICY_VIOLATION = 1008
GOING_AWAY = 1001
MAX_MESSAGE_CHARS = 4096
QUEUE_LENGTH = 32
"""Messages of one socket waiting to be processed; beyond, 429 ``too-many-messages``."""
OUTBOX_LENGTH = 256
"""Messages other than snapshots waiting for a browser that does not read; beyond, the
socket is closed (the dead-man then ends its jog)."""
MOVING = frozenset({"jog_start", "hand_toggle"})
"""Messages after which the arm moves: their session is re-read first."""


def message_of(event: Event) -> ServerMessage | None:
    """The WebSocket message for a service event (None: not sent to browsers)."""
    if isinstance(event, StateSnapshot):
        return StateMessage.model_validate(state_dict(event))
    if isinstance(event, QueueChanged):
        return message_of_change(event)
    if isinstance(event, AuditEvent) or not isinstance(
        event,
        DebugUpdate
        | LinkStatusChanged
        | UploadProgress
        | CommandResult
        | LeaseChanged
        | JogChanged,
    ):
        return None
    out = event_to_dict(event)
    out.pop("name", None)
    out["actor"] = actor_dict(event.actor)
    if isinstance(event, DebugUpdate):
        return DebugMessage.model_validate(out)
    if isinstance(event, LinkStatusChanged):
        return LinkMessage.model_validate(out)
    if isinstance(event, JogChanged):
        return JogMessage.model_validate(out)
    if isinstance(event, LeaseChanged):
        out["holder"] = actor_dict(event.holder)
        out["previous"] = actor_dict(event.previous)
        return LeaseMessage.model_validate(out)
    out["label"] = command_label(event.command)  # the command in a student's words
    if isinstance(event, UploadProgress):
        return ProgressMessage.model_validate(out)
    if not event.ok:
        # Student words, never the sent request or a Python class name.
        if event.error_number is not None:
            advice = advice_for(event.error_number)
            out["error"] = advice.message
            out["advice"] = advice.to_json()
        else:
            out["error"] = _PYTHON_PREFIX.sub("", event.error)
    return CommandResultMessage.model_validate(out)


_PYTHON_PREFIX = re.compile(r"^[A-Z][A-Za-z]*(Error|Closed|Down|Cancelled|Refused|Busy)?: ")


def origin_allowed(websocket: WebSocket, allowed: tuple[str, ...]) -> bool:
    """Browsers always send Origin: it must be this site (or configured), never ``null``.
    Non-browser clients without Origin still need the session cookie."""
    return same_site(websocket.headers.get("origin"), websocket.headers.get("host", ""), allowed)


class Outbox:
    """What waits for one browser, in order, bounded: a snapshot replaces a snapshot that
    is still the last thing waiting (the newest state wins), other messages queue up to
    ``limit``; `overflowed` once the browser is that far behind."""

    def __init__(self, limit: int = OUTBOX_LENGTH) -> None:
        self._items: deque[tuple[bool, str]] = deque()
        self.limit = limit
        self.overflowed = False
        self.ready = asyncio.Event()

    def put(self, text: str, *, state: bool = False) -> None:
        if state and self._items and self._items[-1][0]:
            self._items[-1] = (True, text)
        elif len(self._items) >= self.limit:
            self.overflowed = True
        else:
            self._items.append((state, text))
        self.ready.set()

    def take(self) -> str | None:
        return self._items.popleft()[1] if self._items else None

    def __len__(self) -> int:
        return len(self._items)


class SessionEnded(Exception):
    """The socket's session was revoked or expired: the socket closes."""


class Connection:
    """One open socket: its sender (throttled snapshots) and its receiver (commands)."""

    def __init__(
        self, websocket: WebSocket, context: WebContext, actor: Actor, target: Target
    ) -> None:
        self.websocket = websocket
        self.context = context
        self.target = target
        self.service = target.service
        self.actor = target.actor(actor)
        self.interval = 1.0 / context.settings.snapshot_hz
        self.jogging = False
        self.sent_states = 0
        self.token = ""
        self.gate: MessageGate | None = None
        self.tasks: list[asyncio.Task[None]] = []
        self.outbox = Outbox()
        self.ended: str | None = None
        self.checked = time.monotonic()
        self._stops: set[asyncio.Task[None]] = set()

    async def end(self, reason: str) -> None:
        """Close at once (the session was revoked): nothing more is read or done."""
        self.ended = self.ended or reason
        for task in self.tasks:
            task.cancel()

    async def authorise(self, kind: object) -> None:
        """Before acting on a message: the session still lives (in memory every time; a
        fresh read before anything that moves the arm, and every `socket_recheck_s`)."""
        gate = self.gate
        if gate is None:
            return
        handle = gate.handle
        if not handle.alive(dt.datetime.now(dt.UTC)):
            raise SessionEnded(handle.revoked or "the session ended")
        recheck = self.context.settings.limits.socket_recheck_s
        if kind in MOVING or time.monotonic() - self.checked >= recheck:
            session = await find_session(self.context, self.token)
            self.checked = time.monotonic()
            if not self.context.guard.confirm(handle, session):
                raise SessionEnded(handle.revoked or "the session ended")

    async def send(self, message: ServerMessage) -> None:
        """Queue ``message`` for the browser; never waits for it to read. Only what the
        protocol's models say (`melfa.live.messages`) goes out."""
        self.outbox.put(message.model_dump_json(), state=isinstance(message, StateMessage))
        if self.outbox.overflowed:
            await self.end("the browser does not read its messages")

    async def sender(self) -> None:
        """The one writer to the socket: the outbox, oldest first."""
        while True:
            await self.outbox.ready.wait()
            self.outbox.ready.clear()
            while (text := self.outbox.take()) is not None:
                await self.websocket.send_text(text)

    async def error(self, error: ApiError, request_id: RequestId = None) -> None:
        body = error.body()["error"]
        await self.send(ErrorMessage(id=_echo(request_id), error=ErrorBody.model_validate(body)))

    async def pump(self, sub: Subscription) -> None:
        """Events to the browser; at most one snapshot per interval, always the newest."""
        pending: StateSnapshot | None = None
        last = -1e9
        while True:
            timeout = None if pending is None else max(0.0, last + self.interval - time.monotonic())
            try:
                event = await sub.get_within(timeout)
            except ServiceClosed:
                return
            if event is None:
                assert pending is not None
                await self.send(StateMessage.model_validate(state_dict(pending)))
                self.sent_states += 1
                last, pending = time.monotonic(), None
                continue
            if isinstance(event, StateSnapshot):
                if pending is None and time.monotonic() - last >= self.interval:
                    await self.send(StateMessage.model_validate(state_dict(event)))
                    self.sent_states += 1
                    last = time.monotonic()
                else:
                    pending = event
                continue
            message = message_of(event)
            if message is not None:
                await self.send(message)

    async def receive(self) -> None:
        """Read messages: a ``stop`` is acted on at once in a task of its own (never behind
        another message); the rest are processed in order by `process`."""
        queue: asyncio.Queue[tuple[str, dict[str, Any]]] = asyncio.Queue(QUEUE_LENGTH)
        worker = asyncio.create_task(self.process(queue), name="ws-process")
        try:
            while True:
                frame = await self.websocket.receive()
                if frame["type"] == "websocket.disconnect":
                    raise WebSocketDisconnect(frame.get("code", 1000))
                text = frame.get("text")
                if not isinstance(text, str):
                    await self.error(
                        ApiError(400, "bad-message", "binary frames are not read: send JSON text")
                    )
                    continue
                parsed = await self.parse(text)
                if parsed is None:
                    continue
                if parsed.get("type") == "stop":
                    task = asyncio.create_task(self.run(text, parsed), name="ws-stop")
                    self._stops.add(task)
                    task.add_done_callback(self._stops.discard)
                    continue
                if queue.full():
                    await self.error(
                        ApiError(429, "too-many-messages", "too many messages waiting; slow down"),
                        _echo(parsed.get("id")),
                    )
                    continue
                queue.put_nowait((text, parsed))
        finally:
            worker.cancel()
            with contextlib.suppress(BaseException):
                await worker

    async def parse(self, text: str) -> dict[str, Any] | None:
        """The message as a dict, or None after answering with an error (or closing)."""
        try:
            if len(text) > MAX_MESSAGE_CHARS:
                raise ApiError(413, "too-large", "WebSocket messages are at most 4096 chars")
            problem = self.gate.check(text) if self.gate is not None else None
            if problem is not None:
                if self.gate is not None and self.gate.closing:
                    await self.end(problem)
                raise ApiError(400, "refused-message", problem)
            try:
                message = json.loads(text)
            except ValueError:
                raise ApiError(400, "bad-message", "messages are JSON objects") from None
            if not isinstance(message, dict):
                raise ApiError(400, "bad-message", "messages are JSON objects")
            return message
        except ApiError as exc:
            await self.error(exc, None)
            return None

    async def process(self, queue: asyncio.Queue[tuple[str, dict[str, Any]]]) -> None:
        while True:
            text, message = await queue.get()
            await self.run(text, message)

    async def run(self, text: str, message: dict[str, Any]) -> None:
        request_id = _echo(message.get("id"))
        try:
            request = read_request(message)
            if request.type != "stop":  # stop is everyone's, always
                await self.authorise(request.type)
            await self.handle(request)
        except SessionEnded as exc:
            await self.error(ApiError(401, "session-ended", str(exc)), request_id)
            await self.end(str(exc))
        except ApiError as exc:
            await self.error(exc, request_id)
        except Exception as exc:
            mapped = from_robot(exc)  # `InvalidArgument` is the only 422 among these
            if mapped is None:
                _log.exception("WebSocket message failed: %r", text[:200])
                mapped = ApiError(500, "internal-error", "the server failed; it was logged")
            await self.error(mapped, request_id)

    async def handle(self, request: ClientRequest) -> None:
        service = self.service
        actor = self.actor
        match request:
            case Ping():
                await self.send(Pong(id=request.id))
            case JogHeartbeat():
                alive = service.jog_heartbeat(actor)
                if not alive and self.jogging:
                    self.jogging = False
                    await self.send(JogHeartbeatAck(id=request.id))
            case JogStart():
                policy = ServoPolicy.TURN_ON if request.servo_on else ServoPolicy.ASK
                self.jogging = True
                try:
                    method = await service.jog_start(
                        actor, request.frame, request.axis, request.direction, servo=policy
                    )
                except BaseException:
                    self.jogging = False
                    raise
                await self.send(
                    JogStartAck.model_validate({"id": request.id, "method": method.value})
                )
            case JogRelease():
                self.jogging = False
                await service.jog_release(actor)
                await self.send(JogReleaseAck(id=request.id))
            case HandToggle():
                is_open = await service.hand_toggle(actor, request.hand)
                await self.send(HandToggleAck(id=request.id, hand=request.hand, open=is_open))
            case Stop():
                await self.target.stop(actor)
                await self.send(StopAck(id=request.id))


ClientRequest = Ping | JogStart | JogHeartbeat | JogRelease | HandToggle | Stop

_PROBLEMS = {
    "frame": "jog frame is tool, xyz or joint",
    "axis": "jog_start needs axis (0–5 or a name) and direction (1, -1, + or -)",
    "direction": "jog_start needs axis (0–5 or a name) and direction (1, -1, + or -)",
    "hand": f"hand is a number {span_text(HANDS)}",
    "id": "id is a number or a string",
}


def read_request(message: dict[str, Any]) -> ClientRequest:
    """The client's message as its model (`melfa.live.messages.ClientMessage`), or the
    API error that says what is wrong with it. A ``stop`` is always read: whatever came
    with it, STOP works."""
    kind = message.get("type")
    if not isinstance(kind, str) or kind not in CLIENT_TYPES:
        raise ApiError(400, "unknown-message", f"unknown message type {kind!r}"[:120])
    try:
        return parse_client(message)
    except ValidationError as exc:
        if kind == "stop":
            return Stop()
        first = exc.errors()[0]
        field = str(first["loc"][1]) if len(first["loc"]) > 1 else ""
        problem = _PROBLEMS.get(field, f"{kind}: {field} {first['msg']}".strip())
        where = {"field": field} if field else None
        raise ApiError(422, "invalid-value", problem, where=where) from None


def _echo(request_id: object) -> RequestId:
    """The id to echo: a number or a string, as the schema says (anything else: none)."""
    if isinstance(request_id, int | str) and not isinstance(request_id, bool):
        return request_id
    return None


@router.websocket("/api/ws")
async def live(websocket: WebSocket) -> None:
    context: WebContext = websocket.app.state.web
    # A personal access token in the URL (?token=) is a program's credential, not a
    # browser's ambient cookie: no origin check needed for it.
    token = websocket.query_params.get("token")
    if token is not None and not is_access_token(token):
        await websocket.close(code=POLICY_VIOLATION, reason="?token= takes a personal access token")
        return
    if token is None and not origin_allowed(websocket, context.settings.allowed_origins):
        await websocket.close(code=POLICY_VIOLATION, reason="origin not allowed")
        return
    session = await find_session(context, token or websocket.cookies.get(SESSION_COOKIE))
    if session is None:
        await websocket.close(code=POLICY_VIOLATION, reason="sign in first")
        return
    try:
        target = await context.targets.get(
            session.user.username, websocket.query_params.get("target", LAB)
        )
    except UnknownTarget:
        await websocket.close(code=POLICY_VIOLATION, reason="unknown target (lab or mine)")
        return
    service = target.service
    try:
        sub = service.subscribe()
    except ServiceClosed:
        await websocket.close(code=GOING_AWAY, reason="server shutting down")
        return
    connection = Connection(websocket, context, actor_of(session, peer_of(websocket)), target)
    connection.token = websocket.cookies.get(SESSION_COOKIE, "")
    try:
        handle = context.guard.open(session, connection.token, connection.end)
    except TooManySockets as exc:
        sub.close()
        await websocket.close(code=POLICY_VIOLATION, reason=str(exc)[:120])
        return
    connection.gate = MessageGate(context.guard, handle, context.settings.limits)
    await websocket.accept()
    actor = connection.actor
    if target.shared:
        context.sockets.add(actor)
    target.sockets += 1
    service.connect(actor)
    holder = service.lease_holder
    _log.info(
        "websocket open for %s on %s",
        actor.user,
        target.id,
        extra={"fields": {"user": actor.user, "session": actor.session_id, "target": target.id}},
    )
    await connection.send(
        Hello(
            user=session.user.username,
            role=session.user.role.value,
            robot_role=actor.role.value,
            session=actor.session_id,
            robot=context.settings.robot if target.shared else "sim",
            target=TargetRef.model_validate(target_dict(target)),
            link=service.link_status,
            lease_holder=actor_out(holder) if target.shared else None,
            snapshot_hz=context.settings.snapshot_hz,
            jog_override_ceiling=service.config.jog_override_ceiling,
            stopped_when_you_left=service.stopped_when_left(actor.user),
        )
    )
    for keeper in context.queues.values():  # everyone sees the shared robots' queues
        await connection.send(queue_message(keeper.view()))
    pump = asyncio.create_task(connection.pump(sub), name=f"ws-pump-{actor.user}")
    receive = asyncio.create_task(connection.receive(), name=f"ws-recv-{actor.user}")
    sender = asyncio.create_task(connection.sender(), name=f"ws-send-{actor.user}")
    connection.tasks = [pump, receive, sender]
    queues = None
    if not target.shared:  # on your own simulator, the lab's queue still reaches you
        with contextlib.suppress(ServiceClosed):
            queues = context.service.subscribe(QueueChanged)
            connection.tasks.append(
                asyncio.create_task(connection.pump(queues), name=f"ws-queue-{actor.user}")
            )
    if connection.ended is not None or not handle.alive(dt.datetime.now(dt.UTC)):
        await connection.end(handle.revoked or "the session ended")
    try:
        done, _ = await asyncio.wait(set(connection.tasks), return_when=asyncio.FIRST_COMPLETED)
        for task in done:
            if task.cancelled():
                continue
            failure = task.exception()
            if failure is not None and not isinstance(failure, WebSocketDisconnect | RuntimeError):
                _log.warning("websocket of %s ended: %r", actor.user, failure)
    finally:
        for task in connection.tasks:
            task.cancel()
        for task in connection.tasks:
            with contextlib.suppress(BaseException):
                await task
        sub.close()
        if queues is not None:
            queues.close()
        connection.gate.close()
        await _goodbye(context, connection)
        with contextlib.suppress(Exception):
            if connection.ended is not None:
                await websocket.close(code=POLICY_VIOLATION, reason=connection.ended[:120])
            else:
                await websocket.close(code=GOING_AWAY)


async def _goodbye(context: WebContext, connection: Connection) -> None:
    """The dead-man: a jog started here stops; the user's last connection ends their jog
    and, by `ServiceConfig.when_holder_leaves`, stops or keeps their move (lease.py). A
    private simulator has no shared lease, only its owner."""
    service = connection.service
    actor = connection.actor
    target = connection.target
    target.sockets -= 1
    context.targets.touch(target)
    left = context.sockets.remove(actor) if target.shared else target.sockets
    with contextlib.suppress(Exception):
        # Shielded: the socket's task is being cancelled as it closes, and the STOP and
        # lease release inside must finish anyway (a dead-man that half-runs is none).
        last = await asyncio.shield(service.disconnect(actor))
        if not last and connection.jogging:
            await service.jog_release(actor)
    _log.info(
        "websocket closed for %s",
        actor.user,
        extra={"fields": {"user": actor.user, "session": actor.session_id, "left": left}},
    )


__all__ = ["Connection", "Outbox", "message_of", "origin_allowed", "router"]
