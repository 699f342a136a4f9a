"""The debugger API on a user's own simulator: breakpoints, stepping, variables, inputs,
run to cursor, run-time errors, and the socket's ``debug`` messages."""

from __future__ import annotations

from typing import Any

from tests.waiting import wait_until
from tests.web.conftest import Web, assert_error
from tests.web.test_robot import ok
from tests.web.test_ws import until

PROGRAM = """SERVO ON
M1 = 1
GOSUB *SUB
M1 = M1 + 1
WAIT M_IN(8) = 1
MOV P1
M2 = M1 * 10
END
*SUB
M3 = 5
RETURN
"""
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def status(browser: Any) -> dict[str, Any]:
    return dict(ok(browser.get("/api/debug"))["status"])


def stopped_at(browser: Any, line: int) -> bool:
    s = status(browser)
    return s["state"] == "paused" and s["location"]["line"] == line


def values(out: dict[str, Any]) -> dict[str, tuple[str, bool]]:
    return {v["name"]: (v["value"], v["changed"]) for v in out["variables"]}


def test_breakpoint_step_over_into_variables_input_and_end(web: Web) -> None:
    ann = web.ann
    body = {"program": PROGRAM, "points": POINTS, "lines": [3], "speed": "instant"}
    started = ok(ann.post("/api/debug", json=body))
    assert started["status"]["state"] == "idle" and started["program"] == PROGRAM
    assert [b["line"] for b in started["status"]["breakpoints"]] == [3]
    ok(ann.post("/api/debug/command/run"))
    wait_until(lambda: stopped_at(ann, 3))
    assert status(ann)["stop"]["reason"] == "breakpoint"
    ok(ann.post("/api/debug/command/step"))  # into the GOSUB: its label
    wait_until(lambda: stopped_at(ann, 9))
    ok(ann.post("/api/debug/command/step"))
    wait_until(lambda: stopped_at(ann, 10))
    ok(ann.post("/api/debug/command/step"))
    wait_until(lambda: stopped_at(ann, 11))
    out = ok(ann.get("/api/debug"))
    assert values(out)["M3"] == ("5", True)  # changed by the last step
    assert [f["line"] for f in ok(ann.get("/api/debug"))["status"]["breakpoints"]] == [3]
    ok(ann.post("/api/debug/command/step-out"))
    wait_until(lambda: stopped_at(ann, 4))
    ok(ann.post("/api/debug/command/step-over"))
    wait_until(lambda: stopped_at(ann, 5))
    out = ok(ann.get("/api/debug"))
    assert values(out)["M1"] == ("2", True) and values(out)["M3"] == ("5", False)
    ok(ann.post("/api/debug/command/continue"))
    wait_until(lambda: status(ann)["waiting"] is True)  # WAIT M_IN(8) = 1
    assert status(ann)["location"]["line"] == 5
    ok(ann.post("/api/debug/input", json={"bit": 8, "value": 1}))
    wait_until(lambda: status(ann)["state"] == "finished")
    assert ok(ann.post("/api/debug/evaluate", json={"expression": "M2"}))["value"] == "20"
    assert_error(ann.post("/api/debug/command/continue"), 422, "debug-refused")


def test_run_to_cursor_and_a_run_time_error_on_its_line(web: Web) -> None:
    ann = web.ann
    program = "SERVO ON\nM1 = 1\nM2 = 2\nM3 = M9 + 1\nEND\n"
    ok(ann.post("/api/debug", json={"program": program, "points": "", "check": False}))
    ok(ann.post("/api/debug/run-to", json={"line": 3}))
    wait_until(lambda: stopped_at(ann, 3))
    ok(ann.post("/api/debug/command/continue"))
    wait_until(lambda: status(ann)["state"] == "failed")
    error = status(ann)["stop"]["error"]
    assert error["location"]["line"] == 4 and error["code"].startswith("L")
    assert "M9" in error["explanation"] and error["number"] > 0


