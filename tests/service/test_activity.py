"""One truth for what the robot does: a Move to is "moving-to P1", a program "running",
a program stopped mid-way "paused", a held jog "jogging" (never "running line 50")."""

from __future__ import annotations

from melfa.service import ServoPolicy
from melfa.vocab.activity import Activity
from tests.plans import project
from tests.service.helpers import ANN, RecordingController, make_service, run, until

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
            assert await until(lambda: service.state.activity is Activity.IDLE)
            await service.load_project(ANN, project(PROGRAM, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: service.state.activity is Activity.RUNNING)
            assert service.state.activity_detail.startswith("line ")
            await service.stop(ANN)
            assert await until(lambda: service.state.activity is Activity.PAUSED)
            sub.close()

    run(main())
