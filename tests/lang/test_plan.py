"""The upload plan: one decision, from the tokens, of what is sent and which line each step
is; the gate's fingerprint of what is sent."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.lang.plan import Part, plan_upload

GLUED = "1 MOV P1\n2 GOTO 1\n3END"
"""Passes `melfa check`; a regex said "not numbered" (``3END`` has no space), the tokens say
step 3: the upload numbered it 10/20/30 while the IDE mapped steps 1/2/3."""


def test_a_program_numbered_by_its_tokens_is_sent_with_its_own_numbers() -> None:
    plan = plan_upload(GLUED)
    assert not plan.has_errors
    assert plan.numbered
    assert plan.program_texts == ("1 MOV P1", "2 GOTO 1", "3 END")
    assert plan.step_lines == {1: 1, 2: 2, 3: 3}


def test_every_step_sent_maps_to_the_line_it_came_from() -> None:
    for text in (GLUED, "MOV P1\n\n*L\nGOTO *L\n", "5 MOV P1\n\n7 HLT\n9 END\n"):
        plan = plan_upload(text)
        lines = text.split("\n")
        for item in plan.items:
            number = int(item.text.split(" ", 1)[0])
            assert plan.step_lines[number] == item.source_line
            assert item.text.split(" ", 1)[1].strip() in lines[item.source_line - 1]


def test_diagnostics_are_the_checkers_against_the_points_names() -> None:
    plan = plan_upload("MOV P1\nMOV P2\nFOO\n", "DEF POS P1=(1,2,3,4,5,6)(7,0)\n")
    assert [(d.line, d.rule) for d in plan.diagnostics if not d.is_error] == [
        (2, "undefined-point")
    ]
    assert plan.first_error() is not None
    assert plan.first_error()[0] is Part.PROGRAM  # type: ignore[index]
    assert plan.has_errors


def test_what_cannot_be_sent_blocks_the_plan_and_is_said_once() -> None:
    plan = plan_upload("MOV Pé\nEND\n")
    assert plan.items == ()
    assert plan.blocker is not None and plan.blocker.source is Part.PROGRAM
    assert [d.rule for d in plan.diagnostics if d.is_error] == ["illegal-character"]
    broken_points = plan_upload("END\n", "DEF POS P1=(1,2\n")
    assert broken_points.blocker is not None and broken_points.blocker.source is Part.POINTS
    assert broken_points.items == ()


def test_the_fingerprint_is_what_is_sent() -> None:
    same = plan_upload("MOV P1\nEND\n", "DEF POS P1=(1,2,3,4,5,6)(7,0)\n")
    numbered = plan_upload("10 MOV P1  \r\n20 END", "P1=(1.00,2.00,3.00,4.00,5.00,6.00)(7,0)")
    assert same.fingerprint == numbered.fingerprint
    moved = plan_upload("MOV P1\nEND\n", "DEF POS P1=(1,2,3,4,5,7)(7,0)\n")
    other = plan_upload("MVS P1\nEND\n", "DEF POS P1=(1,2,3,4,5,6)(7,0)\n")
    assert len({same.fingerprint, moved.fingerprint, other.fingerprint}) == 3
    assert plan_upload("MOV P1\nEND\n").fingerprint != same.fingerprint


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="0123456789 MOVP1GTEND*L\n'", max_size=60))
def test_any_text_gives_a_plan_never_an_exception(text: str) -> None:
    plan = plan_upload(text, "")
    assert (plan.blocker is None) or plan.items == ()
    assert all(item.text.isascii() for item in plan.items)
