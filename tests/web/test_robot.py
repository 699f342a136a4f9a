"""Every robot operation through the API, against the in-process virtual controller."""

from __future__ import annotations

from typing import Any

import pytest

from tests.waiting import wait_until
from tests.web.conftest import Web, assert_error

PROGRAM = "SERVO ON\nMOV P1\nHLT\nEND\n"
POINTS = (
    "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF JNT JHOME=(0.00,0.00,90.00,0.00,90.00,0.00)\n"
)


def ok(response: Any) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def settle(browser: Any) -> None:
    """Until the arm stands still (EXEC of a move is refused while one runs: L5640)."""

    def still() -> bool:
        state = ok(browser.get("/api/robot/state"))
        return state["moving"] is False

    wait_until(still, what="the arm to stand still")


@pytest.fixture
def ws_id(web: Web) -> int:
    ws = int(web.ann.get("/api/workspaces").json()["default_id"])
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": PROGRAM, "points": POINTS})
    return ws


def test_load_project_from_workspace_run_stop_reset_delete(web: Web, ws_id: int) -> None:
    ann = web.ann
    assert ok(ann.post("/api/robot/servo", json={"on": True})) == {"ok": True}
    report = ok(ann.post("/api/robot/project", json={}))
    assert report["items"] == 4 + 2 and report["bytes_sent"] > 0
    assert ok(ann.post("/api/robot/run")) == {"ok": True}
    assert ok(web.bob.post("/api/robot/stop")) == {"ok": True}  # anyone may stop
    assert ok(ann.post("/api/robot/reset-program")) == {"ok": True}
    assert ok(ann.post("/api/robot/reset-alarm")) == {"ok": True}
    assert ok(ann.delete("/api/robot/program")) == {"ok": True}
    actions = {e["action"] for e in web.ivy.get("/api/audit").json()["entries"]}
    assert {"robot.load_project", "robot.run", "robot.stop", "robot.delete"} <= actions


def test_upload_program_and_points_from_the_request(web: Web) -> None:
    ann = web.ann
    assert (
        ok(ann.post("/api/robot/program", json={"program": PROGRAM, "points": POINTS}))["items"]
        == 4
    )
    assert ok(ann.post("/api/robot/points", json={"points": POINTS}))["items"] == 2
    assert_error(ann.post("/api/robot/points", json={"points": ""}), 422, "no-points")


def test_a_points_load_replies_with_what_the_slot_then_holds(web: Web) -> None:
    """As a program's load does: the fingerprint a run's ``expect`` names, and the steps'
    lines; here the program with the positions it kept and the ones sent."""
    ann = web.ann
    program = ok(ann.post("/api/robot/program", json={"program": PROGRAM}))
    first, more = POINTS.splitlines()[0] + "\n", POINTS.splitlines()[1] + "\n"
    for points in (first, more):  # points onto a program, then onto those points
        loaded = ok(ann.post("/api/robot/points", json={"points": points}))
        slot = ok(ann.get("/api/robot/state"))["slot"]
        assert loaded["fingerprint"] == slot["fingerprint"] != program["fingerprint"]
        assert loaded["step_lines"] == program["step_lines"] != {}
    held = {"program": PROGRAM, "points": more + first}  # the last sent, then those kept
    both = ok(ann.post("/api/robot/slot/match", json=held))
    assert both["same"] is True and both["fingerprint"] == loaded["fingerprint"]
    ok(ann.post("/api/robot/run", json={"servo_on": True, "expect": loaded["fingerprint"]}))
    ok(ann.post("/api/robot/stop"))


def test_program_with_errors_is_refused_before_sending(web: Web) -> None:
    response = web.ann.post(
        "/api/robot/project", json={"program": "MOV P1\nGOTO 99\n", "points": POINTS}
    )
    error = assert_error(response, 422, "program-has-errors")
    assert error["where"] == {"source": "program", "line": 2, "column": 6}
    bad_points = web.ann.post(
        "/api/robot/project", json={"program": "END\n", "points": "DEF POS P1=(1,\n"}
    )
    assert assert_error(bad_points, 422, "points-have-errors")["where"]["line"] == 1
    audit = web.ivy.get("/api/audit", params={"action": "robot.load_project"}).json()
    # The service's policy refused both (audited), and nothing was accepted or sent.
    results = [str(e["result"]) for e in audit["entries"]]
    assert len(results) == 2 and all(r.startswith("refused") for r in results), audit


