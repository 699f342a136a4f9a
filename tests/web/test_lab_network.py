"""The lab's networks at every door, through a real `melfa serve --lab-network 10.0.0.0/8
--rosbridge-port P` (a subprocess: real uvicorn, real sockets; every byte to the virtual
controller traced): the tests connect from 127.0.0.1, outside 10.0.0.0/8, so a student's
take control, load, run, servo, hand, jog and queue are refused with the same words from
REST, the WebSocket, rosbridge and the thesis's messages, nothing reaches the controller,
STOP is answered everywhere, reading works, a private simulator is not restricted and staff
are exempt. The desk then lets 127.0.0.0/8 in, live, and the same commands go. Third-party
clients unmodified: httpx, websockets, roslibpy."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
import roslibpy
from websockets.sync.client import connect

from melfa.link.wrappers import load_trace
from melfa.vocab.refusals import Refusal
from tests.serving import free_port, melfa_serve, stop_process
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(300)

ADMIN = "admin-password-1"
POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
OUTSIDE = " ".join(Refusal.OUTSIDE_LAB.words())
"""What every door says (one home: `melfa.vocab.refusals`)."""
ELSEWHERE, HERE = ["10.0.0.0/8"], ["127.0.0.0/8"]


def program(door: str) -> str:
    """A program only this door loads (its comment marks its bytes in the trace)."""
    return f"' door {door}\nSERVO ON\nMOV P1\nEND\n"


@dataclass
class Lab:
    url: str
    bridge: str
    trace: Path
    cookies: dict[str, tuple[str, str]]
    """user -> (session token, CSRF token)"""
    tokens: dict[str, str]
    """user -> personal access token"""

    def sent(self) -> bytes:
        events = load_trace(self.trace.read_text(encoding="utf-8").splitlines())
        return b"".join(e.data for e in events if e.direction == "->")

    def rest(self, user: str, method: str, path: str, body: Any = None) -> httpx.Response:
        session, csrf = self.cookies[user]
        return httpx.request(
            method,
            self.url + path,
            json=body,
            headers={"x-csrf-token": csrf},
            cookies={"melfa_session": session},
            timeout=60,
        )

    def networks(self, networks: list[str]) -> dict[str, Any]:
        """What the instructor's desk does (as admin)."""
        reply = self.rest("admin", "PUT", "/api/desk/lab-network", {"networks": networks})
        assert reply.status_code == 200, reply.text
        desk: dict[str, Any] = reply.json()
        return desk

    def ros(self, user: str, mode: str) -> Any:
        ros = roslibpy.Ros(host=f"{self.bridge}/?token={self.tokens[user]}&mode={mode}")
        ros.run(timeout=20)
        return ros

    def idle(self) -> bool:
        state = self.rest("admin", "GET", "/api/robot/state").json()
        return not (state["running"] or state["program_running"] or state["moving"])


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Lab]:
    data = tmp_path_factory.mktemp("lab")
    sim_port, bridge_port = free_port(), free_port()
    sim = subprocess.Popen(
        [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{sim_port}", "--no-pacing"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    trace = data / "robot.trace"
    try:
        with melfa_serve(
            data,
            "--robot",
            f"tcp://127.0.0.1:{sim_port}",
            "--trace",
            str(trace),
            "--lab-network",
            ELSEWHERE[0],
            "--rosbridge-port",
            str(bridge_port),
            admin_password=ADMIN,
            timeout=60,
        ) as url:
            yield _accounts(Lab(url, f"ws://127.0.0.1:{bridge_port}", trace, {}, {}))
    finally:
        stop_process(sim)


def _accounts(lab: Lab) -> Lab:
    """admin and ann (a student) signed in, each with a personal access token."""
    for user, password in (("admin", ADMIN), ("ann", "ann-password-12")):
        if user != "admin":
            made = lab.rest("admin", "POST", "/api/users", {"username": user, "password": password})
            assert made.status_code == 201, made.text
        signed = httpx.post(
            lab.url + "/api/session", json={"username": user, "password": password}, timeout=30
        )
        lab.cookies[user] = (signed.cookies["melfa_session"], signed.json()["csrf_token"])
        lab.tokens[user] = lab.rest(user, "POST", "/api/tokens", {"label": "net"}).json()["token"]
    return lab


@pytest.fixture
def outside(lab: Lab) -> Lab:
    """The lab's network is 10.0.0.0/8 (the tests' 127.0.0.1 is outside); nobody holds the
    robot."""
    assert lab.networks(ELSEWHERE)["lab_networks"] == ELSEWHERE
    wait_until(lab.idle, what="the arm still")
    lab.rest("admin", "POST", "/api/lease/takeover")
    lab.rest("admin", "DELETE", "/api/lease")
    return lab


def test_rest(outside: Lab) -> None:
    lab = outside
    load = {"program": program("rest"), "points": POINTS}
    for method, path, body in [
        ("POST", "/api/lease", None),
        ("POST", "/api/robot/project", load),
        ("POST", "/api/robot/run", {"servo_on": True}),
        ("POST", "/api/robot/servo", {"on": True}),
        ("POST", "/api/robot/hand", {"hand": 1, "action": "toggle"}),
        ("POST", "/api/robot/jog-step", {"frame": "joint", "axis": 1, "direction": 1}),
        ("POST", "/api/queue", load),
    ]:
        refused = lab.rest("ann", method, path, body)
        error = refused.json()["error"]
        assert (refused.status_code, error["code"], error["message"]) == (
            403,
            "outside-lab",
            OUTSIDE,
        ), path
    assert b"door rest" not in lab.sent()
    assert lab.rest("ann", "GET", "/api/lease").json()["holder"] is None

    assert lab.rest("ann", "GET", "/api/robot/state").status_code == 200  # reading: yes
    assert lab.rest("ann", "POST", "/api/robot/stop").status_code == 200  # STOP: always
    mine = lab.rest("ann", "POST", "/api/robot/project?target=mine", load)
    assert mine.status_code == 200, mine.text  # her own simulator: anywhere

    # The refusal is audited, with where it came from.
    entries = lab.rest("admin", "GET", "/api/audit?actor=ann&limit=50").json()["entries"]
    refusals = [e for e in entries if e["result"] == f"refused: {OUTSIDE}"]
    assert refusals and refusals[0]["details"]["address"] == "127.0.0.1"

    # Staff are not restricted (they switch the setting from anywhere anyway).
    assert lab.rest("admin", "POST", "/api/robot/servo", {"on": False}).status_code == 200
    assert lab.rest("admin", "DELETE", "/api/lease").status_code == 200

    desk = lab.networks(HERE)  # the desk lets the tests' network in, live
    assert (desk["lab_networks"], desk["your_address"]) == (HERE, "127.0.0.1")
    loaded = lab.rest("ann", "POST", "/api/robot/project", load)
    assert loaded.status_code == 200, loaded.text
    assert b"door rest" in lab.sent()


def test_websocket(outside: Lab) -> None:
    """What the socket carries that changes the robot (jog, hand) asks the same policy;
    its STOP is always answered."""
    lab = outside
    session = lab.cookies["ann"][0]
    headers = {"Cookie": f"melfa_session={session}", "Origin": lab.url}
    with connect(lab.url.replace("http", "ws") + "/api/ws", additional_headers=headers) as ws:
        numbers = iter(range(1, 100))

        def ask(message: dict[str, Any]) -> dict[str, Any]:
            number = next(numbers)
            ws.send(json.dumps({**message, "id": number}))
            while True:
                reply = json.loads(ws.recv(timeout=30))
                if reply.get("id") == number:
                    return reply

        for message in (
            {"type": "hand_toggle", "hand": 1},
            {"type": "jog_start", "frame": "joint", "axis": 1, "direction": 1},
        ):
            refused = ask(message)
            assert refused["type"] == "error", refused
            assert (refused["error"]["code"], refused["error"]["message"]) == (
                "outside-lab",
                OUTSIDE,
            )
        assert ask({"type": "stop"})["type"] == "ack"

        lab.networks(HERE)

        def toggles() -> bool:
            mine = ask({"type": "hand_toggle", "hand": 1})
            assert mine["type"] == "ack" or mine["error"]["code"] == "controller-refused", mine
            return bool(mine["type"] == "ack")

        wait_until(toggles, what="ann's hand toggle")


def call(ros: Any, name: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
    kind = "std_srvs/SetBool" if name == "servo" else "std_srvs/Trigger"
    service = roslibpy.Service(ros, f"/melfa/{name}", kind)
    reply: dict[str, Any] = service.call(roslibpy.ServiceRequest(args or {}), timeout=60)
    return reply


def test_rosbridge(outside: Lab) -> None:
    lab = outside
    load = {"program": program("ros"), "points": POINTS}
    ros = lab.ros("ann", "melfa")
    try:
        refused = {"success": False, "message": OUTSIDE}
        assert call(ros, "servo", {"data": True}) == refused
        assert call(ros, "load_project", load) == refused
        assert call(ros, "run") == refused
        assert call(ros, "stop")["success"] is True
        assert b"door ros" not in lab.sent()

        lab.networks(HERE)
        assert call(ros, "load_project", load)["success"] is True
        assert b"door ros" in lab.sent()
    finally:
        ros.close()


class Errors:
    """``/execute_error`` as roslibpy delivers it (its own thread)."""

    def __init__(self) -> None:
        self.texts: list[str] = []
        self._lock = threading.Lock()

    def __call__(self, message: dict[str, Any]) -> None:
        with self._lock:
            self.texts.append(message["data"])

    def since(self, start: int) -> list[str]:
        with self._lock:
            return self.texts[start:]


@pytest.mark.parametrize("mode", ["melfa", "thesis"])
def test_thesis_messages(outside: Lab, mode: str) -> None:
    lab = outside
    marker = f"door thesis-{mode}"
    ros = lab.ros("ann", mode)
    try:
        errors = Errors()
        roslibpy.Topic(ros, "/execute_error", "std_msgs/String").subscribe(errors)
        topic = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")

        def send(*texts: str) -> None:
            for text in texts:
                topic.publish(roslibpy.Message({"data": text}))

        def load() -> None:
            lines = program(f"thesis-{mode}").splitlines()
            send("---LOAD PROGRAM BEGIN---", *lines, "---LOAD PROGRAM END---")

        before = len(errors.texts)
        load()
        send("---RUN PROGRAM---")
        wait_until(lambda: len(errors.since(before)) >= 2, what="/execute_error")
        assert set(errors.since(before)) == {OUTSIDE}
        assert call(ros, "stop")["success"] is True  # STOP, on the same connection
        assert marker.encode() not in lab.sent()

        lab.networks(HERE)
        before = len(errors.texts)
        load()
        wait_until(lambda: marker.encode() in lab.sent(), what="the program sent")
        assert OUTSIDE not in errors.since(before)
    finally:
        ros.close()


def test_a_network_that_is_not_one_is_refused_in_words(outside: Lab) -> None:
    lab = outside
    reply = lab.rest("admin", "PUT", "/api/desk/lab-network", {"networks": ["192.168.10.0/33"]})
    error = reply.json()["error"]
    assert reply.status_code == 422 and error["where"] == {"field": "networks"}
    assert error["message"].startswith("'192.168.10.0/33' is not a network")
    assert lab.rest("admin", "GET", "/api/desk").json()["lab_networks"] == ELSEWHERE
    student = lab.rest("ann", "PUT", "/api/desk/lab-network", {"networks": []})
    assert student.status_code == 403  # staff only

    entries = lab.rest("admin", "GET", "/api/audit?action=lab-network.set&limit=5").json()
    assert entries["entries"][0]["details"] == {"networks": "10.0.0.0/8"}


def test_serve_refuses_a_bad_network_before_it_starts(tmp_path: Path) -> None:
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "melfa",
            "serve",
            "--data",
            str(tmp_path / "d"),
            "--lab-network",
            "lab",
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2
    assert "--lab-network: 'lab' is not a network" in done.stderr
    assert not (tmp_path / "d").exists()  # nothing made
