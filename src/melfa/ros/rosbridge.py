"""A rosbridge v2 compatible WebSocket endpoint, without ROS (pure Python, asyncio).

roslibjs and roslibpy clients talk to the robot as if a ``rosbridge_server`` and the melfa
ROS node were running: the same topics and services as `melfa.ros.node` (see
`melfa.ros.interface`), driven by the web server's `RobotService`.

Protocol (rosbridge v2.0): ``advertise``, ``unadvertise``, ``publish``, ``subscribe``
(``throttle_rate`` honoured), ``unsubscribe``, ``call_service``, ``service_response``,
``set_level``, ``auth``; answers ``publish``, ``service_response`` and ``status``. A small
``rosapi`` for the tools clients call: ``/rosapi/topics``, ``services``, ``topic_type``,
``service_type``, ``get_param``, ``set_param``, ``has_param``, ``delete_param``,
``get_param_names``, ``get_time``. Not offered: client-advertised services, fragments,
png/cbor compression (each answered with an error status).

Authentication, before anything else: the web app's session cookie (only from a page of
the server's own origin or an allowed one, so another site cannot ride on it), or
rosbridge's ``auth`` op (rosauth's message) carrying a session token in ``mac``; the other
rosauth fields are accepted and ignored. Anything else first, a bad token, or nothing
within ``auth_timeout_s``: the socket is closed with 1008 (policy violation).

Each connection is its own operator session towards the service (``<session>/rosbridge-N``):
its own thesis state machine, its own parameters (``/melfa/program``…), and the lease
ends when the socket closes.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import datetime as dt
import itertools
import json
import logging
import time
from collections import deque
from collections.abc import Awaitable, Callable, Iterable
from typing import Any, ClassVar, Generic, TypeVar

from fastapi import APIRouter, WebSocket, WebSocketDisconnect

from melfa.ros import interface as ri
from melfa.ros.core import RosCore, ServiceReply
from melfa.ros.messages import BASE_FRAME, JointStateData, PoseData, Stamp
from melfa.service import Actor, RobotService

log = logging.getLogger(__name__)

S = TypeVar("S")

POLICY_VIOLATION = 1008
OUTGOING_MAXLEN = 256
"""Messages waiting for a slow client; beyond that the oldest are dropped (state is
superseded anyway)."""
STATE_TOPICS = frozenset({ri.JOINT_STATES, ri.TOOL_POSE_STAMPED, ri.TOOL_POSE, ri.JOINT_STATE_TEXT})
"""Topics fed by the state stream (a subscriber to any of them starts the stream)."""
LEVELS = ("none", "error", "warning", "info")


class ProtocolError(Exception):
    """The client sent something this endpoint cannot do (its mistake, or unsupported)."""


def topic_name(name: object) -> str:
    """``/joint_states`` → ``joint_states`` (names are in the root namespace).

    >>> topic_name("/execute_instruction"), topic_name("tool_pose")
    ('execute_instruction', 'tool_pose')
    """
    if not isinstance(name, str) or not name.strip("/"):
        raise ProtocolError(f"a topic name is needed, got {name!r}")
    return name.strip().lstrip("/")


def header(seq: int, stamp: Stamp, frame_id: str = "") -> dict[str, Any]:
    return {"seq": seq, "stamp": {"secs": stamp.secs, "nsecs": stamp.nsecs}, "frame_id": frame_id}


def joint_state_msg(message: JointStateData) -> dict[str, Any]:
    """``sensor_msgs/JointState`` as rosbridge JSON."""
    return {
        "header": header(message.seq, message.stamp),
        "name": list(message.name),
        "position": list(message.position),
        "velocity": [],
        "effort": [],
    }


def pose_stamped_msg(message: PoseData) -> dict[str, Any]:
    """``geometry_msgs/PoseStamped`` as rosbridge JSON."""
    x, y, z = message.position
    qx, qy, qz, qw = message.orientation
    return {
        "header": header(message.seq, message.stamp, message.frame_id),
        "pose": {
            "position": {"x": x, "y": y, "z": z},
            "orientation": {"x": qx, "y": qy, "z": qz, "w": qw},
        },
    }


@dataclasses.dataclass
class _Subscribed:
    ids: dict[str | None, float] = dataclasses.field(default_factory=dict)
    """Subscription id → throttle (s); the topic goes out at the smallest."""
    last: float = -float("inf")


class RosbridgeSession:
    """The protocol for one authenticated client, over any transport: feed it decoded
    messages with `handle`; it sends through ``send`` (a JSON-ready dict)."""

    def __init__(
        self,
        service: RobotService,
        actor: Actor,
        send: Callable[[dict[str, Any]], None],
        *,
        namespace: str = ri.NODE_NAME,
        frame_id: str = BASE_FRAME,
        max_rate_hz: float | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.service = service
        self.actor = actor
        self._send = send
        self.namespace = namespace.strip("/")
        self._clock = clock
        self.params: dict[str, Any] = {}
        self.level = "error"
        self.advertised: dict[str, str] = {}
        self.subscribed: dict[str, _Subscribed] = {}
        self._calls: set[asyncio.Task[None]] = set()
        self.core = RosCore(
            service, actor, self, self, frame_id=frame_id, max_rate_hz=max_rate_hz, clock=clock
        )

    def start(self) -> None:
        self.core.start(stream=False)

    async def close(self) -> None:
        for task in list(self._calls):
            task.cancel()
        await self.core.close()

    # ----------------------------------------------------------- RosOutput / ParamSource

    def joint_states(self, message: JointStateData) -> None:
        self._publish(ri.JOINT_STATES, lambda: joint_state_msg(message))

    def tool_pose_stamped(self, message: PoseData) -> None:
        self._publish(ri.TOOL_POSE_STAMPED, lambda: pose_stamped_msg(message))

    def text(self, topic: str, text: str) -> None:
        self._publish(topic, lambda: {"data": text})

    def log(self, level: int, text: str) -> None:
        log.log(level, "rosbridge %s: %s", self.actor, text)

    def get(self, name: str) -> object | None:
        return self.params.get(f"/{self.namespace}/{name}")

    def _publish(self, topic: str, msg: Callable[[], dict[str, Any]]) -> None:
        sub = self.subscribed.get(topic)
        if sub is None:
            return
        now = self._clock()
        if now - sub.last < min(sub.ids.values(), default=0.0):
            return
        sub.last = now
        self._send({"op": "publish", "topic": f"/{topic}", "msg": msg()})

    # ----------------------------------------------------------- protocol

    def status(self, level: str, text: str, op_id: object = None) -> None:
        """A ``status`` message, if the client's level lets it through."""
        if LEVELS.index(level) > LEVELS.index(self.level) or self.level == "none":
            return
        message: dict[str, Any] = {"op": "status", "level": level, "msg": text}
        if op_id is not None:
            message["id"] = op_id
        self._send(message)

    async def handle(self, message: dict[str, Any]) -> None:
        """One client message; a mistake becomes an error ``status``, never an exception."""
        op = message.get("op")
        try:
            handler = self._OPS.get(op) if isinstance(op, str) else None
            if handler is None:
                raise ProtocolError(f"unsupported op {op!r}")
            await handler(self, message)
        except ProtocolError as exc:
            self.status("error", f"{op}: {exc}", message.get("id"))

    async def _advertise(self, message: dict[str, Any]) -> None:
        topic = topic_name(message.get("topic"))
        spec = ri.TOPIC_BY_NAME.get(topic)
        if spec is None or spec.direction is not ri.Direction.IN:
            raise ProtocolError(f"clients may publish only on /{ri.EXECUTE_INSTRUCTION}")
        kind = message.get("type") or spec.type
        if kind != spec.type:
            raise ProtocolError(f"/{topic} is {spec.type}, not {kind}")
        self.advertised[topic] = kind

    async def _unadvertise(self, message: dict[str, Any]) -> None:
        self.advertised.pop(topic_name(message.get("topic")), None)

    async def _publish_op(self, message: dict[str, Any]) -> None:
        topic = topic_name(message.get("topic"))
        if topic != ri.EXECUTE_INSTRUCTION:
            raise ProtocolError(f"clients may publish only on /{ri.EXECUTE_INSTRUCTION}")
        msg = message.get("msg")
        data = msg.get("data") if isinstance(msg, dict) else None
        if not isinstance(data, str):
            raise ProtocolError('std_msgs/String needs "msg": {"data": "<text>"}')
        await self.core.put_instruction(data)

    async def _subscribe(self, message: dict[str, Any]) -> None:
        topic = topic_name(message.get("topic"))
        spec = ri.TOPIC_BY_NAME.get(topic)
        if spec is None or spec.direction is not ri.Direction.OUT:
            names = ", ".join(f"/{t.name}" for t in ri.TOPICS if t.direction is ri.Direction.OUT)
            raise ProtocolError(f"no topic /{topic} to subscribe to; there are {names}")
        kind = message.get("type")
        if kind and kind != spec.type:
            raise ProtocolError(f"/{topic} is {spec.type}, not {kind}")
        compression = message.get("compression") or "none"
        if compression != "none":
            raise ProtocolError(f"compression {compression!r} is not offered (use none)")
        throttle = message.get("throttle_rate") or 0
        if not isinstance(throttle, int | float) or throttle < 0:
            raise ProtocolError(f"throttle_rate must be milliseconds ≥ 0, not {throttle!r}")
        self.subscribed.setdefault(topic, _Subscribed()).ids[_id(message)] = throttle / 1000
        if topic in STATE_TOPICS:
            self.core.start_stream()

    async def _unsubscribe(self, message: dict[str, Any]) -> None:
        topic = topic_name(message.get("topic"))
        sub = self.subscribed.get(topic)
        if sub is None:
            return
        if "id" in message:
            sub.ids.pop(_id(message), None)
        else:
            sub.ids.clear()
        if not sub.ids:
            del self.subscribed[topic]
        if not STATE_TOPICS & self.subscribed.keys():
            await self.core.stop_stream()

    async def _call_service(self, message: dict[str, Any]) -> None:
        name = message.get("service")
        if not isinstance(name, str) or not name.strip("/"):
            raise ProtocolError(f"a service name is needed, got {name!r}")
        args = message.get("args") or {}
        if not isinstance(args, dict):
            raise ProtocolError("args must be an object of the request's fields")
        task = asyncio.create_task(self._serve(name, args, message.get("id")))
        self._calls.add(task)
        task.add_done_callback(self._calls.discard)

    async def _serve(self, name: str, args: dict[str, Any], op_id: object) -> None:
        """One service call (its own task: a stop overtakes an upload in progress)."""
        result = True
        try:
            values: Any = await self._dispatch(name.strip().strip("/"), args)
        except ProtocolError as exc:
            result, values = False, str(exc)
        response: dict[str, Any] = {
            "op": "service_response",
            "service": name,
            "values": values,
            "result": result,
        }
        if op_id is not None:
            response["id"] = op_id
        self._send(response)

    async def _dispatch(self, name: str, args: dict[str, Any]) -> Any:
        prefix = f"{self.namespace}/"
        if name.startswith(prefix) and name[len(prefix) :] in ri.SERVICE_BY_NAME:
            spec = ri.SERVICE_BY_NAME[name[len(prefix) :]]
            data = None
            if spec.type == ri.SET_BOOL:
                if not isinstance(args.get("data"), bool):
                    raise ProtocolError(f"/{name} ({ri.SET_BOOL}) needs args {{data: bool}}")
                data = args["data"]
            reply: ServiceReply = await self.core.call(spec.name, data)
            return {"success": reply.success, "message": reply.message}
        if name.startswith("rosapi/"):
            return self._rosapi(name.removeprefix("rosapi/"), args)
        services = ", ".join(self._services())
        raise ProtocolError(f"no service /{name}; there are {services}")

    def _services(self) -> list[str]:
        ours = [f"/{self.namespace}/{s.name}" for s in ri.SERVICES]
        return ours + [f"/rosapi/{n}" for n in _ROSAPI]

    def _rosapi(self, name: str, args: dict[str, Any]) -> dict[str, Any]:
        if name == "topics":
            return {
                "topics": [f"/{t.name}" for t in ri.TOPICS],
                "types": [t.type for t in ri.TOPICS],
            }
        if name == "services":
            return {"services": self._services()}
        if name == "topic_type":
            spec = ri.TOPIC_BY_NAME.get(topic_name(args.get("topic", "")))
            return {"type": spec.type if spec else ""}
        if name == "service_type":
            wanted = str(args.get("service", "")).strip("/")
            kinds = {f"{self.namespace}/{s.name}": s.type for s in ri.SERVICES}
            return {"type": kinds.get(wanted, "")}
        if name == "get_time":
            stamp = Stamp.of(dt.datetime.now(dt.UTC))
            return {"time": {"secs": stamp.secs, "nsecs": stamp.nsecs}}
        if name == "get_param_names":
            return {"names": sorted(self.params)}
        param = _param_name(args.get("name"))
        if name == "get_param":
            if param in self.params:
                return {"value": json.dumps(self.params[param])}
            default = args.get("default")
            return {"value": default if isinstance(default, str) and default else "null"}
        if name == "has_param":
            return {"exists": param in self.params}
        if name == "delete_param":
            self.params.pop(param, None)
            return {}
        if name == "set_param":
            raw = args.get("value")
            try:
                self.params[param] = json.loads(raw) if isinstance(raw, str) else raw
            except json.JSONDecodeError:
                self.params[param] = raw  # a bare string, as rosapi also accepts
            return {}
        raise ProtocolError(f"no service /rosapi/{name}")

    async def _service_response(self, message: dict[str, Any]) -> None:
        raise ProtocolError("this endpoint never calls client services; nothing was pending")

    async def _set_level(self, message: dict[str, Any]) -> None:
        level = message.get("level")
        if level not in LEVELS:
            raise ProtocolError(f"level must be one of {', '.join(LEVELS)}")
        self.level = str(level)

    async def _auth(self, message: dict[str, Any]) -> None:
        """Already authenticated: a second ``auth`` changes nothing (rosbridge ignores it)."""

    _OPS: ClassVar[dict[str, Callable[[RosbridgeSession, dict[str, Any]], Awaitable[None]]]] = {
        "advertise": _advertise,
        "unadvertise": _unadvertise,
        "publish": _publish_op,
        "subscribe": _subscribe,
        "unsubscribe": _unsubscribe,
        "call_service": _call_service,
        "service_response": _service_response,
        "set_level": _set_level,
        "auth": _auth,
    }


