"""One truth for what the robot does: a Move to is "moving-to P1" until a STATE read shows
it arrived, then "at P1"; a program "running", a program stopped mid-way "paused", a held
jog "jogging" (never "running line 50"), and after STOP → Move to → arrival, with the
program paused, never "running" while the arm goes to the point."""

from __future__ import annotations

from melfa.service import JogFrame, ServoPolicy
from melfa.vocab.activity import Activity
from tests.plans import project
from tests.service.helpers import ANN, RecordingController, clock, make_service, run, until

TURN_ON = ServoPolicy.TURN_ON
PROGRAM = "MOV P1\nMOV P2\nMOV P1\nMOV P2\nEND\n"
POINTS = ["P1=(300,0,400,180,0,180)(7,0)", "P2=(300,150,400,180,0,180)(7,0)"]


def test_move_to_run_pause_and_idle_are_told_apart() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()  # a listener: polling at full rate
            assert await until(lambda: service.state.activity is Activity.IDLE)
            await service.move_to(
                ANN, (300, 150, 400, 180, 0, 180), servo=ServoPolicy.TURN_ON, label="P2"
            )
            assert await until(lambda: service.state.activity is Activity.MOVING_TO)
            assert service.state.activity_detail == "P2"
            assert await until(lambda: service.state.activity is Activity.AT)
            assert service.state.activity_detail == "P2"
            await service.load_project(ANN, project(PROGRAM, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: service.state.activity is Activity.RUNNING)
            assert service.state.activity_detail.startswith("line ")
            await service.stop(ANN)
            assert await until(lambda: service.state.activity is Activity.PAUSED)
            sub.close()

    run(main())


def test_stop_then_move_to_says_moving_then_at_the_point_never_running() -> None:
    controller = RecordingController()
    program = "MOV P1\nMOV P2\nMOV P1\nMOV P2\nMOV P1\nMOV P2\nEND\n"
    points = [*POINTS, "P3=(350,-150,300,180,0,180)(7,0)"]

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()
            assert await until(lambda: service.state.activity is Activity.IDLE)
            await service.load_project(ANN, project(program, points))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: (service.state.line or 0) >= 20)  # under way
            await service.stop(ANN)
            assert await until(lambda: service.state.activity is Activity.PAUSED)
            said: list[tuple[Activity, str, bool | None]] = []
            await service.move_to(ANN, "P3", servo=ServoPolicy.TURN_ON)
            # The controller has taken the move; no read has seen the arm go yet: not "At".
            assert service.state.activity is Activity.MOVING_TO
            while service.state.activity is not Activity.AT and len(said) < 2000:
                s = service.state
                said.append((s.activity, s.activity_detail, s.running))
                await clock().sleep(0.01)
            assert service.state.activity is Activity.AT
            assert service.state.activity_detail == "P3"
            assert service.state.paused  # the program stays paused: Run continues it
            assert {a for a, _, _ in said} == {Activity.MOVING_TO}, said
            assert {d for _, d, _ in said} == {"P3"}
            assert any(running for _, _, running in said)  # the arm really went
            assert not service.state.running and not service.state.moving
            sub.close()

    run(main())


def test_a_jog_step_moves_to_its_label_then_the_arm_is_idle() -> None:
    """A step jog is "moving-to X+" while it moves and idle once the arm stopped (it
    stayed "moving-to" for ever: the step never told the activity it was sent)."""
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()
            assert await until(lambda: service.state.activity is Activity.IDLE)
            await service.jog_step(ANN, JogFrame.XYZ, "X", +1, wait=True, servo=TURN_ON)
            assert await until(lambda: service.state.activity is Activity.IDLE)
            assert not service.state.moving
            sub.close()

    run(main())
