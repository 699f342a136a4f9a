"""State keeps flowing while a jog step moves: between the step's move and its end the
worker never waits on the controller twice without a state poll in between (the wire
shows DSTATE and polls interleaved), snapshots arrive during the move, and a moving arm's
pose is of one kind (computed or measured), never alternating."""

from __future__ import annotations

import asyncio
import itertools

from melfa.service import JogFrame, ServoPolicy, StateSnapshot
from tests.service.helpers import ANN, RecordingController, make_service, run, until

TURN_ON = ServoPolicy.TURN_ON


def test_a_jog_step_polls_state_while_it_moves() -> None:
    controller = RecordingController()

    async def main() -> list[StateSnapshot]:
        service, _ = make_service(controller, poll_floor_s=0.005)
        snapshots: list[StateSnapshot] = []
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
                await asyncio.sleep(0.05)
                collector.cancel()
        return snapshots

    snapshots = run(main())
    commands = [c.split(";", 2)[-1] for c in controller.commands()]
    start = next(i for i, c in enumerate(commands) if c.startswith("EXECMVS P_CURR+"))
    end = max(i for i, c in enumerate(commands) if c == "DSTATE")
    window = commands[start + 1 : end + 1]
    assert window.count("DSTATE") >= 3  # the move took a while
    for a, b in itertools.pairwise(window):
        assert not (a == "DSTATE" and b == "DSTATE"), window  # a poll between two waits
    assert sum(c.startswith("JPOSF") for c in window) >= 2

    heights = [s.pose[2] for s in snapshots if s.pose is not None]
    assert len({round(h, 3) for h in heights}) >= 4, heights  # seen on its way up
    moving = [s for s in snapshots if s.moving and s.pose is not None]
    kinds = [s.pose_measured for s in moving]
    changes = sum(a != b for a, b in itertools.pairwise(kinds))
    assert changes <= 1, kinds  # one kind while moving (at most the switch at the start)
