"""The live protocol's schema: the committed docs/ws-schema.json is the models', and every
message a real server sends, and every message it acts on, validates against it.

A real uvicorn on a loopback port, real WebSocket clients, the in-process virtual
controller: one session that makes the server send every kind of message."""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jsonschema_rs
import pytest
from websockets.sync.client import ClientConnection, connect

from melfa.link.memory import MemoryLink
from melfa.live.messages import (
    CLIENT_TYPES,
    SERVER,
    CommandResultMessage,
    DebugMessage,
    JogMessage,
    LeaseMessage,
    LinkMessage,
    ProgressMessage,
    StateMessage,
)
from melfa.live.schema import ws_schema
from melfa.service import (
    CommandResult,
    JogChanged,
    LeaseChanged,
    LinkStatusChanged,
    StateSnapshot,
    UploadProgress,
)
from melfa.service.debugging import DebugUpdate
from tests.web.live_server import Live, fresh_live

ROOT = Path(__file__).resolve().parents[2]
COMMITTED = ROOT / "docs" / "ws-schema.json"
PROGRAM = "SERVO ON\nMOV P1\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def committed() -> dict[str, Any]:
    return dict(json.loads(COMMITTED.read_text(encoding="utf-8")))


def validator(name: str) -> Any:
    """A validator of ``$defs/<name>`` in the committed document."""
    document = committed()
    document.pop("anyOf")
    return jsonschema_rs.validator_for({**document, "$ref": f"#/$defs/{name}"})


def test_committed_schema_matches_the_models() -> None:
    assert committed() == json.loads(json.dumps(ws_schema())), (
        "docs/ws-schema.json is stale: regenerate it with "
        "python -c 'import json; from melfa.live.schema import ws_schema; "
        "print(json.dumps(ws_schema(), indent=2))' > docs/ws-schema.json"
    )


def test_every_kind_of_server_message_is_in_the_schema() -> None:
    kinds = set(committed()["$defs"]["ServerMessage"]["discriminator"]["mapping"])
    assert kinds == {
        "hello", "state", "debug", "link", "progress", "result", "lease", "jog", "queue",
        "ack", "error", "pong",
    }  # fmt: skip
    assert set(committed()["$defs"]["ClientMessage"]["discriminator"]["mapping"]) == CLIENT_TYPES


class Recorder:
    """A signed-in WebSocket client that keeps every message it sent and received."""

    def __init__(self, live: Live, user: str, target: str = "lab") -> None:
        self.live = live
        self.token, self.csrf = live.login(user)
        url = f"ws://127.0.0.1:{live.port}/api/ws?target={target}"
        self.ws: ClientConnection = connect(
            url, additional_headers={"Cookie": f"melfa_session={self.token}"}, legacy=True
        )
        self.received: list[dict[str, Any]] = []
        self.sent: list[dict[str, Any]] = []
        self.unread: list[dict[str, Any]] = []

    def send(self, message: dict[str, Any]) -> None:
        self.sent.append(message)
        self.ws.send(json.dumps(message))

    def until(self, kind: str, limit: int = 2000, **match: Any) -> dict[str, Any]:
        """The first message of ``kind`` (with ``match``) not yet waited for: acks and
        events travel separately, so it may have come before the one waited for last."""

        def fits(message: dict[str, Any]) -> bool:
            same = all(message.get(k) == v for k, v in match.items())
            return message.get("type") == kind and same

        for message in self.unread:
            if fits(message):
                self.unread.remove(message)
                return message
        for _ in range(limit):
            message = json.loads(self.ws.recv(timeout=30))
            self.received.append(message)
            if fits(message):
                return message
            self.unread.append(message)
        raise AssertionError(f"no {kind} with {match}")

    def rest(self, method: str, path: str, body: Any = None) -> Any:
        headers = {"Cookie": f"melfa_session={self.token}", "X-CSRF-Token": self.csrf}
        with self.live.client() as c:
            return c.request(method, path, json=body, headers=headers)


@pytest.fixture
def live(tmp_path: Path) -> Iterator[Live]:
    with fresh_live(tmp_path) as server:
        yield server


