"""One policy at every door, through a real `melfa serve --require-simulation --rosbridge-port
P` (a subprocess: real uvicorn, real sockets) on a real TCP virtual controller whose every
byte is traced (``--trace``): REST, the WebSocket, rosbridge services and the thesis's
control messages in both modes refuse an unsimulated program on the lab robot with the same
words and fix, run it once pre-flight passed, never send a program with errors, and refuse a
student without the lease. Third-party clients unmodified: httpx, websockets, roslibpy."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

import pytest
import roslibpy
from websockets.sync.client import connect

from melfa.lang.plan import plan_upload
from melfa.service.policy import plan_refusal
from melfa.vocab.refusals import Refusal
from tests.waiting import wait_until
from tests.web.doors import POINTS, Errors, Lab, lab_server
from tests.web.doors import call as ros_call
from tests.web.doors import program as good

pytestmark = pytest.mark.timeout(300)

GATE_TEXT = " ".join(Refusal.SIMULATION_REQUIRED.words())
"""What every door says when the gate refuses (one home: `melfa.vocab.refusals`)."""
LEASE_TEXT = " ".join(Refusal.LEASE_REQUIRED.words(holder="ann"))


def broken(door: str) -> str:
    return f"' broken {door}\nMOV P1\nGOTO 99\n"


def errors_text(program: str, points: str | None = POINTS) -> str:
    refusal = plan_refusal(plan_upload(program, points))
    assert refusal is not None
    return str(refusal)


class GateLab(Lab):
    def preflight(self, program: str, points: str = POINTS) -> None:
        """What the IDE's *Run pre-flight* does; its pass opens the gate for this text."""
        reply = self.rest("ann", "POST", "/api/preflight", {"program": program, "points": points})
        assert reply.status_code == 200 and reply.json()["passed"] is True, reply.text


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[GateLab]:
    with lab_server(tmp_path_factory.mktemp("lab"), "--require-simulation") as served:
        lab = GateLab(served.url, served.bridge, served.trace, served.cookies, served.tokens)
        lab.add_students(("ann", "bob"))
        # ann takes the lease (her first command) and keeps a connection open all along,
        # as a student with the IDE open (a lease ends with its holder's last
        # connection); bob is the student without it.
        holder = lab.ros("ann", "melfa")
        try:
            servo = lab.rest("ann", "POST", "/api/robot/servo", {"on": True})
            assert servo.status_code == 200, servo.text
            yield lab
        finally:
            holder.close()


def test_rest(lab: GateLab) -> None:
    program = good("rest")
    assert lab.rest("ann", "DELETE", "/api/robot/program").status_code == 200
    refused = lab.rest("ann", "POST", "/api/robot/project", {"program": program, "points": POINTS})
    error = refused.json()["error"]
    assert (refused.status_code, error["code"], error["message"]) == (
        409,
        "simulation-required",
        GATE_TEXT,
    )
    assert error["detail"]["fix"] == "preflight"  # the IDE's one-click fix
    ran = lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True})
    assert (ran.status_code, ran.json()["error"]["message"]) == (409, GATE_TEXT)
    assert b"door rest" not in lab.sent()

    lab.preflight(program)
    loaded = lab.rest("ann", "POST", "/api/robot/project", {"program": program, "points": POINTS})
    assert loaded.status_code == 200, loaded.text
    assert b"door rest" in lab.sent()
    assert lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}).status_code == 200
    wait_until(lambda: b"RUN" in lab.sent().split(b"door rest")[-1], what="RUN sent")
    wait_until(lab.idle, what="the program to end")

    wrong = broken("rest")
    failed = lab.rest("ann", "POST", "/api/robot/project", {"program": wrong, "points": POINTS})
    assert failed.status_code == 422 and failed.json()["error"]["code"] == "program-has-errors"
    assert failed.json()["error"]["message"] == errors_text(wrong)
    assert b"broken rest" not in lab.sent()  # the controller never got it

    taken = lab.rest("bob", "POST", "/api/robot/project", {"program": program, "points": POINTS})
    assert (taken.status_code, taken.json()["error"]["message"]) == (423, LEASE_TEXT)
    assert lab.rest("bob", "POST", "/api/robot/run", {}).json()["error"]["message"] == LEASE_TEXT


