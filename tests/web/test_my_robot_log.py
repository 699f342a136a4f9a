"""Everyone's own robot log is kept on the server (`GET /api/robot/log`): what they asked
the robot they drive and what came of it, per robot (the lab's, their simulator's), never
another person's entries; the IDE's *Robot log* reads it."""

from __future__ import annotations

from typing import Any

from tests.web.conftest import Web, assert_error


def ok(response: Any) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def test_my_robot_log_is_mine_and_per_robot(web: Web) -> None:
    ok(web.ann.post("/api/robot/servo", json={"on": True}))
    ok(web.bob.post("/api/robot/stop"))
    ok(web.ann.post("/api/robot/stop?target=mine"))
    lab = ok(web.ann.get("/api/robot/log"))["entries"]
    assert {e["actor"] for e in lab} == {"ann"}
    actions = [e["action"] for e in lab]
    assert "robot.servo" in actions and "control.changed" in actions
    assert "robot.stop" not in actions  # bob's, and ann's own on her simulator
    assert {e["details"]["robot"] for e in lab} == {"lab"}
    mine = ok(web.ann.get("/api/robot/log?target=mine"))["entries"]
    assert [(e["action"], e["result"]) for e in mine][:2] == [
        ("robot.stop", "ok"),
        ("robot.stop", "accepted"),
    ]
    assert_error(web.ann.get("/api/robot/log?target=bob"), 404, "unknown-target")