def test_every_message_of_a_session_validates_against_the_committed_schema(live: Live) -> None:
    ann = Recorder(live, "ann")
    ann.until("hello")
    ann.until("state")
    ann.send({"type": "ping", "id": 1})
    ann.until("pong", id=1)
    assert ann.rest("POST", "/api/robot/servo", {"on": True}).status_code == 200
    ann.until("lease", command="servo")  # a command took the free lease: which one, as a code
    ann.until("result", command="servo", ok=True)
    # A held key: start, heartbeat, release; then a jog the heartbeat lets lapse.
    ann.send({"type": "jog_start", "frame": "xyz", "axis": "Z", "direction": "+", "id": 2})
    ann.until("ack", id=2)
    ann.send({"type": "jog_heartbeat"})
    ann.send({"type": "jog_release", "id": 3})
    ann.until("ack", id=3)
    ann.until("jog", active=False)
    ann.send({"type": "jog_start", "frame": "joint", "axis": 0, "direction": -1, "id": 4})
    ann.until("ack", id=4)
    ann.until("jog", active=False, end="heartbeat-lost")  # no heartbeat: the dead-man ends it
    ann.send({"type": "jog_heartbeat", "id": 5})
    ann.until("ack", id=5, op="jog_heartbeat")
    ann.send({"type": "hand_toggle", "hand": 1, "id": 6})
    ann.until("ack", id=6)
    # An upload (progress), a move the controller refuses (a result with advice).
    loaded = ann.rest("POST", "/api/robot/project", {"program": PROGRAM, "points": POINTS})
    assert loaded.status_code == 200, loaded.text
    ann.until("progress")
    ann.until("result", command="load_project")
    far = ann.rest("POST", "/api/robot/move", {"joints": [0, 0, 200, 0, 0, 0]})
    assert far.status_code >= 400
    ann.until("result", ok=False)
    ann.send({"type": "dance", "id": 7})
    ann.until("error", id=7)
    ann.send({"type": "hand_toggle", "hand": 12, "id": 8})
    ann.until("error", id=8)
    ann.send({"type": "stop", "id": 9})
    ann.until("ack", id=9, op="stop")
    assert ann.rest("DELETE", "/api/lease").status_code == 200
    ann.until("lease", holder=None)
    # The cable is pulled: the service says so, and reconnects.
    worker = live.context.service.worker
    assert worker is not None and worker.robot is not None
    link = worker.robot.link
    assert isinstance(link, MemoryLink)
    link.hang_up()
    ann.until("link", status="reconnecting")
    ann.until("link", status="connected")
    # Her own simulator, where the debugger streams.
    mine = Recorder(live, "ann", target="mine")
    mine.until("hello")
    body = {"program": PROGRAM, "points": POINTS, "speed": "instant"}
    assert mine.rest("POST", "/api/debug?target=mine", body).status_code == 200
    assert mine.rest("POST", "/api/debug/command/run?target=mine").status_code == 200
    mine.until("debug")
    for recorder in (ann, mine):
        recorder.ws.close()

    received = ann.received + mine.received
    kinds = {m["type"] for m in received}
    assert kinds == set(committed()["$defs"]["ServerMessage"]["discriminator"]["mapping"])
    server = validator("ServerMessage")
    wrong = [(m, list(server.iter_errors(m))) for m in received if not server.is_valid(m)]
    assert not wrong, wrong[:3]
    for message in received:  # the models read what the schema allows
        SERVER.validate_python(message)

    client = validator("ClientMessage")
    accepted = [m for m in ann.sent if m["type"] in CLIENT_TYPES and m.get("id") != 8]
    assert {m["type"] for m in accepted} == CLIENT_TYPES
    assert all(client.is_valid(m) for m in accepted), accepted
    refused = [m for m in ann.sent if m not in accepted]
    assert not any(client.is_valid(m) for m in refused)


@pytest.mark.parametrize(
    ("event", "message"),
    [
        (StateSnapshot, StateMessage),
        (DebugUpdate, DebugMessage),
        (LinkStatusChanged, LinkMessage),
        (UploadProgress, ProgressMessage),
        (CommandResult, CommandResultMessage),
        (LeaseChanged, LeaseMessage),
        (JogChanged, JogMessage),
    ],
)
def test_every_field_of_an_event_has_its_place_in_the_message(event: Any, message: Any) -> None:
    """A field the service adds to an event and the protocol does not know would be
    dropped on the way to the clients: the message model names every one."""
    dropped = {"actor"} if event is StateSnapshot else set()  # a snapshot is nobody's
    missing = {f.name for f in dataclasses.fields(event)} - set(message.model_fields) - dropped
    assert not missing, f"{message.__name__} has no place for {sorted(missing)}"
