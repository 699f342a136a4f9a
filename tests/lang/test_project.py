"""Checking a project (programs + points files) is one function, used by `melfa check` and
the web API; points used only as offsets are not reach-checked; points files read constants
with the program parser and take COSIMIR's comments (§4.1, §7, §12 of melfa-basic-iv.md)."""

from __future__ import annotations

from pathlib import Path

import melfa
from melfa.kin.reach import reach_diagnostics
from melfa.lang.parser import parse
from melfa.lang.points_read import parse_points
from melfa.lang.project import check_project, offset_only

FAR = "PFAR=(3000,0,600,180,0,180)(7,0)\n"


def test_offsets_are_not_reach_checked_but_targets_are() -> None:
    """§7: P1 + PUP moves to P1 shifted by PUP; PUP itself is never a place."""
    points = "P1=(400,0,600,180,0,180)(7,0)\nDEF POS PUP=(0,0,30,0,0,0)\n" + FAR
    report = check_project(["MOV P1 + PUP\nMOV PFAR\n"], [points], reach_diagnostics)
    assert report.programs == ((),)
    reach = [d for d in report.points[0] if d.rule.startswith("point-")]
    assert [(d.line, d.rule) for d in reach] == [(3, "point-out-of-reach")]


def test_a_point_also_moved_to_is_judged() -> None:
    """§7: an offset that is also a target is reach-checked."""
    program = parse("MOV P1 * PFAR\nMOV PFAR\n")
    assert offset_only(program) == set()
    assert offset_only(parse("MOV P1 * PFAR\nP2 = P1 + PFAR\n")) == {"PFAR"}


def test_points_on_their_own_are_all_judged() -> None:
    """§12: a points file checked without a program: every point."""
    report = check_project([], [FAR], reach_diagnostics)
    assert [d.rule for d in report.points[0]] == ["point-out-of-reach"]


def test_cosimir_point_comments_are_comments() -> None:
    """§4.1: COSIMIR writes `P1=(…)(6,0) *// Home` and reads it back."""
    parsed = parse_points("P1=(355.00,0.00,550.00,0.00,90.00,0.00)(6,0) *// Home\n")
    assert parsed.diagnostics == ()
    assert (parsed.points[0].name, parsed.points[0].fl1) == ("P1", 6)


def test_points_and_programs_read_constants_alike() -> None:
    """§2.2: the same constant text means the same in a program and in a points file."""
    text = "(400,,-5.5,&H10,+2,-0)(7,&H00100000)"
    point = parse_points(f"P1={text}\n").points[0]
    assert point.values == (400.0, None, -5.5, 16.0, 2.0, 0.0)
    assert point.fl2 == 0x00100000
    assert check_project([f"P1 = {text}\n"]).programs == ((),)
    bad = parse_points("P1=(1,2,3,4,5,6)(7,0,1)\n").diagnostics[0]
    assert bad.rule == "points-flags"
    assert [d.rule for d in check_project(["P1 = (1,2,3,4,5,6)(7,0,1)\n"]).programs[0]] == [
        "position-elements"
    ]


def test_the_cli_and_the_web_call_the_one_project_check() -> None:
    """One home: both callers name check_project (and no one else parses points to check)."""
    src = Path(melfa.__file__).parent
    for caller in ("cli/checking.py", "web/routes/check.py"):
        text = (src / caller).read_text(encoding="utf-8")
        assert "check_project(" in text and "parse_points(" not in text, caller
