"""The rosbridge WebSocket transport: authentication, frames, the outgoing queue.

Authentication, before anything else, by the first that is given:

- ``?token=<token>`` in the WebSocket URL (a personal access token, or a session token):
  what a page that cannot send headers or an ``auth`` op uses (the thesis's page only
  lets its URL be changed);
- the web app's session cookie, only from a page of the server's own origin or an allowed
  one, so another site cannot ride on a signed-in student's cookie;
- rosbridge's ``auth`` op (rosauth's message) as the first message, the token in ``mac``;
  the other rosauth fields are accepted and ignored.

Anything else first (or a first message longer than `AUTH_MESSAGE_CHARS`), a bad token,
or nothing within ``auth_timeout_s``: an error status, then close 1008 (policy violation).
The server may cap the sockets still signing in (``admit``): beyond, refused before the
handshake. The credential is checked again every
``recheck_s`` and before each message: a revoked token or ended session closes the socket.

``?mode=thesis`` (or the router's ``mode``) makes the connection behave like the thesis's
execute node (`melfa.service.thesis.THESIS`).

Binary frames (CBOR, BSON) are answered with an error status; the connection stays.
Each connection is its own operator session towards the service (``<session>/rosbridge-N``)
with its own thesis state machine and parameters; the lease is the user's (shared by all
of the user's connections).
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import itertools
import json
import logging
from collections import deque
from collections.abc import Awaitable, Callable, Iterable
from contextlib import AbstractContextManager, nullcontext
from typing import Any, Generic, Protocol, TypeVar

from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from melfa.ros import interface as ri
from melfa.ros.messages import BASE_FRAME
from melfa.ros.rosapi import ParamBudget
from melfa.ros.rosbridge import RosbridgeSession
from melfa.service import Actor, RobotService
from melfa.service.lab_network import peer_address
from melfa.service.thesis import MELFA, Dialect, dialect_named

log = logging.getLogger(__name__)

S = TypeVar("S")

POLICY_VIOLATION = 1008
AUTH_MESSAGE_CHARS = 4096
"""Longest first message read before sign-in (an ``auth`` op is a few hundred)."""
OUTGOING_MAXLEN = 256
"""Messages waiting for a slow client; beyond that the oldest are dropped (state is
superseded anyway)."""


class Outbox:
    """Messages waiting for the client, oldest first: at most ``maxlen`` in all, and at
    most a subscription's ``queue_length`` of one topic (the oldest of it dropped first,
    as rosbridge_server does)."""

    def __init__(self, maxlen: int = OUTGOING_MAXLEN) -> None:
        self._items: deque[tuple[str | None, str]] = deque()
        self.maxlen = maxlen
        self.dropped = 0
        self.ready = asyncio.Event()

    def put(self, message: dict[str, Any], topic: str | None, queue: int | None) -> None:
        if topic is not None and queue is not None:
            waiting = [i for i, (t, _) in enumerate(self._items) if t == topic]
            for index in reversed(waiting[: max(0, len(waiting) - queue + 1)]):
                del self._items[index]
                self.dropped += 1
        self._items.append((topic, json.dumps(message)))
        while len(self._items) > self.maxlen:
            self._items.popleft()
            self.dropped += 1
        self.ready.set()

    def take(self) -> str | None:
        return self._items.popleft()[1] if self._items else None

    def __len__(self) -> int:
        return len(self._items)


def origin_allowed(websocket: WebSocket, allowed: Iterable[str]) -> bool:
    """Whether a browser page at the request's Origin may use the session cookie: none
    (not a browser), the server's own host, or one of ``allowed``. Same rule as the web
    app's sign-in check."""
    origin = websocket.headers.get("origin")
    if origin is None:
        return True
    if origin == "null":
        return False  # a sandboxed frame or a file: page may not ride on the cookie
    host = websocket.headers.get("host", "")
    return origin.split("://", 1)[-1] == host or origin in set(allowed)


def _status(text: str) -> str:
    return json.dumps({"op": "status", "level": "error", "msg": text})


class Gate(Protocol):
    """Per-connection limits from the server: ``check(text)`` says why a message is refused
    (None: fine); ``closing`` when the socket must go (rate far exceeded)."""

    closing: bool

    def check(self, text: str) -> str | None: ...

    def close(self) -> None: ...


Gatekeeper = Callable[[WebSocket, str, Callable[[str], Awaitable[None]]], Awaitable[Gate | None]]
Admission = Callable[[WebSocket], AbstractContextManager[bool]]
"""Held while a socket signs in; False: too many are signing in, refuse it."""


