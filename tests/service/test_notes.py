"""What happens to the robot that no command asked for reaches the audit sink as notes
(`melfa.service.notes`), so the robot's log on the server has it: control changing hands
(whoever caused it), an alarm raised on the controller and cleared, the link going up."""

from __future__ import annotations

import pytest

from melfa.robot import ControllerError
from melfa.service import MemoryAuditSink
from melfa.service.events import StateSnapshot
from melfa.vocab.robot_log import NoteKind
from tests.service.helpers import ANN, IRIS, RecordingController, make_service, run, until


def test_control_alarms_and_the_link_are_noted_for_the_robot_log() -> None:
    controller = RecordingController()
    sink = MemoryAuditSink()

    async def main() -> None:
        service, _ = make_service(controller)
        service.audit = sink
        async with service:
            states = service.subscribe(StateSnapshot)  # a reader: the service polls
            service.acquire_lease(ANN)
            service.take_over(IRIS)
            with pytest.raises(ControllerError):
                await service.exec(IRIS, "MOV J_CURR")  # the controller refuses: alarm 2000
            assert await until(lambda: any(n.kind is NoteKind.ALARM for n in sink.notes))
            await service.reset_alarm(IRIS)
            assert await until(lambda: any(n.kind is NoteKind.ALARM_CLEARED for n in sink.notes))
            states.close()
        control = [n for n in sink.notes if n.kind is NoteKind.CONTROL]
        assert [(n.facts["reason"], n.facts["by"], n.facts["previous"]) for n in control][:2] == [
            ("acquired", "ann", None),
            ("taken-over", "iris", "ann"),
        ]
        alarm = next(n for n in sink.notes if n.kind is NoteKind.ALARM)
        assert alarm.facts["number"] == 2000 and alarm.actor == IRIS and alarm.facts["text"]
        links = [n.facts["status"] for n in sink.notes if n.kind is NoteKind.LINK]
        assert links[0] == "connected" and links.count("connected") == 1

    run(main())