def test_websocket(lab: GateLab) -> None:
    """The WebSocket carries no load or run (those are REST's); what it does carry that
    changes the robot (jog, hand) passes the same policy: bob, without the lease, is
    refused with the same words; ann, holding it, is not."""

    def ask(user: str, message: dict[str, Any]) -> dict[str, Any]:
        session = lab.cookies[user][0]
        headers = {"Cookie": f"melfa_session={session}", "Origin": lab.url}
        with connect(lab.url.replace("http", "ws") + "/api/ws", additional_headers=headers) as ws:
            ws.send(json.dumps({**message, "id": 7}))
            while True:
                reply = json.loads(ws.recv(timeout=30))
                if reply.get("id") == 7:
                    return reply

    refused = ask("bob", {"type": "hand_toggle", "hand": 1})
    assert refused["type"] == "error"
    assert (refused["error"]["code"], refused["error"]["message"]) == ("lease-required", LEASE_TEXT)
    jog = ask("bob", {"type": "jog_start", "frame": "joint", "axis": 1, "direction": 1})
    assert jog["error"]["message"] == LEASE_TEXT

    def ann_toggles() -> bool:
        """The policy lets the holder through; the controller itself may say it is busy
        while a program from an earlier door still ends."""
        mine = ask("ann", {"type": "hand_toggle", "hand": 1})
        assert mine["type"] == "ack" or mine["error"]["code"] == "controller-refused", mine
        return bool(mine["type"] == "ack")

    wait_until(ann_toggles, what="ann's hand toggle")


def test_rosbridge_services(lab: GateLab) -> None:
    program = good("ros")

    def call(user: str, name: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
        ros = lab.ros(user, "melfa")
        try:
            return ros_call(ros, name, args)
        finally:
            ros.close()

    assert call("ann", "delete")["success"] is True
    load = {"program": program, "points": POINTS}
    assert call("ann", "load_project", load) == {"success": False, "message": GATE_TEXT}
    assert call("ann", "run") == {"success": False, "message": GATE_TEXT}
    assert call("ann", "load_program", {"program": program})["message"] == GATE_TEXT
    assert b"door ros" not in lab.sent()

    lab.preflight(program)
    assert call("ann", "load_project", load)["success"] is True
    assert call("ann", "run")["success"] is True
    assert b"door ros" in lab.sent()
    wait_until(lab.idle, what="the program to end")

    wrong = broken("ros")
    reply = call("ann", "load_project", {"program": wrong, "points": POINTS})
    assert reply == {"success": False, "message": errors_text(wrong)}
    assert b"broken ros" not in lab.sent()

    assert call("bob", "servo", {"data": True}) == {"success": False, "message": LEASE_TEXT}
    assert call("bob", "load_project", load) == {"success": False, "message": LEASE_TEXT}


@pytest.mark.parametrize("mode", ["melfa", "thesis"])
def test_thesis_messages(lab: GateLab, mode: str) -> None:
    program = good(f"thesis-{mode}")
    marker = f"door thesis-{mode}".encode()
    ros = lab.ros("ann", mode)
    bob = lab.ros("bob", mode)
    try:
        errors, bob_errors = Errors(), Errors()
        roslibpy.Topic(ros, "/execute_error", "std_msgs/String").subscribe(errors)
        roslibpy.Topic(bob, "/execute_error", "std_msgs/String").subscribe(bob_errors)
        topic = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")

        def send(*texts: str) -> None:
            for text in texts:
                topic.publish(roslibpy.Message({"data": text}))

        def load(text: str) -> None:
            send("---LOAD PROGRAM BEGIN---", *text.splitlines(), "---LOAD PROGRAM END---")
            send("---LOAD POINTS BEGIN---", *POINTS.splitlines(), "---LOAD POINTS END---")

        def said(start: int, count: int) -> list[str]:
            wait_until(lambda: len(errors.since(start)) >= count, what="/execute_error")
            return errors.since(start)

        before = len(errors.texts)
        send("---DELETE---")
        load(program)
        send("---RUN PROGRAM---")
        # The program, its points (the loaded program has not passed) and the run: refused.
        assert said(before, 3) == [GATE_TEXT] * 3
        assert marker not in lab.sent()

        lab.preflight(program)
        before = len(errors.texts)
        load(program)
        send("---RUN PROGRAM---")
        wait_until(lambda: marker in lab.sent(), what="the program sent")
        wait_until(
            lambda: b"RUN" in lab.sent().split(marker)[-1] or bool(errors.since(before)),
            what="RUN sent",
        )
        assert errors.since(before) == []
        wait_until(lab.idle, what="the program to end")

        wrong = broken(f"thesis-{mode}")
        before = len(errors.texts)
        send("---LOAD PROGRAM BEGIN---", *wrong.splitlines(), "---LOAD PROGRAM END---")
        assert said(before, 1) == [errors_text(wrong, None)]
        assert f"broken thesis-{mode}".encode() not in lab.sent()

        start = len(bob_errors.texts)
        roslibpy.Topic(bob, "/execute_instruction", "std_msgs/String").publish(
            roslibpy.Message({"data": "---RUN PROGRAM---"})
        )
        wait_until(lambda: LEASE_TEXT in bob_errors.since(start), what="bob refused")
    finally:
        ros.close()
        bob.close()