_ROSAPI = (
    "topics",
    "services",
    "topic_type",
    "service_type",
    "get_param",
    "set_param",
    "has_param",
    "delete_param",
    "get_param_names",
    "get_time",
)


def _id(message: dict[str, Any]) -> str | None:
    value = message.get("id")
    return None if value is None else str(value)


def _param_name(name: object) -> str:
    if not isinstance(name, str) or not name.strip("/"):
        raise ProtocolError(f"a parameter name is needed, got {name!r}")
    return "/" + name.strip().strip("/")


# =============================================================================== transport


def origin_allowed(websocket: WebSocket, allowed: Iterable[str]) -> bool:
    """Whether a browser page at the request's Origin may use the session cookie: none
    (not a browser), the server's own host, or one of ``allowed``. Same rule as the web
    app's sign-in check."""
    origin = websocket.headers.get("origin")
    if origin is None or origin == "null":
        return True
    host = websocket.headers.get("host", "")
    return origin.split("://", 1)[-1] == host or origin in set(allowed)


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
        auth_timeout_s: float,
    ) -> None:
        self.service = service
        self.find_session = find_session
        self.actor_of = actor_of
        self.cookie_name = cookie_name
        self.allowed_origins = allowed_origins
        self.options = options
        self.auth_timeout_s = auth_timeout_s
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

    async def _from_cookie(self, websocket: WebSocket) -> Actor | None:
        token = websocket.cookies.get(self.cookie_name)
        if not token:
            return None
        allowed = self.allowed_origins
        origins = allowed(websocket) if callable(allowed) else allowed
        if not origin_allowed(websocket, origins):
            return None
        return await self._actor(websocket, token)

    async def _from_auth_op(self, websocket: WebSocket) -> Actor | None:
        """The first message must be ``auth`` with a valid token; else None."""
        try:
            raw = await asyncio.wait_for(websocket.receive_text(), self.auth_timeout_s)
            message = json.loads(raw)
        except (TimeoutError, json.JSONDecodeError, KeyError):
            return None
        if not isinstance(message, dict) or message.get("op") != "auth":
            return None
        mac = message.get("mac")
        return await self._actor(websocket, mac if isinstance(mac, str) else None)

    async def __call__(self, websocket: WebSocket) -> None:
        await websocket.accept()
        try:
            actor = await self._from_cookie(websocket) or await self._from_auth_op(websocket)
        except WebSocketDisconnect:
            return
        if actor is None:
            with contextlib.suppress(Exception):
                await websocket.send_text(
                    json.dumps(
                        {
                            "op": "status",
                            "level": "error",
                            "msg": "authentication failed: sign in (session cookie) or send "
                            '{"op": "auth", "mac": "<session token>", ...} first',
                        }
                    )
                )
                await websocket.close(POLICY_VIOLATION, "authentication failed")
            return
        number = next(self._numbers)
        actor = dataclasses.replace(actor, session_id=f"{actor.session_id}/rosbridge-{number}")
        await self._serve(websocket, self._service(websocket), actor)

    async def _serve(self, websocket: WebSocket, service: RobotService, actor: Actor) -> None:
        outgoing: deque[str] = deque(maxlen=OUTGOING_MAXLEN)
        ready = asyncio.Event()

        def send(message: dict[str, Any]) -> None:
            outgoing.append(json.dumps(message))
            ready.set()

        async def sender() -> None:
            while True:
                await ready.wait()
                ready.clear()
                while outgoing:
                    await websocket.send_text(outgoing.popleft())

        session = RosbridgeSession(service, actor, send, **self.options)
        session.start()
        writer = asyncio.create_task(sender(), name="rosbridge-sender")
        try:
            while True:
                raw = await websocket.receive_text()
                try:
                    message = json.loads(raw)
                except json.JSONDecodeError as exc:
                    session.status("error", f"not JSON: {exc}")
                    continue
                if not isinstance(message, dict):
                    session.status("error", "a rosbridge message is a JSON object with an op")
                    continue
                await session.handle(message)
        except (WebSocketDisconnect, RuntimeError):
            pass
        finally:
            writer.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await writer
            await session.close()
            with contextlib.suppress(Exception):
                await service.disconnect(actor)


