"""rosbridge done properly, against the real app under uvicorn with roslibpy and raw
WebSockets: personal access tokens (URL, auth op, revocation), binary frames, every rosapi
call answered or "not supported", fragment_size, queue_length, call_service arguments,
thesis mode per connection, and the rosbridge port of its own."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import roslibpy
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from melfa.ros.rosbridge_server import Outbox
from tests.ros.test_rosbridge import Inbox, receive
from tests.ros.webserver import Server, serve
from tests.waiting import wait_until


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with serve(Path(tmp_path_factory.mktemp("web")), rosbridge_mode="melfa") as running:
        yield running


def raw(url: str) -> ClientConnection:
    return connect(url, open_timeout=20)


def ros_at(url: str) -> Any:
    ros = roslibpy.Ros(host=url)
    ros.run(timeout=20)
    return ros


# ------------------------------------------------------------------ tokens


def test_a_token_in_the_url_signs_in_and_revoking_it_closes_the_socket(server: Server) -> None:
    token = server.token("ann")
    ros = ros_at(f"{server.ws_url}?token={token}")
    closed = threading.Event()
    ros.on("close", lambda *_: closed.set())
    try:
        joints = Inbox()
        roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState").subscribe(joints)
        wait_until(lambda: len(joints) >= 2)
        user = server.store.accounts.get_user("ann")
        (listed,) = server.store.tokens.list(user)
        server.store.tokens.revoke(user, listed.id)
        assert closed.wait(20), "a revoked token's socket stays open"
    finally:
        ros.close()
    with raw(f"{server.ws_url}?token={token}") as ws:  # and it no longer signs in
        assert "authentication failed" in receive(ws)["msg"]


def test_a_token_in_the_auth_op_and_on_the_own_port(server: Server) -> None:
    token = server.token("ann")
    for url in (server.ws_url, server.bridge_url, f"{server.bridge_url}/rosbridge"):
        ros = roslibpy.Ros(host=url)
        ros.run(timeout=20)
        # The auth op first, in order with what follows: roslibpy's authenticate() sends it
        # from its "ready" event, which may fire after a call made at once, and the server
        # rightly refuses a first message that is not auth (2 of 5 clean clones lost it).
        auth = {"op": "auth", "mac": token, "client": "roslibpy", "dest": "melfa"}
        ros.send_on_ready(roslibpy.Message({**auth, "rand": "", "t": 0, "level": "user", "end": 0}))
        try:
            assert "/melfa/run" in ros.get_services()
        finally:
            ros.close()


def test_no_token_no_access_on_the_own_port(server: Server) -> None:
    for url in (server.bridge_url, f"{server.bridge_url}/?token=melfa_pat_forged"):
        with raw(url) as ws:
            if "token" not in url:  # the server waits for an auth op first
                ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states"}))
            assert "authentication failed" in receive(ws)["msg"]
            with pytest.raises(ConnectionClosed):
                ws.recv(timeout=20)


# ------------------------------------------------------------------ frames and arguments


def test_binary_frames_are_refused_and_the_connection_stays(server: Server) -> None:
    with raw(f"{server.ws_url}?token={server.token('ann')}") as ws:
        ws.send(b"\xa2bopisubscribe")  # CBOR
        status = receive(ws)
        assert status["op"] == "status" and "binary frames" in status["msg"]
        ws.send(json.dumps({"op": "call_service", "id": "t", "service": "/rosapi/get_time"}))
        assert receive(ws)["values"]["time"]["secs"] > 0


def test_call_service_arguments_are_checked_before_anything_runs(server: Server) -> None:
    with raw(f"{server.ws_url}?token={server.token('ann')}") as ws:
        for args in ([], ["go"], {"bogus": 1}, "x"):
            ws.send(json.dumps({"op": "call_service", "service": "/melfa/run", "args": args}))
            reply = receive(ws)
            if reply["op"] == "status":
                assert "args must be an object" in reply["msg"]
            else:
                assert reply["result"] is False and "takes no arguments" in reply["values"]
        ws.send(json.dumps({"op": "call_service", "service": "/melfa/servo", "args": {"data": 1}}))
        assert "data: bool" in receive(ws)["values"]
    assert not server.app.state.web.service.state.running


def test_load_services_take_the_texts_as_arguments(server: Server) -> None:
    ros = ros_at(f"{server.ws_url}?token={server.token('ivy')}")
    try:
        load = roslibpy.Service(ros, "/melfa/load_project", "std_srvs/Trigger")
        reply = load.call(
            roslibpy.ServiceRequest(
                {
                    "program": "10 SERVO ON\n20 MOV P1\n30 END\n",
                    "points": "DEF POS P1=(400.00,0.00,600.00,180.00,0.00,180.00)(7,0)\n",
                }
            ),
            timeout=60,
        )
        assert reply["success"] is True, reply
        assert "program and points loaded" in reply["message"]
    finally:
        ros.close()


# ------------------------------------------------------------------ rosapi


def test_rosapi_answers_what_clients_ask(server: Server) -> None:
    ros = ros_at(f"{server.ws_url}?token={server.token('ann')}")
    try:
        assert "/melfa" in ros.get_nodes()
        assert set(ros.get_topics_for_type("std_msgs/String")) >= {
            "/execute_instruction",
            "/tool_pose",
        }
        details = ros.get_message_details("sensor_msgs/JointState")
        names = {d["type"] for d in details["typedefs"]}
        assert {"sensor_msgs/JointState", "std_msgs/Header"} <= names
        assert ros.get_service_type("/melfa/servo") == "std_srvs/SetBool"
        node = ros.get_node_details("/melfa")
        assert "/joint_states" in node["publishing"] and "/melfa/reset" in node["services"]
        assert ros.get_services_for_type("std_srvs/SetBool") == ["/melfa/servo"]
        request = ros.get_service_request_details("std_srvs/SetBool")
        assert request["typedefs"][0]["fieldnames"] == ["data"]
    finally:
        ros.close()


def test_rosapi_calls_not_offered_say_so(server: Server) -> None:
    with raw(f"{server.ws_url}?token={server.token('ann')}") as ws:
        for name in ("search_params", "action_servers", "no_such_thing"):
            ws.send(json.dumps({"op": "call_service", "service": f"/rosapi/{name}", "args": {}}))
            reply = receive(ws)
            assert reply["result"] is False
            assert "not supported here" in reply["values"] or "not a rosapi" in reply["values"]
            assert "parameter name" not in reply["values"]


# ------------------------------------------------------------------ fragments and queues


def test_fragment_size_splits_what_the_client_receives(server: Server) -> None:
    with raw(f"{server.ws_url}?token={server.token('ann')}") as ws:
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states", "fragment_size": 64}))
        parts = []
        while True:
            message = receive(ws)
            assert message["op"] == "fragment" and len(message["data"]) <= 64
            if message["num"] == 0:
                parts = []
            parts.append(message)
            if message["num"] == message["total"] - 1 and len(parts) == message["total"]:
                break
        whole = json.loads("".join(p["data"] for p in parts))
        assert whole["op"] == "publish" and whole["topic"] == "/joint_states"
        assert len(whole["msg"]["position"]) == 6
        ws.send(json.dumps({"op": "subscribe", "topic": "/tool_pose", "fragment_size": -1}))
        while (status := receive(ws))["op"] != "status":
            pass
        assert "fragment_size" in status["msg"]


def test_queue_length_keeps_only_the_newest_of_a_topic() -> None:
    outbox = Outbox(maxlen=10)
    for n in range(5):
        outbox.put({"n": n}, "joint_states", 2)
        outbox.put({"s": n}, None, None)
    waiting = [json.loads(t) for t in iter(outbox.take, None)]
    assert [m["n"] for m in waiting if "n" in m] == [3, 4]
    assert [m["s"] for m in waiting if "s" in m] == [0, 1, 2, 3, 4]
    assert outbox.dropped == 3


def test_queue_length_is_accepted_from_roslibpy_and_checked(server: Server) -> None:
    with raw(f"{server.ws_url}?token={server.token('ann')}") as ws:
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states", "queue_length": 1}))
        assert receive(ws)["topic"] == "/joint_states"
        ws.send(json.dumps({"op": "subscribe", "topic": "/tool_pose", "queue_length": "x"}))
        while (status := receive(ws))["op"] != "status":
            pass
        assert "queue_length" in status["msg"]


# ------------------------------------------------------------------ thesis mode


def test_thesis_mode_answers_only_when_asked_without_parentheses(server: Server) -> None:
    ros = ros_at(f"{server.ws_url}?token={server.token('ann')}&mode=thesis")
    try:
        poses, joints = Inbox(), Inbox()
        roslibpy.Topic(ros, "/tool_pose", "std_msgs/String").subscribe(poses)
        roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState").subscribe(joints)
        wait_until(lambda: len(joints) >= 10)
        assert len(poses) == 0  # the thesis's node published on request only
        roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String").publish(
            roslibpy.Message({"data": "---REQUEST TOOL POSE---"})
        )
        wait_until(lambda: len(poses) == 1)
        text = poses.last()["data"]  # type: ignore[index]
        values = [float(v) for v in text.split(",")]
        assert not text.startswith("(") and len(values) == 6
        assert values[0] > 0.1 and values[3] != 0  # metres and radians, X and roll set
    finally:
        ros.close()


def test_override_and_state_services(server: Server) -> None:
    ros = ros_at(f"{server.ws_url}?token={server.token('ivy')}")
    try:

        def call(name: str, args: dict[str, Any]) -> dict[str, Any]:
            service = roslibpy.Service(ros, f"/melfa/{name}", "std_srvs/Trigger")
            reply: dict[str, Any] = service.call(roslibpy.ServiceRequest(args), timeout=30)
            return reply

        missing = call("override", {})
        assert missing["success"] is False and "~override" in missing["message"]
        assert call("override", {"override": 150})["success"] is False
        assert call("override", {"override": 40}) == {"success": True, "message": "override 40 %"}
        wait_until(lambda: "override 40 %" in call("state", {})["message"])
        assert "link connected" in call("state", {})["message"]
        assert call("reset", {}) == {"success": True, "message": "alarm reset"}
    finally:
        ros.close()


def test_two_connections_of_one_user_share_the_lease(server: Server) -> None:
    token = server.token("ivy")
    first, second = (
        ros_at(f"{server.ws_url}?token={token}"),
        ros_at(f"{server.bridge_url}/?token={token}"),
    )
    try:
        servo = roslibpy.Service(first, "/melfa/servo", "std_srvs/SetBool")
        assert servo.call(roslibpy.ServiceRequest({"data": True}), timeout=30)["success"]
        stop = roslibpy.Service(second, "/melfa/stop", "std_srvs/Trigger")
        override = roslibpy.Service(second, "/melfa/override", "std_srvs/Trigger")
        reply = override.call(roslibpy.ServiceRequest({"override": 30}), timeout=30)
        assert reply["success"] is True, reply  # the same user's other connection may act
        assert stop.call(roslibpy.ServiceRequest({}), timeout=30)["success"] is True
    finally:
        first.close()
        second.close()
