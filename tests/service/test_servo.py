"""The servo before a move (`melfa.service.servo`): asked, switched on and audited, or left."""

from __future__ import annotations

import pytest

from melfa.robot import ControllerError
from melfa.service import MemoryAuditSink, ServoOff, ServoPolicy
from tests.service.helpers import ANN, RecordingController, clock, make_service, run


def test_a_move_with_the_servo_off_asks_and_sends_nothing() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            with pytest.raises(ServoOff) as exc:
                await service.move_to(ANN, (0, 0, 90, 0, 90, 0), joints=True, servo=ServoPolicy.ASK)
            assert isinstance(exc.value, ControllerError) and exc.value.number == 2000
            with pytest.raises(ServoOff):
                await service.run(ANN, servo=ServoPolicy.ASK)
        sent = controller.commands(skip_polls=True)
        assert not any("MOV" in c or "RUN" in c for c in sent), sent
        assert controller.alarm is None  # nothing refused, so nothing blocks the next Run

    run(main())


def test_turn_on_switches_the_servo_on_audits_it_and_moves() -> None:
    controller = RecordingController()

    async def main() -> None:
        sink = MemoryAuditSink()
        service, _ = make_service(controller, polling=False)
        service.audit = sink
        async with service:
            await service.move_to(
                ANN, (10, 0, 90, 0, 90, 0), joints=True, servo=ServoPolicy.TURN_ON
            )
            assert controller.arm.servo
            assert service.state.servo is True
            for _ in range(500):
                at = (await service.read_joints(ANN))[0]
                if abs(at - 10) < 1e-6 and not controller.arm.is_moving:
                    break
                await clock().sleep(0.01)
            else:
                raise AssertionError("the arm never reached J1 = 10")
            # Servo already on: no second SRVON.
            await service.exec(ANN, "M1=5", servo=ServoPolicy.TURN_ON)
        sent = controller.commands(skip_polls=True)
        assert sum(c.endswith("SRVON") for c in sent) == 1, sent
        servo_rows = [e for e in sink.entries if e.command == "servo"]
        assert [(e.actor, e.detail, e.result) for e in servo_rows] == [
            (ANN, "on, before Move to", "ok")
        ]

    run(main())


def test_exec_leaves_the_servo_alone_by_default() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False, motion_servo=ServoPolicy.ASK)
        async with service:
            await service.exec(ANN, "M1=5")
        assert not controller.arm.servo
        assert not any(c.endswith("STATE") for c in controller.commands())

    run(main())


def test_a_stale_servo_off_alarm_is_reset_before_turning_on() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False)
        async with service:
            with pytest.raises(ControllerError) as exc:
                await service.exec(ANN, "MOV J_CURR")  # LEAVE: the controller refuses
            assert exc.value.number == 2000 and controller.alarm is not None
            await service.move_to(ANN, (5, 0, 90, 0, 90, 0), joints=True, servo=ServoPolicy.TURN_ON)
            assert controller.arm.servo and controller.alarm is None

    run(main())


def test_the_config_chooses_for_callers_that_do_not_say() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, polling=False, motion_servo=ServoPolicy.TURN_ON)
        async with service:
            await service.jog_step(ANN, "joint", 0, 1)
        assert controller.arm.servo

    run(main())
