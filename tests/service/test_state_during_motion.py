"""State keeps flowing while a jog step moves: between the step's move and its end the
worker reads the joints after every wait check (the wire shows JPOSF between the STATE
checks), snapshots arrive during the move, and a moving arm's
pose is of one kind (computed or measured), never alternating."""

from __future__ import annotations

import asyncio
import itertools

from melfa.service import JogFrame, ServoPolicy, StateSnapshot
from tests.plans import points_plan, program_plan
from tests.service.helpers import ANN, RecordingController, clock, make_service, run, until

TURN_ON = ServoPolicy.TURN_ON


def test_a_jog_step_polls_state_while_it_moves() -> None:
    controller = RecordingController()

    async def main() -> tuple[list[StateSnapshot], int]:
        service, _ = make_service(controller, poll_floor_s=0.005)
        snapshots: list[StateSnapshot] = []
        done: list[int] = []
        async with service:
            with service.subscribe(StateSnapshot) as sub:

                async def collect() -> None:
                    async for event in sub:
                        if isinstance(event, StateSnapshot):
                            snapshots.append(event)

                assert await until(lambda: service.state.joints is not None)
                await service.exec(ANN, "SERVO ON")
                collector = asyncio.create_task(collect())
                await service.jog_step(ANN, JogFrame.XYZ, "Z", +1, wait=True, servo=TURN_ON)
                done.append(len(controller.seen))  # requests up to the step's return
                await clock().sleep(0.05)
                collector.cancel()
        return snapshots, done[0]

    snapshots, returned = run(main())
    seen = [s.command.split(";", 2)[-1] for s in controller.seen[:returned]]
    moved = next(i for i, c in enumerate(seen) if c.startswith("EXECMVS P_CURR+"))
    window = seen[moved + 1 :]  # while the step waited
    assert len(window) >= 6, window  # the move took a while
    assert sum(c.startswith("JPOSF") for c in window) >= 3, window
    runs = [
        len(list(g))
        for is_joints, g in itertools.groupby(window, lambda c: c == "JPOSF")
        if not is_joints
    ]
    assert max(runs) <= 3, window  # joints read after at most the wait check and a poll

    heights = [s.pose[2] for s in snapshots if s.pose is not None]
    assert len({round(h, 3) for h in heights}) >= 4, heights  # seen on its way up
    moving = [s for s in snapshots if s.moving and s.pose is not None]
    kinds = [s.pose_measured for s in moving]
    changes = sum(a != b for a, b in itertools.pairwise(kinds))
    assert changes <= 1, kinds  # one kind while moving (at most the switch at the start)


def _step_time(stop_first: bool) -> tuple[float, bool | None]:
    """Controller time a 10 mm base-frame step takes (from its MVS to its last status
    check), after a program was stopped mid-move or not; and whether the state says a
    program runs afterwards."""
    controller = RecordingController()

    returned: list[int] = []

    async def main() -> bool | None:
        service, _ = make_service(controller, poll_floor_s=0.02)
        async with service:
            assert await until(lambda: service.state.joints is not None)
            await service.exec(ANN, "SERVO ON")
            if stop_first:
                program = ["10 SERVO ON", "20 SPD 5", "30 MVS P1", "40 END"]
                await service.upload_program(ANN, program_plan(program))
                await service.upload_points(
                    ANN, points_plan(["DEF POS P1=(400.00,0.00,300.00,180.00,0.00,180.00)(7,0)"])
                )
                await service.run(ANN)
                assert await until(lambda: bool(service.want_state().running))
                await service.stop(ANN)
                assert await until(lambda: service.want_state().running is False)
            await service.jog_step(ANN, JogFrame.XYZ, "Z", +1, wait=True, servo=TURN_ON)
            returned.append(len(controller.seen))
            await clock().sleep(0.3)
            return service.want_state().running

    running = run(main())
    seen = controller.seen[: returned[0]]  # up to the step's end
    start = max(s.now for s in seen if "EXECMVS P_CURR+" in s.command)
    return seen[-1].now - start, running


def test_after_a_stop_a_jog_step_moves_at_jog_speed_and_nothing_runs() -> None:
    plain, _ = _step_time(stop_first=False)
    after_stop, running = _step_time(stop_first=True)
    assert running is False  # not "running line 30" after the stop
    assert after_stop < 2 * plain, (plain, after_stop)  # no crawl at the program's SPD 5
