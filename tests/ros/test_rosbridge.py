"""The rosbridge endpoint inside the real web app, served by uvicorn: roslibpy (from PyPI)
drives the virtual controller with the thesis's control messages, reads joint states and
tool poses, calls the services; unauthenticated clients are refused."""

from __future__ import annotations

import itertools
import json
import math
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import roslibpy
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from melfa.robot import RobotSettings
from tests.ros.webserver import Server, serve
from tests.waiting import wait_until

STEP_M = RobotSettings().jog_step_mm / 1000
PROGRAM = "10 SERVO ON\n20 MOV P1\n30 END\n"
POINTS = "DEF POS P1=(400.00,100.00,600.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with serve(Path(tmp_path_factory.mktemp("web"))) as running:
        yield running


class Inbox:
    """Messages of one topic, from roslibpy's thread."""

    def __init__(self) -> None:
        self.items: list[dict[str, Any]] = []
        self._lock = threading.Lock()

    def __call__(self, message: dict[str, Any]) -> None:
        with self._lock:
            self.items.append(message)

    def last(self) -> dict[str, Any] | None:
        with self._lock:
            return self.items[-1] if self.items else None

    def __len__(self) -> int:
        with self._lock:
            return len(self.items)


def connect_ros(server: Server, *, token: str | None = None, cookie: str | None = None) -> Any:
    headers = {"Cookie": f"melfa_session={cookie}"} if cookie else None
    ros = roslibpy.Ros(host=server.ws_url, headers=headers)
    if token is not None:
        ros.authenticate(token, "roslibpy", "melfa", "", 0, "user", 0)
    ros.run(timeout=20)
    return ros


def tool_x_axis(orientation: dict[str, float]) -> tuple[float, float, float]:
    """First column of the rotation matrix of a quaternion."""
    x, y, z, w = (orientation[k] for k in "xyzw")
    return (1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w))


def position(pose: dict[str, Any]) -> tuple[float, float, float]:
    p = pose["pose"]["position"]
    return (p["x"], p["y"], p["z"])


def test_roslibpy_control_messages_move_the_tool_and_joint_states_arrive(server: Server) -> None:
    ros = connect_ros(server, token=server.login("ann"))
    try:
        joints, poses = Inbox(), Inbox()
        roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState").subscribe(joints)
        roslibpy.Topic(ros, "/tool_pose_stamped", "geometry_msgs/PoseStamped").subscribe(poses)
        wait_until(lambda: len(joints) >= 5 and len(poses) >= 1)
        first = joints.last()
        assert first is not None
        assert first["name"] == [f"joint_{i}" for i in range(1, 7)]
        assert first["position"][2] == pytest.approx(math.pi / 2, abs=1e-3)  # J3 = 90°
        start = poses.last()
        assert start is not None and start["header"]["frame_id"] == "base"

        instruction = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")
        for text in ("---SINGLE INSTRUCTION---", "SERVO ON", "---MOV TOOL +X---"):
            instruction.publish(roslibpy.Message({"data": text}))

        axis = tool_x_axis(start["pose"]["orientation"])
        expected = [p + STEP_M * a for p, a in zip(position(start), axis, strict=True)]

        def arrived() -> bool:
            pose = poses.last()
            return pose is not None and math.dist(position(pose), expected) < 1e-4

        wait_until(arrived, what=lambda: f"{expected} from {position(start)}: {poses.last()}")
        wait_until(lambda: (joints.last() or first)["position"] != first["position"])
    finally:
        ros.close()


