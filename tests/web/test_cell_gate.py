"""A pre-flight counts only in the lab's cell as it is: once an instructor edits the cell,
the instructor's gate refuses to load or run what passed in the old one, at every door, in
the same words (`Refusal.CELL_CHANGED`), until the text passes pre-flight again. Through a
real `melfa serve --require-simulation --rosbridge-port P` on a traced TCP virtual
controller: REST, the queue, rosbridge services and the thesis's messages in both modes
(the WebSocket carries no load or run). Third-party clients unmodified: httpx, roslibpy.
The gate's rule itself (which cell a pass counts in) is tested pure."""

from __future__ import annotations

import datetime as dt
from collections.abc import Iterator

import httpx
import pytest
import roslibpy

from melfa.lang.plan import plan_upload
from melfa.service.policy import Gate
from melfa.service.slot import Slot
from melfa.store.preflights import Pass
from melfa.vocab.commands import Command
from melfa.vocab.refusals import Asked, Refusal
from tests.waiting import wait_until
from tests.web.doors import POINTS, Errors, Lab, ann_holding, lab_server
from tests.web.doors import call as ros_call
from tests.web.doors import program as good

pytestmark = pytest.mark.timeout(300)

LOAD_TEXT, RUN_TEXT = (
    " ".join(Refusal.CELL_CHANGED.words(asked)) for asked in (Asked.LOAD, Asked.RUN)
)
"""What every door says to a refused load and run (one home: `melfa.vocab.refusals`); a
run's fix is to pass and run again, not to load."""
PROGRAM = good("cell")
MARKER = b"door cell"
FEEDER = {"boxes": [{"name": "feeder", "min": [-600, -600, 0], "max": [-500, -500, 80]}]}
"""A box the instructor adds far from the program's path: it still passes pre-flight."""


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Lab]:
    with (
        lab_server(tmp_path_factory.mktemp("lab"), "--require-simulation") as served,
        ann_holding(served) as held,
    ):
        yield held


def preflight(lab: Lab) -> None:
    reply = lab.rest("ann", "POST", "/api/preflight", {"program": PROGRAM, "points": POINTS})
    assert reply.status_code == 200 and reply.json()["passed"] is True, reply.text


def refused_by_the_cell(reply: httpx.Response, asked: Asked) -> None:
    error = reply.json()["error"]
    text = " ".join(Refusal.CELL_CHANGED.words(asked))
    assert (reply.status_code, error["code"], error["message"]) == (409, "cell-changed", text)
    assert error["detail"]["fix"] == "preflight"  # the IDE's one-click fix: run it again
    assert error["detail"]["asked"] == asked.value  # and what then: load, run or join again


def thesis_run(lab: Lab, mode: str) -> list[str]:
    """What ann's ---RUN PROGRAM--- on /execute_instruction gets on /execute_error."""
    ros = lab.ros("ann", mode)
    try:
        errors = Errors()
        roslibpy.Topic(ros, "/execute_error", "std_msgs/String").subscribe(errors)
        topic = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")
        topic.publish(roslibpy.Message({"data": "---RUN PROGRAM---"}))
        wait_until(lambda: bool(errors.since(0)), what=f"{mode}: /execute_error")
        return errors.since(0)
    finally:
        ros.close()


def test_an_edited_cell_cancels_earlier_passes_at_every_door(lab: Lab) -> None:
    project = {"program": PROGRAM, "points": POINTS}
    preflight(lab)
    assert lab.rest("ann", "POST", "/api/robot/project", project).status_code == 200
    assert lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}).status_code == 200
    wait_until(lab.idle, what="the program to end")
    runs_before = lab.sent().count(b"RUN")

    edited = lab.rest("admin", "PUT", "/api/preflight/cell", FEEDER)
    assert edited.status_code == 200, edited.text

    # REST: the loaded program's run and a new load of the same text.
    refused_by_the_cell(lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}), Asked.RUN)
    refused_by_the_cell(lab.rest("ann", "POST", "/api/robot/project", project), Asked.LOAD)
    refused_by_the_cell(lab.rest("ann", "POST", "/api/queue", project), Asked.QUEUE)

    # rosbridge's services.
    ros = lab.ros("ann", "melfa")
    try:
        assert ros_call(ros, "run") == {"success": False, "message": RUN_TEXT}
        assert ros_call(ros, "load_project", project) == {"success": False, "message": LOAD_TEXT}
    finally:
        ros.close()

    # The thesis's messages, in both modes.
    for mode in ("melfa", "thesis"):
        assert thesis_run(lab, mode) == [RUN_TEXT]
    assert lab.sent().count(b"RUN") == runs_before  # nothing ran in the new cell

    # Pre-flight again in the cell as it is now: the loaded program runs, no new load.
    preflight(lab)
    assert lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True}).status_code == 200
    wait_until(lambda: lab.sent().count(b"RUN") > runs_before, what="RUN sent")
    wait_until(lab.idle, what="the program to end")


def test_a_pass_counts_in_the_cell_it_ran_in() -> None:
    """Gate's rule: a pass in version "a" of the cell opens the gate while the cell is "a"
    (again after an edit is undone), not while it is "b" (then it says why)."""
    plan = plan_upload(PROGRAM, POINTS)
    slot = Slot(
        "ann", dt.datetime(2026, 11, 27, tzinfo=dt.UTC), plan.program_texts, plan.point_texts
    )
    gate = Gate(required=True)
    cell = "a"
    gate.cell = lambda: cell
    for command, sent in ((Command.LOAD_PROJECT, plan), (Command.RUN, None)):
        assert gate.refusal(command, sent, slot) is Refusal.SIMULATION_REQUIRED
    gate.passed(plan, 4.0, cell="a")
    cell = "b"
    for command, sent in ((Command.LOAD_PROJECT, plan), (Command.RUN, None)):
        assert gate.refusal(command, sent, slot) is Refusal.CELL_CHANGED
    assert gate.refusal(Command.UPLOAD_PROGRAM, plan, None) is Refusal.CELL_CHANGED
    cell = "a"
    assert gate.refusal(Command.RUN, None, slot) is None
    cell = "b"
    gate.passed(plan, 5.0, cell="b")
    assert gate.refusal(Command.RUN, None, slot) is None
    assert gate.cycle_time(plan) == 5.0  # the queue's estimate: the cell as it is


def test_passes_read_from_the_store_open_the_gate_as_a_pass_does() -> None:
    """What the server loads at start (`Gate.load`, the store's rows) counts as the pass
    itself did: in its cell, for anyone, its newest cycle time the queue's estimate."""
    plan = plan_upload(PROGRAM, POINTS)
    stored = [
        Pass(plan.program_digest, plan.points_digest, "a", 4.0),
        Pass(plan.program_digest, plan.points_digest, "b", 5.0),
        Pass(plan.program_digest, plan.points_digest, "a", 3.5),  # a again, later
    ]
    gate = Gate(required=True)
    cell = "a"
    gate.cell = lambda: cell
    gate.load(stored)
    assert gate.refusal(Command.LOAD_PROJECT, plan, None) is None
    assert gate.cycle_time(plan) == 3.5
    cell = "c"
    assert gate.refusal(Command.LOAD_PROJECT, plan, None) is Refusal.CELL_CHANGED
    assert gate.cycle_time(plan) == 3.5  # the last known
    other = plan_upload(good("other"), POINTS)
    assert gate.refusal(Command.LOAD_PROJECT, other, None) is Refusal.SIMULATION_REQUIRED
