"""The thesis dialect reproduces the thesis's execute node (tfg-biel's execute_node.cpp):
answers without parentheses, 20 mm jog steps along the base frame (+Z up), the servo on
when a jog session starts and off when it ends, MOVE TOOL STATE, harmless connect messages.
melfa's dialect keeps its own answers and tool-frame steps."""

from __future__ import annotations

import math

import pytest

from melfa.service import ThesisMessages, ThesisOutput
from melfa.service.thesis import MELFA, THESIS, dialect_named, parse_pose
from tests.service.helpers import ANN, RecordingController, make_service, run

POINT = "(417.61,16.40,180.00,180.00,0.00,180.00)"


def _values(text: str) -> list[float]:
    return [float(v) for v in text.split(",")]


def test_thesis_jog_goes_20_mm_up_along_base_z_with_the_servo_on_then_off() -> None:
    controller = RecordingController()

    async def main() -> list[str]:
        service, _ = make_service(controller, polling=False)
        async with service:
            node = ThesisMessages(service, ANN, dialect=THESIS, wall_clock=lambda: 100.0)
            answers = service.subscribe(ThesisOutput)
            await node.feed("---REQUEST TOOL POSE---")
            await node.feed("---MOV TOOL +Z---101")
            await node.feed("---REQUEST TOOL POSE---")  # ends the jog session
            texts = []
            while (event := answers.get_nowait()) is not None:
                assert isinstance(event, ThesisOutput)
                texts.append(event.text)
            return texts

    before, after = run(main())
    assert not before.startswith("(") and len(_values(before)) == 6  # x,y,z,r,p,y
    assert _values(after)[2] == pytest.approx(_values(before)[2] + 0.020, abs=1e-5)
    assert _values(after)[:2] == pytest.approx(_values(before)[:2], abs=1e-5)
    commands = controller.commands()
    step = next(i for i, c in enumerate(commands) if "MVS P_CURR+" in c)
    assert commands[step].endswith("MVS P_CURR+(0,0,20,0,0,0)")
    servo_on = [i for i, c in enumerate(commands) if c.endswith(";SRVON")]
    servo_off = [i for i, c in enumerate(commands) if c.endswith(";SRVOFF")]
    assert servo_on and servo_on[0] < step  # as the thesis's jog thread connected
    assert servo_off and servo_off[-1] > step  # and disconnected (test 7.1.4)


def test_move_tool_state_moves_to_the_point_in_a_straight_line() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            node = ThesisMessages(service, ANN, dialect=THESIS)
            await node.feed("---MOVE TOOL STATE---")
            assert node.state.name == "S5"
            await node.feed(POINT)
            assert node.state.name == "S0"

    run(main())
    commands = controller.commands()
    move = next(i for i, c in enumerate(commands) if c.endswith("EXECMVS PMSVC"))
    # the point is set, then MVS moves to it
    assert "=(417.610,16.400,180.000,180.000,0.000,180.000)" in commands[move - 1]


def test_connect_messages_change_nothing() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            before = len(controller.commands())
            for dialect in (MELFA, THESIS):
                node = ThesisMessages(service, ANN, dialect=dialect)
                await node.feed("---LOAD PROGRAM BEGIN---")
                for text in ("---CONNECT FOR LOAD---", "---CONNECT FOR EXECUTE---"):
                    await node.feed(text)
                await node.feed("---DISCONNECT---")
                assert node.state.name == "S2"  # still receiving the program
            assert len(controller.commands()) == before

    run(main())


def test_melfa_answers_keep_their_parentheses() -> None:
    controller = RecordingController()

    async def main() -> str:
        service, _ = make_service(controller, polling=False)
        async with service:
            node = ThesisMessages(service, ANN)
            text = await node.feed("---REQUEST JOINT STATE---")
            assert text is not None
            return text

    text = run(main())
    assert text.startswith("(") and text.endswith(")")
    assert float(text.strip("()").split(",")[2]) == pytest.approx(math.pi / 2, abs=1e-4)


def test_dialect_names_and_poses() -> None:
    assert dialect_named(" Thesis ") is THESIS
    with pytest.raises(ValueError, match="melfa, thesis"):
        dialect_named("ros2")
    assert parse_pose("1,2,3,4,5,6") == (1, 2, 3, 4, 5, 6)
    assert parse_pose("(1,2,3,4,5,6)(7,0)") == (1, 2, 3, 4, 5, 6)
    with pytest.raises(Exception, match="not a pose"):
        parse_pose("(1,2,x,4,5,6)")
