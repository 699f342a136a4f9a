"""The thesis's control messages give the same controller traffic as the direct calls."""

from __future__ import annotations

import math

import pytest

from melfa.service import (
    JogFrame,
    RobotService,
    ServoPolicy,
    ThesisMessageError,
    ThesisMessages,
    ThesisOutput,
)
from melfa.service.thesis import parse_control
from tests.plans import points_plan, program_plan
from tests.service.helpers import ANN, RecordingController, make_service, run

PROGRAM = ["10 SERVO ON", "20 SPD 10", "30 MOV PA", "40 END"]
POINTS = ["DEF POS PA=(400.00,0.00,600.00,180.00,0.00,180.00)(7,0)"]


def _traffic(scenario: str, use_thesis: bool) -> list[str]:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            if use_thesis:
                await _thesis(ThesisMessages(service, ANN, wall_clock=lambda: 100.0), scenario)
            else:
                await _direct(service, scenario)

    run(main())
    return controller.commands()


async def _thesis(node: ThesisMessages, scenario: str) -> None:
    if scenario == "project":
        for message in ["---DELETE---", "---LOAD PROGRAM BEGIN---", *PROGRAM]:
            await node.feed(message)
        await node.feed("—LOAD PROGRAM END—")  # the PDF's em dashes work too
        for message in ["---LOAD POINTS BEGIN---", *POINTS, "---LOAD POINTS END---"]:
            await node.feed(message)
        await node.feed("---SINGLE INSTRUCTION---")
        await node.feed("SERVO ON")
        await node.feed("---RUN PROGRAM---")
        await node.feed("---REQUEST JOINT STATE---")
    else:
        await node.feed("---SINGLE INSTRUCTION---")
        await node.feed("SERVO ON")
        await node.feed("---MOV TOOL +X---101")
        await node.feed("---MOV TOOL -Z---")  # no timestamp: "now" (100) ≤ last finished
        await node.feed("---REQUEST TOOL POSE---")  # leaves S4 after the move


async def _direct(service: RobotService, scenario: str) -> None:
    if scenario == "project":
        await service.delete(ANN)
        await service.upload_program(ANN, program_plan(PROGRAM))
        await service.upload_points(ANN, points_plan(POINTS))
        await service.exec(ANN, "SERVO ON")
        await service.run(ANN, servo=ServoPolicy.TURN_ON)  # a topic cannot ask back
        await service.read_joints(ANN)
    else:
        await service.exec(ANN, "SERVO ON")
        await service.jog_step(ANN, JogFrame.TOOL, "X", +1, wait=True, servo=ServoPolicy.TURN_ON)
        await service.read_pose(ANN)


@pytest.mark.parametrize("scenario", ["project", "jog"])
def test_thesis_messages_give_the_same_traffic_as_direct_calls(scenario: str) -> None:
    through_thesis = _traffic(scenario, use_thesis=True)
    direct = _traffic(scenario, use_thesis=False)
    assert through_thesis == direct
    assert len(direct) > 5


def test_jog_messages_older_than_the_last_finished_move_are_dropped() -> None:
    controller = RecordingController()
    clock = [1000.0]

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            node = ThesisMessages(service, ANN, wall_clock=lambda: clock[0])
            outputs = service.subscribe(ThesisOutput)
            await node.feed("---SINGLE INSTRUCTION---")
            await node.feed("SERVO ON")
            await node.feed("---MOV TOOL +Y---1001")
            clock[0] = 1005.0
            await node.close()  # the move finishes "at 1005"
            await node.feed("---MOV TOOL +Y---1003")  # generated while it moved: dropped
            await node.feed("---MOV TOOL +Y---999")  # older still: dropped
            await node.feed("---REQUEST JOINT STATE---")
            assert node.moves == 1 and node.dropped == 2
            event = outputs.get_nowait()
            assert isinstance(event, ThesisOutput) and event.topic == "joint_state"
            values = [float(v) for v in event.text.strip("()").split(",")]
            assert len(values) == 6 and values[2] == pytest.approx(math.radians(90), abs=0.01)

    run(main())
    steps = [c for c in controller.commands() if "MVS P_CURR*" in c]
    assert len(steps) == 1


def test_state_machine_errors_return_to_s0() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            node = ThesisMessages(service, ANN)
            with pytest.raises(ThesisMessageError, match="not a control message"):
                await node.feed("10 MOV P1")
            await node.feed("---LOAD PROGRAM BEGIN---")
            with pytest.raises(ThesisMessageError, match="receiving program"):
                await node.feed("---LOAD POINTS BEGIN---")
            assert node.state.name == "S0"
            with pytest.raises(ThesisMessageError, match="unknown control message"):
                await node.feed("---FLY---")

    run(main())
    assert not any("EMDAT" in c for c in controller.commands())


def test_parse_control_variants() -> None:
    assert parse_control("---MOV TOOL -Z---1468360644") == ("MOV TOOL -Z", 1468360644.0)
    assert parse_control("—REQUEST TOOL POSE—") == ("REQUEST TOOL POSE", None)
    assert parse_control("  ---DELETE---  ") == ("DELETE", None)
    assert parse_control("DEF POS P1=(1,2,3,4,5,6)(7,0)") is None
