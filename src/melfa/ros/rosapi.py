"""The ``/rosapi/*`` services of a rosbridge endpoint, answered without ROS (pure).

rosbridge_server's ``rosapi`` node lets web clients ask what a ROS graph offers. Here the
graph is one node (``/melfa``) with the topics and services of `melfa.ros.interface`, and
a per-connection parameter store. Every rosapi call of ROS Noetic is either answered or
refused with "not supported here" (`NOT_SUPPORTED`), never with a misleading error.
"""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Callable
from typing import Any, ClassVar

from melfa.ros import interface as ri
from melfa.ros.messages import Stamp
from melfa.ros.urdf import rv6s_urdf

ROSAPI_NODE = "/rosapi"
BRIDGE_NODE = "/rosbridge_websocket"

NOT_SUPPORTED = frozenset(
    {
        "action_servers",
        "get_action_servers",
        "interfaces",
        "search_params",
    }
)
"""rosapi calls this endpoint does not offer (no actions, no parameter search)."""

MESSAGE_FIELDS: dict[str, list[tuple[str, str]]] = {
    "std_msgs/String": [("data", "string")],
    "std_msgs/Header": [("seq", "uint32"), ("stamp", "time"), ("frame_id", "string")],
    "sensor_msgs/JointState": [
        ("header", "std_msgs/Header"),
        ("name", "string[]"),
        ("position", "float64[]"),
        ("velocity", "float64[]"),
        ("effort", "float64[]"),
    ],
    "geometry_msgs/PoseStamped": [("header", "std_msgs/Header"), ("pose", "geometry_msgs/Pose")],
    "geometry_msgs/Pose": [
        ("position", "geometry_msgs/Point"),
        ("orientation", "geometry_msgs/Quaternion"),
    ],
    "geometry_msgs/Point": [("x", "float64"), ("y", "float64"), ("z", "float64")],
    "geometry_msgs/Quaternion": [
        ("x", "float64"),
        ("y", "float64"),
        ("z", "float64"),
        ("w", "float64"),
    ],
    "std_srvs/TriggerRequest": [],
    "std_srvs/TriggerResponse": [("success", "bool"), ("message", "string")],
    "std_srvs/SetBoolRequest": [("data", "bool")],
    "std_srvs/SetBoolResponse": [("success", "bool"), ("message", "string")],
}
"""The message types this endpoint publishes or serves, field by field (for
``message_details`` and ``service_*_details``)."""


class RosapiError(Exception):
    """A rosapi call this endpoint cannot answer (the text says why)."""


def _typedef(kind: str) -> dict[str, Any]:
    fields = MESSAGE_FIELDS[kind]
    base = [f.removesuffix("[]") for _, f in fields]
    return {
        "type": kind,
        "fieldnames": [n for n, _ in fields],
        "fieldtypes": base,
        "fieldarraylen": [-1 for _ in fields],
        "examples": ["[]" if f.endswith("[]") else "" for _, f in fields],
        "constnames": [],
        "constvalues": [],
    }


def typedefs(kind: str) -> list[dict[str, Any]]:
    """``message_details``: the type and every type it contains."""
    if kind not in MESSAGE_FIELDS:
        raise RosapiError(f"no message type {kind!r} here; known: {', '.join(MESSAGE_FIELDS)}")
    seen: list[str] = []

    def walk(name: str) -> None:
        if name in seen or name not in MESSAGE_FIELDS:
            return
        seen.append(name)
        for _, field in MESSAGE_FIELDS[name]:
            walk(field.removesuffix("[]"))

    walk(kind)
    return [_typedef(name) for name in seen]


PARAM_BYTES = 4 * 1024 * 1024
"""Most characters of parameter values one connection may hold (`set_param`)."""
PARAM_BYTES_TOTAL = 32 * 1024 * 1024
"""Most characters of parameter values all connections together may hold."""


class ParamBudget:
    """How much parameter text the connections of one server hold, against a total, so
    stored parameters cannot grow the process that drives the arm without bound."""

    def __init__(self, per_connection: int = PARAM_BYTES, total: int = PARAM_BYTES_TOTAL) -> None:
        self.per_connection = per_connection
        self.total = total
        self.used = 0

    def change(self, held: int, old: int, new: int) -> None:
        """A connection holding ``held`` characters replaces a value of ``old`` by one of
        ``new``; `RosapiError` (nothing charged) when either limit would be passed.

        >>> budget = ParamBudget(per_connection=10, total=15)
        >>> budget.change(0, 0, 8); budget.change(0, 0, 6); budget.used
        14
        >>> budget.change(8, 8, 11)  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        melfa.ros.rosapi.RosapiError: parameters are limited to 10 characters per connection ...
        """
        if held - old + new > self.per_connection:
            raise RosapiError(
                f"parameters are limited to {self.per_connection} characters per connection"
                f" ({held} held): delete some first"
            )
        if new > old and self.used - old + new > self.total:
            raise RosapiError("the server holds all the parameters it can; try again later")
        self.used += new - old

    def give_back(self, amount: int) -> None:
        self.used = max(0, self.used - amount)


