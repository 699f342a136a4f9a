"""Pre-flight over the lab's cell, the cell model instructors edit, and the gate that keeps
an unsimulated program off the lab robot."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from melfa.store import Store
from melfa.web import WebSettings, create_app
from tests.web.conftest import Web, assert_error, fast_service
from tests.web.test_robot import ok

PROGRAM = "SERVO ON\nMOV P1\nMOV P2\nEND\n"
POINTS = (
    "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,100.00,250.00,180.00,0.00,180.00)(7,0)\n"
)


@pytest.fixture
def gated(store: Store, tmp_path: Path) -> Iterator[Web]:
    settings = WebSettings(
        data_dir=tmp_path / "data", service_config=fast_service(), require_simulation=True
    )
    with TestClient(create_app(settings, store=store)) as client:
        yield Web(client, store, client.app)


def test_preflight_flags_a_move_below_the_instructors_table(web: Web) -> None:
    clean = ok(web.ann.post("/api/preflight", json={"program": PROGRAM, "points": POINTS}))
    assert clean["passed"] is True and clean["report"]["finished"] is True
    assert clean["report"]["cycle_time"] > 0 and len(clean["report"]["path"]) > 2
    assert_error(web.ann.put("/api/preflight/cell", json={"floor_z": 300}), 403, "forbidden")
    cell = {
        "floor_z": 300,
        "boxes": [{"name": "feeder", "min": [0, 300, 0], "max": [100, 400, 80]}],
    }
    assert ok(web.ivy.put("/api/preflight/cell", json=cell))["cell"]["floor_z"] == 300
    assert ok(web.ann.get("/api/preflight"))["cell"]["boxes"][0]["name"] == "feeder"
    flagged = ok(web.ann.post("/api/preflight", json={"program": PROGRAM, "points": POINTS}))
    assert flagged["passed"] is False
    below = [f for f in flagged["report"]["findings"] if f["severity"] == "error"]
    assert below and below[0]["line"] == 3 and below[0]["segment"] is not None
    assert "table" in below[0]["message"]
    bad = web.ivy.put("/api/preflight/cell", json={"boxes": [{"name": "x", "min": [1, 1, 1]}]})
    assert_error(bad, 422, "invalid-cell")
    edits = ok(web.ivy.get("/api/audit", params={"action": "cell.edit"}))["entries"]
    assert [(e["actor"], e["details"]["obstacles"]) for e in edits] == [("ivy", 1)]  # audited


def test_the_gate_refuses_an_unsimulated_program_on_the_lab_robot(gated: Web) -> None:
    ann = gated.ann
    body = {"program": PROGRAM, "points": POINTS}
    error = assert_error(ann.post("/api/robot/project", json=body), 409, "simulation-required")
    assert "simulated run" in error["message"] and error["detail"]["fix"] == "preflight"
    assert_error(ann.post("/api/robot/run"), 409, "simulation-required")
    # The private simulator is not gated: that is where the simulation happens.
    ok(ann.post("/api/robot/project", json=body, params={"target": "mine"}))
    assert ok(ann.get("/api/preflight"))["require_simulation"] is True
    assert ok(ann.post("/api/preflight", json=body))["passed"] is True
    ok(ann.post("/api/robot/project", json=body))  # the same text: allowed now
    ok(ann.post("/api/robot/run", json={"servo_on": True}))
    ok(ann.post("/api/robot/stop"))
    edited = {"program": PROGRAM.replace("MOV P2", "MVS P2"), "points": POINTS}
    assert_error(ann.post("/api/robot/project", json=edited), 409, "simulation-required")