def test_refusals_in_plain_words(web: Web) -> None:
    ann = web.ann
    none = ann.get("/api/debug")  # asked at every page load: no session is no error
    assert none.status_code == 200 and none.json() is None
    ok(ann.post("/api/debug", json={"program": PROGRAM, "points": POINTS}))
    error = assert_error(ann.put("/api/debug/breakpoints", json={"lines": [99]}), 422)
    assert "outside the program" in error["message"]
    error = assert_error(ann.put("/api/debug/breakpoints", json={"labels": ["NOPE"]}), 422)
    assert "*SUB" in error["message"]
    assert_error(ann.post("/api/debug/speed", json={"speed": "warp"}), 422, "invalid-value")
    broken = ann.post("/api/debug", json={"program": "FOO 1\n", "points": ""})
    assert_error(broken, 422, "program-has-errors")
    ok(ann.delete("/api/debug"))
    assert ann.get("/api/debug").json() is None
    assert_error(ann.post("/api/debug/command/step"), 404, "no-debug-session")


def test_the_simulators_socket_streams_debug_updates(web: Web) -> None:
    ann = web.ann
    headers = ann.headers({"origin": "http://testserver"}, csrf=False)
    with web.client.websocket_connect("/api/ws?target=mine", headers=headers) as ws:
        until(ws, "hello")
        body = {"program": PROGRAM, "points": POINTS, "labels": ["*SUB"], "speed": "x4"}
        ok(ann.post("/api/debug", json=body))
        ok(ann.post("/api/debug/command/run"))
        for _ in range(200):
            message = until(ws, "debug")
            if message["status"]["state"] == "paused":
                break
        assert message["status"]["location"]["line"] == 9  # the line of *SUB
        assert message["variables"] is not None and len(message["joints"]) == 6
    # bob's simulator knows nothing of it.
    assert web.bob.get("/api/debug").json() is None


def test_stop_pauses_the_program_under_the_debugger(web: Web) -> None:
    ann = web.ann
    program = "SERVO ON\n*LOOP\nMOV P1\nMOV P2\nGOTO *LOOP\n"
    points = POINTS + "DEF POS P2=(300.00,200.00,400.00,180.00,0.00,180.00)(7,0)\n"
    ok(ann.post("/api/debug", json={"program": program, "points": points}))
    ok(ann.post("/api/debug/command/run"))
    wait_until(lambda: status(ann)["state"] == "running")
    ok(ann.post("/api/robot/stop", params={"target": "mine"}))
    assert status(ann)["state"] == "paused" and status(ann)["stop"]["reason"] == "pause"


def test_a_run_starts_as_the_start_options_say(web: Web) -> None:
    """Servo on, the arm at a position in XYZ (solved to joints), a line for INPUT #1 and
    the override: the program moves at once and reads its line."""
    ann = web.ann
    program = 'OPEN "COM1:" AS #1\nINPUT #1, M1\nM2 = M1 * 2\nMOV P1\nEND\n'
    start = {
        "servo": "on",
        "place": "pose",
        "pose": {"x": 300, "y": 100, "z": 500, "a": 180, "b": 0, "c": 180},
        "override": 40,
        "feed": [{"file": 1, "line": "21"}],
    }
    body = {"program": program, "points": POINTS, "speed": "instant", "start": start}
    ok(ann.post("/api/debug", json=body))
    here = ok(ann.post("/api/debug/evaluate", json={"expression": "P_CURR"}))["value"]
    assert here == "(+300.00,+100.00,+500.00,+180.00,+0.00,+180.00)(7,0)"
    ok(ann.post("/api/debug/command/run"))
    wait_until(lambda: status(ann)["state"] == "finished")
    assert ok(ann.post("/api/debug/evaluate", json={"expression": "M2"}))["value"] == "42"
    assert ok(ann.post("/api/debug/evaluate", json={"expression": "M_OPOVRD"}))["value"] == "40"


def test_a_start_the_arm_cannot_take_is_refused_in_words(web: Web) -> None:
    ann = web.ann
    far = {"place": "pose", "pose": {"x": 2000, "y": 0, "z": 500, "a": 180, "b": 0, "c": 180}}
    body = {"program": "END\n", "points": "", "start": far}
    error = assert_error(ann.post("/api/debug", json=body), 422, "invalid-value")
    assert error["message"].startswith("the start position is out of the RV-6S's reach")
    beyond = {"place": "joints", "joints": [0, 140, 90, 0, 90, 0]}
    error = assert_error(
        ann.post("/api/debug", json={**body, "start": beyond}), 422, "invalid-value"
    )
    assert "J2 = 140°, beyond its limit" in error["message"]
    missing = {"place": "joints"}
    error = assert_error(
        ann.post("/api/debug", json={**body, "start": missing}), 422, "invalid-request"
    )
    assert "give the six joints" in error["message"]
