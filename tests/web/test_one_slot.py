"""What the lab robot's slot holds is one record, the same for the instructor's gate, the
state every client is shown (and `/api/robot/slot/match`) and the recorded run, whichever
door loaded it: through a real `melfa serve --require-simulation --rosbridge-port P` on a
TCP virtual controller that already held a program the server never loaded. Points loaded
onto that program leave it not known everywhere (refused by the gate; with the gate off, a
run of it is recorded as not known, not as "no program"); a program then its points (REST,
rosbridge services, the thesis's LOAD PROGRAM / LOAD POINTS) are the pair they make
everywhere. Third-party clients unmodified: httpx, roslibpy."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
import roslibpy

from melfa.lang.plan import plan_upload
from melfa.vocab.refusals import Refusal
from tests.waiting import wait_until
from tests.web.doors import POINTS, Errors, Lab, ann_holding, lab_server
from tests.web.doors import call as ros_call

pytestmark = pytest.mark.timeout(300)

GATE_TEXT = " ".join(Refusal.SIMULATION_REQUIRED.words())
PRELOADED = "' loaded before the server started\nSERVO ON\nMOV P1\nEND\n"
OTHER_POINTS = "DEF POS P1=(360.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Lab]:
    data = tmp_path_factory.mktemp("lab")
    with (
        lab_server(data, "--require-simulation", preload=PRELOADED) as served,
        ann_holding(served) as held,
    ):
        yield held


def call(lab: Lab, name: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
    ros = lab.ros("ann", "melfa")
    try:
        return ros_call(ros, name, args)
    finally:
        ros.close()


def slot(lab: Lab) -> dict[str, Any] | None:
    found: dict[str, Any] | None = lab.rest("ann", "GET", "/api/robot/state").json()["slot"]
    return found


def runs(lab: Lab) -> list[dict[str, Any]]:
    reply = lab.rest("admin", "GET", "/api/runs")
    assert reply.status_code == 200, reply.text
    found: list[dict[str, Any]] = reply.json()
    return found


def stored_run(lab: Lab, before: int) -> dict[str, Any]:
    """The run started after ``before`` runs were stored, once it ended and was stored."""
    wait_until(lab.idle, what="the program to end")
    wait_until(lambda: len(runs(lab)) > before, what="the run to be stored")
    newest = runs(lab)[0]
    found: dict[str, Any] = lab.rest("admin", "GET", f"/api/runs/{newest['id']}").json()
    return found


def gate(lab: Lab, on: bool) -> None:
    switched = lab.rest("admin", "PUT", "/api/desk/gate", {"require_simulation": on})
    assert switched.status_code == 200, switched.text


def test_points_onto_a_program_the_server_never_loaded(lab: Lab) -> None:
    assert slot(lab) is None  # the controller holds a program; the server never loaded it
    lab.rest("ann", "POST", "/api/preflight", {"program": PRELOADED, "points": OTHER_POINTS})
    points = {"points": OTHER_POINTS}
    # The gate: its program is not known, so no pair passed; nor does a run of it.
    assert call(lab, "load_points", points) == {"success": False, "message": GATE_TEXT}
    ran = lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True})
    assert (ran.status_code, ran.json()["error"]["code"]) == (409, "simulation-required")
    assert call(lab, "run") == {"success": False, "message": GATE_TEXT}

    gate(lab, False)
    try:
        assert call(lab, "load_points", points)["success"] is True
        assert slot(lab) is None  # still not known: the program is not the server's
        before = len(runs(lab))
        assert call(lab, "run")["success"] is True
        run = stored_run(lab, before)
        # The recorded run says what the state said: not known (never "no program").
        assert (run["fingerprint"], run["loaded_by"], run["program"]) == (None, None, None)
        assert run["user"] == "ann" and run["simulated_by"] is None
    finally:
        gate(lab, True)


def _load_over_rest(lab: Lab, program: str) -> None:
    assert lab.rest("ann", "POST", "/api/robot/program", {"program": program}).is_success
    assert lab.rest("ann", "POST", "/api/robot/points", {"points": POINTS}).is_success


def _load_over_services(lab: Lab, program: str) -> None:
    assert call(lab, "load_program", {"program": program})["success"] is True
    assert call(lab, "load_points", {"points": POINTS})["success"] is True


def _load_with_thesis_messages(lab: Lab, program: str) -> None:
    ros = lab.ros("ann", "thesis")
    try:
        errors = Errors()
        roslibpy.Topic(ros, "/execute_error", "std_msgs/String").subscribe(errors)
        topic = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")

        def send(*texts: str) -> None:
            for text in texts:
                topic.publish(roslibpy.Message({"data": text}))

        alone = plan_upload(program).fingerprint
        send("---LOAD PROGRAM BEGIN---", *program.splitlines(), "---LOAD PROGRAM END---")
        first = wait_until(
            lambda: (s := slot(lab)) is not None and s["fingerprint"] == alone and s,
            what="the program loaded",
        )
        send("---LOAD POINTS BEGIN---", *POINTS.splitlines(), "---LOAD POINTS END---")
        wait_until(lambda: slot(lab) != first or errors.texts, what="the points loaded")
        assert errors.texts == []
    finally:
        ros.close()


@pytest.mark.parametrize("door", [_load_over_rest, _load_over_services, _load_with_thesis_messages])
def test_a_program_then_its_points_are_the_pair_they_make(lab: Lab, door: Any) -> None:
    program = f"' {door.__name__}\nSERVO ON\nMOV P1\nEND\n"
    pair = plan_upload(program, POINTS).fingerprint
    preflight = {"program": program, "points": POINTS}
    assert lab.rest("ann", "POST", "/api/preflight", preflight).json()["passed"] is True
    door(lab, program)

    # Every client is shown the pair: the IDE's own text is the one in the slot...
    shown = slot(lab)
    assert shown is not None and shown["user"] == "ann"
    assert shown["fingerprint"] == pair
    match = lab.rest("ann", "POST", "/api/robot/slot/match", preflight).json()
    assert (match["same"], match["fingerprint"]) == (True, pair)
    # ... a run naming it goes (the gate: the pair passed pre-flight) ...
    before = len(runs(lab))
    ran = lab.rest("ann", "POST", "/api/robot/run", {"servo_on": True, "expect": pair})
    assert ran.status_code == 200, ran.text
    # ... and its recording says the same, compared with that pre-flight.
    run = stored_run(lab, before)
    assert (run["fingerprint"], run["loaded_by"], run["simulated_by"]) == (pair, "ann", "ann")
    assert run["program"].splitlines() == program.splitlines()  # the thesis's: no last \n
