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
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import roslibpy
from websockets.sync.client import connect

from melfa.vocab.refusals import Refusal
from tests.waiting import wait_until
from tests.web.doors import POINTS, Errors, Lab, call, lab_server, program

pytestmark = pytest.mark.timeout(300)

OUTSIDE = " ".join(Refusal.OUTSIDE_LAB.words())
"""What every door says (one home: `melfa.vocab.refusals`)."""
ELSEWHERE, HERE = ["10.0.0.0/8"], ["127.0.0.0/8"]


class NetLab(Lab):
    def networks(self, networks: list[str]) -> dict[str, Any]:
        """What the instructor's desk does (as admin)."""
        reply = self.rest("admin", "PUT", "/api/desk/lab-network", {"networks": networks})
        assert reply.status_code == 200, reply.text
        desk: dict[str, Any] = reply.json()
        return desk


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[NetLab]:
    data = tmp_path_factory.mktemp("lab")
    with lab_server(data, "--lab-network", ELSEWHERE[0]) as served:
        lab = NetLab(served.url, served.bridge, served.trace, served.cookies, served.tokens)
        lab.add_students(["ann"])
        yield lab


@pytest.fixture
def outside(lab: NetLab) -> NetLab:
    """The lab's network is 10.0.0.0/8 (the tests' 127.0.0.1 is outside); nobody holds the
    robot."""
    assert lab.networks(ELSEWHERE)["lab_networks"] == ELSEWHERE
    wait_until(lab.idle, what="the arm still")
    lab.rest("admin", "POST", "/api/lease/takeover")
    lab.rest("admin", "DELETE", "/api/lease")
    return lab


def test_rest(outside: NetLab) -> None:
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


def test_websocket(outside: NetLab) -> None:
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


def test_rosbridge(outside: NetLab) -> None:
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


@pytest.mark.parametrize("mode", ["melfa", "thesis"])
def test_thesis_messages(outside: NetLab, mode: str) -> None:
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


def test_a_network_that_is_not_one_is_refused_in_words(outside: NetLab) -> None:
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