def test_exec_hand_move_override_jog_step_and_reads(web: Web, ws_id: int) -> None:
    ann = web.ann
    ok(ann.post("/api/robot/servo", json={"on": True}))
    assert ok(ann.post("/api/robot/exec", json={"statement": "SPD 100"})) == {"ok": True}
    assert ok(ann.post("/api/robot/hand", json={"hand": 1, "action": "close"})) == {
        "hand": 1,
        "open": False,
    }
    assert ok(ann.post("/api/robot/hand", json={"hand": 1, "action": "toggle"}))["open"] is True
    assert ok(ann.post("/api/robot/hand", json={"hand": 2, "action": "open"}))["open"] is True
    assert ok(ann.post("/api/robot/override", json={"percent": 100})) == {"percent": 100}
    ok(ann.post("/api/robot/move", json={"joints": [10, 0, 90, 0, 90, 0]}))
    wait_until(lambda: abs(ok(ann.get("/api/robot/joints"))["values"][0] - 10) < 0.01)
    settle(ann)
    ok(ann.post("/api/robot/move", json={"point": "jhome"}))
    wait_until(lambda: abs(ok(ann.get("/api/robot/joints"))["values"][0]) < 0.01)
    settle(ann)
    ok(ann.post("/api/robot/move", json={"point": "P1", "linear": True}))
    wait_until(lambda: abs(ok(ann.get("/api/robot/pose"))["values"][0] - 300) < 0.5)
    settle(ann)
    pose = ok(ann.get("/api/robot/pose"))
    assert pose["names"] == ["X", "Y", "Z", "A", "B", "C"]
    ok(ann.post("/api/robot/move", json={"pose": [310, 0, 400, 180, 0, 180]}))
    wait_until(lambda: abs(ok(ann.get("/api/robot/pose"))["values"][0] - 310) < 0.5)
    settle(ann)
    ok(ann.post("/api/robot/jog-step", json={"frame": "joint", "axis": 0, "direction": 1}))
    state = ok(ann.get("/api/robot/state"))
    assert state["link"] == "connected" and state["lease_holder"] == "ann"
    assert len(state["joints"]) == 6


def test_move_refusals(web: Web, ws_id: int) -> None:
    ann = web.ann
    assert_error(ann.post("/api/robot/move", json={"point": "PNOPE"}), 404, "unknown-point")
    assert_error(ann.post("/api/robot/move", json={}), 422, "invalid-value")
    assert_error(
        ann.post("/api/robot/move", json={"point": "P1", "pose": [0, 0, 0, 0, 0, 0]}),
        422,
        "invalid-value",
    )
    assert_error(ann.post("/api/robot/move", json={"pose": [1, 2, 3]}), 422, "invalid-request")


def test_controller_refusal_is_409_with_its_number(web: Web) -> None:
    ann = web.ann
    ok(ann.post("/api/robot/servo", json={"on": True}))
    response = ann.post("/api/robot/exec", json={"statement": "MOV PUNDEF1"})
    error = assert_error(response, 409, "controller-refused")
    assert isinstance(error["detail"]["number"], int)


