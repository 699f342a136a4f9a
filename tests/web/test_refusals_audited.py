"""A refused *Take control* and a refused queue request (join, claim, leave, give back) are
audited like every other refusal (a gate refusal of a load, say): who, what, and why in
the refusal's own words (`melfa.vocab.refusals`), on the lab robot's log. Their accepted
counterparts stay what they were: the control change, the queue's step."""

from __future__ import annotations

from typing import Any

from melfa.vocab.commands import Command
from melfa.vocab.refusals import Asked, Refusal
from tests.web.conftest import Web, assert_error

PROGRAM = "MOV P1\nEND"
POINTS = "P1=(400.00,0.00,500.00,180.00,0.00,180.00)(7,0)"


def _entries(web: Web, actor: str) -> list[Any]:
    web.store.db.flush()  # the service's sink queues its writes
    return list(reversed(web.store.audit.query(actor=actor, limit=50).entries))


def test_a_refused_take_control_is_audited_in_the_refusals_words(web: Web) -> None:
    assert web.ann.post("/api/lease").status_code == 200
    error = assert_error(web.bob.post("/api/lease"), 423, "lease-required")
    words = " ".join(Refusal.LEASE_REQUIRED.words(holder="ann"))
    assert error["message"] == words
    refused = [e for e in _entries(web, "bob") if e.action == "robot.take_control"]
    assert len(refused) == 1, refused
    entry = refused[0]
    assert (entry.role, entry.result) == ("student", f"refused: {words}")
    assert entry.details["robot"] == "lab"
    # The accepted one is the control change it made, as before (no second kind of entry).
    ann = [e.action for e in _entries(web, "ann")]
    assert "control.changed" in ann and "robot.take_control" not in ann


def test_a_refused_queue_join_is_audited_in_the_refusals_words(web: Web) -> None:
    assert web.ivy.put("/api/desk/gate", json={"require_simulation": True}).status_code == 200
    body = {"program": PROGRAM, "points": POINTS}
    error = assert_error(web.ann.post("/api/queue", json=body), 409, "simulation-required")
    words = " ".join(Refusal.SIMULATION_REQUIRED.words(asked=Asked.QUEUE))
    assert error["message"] == words
    entries = _entries(web, "ann")
    refused = [e for e in entries if e.action == "robot.join_queue"]
    assert [(e.role, e.result) for e in refused] == [("student", f"refused: {words}")]
    assert refused[0].details["robot"] == "lab"
    assert not [e for e in entries if e.action.startswith("queue.")]  # she is not queued

    # A text with an error is refused by the checker, and audited with its line.
    broken = {"program": "MOV P1\nWIHLE 1\nEND", "points": POINTS}
    error = assert_error(web.ann.post("/api/queue", json=broken), 422, "program-has-errors")
    last = [e for e in _entries(web, "ann") if e.action == "robot.join_queue"][-1]
    assert last.result == f"refused: {error['message']}" and "Line 2" in last.result


def _refused(web: Web, actor: str, command: Command) -> list[tuple[str, str, str]]:
    return [
        (e.role, e.result, e.details["robot"])
        for e in _entries(web, actor)
        if e.action == f"robot.{command.value}"
    ]


def test_a_refused_claim_leave_and_give_back_are_audited_in_the_refusals_words(
    web: Web,
) -> None:
    body = {"program": PROGRAM, "points": POINTS}
    assert web.ivy.post("/api/queue/pause").status_code == 200  # nobody is offered the arm
    assert web.ann.post("/api/queue", json=body).status_code == 200

    error = assert_error(web.ann.post("/api/queue/claim", json={}), 409, "not-your-turn")
    words = " ".join(Refusal.NOT_YOUR_TURN.words())
    assert error["message"] == words
    assert _refused(web, "ann", Command.CLAIM_TURN) == [("student", f"refused: {words}", "lab")]

    error = assert_error(web.bob.delete("/api/queue/me"), 409, "not-queued")
    words = " ".join(Refusal.NOT_QUEUED.words(user="bob"))
    assert error["message"] == words
    assert _refused(web, "bob", Command.LEAVE_QUEUE) == [("student", f"refused: {words}", "lab")]

    error = assert_error(web.ann.post("/api/queue/done", json={}), 409, "not-queued")
    words = " ".join(Refusal.NOT_QUEUED.words(user="ann"))
    assert error["message"] == words
    assert _refused(web, "ann", Command.GIVE_BACK) == [("student", f"refused: {words}", "lab")]

    # Accepted, a leave is the queue's step alone, as a join is.
    assert web.ann.delete("/api/queue/me").status_code == 200
    ann = [e.action for e in _entries(web, "ann")]
    assert "queue.left" in ann and ann.count("robot.leave_queue") == 0
