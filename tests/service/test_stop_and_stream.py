"""Stop overtakes uploads; state reaches every subscriber; slow ones never block; the link
comes back by itself."""

from __future__ import annotations

import asyncio

import pytest

from melfa.link import SerialLink
from melfa.robot import Stopped
from melfa.service import (
    Cancelled,
    LinkStatus,
    LinkStatusChanged,
    RobotService,
    ServiceConfig,
    StateSnapshot,
    UploadProgress,
)
from melfa.sim import Pacing, PtyServer
from tests.plans import program_plan
from tests.service.helpers import (
    ANN,
    LINK,
    OLGA,
    RecordingController,
    clock,
    make_service,
    run,
    until,
)

PROGRAM = "\n".join(f"{10 * i} MOV P{i % 7 + 1}" for i in range(1, 160))


def _after_stop(commands: list[str]) -> list[str]:
    index = next(i for i, c in enumerate(commands) if c.endswith(";STOP"))
    return commands[index + 1 :]


async def _stop_during_upload(
    service: RobotService, controller: RecordingController, *, most_chunks: int
) -> None:
    sub = service.subscribe(UploadProgress)
    upload = asyncio.create_task(service.upload_program(ANN, program_plan(PROGRAM)))
    while True:
        event = await sub.get()
        assert isinstance(event, UploadProgress)
        if event.sent > 0:
            break
    queued = asyncio.create_task(service.run(ANN))  # waits behind the upload
    await asyncio.sleep(0)
    await service.stop(OLGA)  # an observer may stop
    with pytest.raises(Stopped):
        await upload
    with pytest.raises(Cancelled):
        await queued
    commands = controller.commands()
    after = _after_stop(commands)
    # Controller side: STOP arrived while chunks were still to come; none came after it,
    # the edit was never saved, and the queued RUN never went out.
    emdat_total = sum(1 for c in commands if ";EMDAT" in c)
    assert emdat_total < most_chunks
    assert not any(";EMDAT" in c for c in after)
    assert not any(c.endswith(";SAVE") for c in commands)
    assert not any(";RUN" in c for c in commands)
    assert "1" not in controller.store
    # The stopped upload was abandoned with NEW (sent in turn after STOP's reply), so no
    # edit session is left open on the controller.
    assert any(c.endswith(";NEW") for c in after)
    assert controller.edit is None


def test_stop_overtakes_upload_in_memory_paced() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, pace=True, polling=False)
        async with service:
            # The STOP leaves from a thread in real time while the test's clock paces the
            # upload as fast as the CPU allows: how many chunks slip out first measures the
            # machine's load, not the service; what holds is that the upload never finished
            # and nothing came after the STOP.
            await _stop_during_upload(service, controller, most_chunks=PROGRAM.count("\n"))

    run(main())


def test_stop_overtakes_upload_through_a_pty() -> None:
    controller = RecordingController()
    # 115200 baud: the real 9600 line twelve times faster; STOP still overtakes the chunks.
    with PtyServer(controller, pacing=Pacing.for_baud(115200, latency=0.0)) as server:

        async def main() -> None:
            service = RobotService(
                lambda: SerialLink(server.new_port(), LINK), config=ServiceConfig(polling=False)
            )
            async with service:
                await _stop_during_upload(service, controller, most_chunks=10)

        run(main())


def test_stream_reaches_many_subscribers() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            subs = [service.subscribe(StateSnapshot) for _ in range(25)]
            seen: list[list[StateSnapshot]] = [[] for _ in subs]

            async def read(index: int) -> None:
                async for event in subs[index]:
                    assert isinstance(event, StateSnapshot)
                    seen[index].append(event)
                    if len(seen[index]) >= 6 and event.joints is not None:
                        return

            await asyncio.gather(*(read(i) for i in range(len(subs))))
            for snapshots in seen:
                seqs = [s.seq for s in snapshots]
                assert seqs == sorted(seqs) and len(set(seqs)) == len(seqs)
                assert snapshots[-1].joints == pytest.approx((0, 0, 90, 0, 90, 0))
                assert snapshots[-1].link is LinkStatus.CONNECTED
            assert any(s.pose is not None for s in seen[0])
            assert any(s.servo is not None for snaps in seen for s in snaps)

    run(main())


