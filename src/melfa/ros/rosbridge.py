"""A rosbridge v2 compatible WebSocket endpoint, without ROS (pure Python, asyncio).

roslibjs and roslibpy clients talk to the robot as if a ``rosbridge_server`` and the melfa
ROS node were running: the same topics and services as `melfa.ros.node` (see
`melfa.ros.interface`), driven by the web server's `RobotService`.

Protocol (rosbridge v2.0): ``advertise``, ``unadvertise``, ``publish``, ``subscribe``
(``throttle_rate``, ``queue_length`` and ``fragment_size`` honoured), ``unsubscribe``,
``call_service`` (``fragment_size`` honoured; ``args`` checked against the service's
request), ``service_response``, ``set_level``, ``auth``; answers ``publish``,
``service_response``, ``fragment`` and ``status``. ``rosapi`` is `melfa.ros.rosapi`. Not
offered: client-advertised services, incoming fragments, png/cbor compression (each
answered with an error status).

This module is the protocol for one authenticated client; `melfa.ros.rosbridge_server` is
the WebSocket transport (authentication, binary frames, the outgoing queue).
"""

from __future__ import annotations

import asyncio
import dataclasses
import itertools
import json
import logging
import time
from collections.abc import Awaitable, Callable
from typing import Any, ClassVar

from melfa.ros import interface as ri
from melfa.ros.core import RosCore, ServiceReply
from melfa.ros.messages import BASE_FRAME, JointStateData, PoseData, Stamp
from melfa.ros.rosapi import ParamBudget, Rosapi, RosapiError
from melfa.service import Actor, RobotService
from melfa.service.thesis import MELFA, Dialect

log = logging.getLogger(__name__)

Send = Callable[[dict[str, Any], str | None, int | None], None]
"""How a session sends: (message, topic it belongs to or None, that topic's queue_length)."""
STATE_TOPICS = frozenset({ri.JOINT_STATES, ri.TOOL_POSE_STAMPED, ri.TOOL_POSE, ri.JOINT_STATE_TEXT})
"""Topics fed by the state stream (a subscriber to any of them starts the stream)."""
LEVELS = ("none", "error", "warning", "info")
FRAGMENTS_PER_S = 50.0
"""Fragments a second of one topic when the session has no rate limit of its own."""


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
    not_before: float = -float("inf")
    """A fragmented message pays for its parts: the next one waits (see `_publish`)."""
    queue_length: int | None = None
    """Most messages of this topic waiting for the client (None: no own limit)."""
    fragment_size: int | None = None


MIN_FRAGMENT_CHARS = 64
"""The smallest fragment sent, whatever ``fragment_size`` asks: one character per
fragment would turn a 400-character message into 400 messages (amplification)."""
MAX_FRAGMENTS = 16
"""The most fragments one message is cut into; longer fragments beyond that."""