def test_lease_take_release_and_refusal(web: Web) -> None:
    ann, bob = web.ann, web.bob
    free = ok(ann.get("/api/lease"))
    assert (free["holder"], free["you"], free["label"]) == (None, False, "free")
    taken = ok(ann.post("/api/lease"))
    assert taken["holder"] == {"user": "ann", "role": "student"} and taken["you"] is True
    assert taken["state"] == "no connection" and taken["label"] == "ann — no connection"
    assert taken["since"] is not None and taken["idle_expires_in_s"] > 0
    error = assert_error(bob.post("/api/robot/servo", json={"on": True}), 423, "lease-required")
    assert error["detail"]["holder"] == {"user": "ann", "role": "student"}
    assert_error(bob.post("/api/lease"), 423, "lease-required")
    assert ok(bob.post("/api/robot/stop")) == {"ok": True}  # stop needs no lease
    assert ok(bob.get("/api/lease"))["you"] is False
    released = ok(ann.delete("/api/lease"))
    assert (released["holder"], released["you"]) == (None, False)
    assert ok(bob.post("/api/robot/servo", json={"on": True})) == {"ok": True}  # auto lease
    assert ok(bob.get("/api/lease"))["holder"]["user"] == "bob"


def test_takeover_by_instructor_not_student(web: Web) -> None:
    ok(web.ann.post("/api/lease"))
    assert_error(web.bob.post("/api/lease/takeover"), 403, "forbidden")
    taken = ok(web.ivy.post("/api/lease/takeover"))
    assert taken["holder"] == {"user": "ivy", "role": "instructor"} and taken["you"] is True
    assert_error(web.ann.post("/api/robot/run"), 423, "lease-required")
    assert ok(web.admin.post("/api/lease/takeover"))["holder"]["user"] == "admin"


def test_audit_api_and_the_old_page_leads_to_the_desk(web: Web) -> None:
    ok(web.ann.post("/api/robot/servo", json={"on": True}))
    ok(web.ann.post("/api/robot/servo", json={"on": False}))
    page = ok(web.ivy.get("/api/audit", params={"actor": "ann", "limit": 2}))
    assert len(page["entries"]) == 2 and page["next_before"] is not None
    assert all(e["actor"] == "ann" for e in page["entries"])
    rest = ok(web.ivy.get("/api/audit", params={"actor": "ann", "before": page["next_before"]}))
    assert rest["entries"] and rest["entries"][0]["id"] < page["entries"][-1]["id"]
    assert_error(web.ann.get("/api/audit"), 403, "forbidden")
    moved = web.ivy.get("/audit", follow_redirects=False)  # read on the desk, in plain words
    assert moved.status_code == 308 and moved.headers["location"] == "/desk#audit"
    assert web.ann.get("/desk").status_code == 403


def test_health(web: Web) -> None:
    body = web.client.get("/api/health").json()
    assert body["status"] == "ok" and body["store"] == "ok"
    assert body["robot"] == {**body["robot"], "link": "connected", "robot": "sim"}


def test_a_move_with_the_servo_off_is_refused_until_the_operator_asks_for_it(
    web: Web, ws_id: int
) -> None:
    ann = web.ann
    error = assert_error(ann.post("/api/robot/move", json={"point": "JHOME"}), 409)
    assert error["code"] == "controller-refused", error
    assert error["detail"]["number"] == 2000
    assert ok(ann.get("/api/robot/state"))["alarm"] is None  # nothing was sent
    assert_error(ann.post("/api/robot/run", json={}), 409)
    assert ok(ann.post("/api/robot/move", json={"point": "P1", "servo_on": True})) == {"ok": True}

    def at_p1() -> bool:
        state = ok(ann.get("/api/robot/state"))
        return bool(state["servo"]) and abs(state["pose"][0] - 300) < 0.5

    wait_until(at_p1)  # the move's answer comes when it starts; the arm then takes its time
    entries = web.ivy.get("/api/audit").json()["entries"]
    servo = [e for e in entries if e["action"] == "robot.servo"]
    assert any("before Move to" in str(e["details"]) for e in servo)  # the label, no method


def test_the_upload_reply_maps_steps_to_the_students_own_lines(web: Web, ws_id: int) -> None:
    numbered = "5 MOV P1\n\n7 HLT\n9 END\n"
    report = ok(web.ann.post("/api/robot/project", json={"program": numbered}))
    assert report["step_lines"] == {"5": 1, "7": 3, "9": 4}
    plain = ok(web.ann.post("/api/robot/project", json={"program": "MOV P1\n' note\nEND\n"}))
    assert plain["step_lines"] == {"10": 1, "20": 2, "30": 3}