class _Endpoint(Generic[S]):
    """The WebSocket route: authentication, then a `RosbridgeSession`."""

    def __init__(
        self,
        service: RobotService | Callable[[WebSocket], RobotService],
        find_session: Callable[[WebSocket, str], Awaitable[S | None]],
        actor_of: Callable[[S], Actor],
        *,
        cookie_name: str,
        allowed_origins: Iterable[str] | Callable[[WebSocket], Iterable[str]],
        options: dict[str, Any],
        mode: Dialect,
        auth_timeout_s: float,
        recheck_s: float,
        gate: Gatekeeper | None = None,
        admit: Admission | None = None,
        params: Callable[[WebSocket], ParamBudget] | None = None,
    ) -> None:
        self.service = service
        self.find_session = find_session
        self.actor_of = actor_of
        self.cookie_name = cookie_name
        self.allowed_origins = allowed_origins
        self.options = options
        self.mode = mode
        self.auth_timeout_s = auth_timeout_s
        self.recheck_s = recheck_s
        self.gate = gate
        self.admit = admit
        self.params = params
        self._budget = ParamBudget()
        self._numbers = itertools.count(1)

    def _service(self, websocket: WebSocket) -> RobotService:
        if isinstance(self.service, RobotService):
            return self.service
        return self.service(websocket)

    async def _actor(self, websocket: WebSocket, token: str | None) -> Actor | None:
        if not token:
            return None
        session = await self.find_session(websocket, token)
        return None if session is None else self.actor_of(session)

    def _cookie(self, websocket: WebSocket) -> str | None:
        token = websocket.cookies.get(self.cookie_name)
        if not token:
            return None
        allowed = self.allowed_origins
        origins = allowed(websocket) if callable(allowed) else allowed
        return token if origin_allowed(websocket, origins) else None

    async def _from_auth_op(self, websocket: WebSocket) -> str | None:
        """The first message must be ``auth`` with a token in ``mac``; its token or None."""
        try:  # asyncio.timeout: a cancel that meets the message still cancels
            async with asyncio.timeout(self.auth_timeout_s):
                raw = await websocket.receive()
        except TimeoutError:
            return None
        if raw.get("type") == "websocket.disconnect":
            raise WebSocketDisconnect(raw.get("code", 1000))
        text = raw.get("text")
        if not isinstance(text, str) or len(text) > AUTH_MESSAGE_CHARS:
            return None
        try:
            message = json.loads(text)
        except (ValueError, RecursionError):
            return None
        if not isinstance(message, dict) or message.get("op") != "auth":
            return None
        mac = message.get("mac")
        return mac if isinstance(mac, str) else None

    async def __call__(self, websocket: WebSocket) -> None:
        token = websocket.query_params.get("token") or self._cookie(websocket)
        waits = token is None and self.admit is not None  # for its auth op: a place is held
        admission = self.admit(websocket) if waits and self.admit else nullcontext(True)
        with admission as admitted:
            if not admitted:
                await websocket.close(POLICY_VIOLATION, "too many connections are signing in")
                return
            await websocket.accept()
            signed_in = await self._sign_in(websocket, token)
        if signed_in is not None:
            await self._serve(websocket, self._service(websocket), *signed_in)

    async def _sign_in(
        self, websocket: WebSocket, token: str | None
    ) -> tuple[Actor, str, Dialect] | None:
        """The connection's actor, token and dialect (``token``: the URL's or the
        cookie's, None to read the auth op); None after refusing it."""
        try:
            mode = dialect_named(websocket.query_params.get("mode") or self.mode.name)
        except ValueError as exc:
            await self._refuse(websocket, f"{exc} (in ?mode=)")
            return None
        try:
            if token is None:
                token = await self._from_auth_op(websocket)
            actor = await self._actor(websocket, token)
        except WebSocketDisconnect:
            return None
        if actor is None or token is None:
            await self._refuse(
                websocket,
                "authentication failed: put a token in the URL (?token=…, from `melfa users "
                'token`), sign in (session cookie), or send {"op": "auth", "mac": "<token>"} '
                "first",
            )
            return None
        number = next(self._numbers)
        client = websocket.client
        actor = dataclasses.replace(
            actor,
            session_id=f"{actor.session_id}/rosbridge-{number}",
            address=peer_address(client.host if client is not None else None),
        )
        return actor, token, mode

    async def _refuse(self, websocket: WebSocket, text: str) -> None:
        with contextlib.suppress(Exception):
            await websocket.send_text(_status(text))
            await websocket.close(POLICY_VIOLATION, text[:120])

    async def _serve(
        self, websocket: WebSocket, service: RobotService, actor: Actor, token: str, mode: Dialect
    ) -> None:
        outbox = Outbox()

        async def sender() -> None:
            while True:
                await outbox.ready.wait()
                outbox.ready.clear()
                while (text := outbox.take()) is not None:
                    await websocket.send_text(text)

        async def still_allowed() -> None:
            while True:
                await asyncio.sleep(self.recheck_s)
                if await self._actor(websocket, token) is None:
                    await self._refuse(websocket, "the token was revoked or the session ended")
                    return

        revoked = asyncio.Event()

        async def end(reason: str) -> None:
            revoked.set()
            await self._refuse(websocket, reason)

        gate = None
        if self.gate is not None:
            gate = await self.gate(websocket, token, end)
            if gate is None:
                await self._refuse(websocket, "too many connections")
                return
        budget = self.params(websocket) if self.params is not None else self._budget
        session = RosbridgeSession(
            service, actor, outbox.put, dialect=mode, params=budget, **self.options
        )
        session.start()
        service.connect(actor)  # the user's connections share one lease
        tasks = [
            asyncio.create_task(sender(), name="rosbridge-sender"),
            asyncio.create_task(still_allowed(), name="rosbridge-recheck"),
        ]
        try:
            while True:
                frame = await websocket.receive()
                if frame.get("type") == "websocket.disconnect":
                    break
                text = frame.get("text")
                if revoked.is_set():
                    break  # the session ended: nothing more is done for this socket
                problem = gate.check(text) if gate is not None and text is not None else None
                if problem is not None:
                    session.status("error", problem)
                    if gate is not None and gate.closing:
                        await self._refuse(websocket, problem)
                        break
                    continue
                if text is None:
                    session.status(
                        "error",
                        "binary frames (CBOR, BSON) are not supported here: send rosbridge "
                        "JSON as text",
                    )
                    continue
                try:
                    message = json.loads(text)
                except json.JSONDecodeError as exc:
                    session.status("error", f"not JSON: {exc}")
                    continue
                except RecursionError:
                    session.status("error", "the message nests too deep")
                    continue
                if not isinstance(message, dict):
                    session.status("error", "a rosbridge message is a JSON object with an op")
                    continue
                await session.handle(message)
        except (WebSocketDisconnect, RuntimeError):
            pass
        finally:
            for task in tasks:
                task.cancel()
            for task in tasks:
                with contextlib.suppress(asyncio.CancelledError, Exception):
                    await task
            await session.close()
            if gate is not None:
                gate.close()
            with contextlib.suppress(Exception):
                await service.disconnect(actor)