def fragments(message: dict[str, Any], size: int | None, ids: Any) -> list[dict[str, Any]]:
    """``message`` itself, or rosbridge ``fragment`` ops of at most ``size`` characters
    of its JSON when it is longer (at least `MIN_FRAGMENT_CHARS` each, at most
    `MAX_FRAGMENTS` of them: clients reassemble fragments of any size).

    >>> [len(f["data"]) for f in fragments({"op": "x" * 70}, 1, iter(["f1"]))]
    [64, 16]
    >>> len(fragments({"op": "x" * 5000}, 1, iter(["f1"])))
    16
    """
    text = json.dumps(message)
    if size is None or len(text) <= size:
        return [message]
    size = max(size, MIN_FRAGMENT_CHARS, -(-len(text) // MAX_FRAGMENTS))
    if len(text) <= size:
        return [message]
    parts = [text[i : i + size] for i in range(0, len(text), size)]
    number = next(ids)
    return [
        {"op": "fragment", "id": number, "data": part, "num": i, "total": len(parts)}
        for i, part in enumerate(parts)
    ]


SERVICE_ARGS: dict[str, frozenset[str]] = {
    ri.TRIGGER: frozenset(),
    ri.SET_BOOL: frozenset({"data"}),
}
TEXT_ARGS = {
    ri.LOAD_PROGRAM: frozenset({ri.PROGRAM_PARAM}),
    ri.LOAD_POINTS: frozenset({ri.POINTS_PARAM}),
    ri.LOAD_PROJECT: frozenset({ri.PROGRAM_PARAM, ri.POINTS_PARAM}),
    ri.OVERRIDE: frozenset({ri.OVERRIDE_PARAM}),
}
"""Fields our services take over rosbridge besides their ROS type's (the texts)."""


class RosbridgeSession:
    """The protocol for one authenticated client, over any transport: feed it decoded
    messages with `handle`; it sends through ``send`` (a JSON-ready dict)."""

    def __init__(
        self,
        service: RobotService,
        actor: Actor,
        send: Send,
        *,
        namespace: str = ri.NODE_NAME,
        frame_id: str = BASE_FRAME,
        max_rate_hz: float | None = None,
        dialect: Dialect = MELFA,
        clock: Callable[[], float] = time.monotonic,
        params: ParamBudget | None = None,
    ) -> None:
        self.service = service
        self.actor = actor
        self._raw_send = send
        self.namespace = namespace.strip("/")
        self._clock = clock
        self._parts_hz = max_rate_hz or FRAGMENTS_PER_S
        self.rosapi = Rosapi(self.namespace, budget=params)
        self.params = self.rosapi.params
        self.level = "error"
        self.advertised: dict[str, str] = {}
        self.subscribed: dict[str, _Subscribed] = {}
        self._calls: set[asyncio.Task[None]] = set()
        self._fragment_ids = itertools.count(1)
        self.core = RosCore(
            service,
            actor,
            self,
            self,
            frame_id=frame_id,
            max_rate_hz=max_rate_hz,
            dialect=dialect,
            clock=clock,
        )

    def _send(
        self, message: dict[str, Any], topic: str | None = None, queue: int | None = None
    ) -> None:
        self._raw_send(message, topic, queue)

    def start(self) -> None:
        self.core.start(stream=False)

    async def close(self) -> None:
        for task in list(self._calls):
            task.cancel()
        self.rosapi.clear()
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
        if now - sub.last < min(sub.ids.values(), default=0.0) or now < sub.not_before:
            return
        sub.last = now
        message = {"op": "publish", "topic": f"/{topic}", "msg": msg()}
        parts = fragments(message, sub.fragment_size, self._fragment_ids)
        # A topic in k fragments goes out k times less often: fragmenting never sends more
        # messages a second than the unfragmented topic would.
        sub.not_before = now + (len(parts) - 1) / self._parts_hz
        for part in parts:
            self._send(part, topic, sub.queue_length)

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
        queue = _positive(message, "queue_length")
        fragment = _positive(message, "fragment_size")
        sub = self.subscribed.setdefault(topic, _Subscribed())
        sub.ids[_id(message)] = throttle / 1000
        if queue is not None:
            sub.queue_length = queue if sub.queue_length is None else max(queue, sub.queue_length)
        if fragment is not None:
            sub.fragment_size = fragment
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
        args = message.get("args", {})
        if args is None:
            args = {}
        if not isinstance(args, dict):
            raise ProtocolError(
                f"args must be an object of the request's fields (e.g. {{}}), not {args!r}"
            )
        fragment = _positive(message, "fragment_size")
        task = asyncio.create_task(self._serve(name, args, message.get("id"), fragment))
        self._calls.add(task)
        task.add_done_callback(self._calls.discard)

    async def _serve(
        self, name: str, args: dict[str, Any], op_id: object, fragment: int | None = None
    ) -> None:
        """One service call (its own task: a stop overtakes an upload in progress)."""
        result = True
        try:
            values: Any = await self._dispatch(name.strip().strip("/"), args)
        except (ProtocolError, RosapiError) as exc:
            result, values = False, str(exc)
        response: dict[str, Any] = {
            "op": "service_response",
            "service": name,
            "values": values,
            "result": result,
        }
        if op_id is not None:
            response["id"] = op_id
        for part in fragments(response, fragment, self._fragment_ids):
            self._send(part)

    async def _dispatch(self, name: str, args: dict[str, Any]) -> Any:
        prefix = f"{self.namespace}/"
        if name.startswith(prefix) and name[len(prefix) :] in ri.SERVICE_BY_NAME:
            spec = ri.SERVICE_BY_NAME[name[len(prefix) :]]
            allowed = SERVICE_ARGS[spec.type] | TEXT_ARGS.get(spec.name, frozenset())
            extra = sorted(set(args) - allowed)
            if extra:
                takes = ", ".join(sorted(allowed)) or "no arguments"
                raise ProtocolError(f"/{name} takes {takes}; not {', '.join(extra)}")
            data = None
            if spec.type == ri.SET_BOOL:
                if not isinstance(args.get("data"), bool):
                    raise ProtocolError(f"/{name} ({ri.SET_BOOL}) needs args {{data: bool}}")
                data = args["data"]
            texts = {k: v for k, v in args.items() if k in TEXT_ARGS.get(spec.name, ())}
            for key, value in texts.items():
                if not isinstance(value, str | int) or isinstance(value, bool):
                    raise ProtocolError(f"/{name}: {key} must be text, not {value!r}")
            reply: ServiceReply = await self.core.call(
                spec.name, data, {k: str(v) for k, v in texts.items()}
            )
            return {"success": reply.success, "message": reply.message}
        if name.startswith("rosapi/"):
            return self.rosapi.call(name.removeprefix("rosapi/"), args)
        services = ", ".join(self.rosapi.services())
        raise ProtocolError(f"no service /{name}; there are {services}")

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


def _id(message: dict[str, Any]) -> str | None:
    value = message.get("id")
    return None if value is None else str(value)


def _positive(message: dict[str, Any], key: str) -> int | None:
    """A count option; None when absent or 0 (roslibjs's "no limit")."""
    value = message.get(key)
    if value is None or value == 0:
        return None
    if not isinstance(value, int) or isinstance(value, bool) or value < 1:
        raise ProtocolError(f"{key} must be a whole number ≥ 0, not {value!r}")
    return value


__all__ = [
    "MAX_FRAGMENTS",
    "MIN_FRAGMENT_CHARS",
    "ProtocolError",
    "RosbridgeSession",
    "fragments",
    "joint_state_msg",
    "pose_stamped_msg",
    "topic_name",
]
