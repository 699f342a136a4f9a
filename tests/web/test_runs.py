"""`/api/runs`: a run on the lab robot is recorded and stored with the report against the
runner's passed pre-flight of the same text; a student sees their own runs, an instructor
everyone's (one rule: `melfa.web.routes.runs.may_see`)."""

from __future__ import annotations

import asyncio
from typing import Any

from melfa.web.pools import Busy
from melfa.web.recorded_runs import RETRY_MAX_S, patiently
from tests.waiting import wait_until
from tests.web.conftest import Web, assert_error
from tests.web.test_robot import ok

PROGRAM = "' a corner and back, unnumbered\nSERVO ON\nMOV P1\nMVS P2\nDLY 0.2\nMOV P1\nEND\n"
POINTS = (
    "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,100.00,300.00,180.00,0.00,180.00)(7,0)\n"
)
BODY = {"program": PROGRAM, "points": POINTS}


def _run_once(web: Web, who: str = "ann") -> dict[str, Any]:
    person = getattr(web, who)
    before = len(ok(web.ivy.get("/api/runs")))
    ok(person.post("/api/robot/project", json=BODY))
    ok(person.post("/api/robot/run", json={"servo_on": True}))
    runs = wait_until(
        lambda: (found := ok(web.ivy.get("/api/runs"))) and len(found) > before and found,
        what="the run to be stored",
    )
    ok(person.delete("/api/lease"))
    return runs[0]


def test_a_run_is_recorded_with_its_report_against_the_passed_preflight(web: Web) -> None:
    preflight = ok(web.ann.post("/api/preflight", json=BODY))
    assert preflight["passed"] is True
    summary = _run_once(web)
    assert summary["user"] == "ann" and summary["target"] == "lab"
    assert summary["outcome"] == "finished" and not summary["thinned"]
    assert summary["simulated_by"] == "ann"
    assert summary["cycle_simulated"] == preflight["report"]["cycle_time"]
    assert summary["cycle_real"] > 0.2  # the DLY at least
    report = summary["report"]
    assert report["compared"] > 0
    assert report["cycle_difference"] == round(
        summary["cycle_real"] - summary["cycle_simulated"], 3
    )
    deviation = report["deviation"]
    # The virtual lab robot runs the same motion planner as the pre-flight: a few mm at
    # most (the line is read every fourth poll), never the 100 mm between the points.
    assert 0 <= deviation["mm"] < 30, deviation
    assert deviation["line"] in {2, 3, 4, 5, 6, 7}
    assert summary["frames_bytes"] < 1_000_000

    run = ok(web.ann.get(f"/api/runs/{summary['id']}"))
    assert run["program"] == PROGRAM and run["loaded_by"] == "ann"
    frames = run["frames"]
    assert len(frames["t"]) == summary["frame_count"] == len(frames["pose"])
    assert {line for line in frames["line"] if line} <= {2, 3, 4, 5, 6, 7}
    ys = [p[1] for p in frames["pose"] if p]
    assert max(ys) > 95 and min(ys) < 5  # it went to P2 and back
    assert run["simulated"]["path"] and run["simulated"]["cycle_time"] == summary["cycle_simulated"]


def test_a_run_without_a_simulation_has_no_deviation(web: Web) -> None:
    summary = _run_once(web, "bob")
    assert summary["simulated_by"] is None and summary["report"]["deviation"] is None
    assert summary["cycle_simulated"] is None and summary["report"]["cycle_difference"] is None
    run = ok(web.bob.get(f"/api/runs/{summary['id']}"))
    assert run["simulated"] is None and run["frames"]["t"]


def test_students_see_their_own_runs_and_instructors_everyones(web: Web) -> None:
    ok(web.ann.post("/api/preflight", json=BODY))
    anns = _run_once(web, "ann")["id"]
    bobs = _run_once(web, "bob")["id"]  # bob's partner passed the pre-flight: compared with hers
    assert ok(web.ivy.get(f"/api/runs/{bobs}"))["simulated_by"] == "ann"
    assert [r["id"] for r in ok(web.ann.get("/api/runs"))] == [anns]
    assert [r["id"] for r in ok(web.bob.get("/api/runs"))] == [bobs]
    assert [r["id"] for r in ok(web.ivy.get("/api/runs"))] == [bobs, anns]
    assert [r["id"] for r in ok(web.ivy.get("/api/runs", params={"user": "ann"}))] == [anns]
    assert_error(web.ann.get("/api/runs", params={"user": "bob"}), 403, "forbidden")
    assert_error(web.ann.get(f"/api/runs/{bobs}"), 404, "not-found")  # as if there were none
    assert_error(web.ann.get("/api/runs/99999"), 404, "not-found")
    assert_error(web.ann.put(f"/api/runs/{anns}/kept", json={"kept": True}), 403, "forbidden")
    assert ok(web.ivy.put(f"/api/runs/{anns}/kept", json={"kept": True}))["kept"] is True


def test_a_run_is_compared_with_the_preflight_of_the_cell_it_ran_in(web: Web) -> None:
    """ann's pass from before the instructor moved things in the cell is not what her run
    in the new cell is compared with: bob's pass of the same text in the new cell is."""
    ok(web.ann.post("/api/preflight", json=BODY))
    feeder = {"boxes": [{"name": "feeder", "min": [-600, -600, 0], "max": [-500, -500, 80]}]}
    ok(web.ivy.put("/api/preflight/cell", json=feeder))
    assert ok(web.bob.post("/api/preflight", json=BODY))["passed"] is True
    assert _run_once(web, "ann")["simulated_by"] == "bob"


def test_a_full_pool_delays_a_runs_record_and_never_loses_it() -> None:
    """A class checking as it types fills the CPU pool for moments: storing a run waits
    for room (pauses growing to a ceiling) instead of dropping the record."""
    pauses: list[float] = []
    tries = iter([Busy("cpu")] * 7 + ["stored"])

    async def call() -> str:
        outcome = next(tries)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    async def sleep(seconds: float) -> None:
        pauses.append(seconds)

    assert asyncio.run(patiently(call, sleep)) == "stored"
    assert pauses == [0.1, 0.2, 0.4, 0.8, 1.6, 3.2, RETRY_MAX_S]