def test_slow_subscriber_holds_one_snapshot_and_blocks_nobody() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            slow = service.subscribe(StateSnapshot)  # never read until the end
            fast = service.subscribe(StateSnapshot)
            got = 0
            async for _ in fast:
                got += 1
                if got >= 40:
                    break
            assert slow.pending() == 1  # only the newest snapshot waits
            newest = slow.get_nowait()
            assert isinstance(newest, StateSnapshot)
            assert newest.seq >= 40
            assert slow.dropped == 0 and slow.replaced >= 39

    run(main())


def test_nobody_listening_polls_slowly() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, idle_poll_s=5.0)
        async with service:
            await clock().sleep(0.3)
            idle = len(controller.commands())
            with service.subscribe(StateSnapshot):
                await clock().sleep(0.3)
            busy = len(controller.commands()) - idle
            assert idle <= 3  # OPEN and at most one poll
            assert busy > 5 * idle

    run(main())


def test_a_rest_reader_gets_fresh_state_for_a_while() -> None:
    """`want_state` (what GET /api/robot/state calls) counts as a listener for
    `state_interest_s`, so a client polling over REST sees fresh joints, not an idle
    snapshot; once the interest lapses the service is back to idle polling."""
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, idle_poll_s=5.0, state_interest_s=0.5)
        async with service:
            await clock().sleep(0.3)
            # Idle polling (one request per 5 s) could not give 5 snapshots in 4 s.
            first = service.want_state().seq
            assert await until(lambda: service.state.seq >= first + 5, timeout=4.0)
            await clock().sleep(0.6)  # interest over: idle again
            settled = len(controller.commands())
            await clock().sleep(0.3)
            assert len(controller.commands()) - settled <= 1

    run(main())


def test_reconnects_after_the_in_memory_link_hangs_up() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, links = make_service(controller, reconnect_initial_s=0.05)
        async with service:
            sub = service.subscribe(LinkStatusChanged)
            links.memory[-1].hang_up()
            statuses = []
            while LinkStatus.CONNECTED not in statuses:
                event = await sub.get()
                assert isinstance(event, LinkStatusChanged)
                statuses.append(event.status)
            assert statuses[0] is LinkStatus.RECONNECTING
            assert len(links.opened) == 2
            assert await service.read_joints(ANN) == pytest.approx((0, 0, 90, 0, 90, 0))

    run(main())


def test_reconnects_after_the_pty_server_side_dies() -> None:
    controller = RecordingController()
    servers: list[PtyServer] = []

    def open_port() -> SerialLink:
        server = PtyServer(controller)  # one server per connection: we kill it whole
        servers.append(server)
        return SerialLink(server.new_port(), LINK)

    async def main() -> None:
        service = RobotService(open_port, config=ServiceConfig(reconnect_initial_s=0.05))
        async with service:
            sub = service.subscribe(LinkStatusChanged)
            with service.subscribe(StateSnapshot):  # keep it polling
                servers[-1].close()  # the far end of the line is gone
                statuses = []
                while LinkStatus.CONNECTED not in statuses:
                    event = await sub.get()
                    assert isinstance(event, LinkStatusChanged)
                    statuses.append(event.status)
            assert statuses[0] is LinkStatus.RECONNECTING
            assert len(servers) == 2
            await service.servo(ANN, True)
            assert await until(lambda: controller.arm.servo)

    try:
        run(main())
    finally:
        for server in servers:
            server.close()


def test_a_still_arm_shows_one_steady_pose() -> None:
    """Away from home, the pose computed from 2-decimal joints differs from the measured
    one by a fraction of a mm; a still arm must show the measured pose, not flicker."""
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            await service.servo(ANN, True)
            await service.move_to(ANN, (350.0, -250.0, 390.0, 180.0, 0.0, 180.0))
            with service.subscribe(StateSnapshot) as sub:
                while True:  # until the move is over and a PPOSF was read at rest
                    snap = await sub.get()
                    assert isinstance(snap, StateSnapshot)
                    arrived = snap.pose is not None and abs(snap.pose[1] + 250.0) < 1.0
                    if arrived and not snap.moving and snap.pose_measured:
                        break
                poses = set()
                for _ in range(16):  # four poll cycles (JPOSF, PPOSF, STATE, HNDSTS)
                    snap = await sub.get()
                    assert isinstance(snap, StateSnapshot)
                    poses.add(snap.pose)
            assert len(poses) == 1
            (pose,) = poses
            assert pose[:3] == pytest.approx((350.0, -250.0, 390.0), abs=0.02)

    run(main())