def rosbridge_router(
    service: RobotService | Callable[[WebSocket], RobotService],
    find_session: Callable[[WebSocket, str], Awaitable[S | None]],
    actor_of: Callable[[S], Actor],
    *,
    path: str = "/rosbridge",
    cookie_name: str = "melfa_session",
    allowed_origins: Iterable[str] | Callable[[WebSocket], Iterable[str]] = (),
    namespace: str = ri.NODE_NAME,
    frame_id: str = BASE_FRAME,
    max_rate_hz: float | None = 50.0,
    auth_timeout_s: float = 10.0,
) -> APIRouter:
    """A router with the rosbridge WebSocket at ``path``.

    - ``service``: the `RobotService`, or a function of the WebSocket returning it (when the
      app builds the service at startup, e.g. ``lambda ws: ws.app.state.web.service``).
    - ``find_session(websocket, token)``: the live session for a token (the cookie's or the
      ``auth`` op's ``mac``), or None; ``actor_of(session)`` makes it an `Actor`.
    - ``allowed_origins``: browser origins besides the server's own that may use the cookie.
    - ``max_rate_hz``: most state messages per second per client (None: every snapshot).
    """
    endpoint: _Endpoint[S] = _Endpoint(
        service,
        find_session,
        actor_of,
        cookie_name=cookie_name,
        allowed_origins=allowed_origins,
        options={"namespace": namespace, "frame_id": frame_id, "max_rate_hz": max_rate_hz},
        auth_timeout_s=auth_timeout_s,
    )
    router = APIRouter()

    async def rosbridge(websocket: WebSocket) -> None:
        await endpoint(websocket)

    router.add_api_websocket_route(path, rosbridge, name="rosbridge")
    return router


__all__ = [
    "ProtocolError",
    "RosbridgeSession",
    "joint_state_msg",
    "origin_allowed",
    "pose_stamped_msg",
    "rosbridge_router",
    "topic_name",
]