class Rosapi:
    """One connection's rosapi: the graph of `melfa.ros.interface`, its own parameters
    (within a `ParamBudget`; `clear` when the connection closes)."""

    def __init__(
        self,
        namespace: str,
        clock: Callable[[], dt.datetime] | None = None,
        budget: ParamBudget | None = None,
    ) -> None:
        self.namespace = namespace.strip("/")
        self.params: dict[str, Any] = {"/robot_description": rv6s_urdf()}
        """Per connection; ``/robot_description`` is the RV-6S URDF, as on a ROS master
        where `melfa ros` runs (roslibjs's UrdfClient reads it)."""
        self._sizes: dict[str, int] = {}
        """Characters charged to the budget per parameter set by the client."""
        self.budget = budget if budget is not None else ParamBudget()
        self._now = clock or (lambda: dt.datetime.now(dt.UTC))

    @property
    def held(self) -> int:
        """Characters of parameter values this connection holds."""
        return sum(self._sizes.values())

    def clear(self) -> None:
        """Forget every parameter set by the client and give its budget back."""
        for name in list(self._sizes):
            self._forget(name)

    def _forget(self, name: str) -> None:
        self.budget.give_back(self._sizes.pop(name, 0))
        self.params.pop(name, None)

    @property
    def node(self) -> str:
        return f"/{self.namespace}"

    def services(self) -> list[str]:
        ours = [f"{self.node}/{s.name}" for s in ri.SERVICES]
        return ours + [f"{ROSAPI_NODE}/{n}" for n in sorted(self._ANSWERS)]

    def service_type(self, name: str) -> str:
        wanted = name.strip().strip("/")
        kinds = {f"{self.namespace}/{s.name}": s.type for s in ri.SERVICES}
        return kinds.get(wanted, "")

    def call(self, name: str, args: dict[str, Any]) -> dict[str, Any]:
        """Answer ``/rosapi/<name>``; `RosapiError` when not offered or the args are bad."""
        if name in NOT_SUPPORTED:
            raise RosapiError(f"/rosapi/{name} is not supported here")
        answer = self._ANSWERS.get(name)
        if answer is None:
            raise RosapiError(f"/rosapi/{name} is not a rosapi service")
        return answer(self, args)

    # ------------------------------------------------------------------ graph

    def _topics(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"topics": [f"/{t.name}" for t in ri.TOPICS], "types": [t.type for t in ri.TOPICS]}

    def _topics_for_type(self, args: dict[str, Any]) -> dict[str, Any]:
        kind = _text(args, "type")
        return {"topics": [f"/{t.name}" for t in ri.TOPICS if t.type == kind]}

    def _topics_and_raw_types(self, args: dict[str, Any]) -> dict[str, Any]:
        topics = self._topics(args)
        return {**topics, "typedefs_full_text": ["" for _ in ri.TOPICS]}

    def _topic_type(self, args: dict[str, Any]) -> dict[str, Any]:
        spec = ri.TOPIC_BY_NAME.get(_text(args, "topic").strip("/"))
        return {"type": spec.type if spec else ""}

    def _services(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"services": self.services()}

    def _services_for_type(self, args: dict[str, Any]) -> dict[str, Any]:
        kind = _text(args, "type")
        return {"services": [f"{self.node}/{s.name}" for s in ri.SERVICES if s.type == kind]}

    def _service_type(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"type": self.service_type(_text(args, "service"))}

    def _service_node(self, args: dict[str, Any]) -> dict[str, Any]:
        name = _text(args, "service")
        if self.service_type(name):
            return {"node": self.node}
        return {"node": ROSAPI_NODE if name.startswith(f"{ROSAPI_NODE}/") else ""}

    def _service_host(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"host": "localhost"}

    def _service_providers(self, args: dict[str, Any]) -> dict[str, Any]:
        kind = _text(args, "service")
        found = any(s.type == kind for s in ri.SERVICES)
        return {"providers": [self.node] if found else []}

    def _nodes(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"nodes": [self.node, ROSAPI_NODE, BRIDGE_NODE]}

    def _node_details(self, args: dict[str, Any]) -> dict[str, Any]:
        node = _text(args, "node")
        if node != self.node:
            return {"subscribing": [], "publishing": [], "services": []}
        return {
            "subscribing": [f"/{t.name}" for t in ri.TOPICS if t.direction is ri.Direction.IN],
            "publishing": [f"/{t.name}" for t in ri.TOPICS if t.direction is ri.Direction.OUT],
            "services": [f"{self.node}/{s.name}" for s in ri.SERVICES],
        }

    def _publishers(self, args: dict[str, Any]) -> dict[str, Any]:
        spec = ri.TOPIC_BY_NAME.get(_text(args, "topic").strip("/"))
        out = spec is not None and spec.direction is ri.Direction.OUT
        return {"publishers": [self.node] if out else []}

    def _subscribers(self, args: dict[str, Any]) -> dict[str, Any]:
        spec = ri.TOPIC_BY_NAME.get(_text(args, "topic").strip("/"))
        inward = spec is not None and spec.direction is ri.Direction.IN
        return {"subscribers": [self.node] if inward else []}

    def _message_details(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"typedefs": typedefs(_text(args, "type"))}

    def _service_request_details(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"typedefs": typedefs(_text(args, "type") + "Request")}

    def _service_response_details(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"typedefs": typedefs(_text(args, "type") + "Response")}

    def _get_time(self, args: dict[str, Any]) -> dict[str, Any]:
        stamp = Stamp.of(self._now())
        return {"time": {"secs": stamp.secs, "nsecs": stamp.nsecs}}

    # ------------------------------------------------------------------ parameters

    def _get_param_names(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"names": sorted(self.params)}

    def _get_param(self, args: dict[str, Any]) -> dict[str, Any]:
        param = param_name(args.get("name"))
        if param in self.params:
            return {"value": json.dumps(self.params[param])}
        default = args.get("default")
        return {"value": default if isinstance(default, str) and default else "null"}

    def _has_param(self, args: dict[str, Any]) -> dict[str, Any]:
        return {"exists": param_name(args.get("name")) in self.params}

    def _delete_param(self, args: dict[str, Any]) -> dict[str, Any]:
        self._forget(param_name(args.get("name")))
        return {}

    def _set_param(self, args: dict[str, Any]) -> dict[str, Any]:
        param = param_name(args.get("name"))
        raw = args.get("value")
        size = len(raw) if isinstance(raw, str) else len(json.dumps(raw))
        self.budget.change(self.held, self._sizes.get(param, 0), size)  # raises: not stored
        self._sizes[param] = size
        try:
            self.params[param] = json.loads(raw) if isinstance(raw, str) else raw
        except (json.JSONDecodeError, RecursionError):
            self.params[param] = raw  # a bare string, as rosapi also accepts
        return {}

    _ANSWERS: ClassVar[dict[str, Callable[[Rosapi, dict[str, Any]], dict[str, Any]]]] = {
        "topics": _topics,
        "topics_for_type": _topics_for_type,
        "topics_and_raw_types": _topics_and_raw_types,
        "topic_type": _topic_type,
        "services": _services,
        "services_for_type": _services_for_type,
        "service_type": _service_type,
        "service_node": _service_node,
        "service_host": _service_host,
        "service_providers": _service_providers,
        "nodes": _nodes,
        "node_details": _node_details,
        "publishers": _publishers,
        "subscribers": _subscribers,
        "message_details": _message_details,
        "service_request_details": _service_request_details,
        "service_response_details": _service_response_details,
        "get_time": _get_time,
        "get_param_names": _get_param_names,
        "get_param": _get_param,
        "has_param": _has_param,
        "delete_param": _delete_param,
        "set_param": _set_param,
    }


def _text(args: dict[str, Any], key: str) -> str:
    value = args.get(key)
    if not isinstance(value, str) or not value.strip():
        raise RosapiError(f"{key!r} is needed (a name), got {value!r}")
    return value.strip()


def param_name(name: object) -> str:
    """``/melfa/program`` from any spelling of it."""
    if not isinstance(name, str) or not name.strip("/"):
        raise RosapiError(f"a parameter name is needed, got {name!r}")
    return "/" + name.strip().strip("/")


__all__ = [
    "MESSAGE_FIELDS",
    "NOT_SUPPORTED",
    "PARAM_BYTES",
    "PARAM_BYTES_TOTAL",
    "ParamBudget",
    "Rosapi",
    "RosapiError",
    "param_name",
    "typedefs",
]
