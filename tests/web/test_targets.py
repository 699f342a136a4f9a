"""Targets: the lab robot (shared, leased) and each user's own simulator (no lease)."""

from __future__ import annotations

import asyncio
from typing import Any

from melfa.service import RobotService
from melfa.web.targets import LAB, MINE, Targets, UnknownTarget
from tests.waiting import wait_until
from tests.web.conftest import Web, assert_error
from tests.web.test_robot import ok
from tests.web.test_ws import until

PROGRAM = "SERVO ON\nMOV P1\nDLY 30\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
MINE_Q = {"target": MINE}


def test_every_user_sees_the_lab_robot_and_their_own_simulator(web: Web) -> None:
    body = ok(web.ann.get("/api/targets"))
    assert [(t["id"], t["kind"], t["label"], t["shared"]) for t in body["targets"]] == [
        (LAB, "lab", "Lab RV-6S", True),
        (MINE, "private", "My simulator", False),
    ]
    assert body["targets"][1]["robot"] == "sim" and body["targets"][1]["exists"] is False
    ok(web.ann.get("/api/robot/state", params=MINE_Q))  # using it makes it
    assert ok(web.ann.get("/api/targets"))["targets"][1]["exists"] is True
    assert_error(web.ann.get("/api/robot/state", params={"target": "bob"}), 404, "unknown-target")


def test_a_student_runs_on_their_simulator_while_the_lab_robot_is_held(web: Web) -> None:
    ann, bob = web.ann, web.bob
    ok(bob.post("/api/lease"))
    assert_error(ann.post("/api/robot/servo", json={"on": True}), 423, "lease-required")
    ok(ann.post("/api/robot/servo", json={"on": True}, params=MINE_Q))
    ok(ann.post("/api/robot/project", json={"program": PROGRAM, "points": POINTS}, params=MINE_Q))
    ok(ann.post("/api/robot/run", params=MINE_Q))
    wait_until(lambda: ok(ann.get("/api/robot/state", params=MINE_Q))["running"] is True)
    assert ok(bob.get("/api/robot/state"))["running"] is not True  # the lab robot did not run
    assert ok(bob.get("/api/lease"))["holder"]["user"] == "bob"  # nor was its lease touched
    # bob's simulator is his own: ann's run is not on it.
    assert ok(bob.get("/api/robot/state", params=MINE_Q))["running"] is not True
    ok(ann.post("/api/robot/stop", params=MINE_Q))
    wait_until(lambda: ok(ann.get("/api/robot/state", params=MINE_Q))["running"] is False)


def test_the_socket_streams_the_chosen_target(web: Web) -> None:
    ok(web.ann.post("/api/robot/servo", json={"on": True}, params=MINE_Q))
    headers = web.ann.headers({"origin": "http://testserver"}, csrf=False)
    with web.client.websocket_connect("/api/ws?target=mine", headers=headers) as ws:
        hello = until(ws, "hello")
        assert hello["target"] == {"id": MINE, "kind": "private", "label": "My simulator"}
        assert hello["lease_holder"] is None
        until(ws, "state", servo=True)  # the servo this user switched on, on this target
    with web.ann.ws() as ws:
        assert until(ws, "hello")["target"]["id"] == LAB
        for _ in range(3):
            assert until(ws, "state")["servo"] is not True  # the lab's servo stayed off


def test_idle_simulators_are_freed_and_made_again() -> None:
    async def scenario() -> list[Any]:
        now = [0.0]
        async with RobotService.from_spec("sim") as lab:
            targets = Targets(lab, idle_s=60.0, clock=lambda: now[0])
            first = await targets.get("ann", MINE)
            assert await targets.get("ann", LAB) is targets.lab
            try:
                await targets.get("ann", "other")
            except UnknownTarget:
                pass
            else:
                raise AssertionError("unknown target accepted")
            first.sockets = 1
            now[0] = 100.0
            kept = await targets.reap()  # a socket is open: still working
            first.sockets = 0
            freed = await targets.reap()
            again = await targets.get("ann", MINE)
            out = [kept, freed, first.service.closed, again is not first, targets.private_count]
            await targets.close()
            return out

    assert asyncio.run(scenario()) == [[], ["ann"], True, True, 1]


def test_slot_match_says_whether_a_text_is_the_loaded_program_with_its_step_map(web: Web) -> None:
    """A page that did not load the program itself (the queue's claim, another tab) asks
    whether its editor holds it, and gets the step map to mark the running line."""
    ann = web.ann
    match = "/api/robot/slot/match"
    body = {"program": PROGRAM, "points": POINTS}
    assert ok(ann.post(match, json=body, params=MINE_Q))["same"] is False  # nothing loaded
    loaded = ok(ann.post("/api/robot/project", json=body, params=MINE_Q))
    same = ok(ann.post(match, json=body, params=MINE_Q))
    assert same["same"] is True and same["fingerprint"] == loaded["fingerprint"]
    assert same["step_lines"] == loaded["step_lines"]
    changed = {"program": PROGRAM.replace("DLY 30", "DLY 31"), "points": POINTS}
    assert ok(ann.post(match, json=changed, params=MINE_Q)) == {
        "same": False,
        "fingerprint": None,
        "step_lines": None,
    }