def rosbridge_router(
    service: RobotService | Callable[[WebSocket], RobotService],
    find_session: Callable[[WebSocket, str], Awaitable[S | None]],
    actor_of: Callable[[S], Actor],
    *,
    paths: Iterable[str] = ("/rosbridge",),
    cookie_name: str = "melfa_session",
    allowed_origins: Iterable[str] | Callable[[WebSocket], Iterable[str]] = (),
    namespace: str = ri.NODE_NAME,
    frame_id: str = BASE_FRAME,
    max_rate_hz: float | None = 50.0,
    mode: Dialect = MELFA,
    auth_timeout_s: float = 10.0,
    recheck_s: float = 2.0,
    gate: Gatekeeper | None = None,
    admit: Admission | None = None,
    params: Callable[[WebSocket], ParamBudget] | None = None,
) -> APIRouter:
    """A router with the rosbridge WebSocket at each of ``paths``.

    - ``service``: the `RobotService`, or a function of the WebSocket returning it (when the
      app builds the service at startup, e.g. ``lambda ws: ws.app.state.web.service``).
    - ``find_session(websocket, token)``: the live session for a token (the URL's, the
      cookie's or the ``auth`` op's ``mac``), or None; ``actor_of(session)`` makes it an
      `Actor`.
    - ``allowed_origins``: browser origins besides the server's own that may use the cookie.
    - ``max_rate_hz``: most state messages per second per client (None: every snapshot).
    - ``mode``: the connections' default dialect (``?mode=`` chooses per connection).
    - ``gate(websocket, token, end)``: the web server's limits and revocation (a `Gate`,
      or None to refuse: too many connections); it calls ``end(reason)`` to close the
      socket at once when the session is revoked.
    - ``admit(websocket)``: held while a socket signs in (False: refuse it, too many are).
    - ``params(websocket)``: the `ParamBudget` the connections' rosapi parameters share
      (None: one for this router).
    """
    endpoint: _Endpoint[S] = _Endpoint(
        service,
        find_session,
        actor_of,
        cookie_name=cookie_name,
        allowed_origins=allowed_origins,
        options={"namespace": namespace, "frame_id": frame_id, "max_rate_hz": max_rate_hz},
        mode=mode,
        auth_timeout_s=auth_timeout_s,
        recheck_s=recheck_s,
        gate=gate,
        admit=admit,
        params=params,
    )
    router = APIRouter()

    async def rosbridge(websocket: WebSocket) -> None:
        await endpoint(websocket)

    for number, path in enumerate(paths):
        name = "rosbridge" if number == 0 else f"rosbridge-{number}"
        router.add_api_websocket_route(path, rosbridge, name=name)
    return router


__all__ = [
    "AUTH_MESSAGE_CHARS",
    "OUTGOING_MAXLEN",
    "Admission",
    "Gate",
    "Gatekeeper",
    "Outbox",
    "origin_allowed",
    "rosbridge_router",
]