def test_roslibpy_services_load_and_run_a_program(server: Server) -> None:
    ros = connect_ros(server, cookie=server.login("ivy"))
    try:
        poses = Inbox()
        roslibpy.Topic(ros, "/tool_pose_stamped", "geometry_msgs/PoseStamped").subscribe(poses)

        def call(name: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
            kind = "std_srvs/SetBool" if name == "servo" else "std_srvs/Trigger"
            service = roslibpy.Service(ros, f"/melfa/{name}", kind)
            result: dict[str, Any] = service.call(roslibpy.ServiceRequest(args or {}), timeout=60)
            return result

        missing = call("load_program")
        assert missing["success"] is False and "~program" in missing["message"]

        roslibpy.Param(ros, "/melfa/program").set(PROGRAM)
        roslibpy.Param(ros, "/melfa/points").set(POINTS)
        assert roslibpy.Param(ros, "/melfa/program").get(timeout=10) == PROGRAM
        loaded = call("load_program")
        assert loaded["success"] is True, loaded
        assert "program loaded" in loaded["message"]
        assert call("load_points")["success"] is True
        assert call("servo", {"data": True}) == {"success": True, "message": "servo on"}
        assert call("run")["success"] is True

        def at_p1() -> bool:
            pose = poses.last()
            return pose is not None and math.dist(position(pose), (0.4, 0.1, 0.6)) < 1e-3

        wait_until(at_p1, what=lambda: f"P1; the pose is {poses.last()}")
        assert call("stop") == {"success": True, "message": "stopped"}
    finally:
        ros.close()


def test_roslibpy_string_topics_and_requests(server: Server) -> None:
    ros = connect_ros(server, token=server.login("ann"))
    try:
        texts, joints = Inbox(), Inbox()
        roslibpy.Topic(ros, "/joint_state", "std_msgs/String").subscribe(texts)
        roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState").subscribe(joints)
        wait_until(lambda: len(texts) >= 3 and len(joints) >= 3)
        last, state = texts.last(), joints.last()
        assert last is not None and state is not None
        values = [float(v) for v in last["data"].strip("()").split(",")]
        assert values == pytest.approx(state["position"], abs=1e-5)  # the arm is still
        topics = ros.get_topics()
        assert "/execute_instruction" in topics and "/joint_states" in topics
    finally:
        ros.close()


# ------------------------------------------------------------------ the protocol, raw


def open_raw(server: Server, headers: dict[str, str] | None = None) -> ClientConnection:
    return connect(server.ws_url, additional_headers=headers, open_timeout=20)


def receive(ws: ClientConnection, timeout: float = 20.0) -> dict[str, Any]:
    message: dict[str, Any] = json.loads(ws.recv(timeout=timeout))
    return message


def refused(ws: ClientConnection) -> tuple[dict[str, Any], int | None]:
    """The status message before the close, and the close code."""
    status = receive(ws)
    with pytest.raises(ConnectionClosed) as closed:
        ws.recv(timeout=20)
    return status, closed.value.rcvd.code if closed.value.rcvd else None


def test_unauthenticated_clients_are_refused(server: Server) -> None:
    with open_raw(server) as ws:
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states"}))
        status, code = refused(ws)
    assert status["level"] == "error" and "authentication failed" in status["msg"]
    assert code == 1008


def test_a_wrong_token_is_refused(server: Server) -> None:
    with open_raw(server) as ws:
        ws.send(json.dumps({"op": "auth", "mac": "not-a-session", "client": "x"}))
        _, code = refused(ws)
    assert code == 1008


def test_the_session_cookie_counts_only_from_an_allowed_origin(server: Server) -> None:
    token = server.login("ann")
    evil = {"Cookie": f"melfa_session={token}", "Origin": "http://evil.example"}
    with open_raw(server, evil) as ws:
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states"}))
        _, code = refused(ws)
    assert code == 1008
    own = {"Cookie": f"melfa_session={token}", "Origin": server.http}
    with open_raw(server, own) as ws:
        ws.send(json.dumps({"op": "subscribe", "id": "s1", "topic": "/joint_states"}))
        message = receive(ws)
    assert message["op"] == "publish" and message["topic"] == "/joint_states"


def test_mistakes_get_an_error_status_and_the_connection_stays(server: Server) -> None:
    with open_raw(server) as ws:
        ws.send(json.dumps({"op": "auth", "mac": server.login("ann")}))
        ws.send(json.dumps({"op": "publish", "id": "p1", "topic": "/joint_states", "msg": {}}))
        status = receive(ws)
        assert status["op"] == "status" and status["id"] == "p1"
        assert "execute_instruction" in status["msg"]
        ws.send(json.dumps({"op": "subscribe", "topic": "/camera"}))
        assert "no topic /camera" in receive(ws)["msg"]
        ws.send(json.dumps({"op": "advertise", "topic": "/execute_instruction", "type": "x/Y"}))
        assert "std_msgs/String" in receive(ws)["msg"]
        ws.send("{not json")
        assert "not JSON" in receive(ws)["msg"]
        ws.send(json.dumps({"op": "call_service", "id": "c1", "service": "/nope"}))
        response = receive(ws)
        assert response["op"] == "service_response" and response["id"] == "c1"
        assert response["result"] is False and "/melfa/run" in response["values"]
        ws.send(json.dumps({"op": "call_service", "id": "c2", "service": "/melfa/servo"}))
        response = receive(ws)
        assert response["result"] is False and "data" in response["values"]
        ws.send(json.dumps({"op": "publish", "topic": "/execute_instruction", "msg": {}}))
        assert '{"data"' in receive(ws)["msg"]
        ws.send(json.dumps({"op": "subscribe", "topic": "/execute_error"}))
        ws.send(
            json.dumps(
                {"op": "publish", "topic": "/execute_instruction", "msg": {"data": "10 MOV P1"}}
            )
        )
        error = receive(ws)
        assert error["topic"] == "/execute_error"
        assert "not a control message" in error["msg"]["data"]


def test_throttle_rate_limits_what_one_subscription_receives(server: Server) -> None:
    with open_raw(server) as ws:
        ws.send(json.dumps({"op": "auth", "mac": server.login("ann")}))
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states", "throttle_rate": 500}))
        stamps = []
        for _ in range(3):
            message = receive(ws)
            stamp = message["msg"]["header"]["stamp"]
            stamps.append(stamp["secs"] + stamp["nsecs"] / 1e9)
    gaps = [b - a for a, b in itertools.pairwise(stamps)]
    assert all(gap >= 0.45 for gap in gaps), gaps
