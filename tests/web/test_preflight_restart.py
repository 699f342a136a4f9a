"""What passed pre-flight is the store's one record, so a restart keeps it: a real
`melfa serve --require-simulation` (a subprocess, a traced TCP virtual controller, rosbridge
on its own port) is stopped and started again on the same data directory. A student's pass
from before opens the gate after it, over REST (load and run) and rosbridge's services
(roslibpy, unmodified), without simulating again; an instructor's edit of the cell still
cancels it, after a restart too (`Refusal.CELL_CHANGED`, not "never simulated": the old
pass is remembered in its cell); undoing the edit makes it count again."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import pytest

from melfa.vocab.refusals import Refusal
from tests.waiting import wait_until
from tests.web.doors import POINTS, Lab, call, holding, lab_server, program

pytestmark = [pytest.mark.timeout(300), pytest.mark.slow]

PASSWORD = "ann-password-12"
REST_PROGRAM, ROS_PROGRAM = program("restart rest"), program("restart ros")
FEEDER = {"boxes": [{"name": "feeder", "min": [-600, -600, 0], "max": [-500, -500, 80]}]}
"""A box the instructor adds far from the programs' path."""


@contextmanager
def ann_at_the_arm(data: Path) -> Iterator[Lab]:
    """The lab served on ``data`` with the gate on; ann signed in, holding the robot with
    the servo on, a rosbridge connection open all along (as the IDE keeps one)."""
    with lab_server(data, "--require-simulation") as lab:
        lab.sign_in("ann", PASSWORD)
        with holding(lab, "ann"):
            yield lab


def load(lab: Lab, text: str) -> httpx.Response:
    return lab.rest("ann", "POST", "/api/robot/project", {"program": text, "points": POINTS})


def ros_load(lab: Lab, text: str) -> dict[str, Any]:
    ros = lab.ros("ann", "melfa")
    try:
        return call(ros, "load_project", {"program": text, "points": POINTS})
    finally:
        ros.close()


def refused(reply: httpx.Response, reason: Refusal) -> None:
    error = reply.json()["error"]
    assert (reply.status_code, error["code"]) == (409, reason.value), reply.text


def test_a_pass_survives_a_restart_and_a_cell_edit_still_cancels_it(tmp_path: Path) -> None:
    data = tmp_path / "lab"
    data.mkdir()
    with lab_server(data, "--require-simulation") as lab:
        lab.add_students(["ann"])
        for text in (REST_PROGRAM, ROS_PROGRAM):
            passed = lab.rest("ann", "POST", "/api/preflight", {"program": text, "points": POINTS})
            assert passed.status_code == 200 and passed.json()["passed"] is True, passed.text
        cell = lab.rest("admin", "GET", "/api/preflight").json()["cell"]

    with ann_at_the_arm(data) as lab:  # restarted: no pre-flight since
        assert load(lab, REST_PROGRAM).status_code == 200
        assert lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}).status_code == 200
        wait_until(lambda: b"RUN" in lab.sent(), what="RUN sent")
        wait_until(lab.idle, what="the program to end")
        assert ros_load(lab, ROS_PROGRAM)["success"] is True
        assert b"door restart ros" in lab.sent()

        edited = lab.rest("admin", "PUT", "/api/preflight/cell", FEEDER)
        assert edited.status_code == 200, edited.text
        refused(load(lab, REST_PROGRAM), Refusal.CELL_CHANGED)
        refused(lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}), Refusal.CELL_CHANGED)
        found = ros_load(lab, ROS_PROGRAM)
        assert found["success"] is False and "cell" in found["message"], found

    with ann_at_the_arm(data) as lab:  # restarted in the edited cell: still cancelled
        before = lab.sent()
        refused(load(lab, REST_PROGRAM), Refusal.CELL_CHANGED)
        assert ros_load(lab, ROS_PROGRAM)["success"] is False
        assert b"door restart" not in lab.sent()[len(before) :]
        # The instructor undoes the edit: the cell is the one they passed in again.
        undone = lab.rest("admin", "PUT", "/api/preflight/cell", cell)
        assert undone.status_code == 200, undone.text
        assert load(lab, REST_PROGRAM).status_code == 200
