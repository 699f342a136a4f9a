"""Dead-man jog, step jog without backlog, operator lease, audit entries, closing."""

from __future__ import annotations

import asyncio

import pytest

from melfa.protocol import JOG_WATCHDOG_S
from melfa.robot import ControllerError, JogMethod
from melfa.service import (
    JogBusy,
    JogChanged,
    LeaseRequired,
    MemoryAuditSink,
    NotAllowed,
    ServiceClosed,
    UploadProgress,
)
from melfa.service.service import describe_error
from melfa.sim import SimConfig
from melfa.sim.machine import SimArm
from melfa.vocab.jog import JogEnd
from tests.plans import program_plan
from tests.service.helpers import (
    ANN,
    BOB,
    IRIS,
    OLGA,
    RecordingController,
    clock,
    make_service,
    run,
    until,
)

# Continuous JOG is documented only (no real answer on record), so strict simulators refuse
# it; this module tests the path melfa keeps for a controller that accepts it.
pytestmark = pytest.mark.usefixtures("not_strict")


def _jogs(controller: RecordingController) -> list[float]:
    return [s.now for s in controller.seen if ";JOG0" in s.command and s.command[-8:] != "00;00;00"]


def test_jog_stops_within_the_watchdog_when_heartbeats_stop() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, jog_heartbeat_timeout_s=0.3)
        async with service:
            events = service.subscribe(JogChanged)
            await service.servo(ANN, True)
            assert await service.jog_start(ANN, "joint", "J1", +1) is JogMethod.JOG
            for _ in range(8):
                await clock().sleep(0.05)
                assert service.jog_heartbeat(ANN)
            seen_at_last = len(controller.seen)
            await clock().sleep(0.6)  # key "released" without a release call
            # The service sent no JOG after the last heartbeat's renewal …
            late = [s for s in controller.seen[seen_at_last:] if ";JOG0" in s.command]
            assert all(s.command.endswith("00;00;00") for s in late[1:])
            # … so, in the controller's own time, the arm stopped within the watchdog of
            # the last JOG it received.
            last_jog = max(_jogs(controller))
            arm = controller.arm
            assert isinstance(arm, SimArm)
            samples = arm.arm.recorder.samples
            final = samples[-1].joints
            moving_until = max(s.time for s in samples if s.joints != final)
            assert moving_until <= last_jog + JOG_WATCHDOG_S + 1e-6
            assert final[0] > 0  # it did move
            assert not service.jog_heartbeat(ANN)  # the jog is over
            kinds = []
            while (event := events.get_nowait()) is not None:
                assert isinstance(event, JogChanged)
                kinds.append((event.active, event.end))
            assert kinds == [(True, None), (False, JogEnd.HEARTBEAT_LOST)]

    run(main())


def test_release_stops_at_once_and_override_is_capped() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, jog_override_ceiling=20)
        async with service:
            await service.servo(ANN, True)
            await service.override(ANN, 80)
            await service.jog_start(ANN, "tool", "Z", -1)
            assert controller.arm.op_override == 20  # capped while jogging
            service.jog_heartbeat(ANN)
            await clock().sleep(0.05)
            await service.jog_release(ANN)
            assert not controller.moving
            assert controller.commands()[-1].endswith("JOG00;00;00;00;00")
            await service.exec(ANN, "JT=(1,0,0,0,0,0)")  # the next user command restores
            assert controller.arm.op_override == 80

    run(main())


def test_jog_fallback_steps_never_queue_behind_a_released_key() -> None:
    controller = RecordingController(SimConfig(jog_supported=False))

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            await service.servo(ANN, True)
            assert await service.jog_start(ANN, "xyz", "X", +1) is JogMethod.STEP
            for _ in range(20):  # heartbeats far faster than steps can finish
                service.jog_heartbeat(ANN)
                await clock().sleep(0.01)
            await service.jog_release(ANN)
            sent = len(controller.commands())
            await clock().sleep(0.3)
            assert len(controller.commands()) == sent  # nothing left to send
            accepted = [c for c in controller.commands() if "EXECMVS" in c]
            assert 1 <= len(accepted) <= 21

    run(main())


def test_step_mode_refuses_rather_than_queues() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            await service.servo(ANN, True)
            first = asyncio.create_task(service.jog_step(ANN, "joint", 0, +1))
            await asyncio.sleep(0)
            with pytest.raises(JogBusy):
                await service.jog_step(ANN, "joint", 0, +1)  # still queued
            await first
            assert controller.moving
            with pytest.raises(JogBusy, match="still moving") as busy:
                await service.jog_step(ANN, "joint", 0, +1)  # controller: 5640
            # In words, as ROS's /execute_error and every door say it: no class name.
            said = describe_error(busy.value)
            assert "JogBusy" not in said and said.startswith("the arm is still moving")
            assert "then jog again" in said
            for _ in range(500):  # the controller's time moves on with each request
                await service.read_joints(ANN)
                if not controller.moving:
                    break
                await clock().sleep(0.01)
            await service.jog_step(ANN, "joint", 0, +1)
            moves = [c for c in controller.commands() if "MOV J_CURR" in c]
            assert len(moves) == 2

    run(main())


