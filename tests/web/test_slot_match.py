"""`POST /api/robot/slot/match` ("is this text in the slot?") answers for what the
controller holds, against the in-process virtual controller: its steps in their order (the
step → line map refers to them), its positions by name in any order — the controller keeps
positions as named variables (`melfa.service.slot.Slot.holds`)."""

from __future__ import annotations

import datetime as dt
from typing import Any

from melfa.lang.plan import plan_upload
from melfa.service.slot import Slot, positions_of
from tests.web.conftest import Web

PROGRAM = "SERVO ON\nMOV P1\nMOV P2\nMOV JHOME\nEND\n"
P1 = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
P2 = "DEF POS P2=(320.00,40.00,380.00,180.00,0.00,180.00)(7,0)\n"
JHOME = "DEF JNT JHOME=(0.00,0.00,90.00,0.00,90.00,0.00)\n"


def ok(response: Any) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def match(web: Web, program: str, points: str) -> Any:
    return ok(web.ann.post("/api/robot/slot/match", json={"program": program, "points": points}))


def test_the_same_points_in_another_order_are_the_text_in_the_slot(web: Web) -> None:
    loaded = ok(
        web.ann.post("/api/robot/project", json={"program": PROGRAM, "points": P1 + P2 + JHOME})
    )
    for points in (P1 + P2 + JHOME, JHOME + P2 + P1, P2 + JHOME + P1.replace("P1=", "p1=")):
        found = match(web, PROGRAM, points)
        assert found["same"] is True, points
        # The slot's fingerprint (what a run names) and its step map, whatever the order.
        assert found["fingerprint"] == loaded["fingerprint"]
        assert found["step_lines"] == loaded["step_lines"] != {}
    ok(web.ann.post("/api/robot/run", json={"servo_on": True, "expect": found["fingerprint"]}))
    ok(web.ann.post("/api/robot/stop"))


def test_points_loaded_on_their_own_match_the_student_s_whole_file(web: Web) -> None:
    """Points sent onto the program one by one (the thesis's LOAD POINTS, a second file):
    the controller holds all three, and the student's file listing them in its own order
    is the text in the slot."""
    ok(web.ann.post("/api/robot/program", json={"program": PROGRAM}))
    for points in (P1, P2, JHOME):
        ok(web.ann.post("/api/robot/points", json={"points": points}))
    assert match(web, PROGRAM, P1 + P2 + JHOME)["same"] is True


def test_what_the_controller_would_hold_differently_is_not_the_text_in_the_slot(
    web: Web,
) -> None:
    ok(web.ann.post("/api/robot/project", json={"program": PROGRAM, "points": P1 + P2 + JHOME}))
    moved = P2.replace("320.00", "321.00")
    steps = "SERVO ON\nMOV P2\nMOV P1\nMOV JHOME\nEND\n"  # steps swapped: another program
    for program, points in (
        (PROGRAM, P1 + moved + JHOME),  # a position moved
        (PROGRAM, P1 + P2),  # one fewer: the slot holds JHOME as well
        (PROGRAM, P1 + P2 + JHOME + "DEF POS P3=(1,2,3,4,5,6)(7,0)\n"),  # one more
        (steps, P1 + P2 + JHOME),
        (PROGRAM, P1 + P2 + JHOME.replace("DEF JNT JHOME", "DEF JNT J2")),  # renamed
    ):
        found = match(web, program, points)
        assert (found["same"], found["fingerprint"], found["step_lines"]) == (False, None, None)


def test_a_position_is_known_by_the_name_the_controller_sees() -> None:
    plan = plan_upload(PROGRAM, P1 + P2 + JHOME)
    held = positions_of(plan.point_texts)
    assert set(held) == {"P1", "P2", "JHOME"}
    assert held["P1"] == "(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)"
    slot = Slot("ann", dt.datetime(2026, 1, 1), plan.program_texts, plan.point_texts)
    assert slot.holds(plan_upload(PROGRAM, JHOME + P1 + P2))
    assert not slot.holds(plan_upload(PROGRAM, P1 + P2))
