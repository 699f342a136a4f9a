"""A refused *Take control* and a refused queue join are audited like every other refusal
(a gate refusal of a load, say): who, what, and why in the refusal's own words
(`melfa.vocab.refusals`), on the lab robot's log. Their accepted counterparts stay what
they were: the control change, the queue's step."""

from __future__ import annotations

from typing import Any

from melfa.vocab.refusals import Refusal
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
    words = " ".join(Refusal.SIMULATION_REQUIRED.words())
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
