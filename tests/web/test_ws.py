"""The WebSocket: hello, streaming snapshots, lease broadcasts, the jog dead-man."""

from __future__ import annotations

from typing import Any

import pytest
from starlette.websockets import WebSocketDisconnect

from tests.web.conftest import Web


def until(ws: Any, kind: str, limit: int = 500, **match: Any) -> dict[str, Any]:
    """The next message of type ``kind`` whose fields include ``match``."""
    for _ in range(limit):
        message: dict[str, Any] = ws.receive_json()
        if message["type"] == kind and all(message.get(k) == v for k, v in match.items()):
            return message
    raise AssertionError(f"no {kind} message with {match}")


def test_hello_then_state_snapshots(web: Web) -> None:
    with web.ann.ws() as ws:
        hello = ws.receive_json()
        assert hello["type"] == "hello" and hello["user"] == "ann"
        assert hello["link"] == "connected" and hello["robot"] == "sim"
        first = until(ws, "state")
        second = until(ws, "state")
        assert second["seq"] > first["seq"]
        assert len(second["joints"]) == 6 and second["link"] == "connected"
        ws.send_json({"type": "ping", "id": 7})
        assert until(ws, "pong") == {"type": "pong", "id": 7}


def test_websocket_needs_login_and_same_origin(web: Web) -> None:
    with pytest.raises(WebSocketDisconnect) as refused, web.client.websocket_connect("/api/ws"):
        pass
    assert refused.value.code == 1008
    with pytest.raises(WebSocketDisconnect) as foreign, web.ann.ws(origin="http://evil.example"):
        pass
    assert foreign.value.code == 1008


def test_results_and_progress_reach_every_viewer(web: Web) -> None:
    with web.bob.ws() as viewer:
        until(viewer, "hello")
        web.ann.post("/api/robot/project", json={"program": "END\n", "points": ""})
        progress = until(viewer, "progress", command="load_project")
        assert progress["actor"] == {"user": "ann", "role": "student"}
        result = until(viewer, "result", command="load_project")
        assert result["ok"] is True and result["command_id"] == progress["command_id"]


def test_lease_changes_are_broadcast(web: Web) -> None:
    with web.bob.ws() as viewer:
        until(viewer, "hello")
        web.ann.post("/api/lease")
        taken = until(viewer, "lease", reason="acquired")
        assert taken["holder"] == {"user": "ann", "role": "student"} and taken["previous"] is None
        web.ivy.post("/api/lease/takeover")
        over = until(viewer, "lease", reason="taken-over")
        assert over["holder"]["user"] == "ivy" and over["previous"]["user"] == "ann"


@pytest.mark.usefixtures("not_strict")  # continuous JOG: documented only
def test_jog_stops_and_lease_ends_when_the_socket_closes(web: Web) -> None:
    web.ann.post("/api/robot/servo", json={"on": True})
    with web.bob.ws() as viewer:
        until(viewer, "hello")
        with web.ann.ws() as ws:
            until(ws, "hello")
            ws.send_json(
                {"type": "jog_start", "frame": "joint", "axis": 0, "direction": 1, "id": 1}
            )
            ack = until(ws, "ack", id=1)
            assert ack["op"] == "jog_start"
            ws.send_json({"type": "jog_heartbeat"})
            until(viewer, "jog", active=True)
        ended = until(viewer, "jog", active=False)
        assert ended["end"] == "client-disconnected"
        lease = until(viewer, "lease", holder=None)
        assert lease["reason"] == "holder-disconnected"  # after the arm stopped
    assert web.service.state.jogging is False
    assert web.ann.get("/api/lease").json()["holder"] is None


def test_lease_stays_while_another_socket_of_the_session_is_open(web: Web) -> None:
    web.ann.post("/api/lease")
    with web.ann.ws() as first:
        until(first, "hello")
        with web.ann.ws() as second:
            until(second, "hello")
        first.send_json({"type": "ping", "id": 1})
        until(first, "pong")
        assert web.ann.get("/api/lease").json()["you"] is True
    assert web.ann.get("/api/lease").json()["holder"] is None


@pytest.mark.usefixtures("not_strict")  # continuous JOG: documented only
def test_jog_release_and_hand_toggle_and_stop(web: Web) -> None:
    web.ann.post("/api/robot/servo", json={"on": True})
    with web.ann.ws() as ws:
        until(ws, "hello")
        ws.send_json({"type": "jog_start", "frame": "xyz", "axis": "Z", "direction": "+", "id": 1})
        until(ws, "ack", id=1)
        ws.send_json({"type": "jog_release", "id": 2})
        seen: list[dict[str, Any]] = []  # the ack and the event may come in either order
        while not ({"ack", "jog"} <= {m["type"] for m in seen}):
            message = ws.receive_json()
            if message["type"] == "ack" or (message["type"] == "jog" and not message["active"]):
                seen.append(message)
        assert next(m for m in seen if m["type"] == "jog")["end"] == "released"
        # The first toggle's result depends on whether a hand poll came first (unknown is
        # taken as open); the second always undoes the first.
        ws.send_json({"type": "hand_toggle", "hand": 1, "id": 3})
        first = until(ws, "ack", id=3)["open"]
        ws.send_json({"type": "hand_toggle", "hand": 1, "id": 5})
        assert until(ws, "ack", id=5)["open"] is (not first)
        ws.send_json({"type": "stop", "id": 4})
        until(ws, "ack", id=4)


@pytest.mark.parametrize(
    ("message", "code"),
    [
        ("not json", "bad-message"),
        ("[1, 2]", "bad-message"),
        ('{"type": "dance"}', "unknown-message"),
        ('{"type": "jog_start", "frame": "joint", "axis": 9, "direction": 1}', "invalid-value"),
        ('{"type": "jog_start", "frame": 3, "axis": 1, "direction": 1}', "invalid-value"),
        ('{"type": "hand_toggle", "hand": 12}', "invalid-value"),
        ("x" * 5000, "too-large"),
    ],
)
def test_bad_messages_get_the_error_shape(web: Web, message: str, code: str) -> None:
    with web.ann.ws() as ws:
        until(ws, "hello")
        ws.send_text(message)
        error = until(ws, "error")
        assert error["error"]["code"] == code
        assert set(error["error"]) == {"code", "message", "status", "where", "detail"}
        ws.send_json({"type": "ping", "id": 1})
        until(ws, "pong")  # the socket survives


def test_jog_without_lease_is_refused(web: Web) -> None:
    web.ann.post("/api/lease")
    with web.bob.ws() as ws:
        until(ws, "hello")
        ws.send_json({"type": "jog_start", "frame": "joint", "axis": 0, "direction": 1, "id": 5})
        error = until(ws, "error", id=5)
        assert error["error"]["code"] == "lease-required" and error["error"]["status"] == 423