def test_lease_rules() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            with pytest.raises(LeaseRequired, match="observer"):
                await service.servo(OLGA, True)
            with pytest.raises(LeaseRequired, match="olga is an observer"):
                service.acquire_lease(OLGA)
            await service.servo(ANN, True)  # a free lease is taken by the first mover
            assert service.lease_holder == ANN
            with pytest.raises(LeaseRequired, match="ann holds the robot") as refused:
                await service.exec(BOB, "JT=(1,0,0,0,0,0)")
            assert refused.value.holder == ANN
            with pytest.raises(NotAllowed):
                service.take_over(BOB)
            service.take_over(IRIS)
            assert service.lease_holder == IRIS
            with pytest.raises(LeaseRequired, match="iris"):
                await service.hand(ANN, True)
            await service.stop(OLGA)  # stop is everyone's
            await service.stop(ANN)
            await service.disconnect(IRIS)
            assert service.lease_holder is None
            await service.hand(BOB, False)
            assert service.lease_holder == BOB
            service.release_lease(BOB)
            assert service.lease_holder is None

    run(main())


def test_takeover_ends_the_previous_holders_jog() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            await service.servo(ANN, True)
            await service.jog_start(ANN, "joint", 1, -1)
            service.take_over(IRIS)
            assert not service.jog_heartbeat(ANN)
            assert not service.state.jogging
            assert await until(lambda: not controller.moving, 2)

    run(main())


def test_lease_idle_timeout() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False, lease_idle_timeout_s=0.1)
        async with service:
            await service.servo(ANN, True)
            assert service.lease_holder == ANN
            await clock().sleep(0.25)
            assert service.lease_holder is None
            await service.servo(BOB, True)

    run(main())


def test_audit_entries_for_moving_commands() -> None:
    controller = RecordingController()

    async def main() -> None:
        sink = MemoryAuditSink()
        service, _ = make_service(controller, polling=False)
        service.audit = sink
        async with service:
            await service.servo(ANN, True)
            await service.exec(ANN, "JT=(5,0,0,0,0,0)")
            with pytest.raises(ControllerError) as exc:
                await service.exec(ANN, "MOV J_CURR+JNOPE")
            assert exc.value.number > 0
            with pytest.raises(LeaseRequired):
                await service.run(BOB)
            await service.stop(OLGA)
        rows = [(e.actor.user if e.actor else None, e.command, e.result) for e in sink.entries]
        assert rows[:4] == [
            ("ann", "servo", "accepted"),
            ("ann", "servo", "ok"),
            ("ann", "exec", "accepted"),
            ("ann", "exec", "ok"),
        ]
        assert rows[4][:2] == ("ann", "exec") and rows[4][2] == "accepted"
        assert rows[5][2].startswith("failed: L")  # the controller's code and its advice
        assert "Error" not in rows[5][2]
        assert rows[6][:2] == ("bob", "run") and rows[6][2].startswith("refused: ")
        assert rows[7:] == [("olga", "stop", "accepted"), ("olga", "stop", "ok")]
        ids = [e.command_id for e in sink.entries]
        assert ids[0] == ids[1] != ids[2]
        assert all(e.at.tzinfo is not None for e in sink.entries)

    run(main())


def test_close_fails_queued_commands_and_is_safe_twice() -> None:
    controller = RecordingController()

    async def main() -> None:
        # A paced line: the upload stays on the wire in the test's time, so the worker cannot
        # finish it and take the queued run before close() (on a bare link it sometimes did).
        service, links = make_service(controller, polling=False, pace=True)
        await service.start()
        await service.servo(ANN, True)
        progress = service.subscribe(UploadProgress)
        upload = asyncio.create_task(
            service.upload_program(ANN, program_plan([f"{i * 10} MOV P1" for i in range(1, 40)]))
        )
        await progress.get()  # the upload is on the wire
        queued = asyncio.create_task(service.run(ANN))
        await asyncio.sleep(0)
        await asyncio.gather(service.close(), service.close())
        await upload  # the command in flight completes
        with pytest.raises(ServiceClosed):
            await queued
        with pytest.raises(ServiceClosed):
            await service.servo(ANN, False)
        assert service.lease_holder is None
        assert links.opened[-1].closed
        assert controller.commands()[-1] == "1;1;CLOSE"
        await service.close()

    run(main())


def test_a_released_step_jog_stops_short_of_its_step() -> None:
    """Where the controller refuses JOG, hold-to-move sends step moves; letting the key go
    stops the step in progress (STOP) instead of letting it run its whole 10 mm."""
    controller = RecordingController(SimConfig(jog_supported=False))

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            await service.servo(ANN, True)
            before = controller.arm.pose.x
            assert await service.jog_start(ANN, "xyz", "X", +1) is JogMethod.STEP
            assert controller.moving
            await clock().sleep(0.02)  # the key is held for a moment
            await service.jog_release(ANN)
            assert controller.commands()[-1].endswith(";STOP")
            for _ in range(20):  # a second of the controller's time, read every 50 ms
                await clock().sleep(0.05)
                await service.read_joints(ANN)
            assert not controller.moving  # it decelerated and stopped
            stopped = controller.arm.pose.x
            for _ in range(20):
                await clock().sleep(0.05)
                await service.read_joints(ANN)
            assert controller.arm.pose.x == stopped
            assert 0 < stopped - before < 0.5 * service.robot_settings.jog_step_mm
            # The next press still jogs.
            assert await service.jog_start(ANN, "xyz", "X", +1) is JogMethod.STEP
            await clock().sleep(0.1)
            await service.jog_release(ANN)
            assert controller.arm.pose.x > stopped

    run(main())
