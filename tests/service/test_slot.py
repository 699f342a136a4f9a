"""Whose program is in the controller's slot: the state names who loaded it, when, its
fingerprint and workspace; a refused load leaves it alone; a run that names the program it
means is refused when the slot holds another; a run-time error names the loaded text's
line through the slot's step map."""

from __future__ import annotations

import pytest

from melfa.protocol.advice import advice_for
from melfa.service import ServoPolicy
from melfa.service.errors import Refused
from melfa.service.slot import LoadOrigin
from melfa.vocab.activity import Activity
from melfa.vocab.refusals import Refusal
from tests.plans import project
from tests.service.helpers import ANN, BOB, RecordingController, make_service, run, until

POINTS = ["P1=(300,0,400,180,0,180)(7,0)", "P2=(300,150,400,180,0,180)(7,0)"]
BOBS = "MOV P1\nMOV P2\nEND\n"
ANNS = "MOV P2\nMOV P1\nMOV P2\nEND\n"


def test_the_slot_names_who_loaded_and_a_run_may_name_what_it_means() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()  # a listener: polling at full rate
            assert service.state.slot is None  # nothing loaded since the service started
            bobs = project(BOBS, POINTS)
            await service.load_project(BOB, bobs, LoadOrigin(7, "group 3"))
            slot = service.state.slot
            assert slot is not None
            assert (slot.user, slot.fingerprint, slot.workspace_id, slot.workspace) == (
                "bob",
                bobs.fingerprint,
                7,
                "group 3",
            )
            service.release_lease(BOB)

            # ann's load is refused (an error): nothing reached the controller, bob's stays.
            broken = project("MOV P1\nMOOV P2\nEND\n", POINTS)
            with pytest.raises(Refused):
                await service.load_project(ANN, broken)
            assert service.state.slot == slot

            # ann means her own program: refused, naming whose program is there; nothing sent.
            before = controller.commands(skip_polls=True)
            with pytest.raises(Refused) as refused:
                mine = project(ANNS, POINTS).fingerprint
                await service.run(ANN, servo=ServoPolicy.TURN_ON, expect=mine)
            assert refused.value.reason is Refusal.SLOT_CHANGED
            assert "bob's program" in str(refused.value)
            assert controller.commands(skip_polls=True) == before
            assert service.state.activity is not Activity.RUNNING

            # She saw it is bob's, and runs it knowingly: it goes.
            await service.run(ANN, servo=ServoPolicy.TURN_ON, expect=slot.fingerprint)
            assert await until(lambda: service.state.activity is Activity.RUNNING)
            await service.stop(ANN)
            assert await until(lambda: not service.state.running)

            # Her own load replaces it; a delete empties it (a run naming any program: refused).
            anns = project(ANNS, POINTS)
            await service.load_project(ANN, anns)
            assert service.state.slot is not None
            assert (service.state.slot.user, service.state.slot.fingerprint) == (
                "ann",
                anns.fingerprint,
            )
            await service.delete(ANN)
            assert service.state.slot is None
            with pytest.raises(Refused) as unknown:
                await service.run(ANN, expect=anns.fingerprint)
            assert unknown.value.reason is Refusal.SLOT_UNKNOWN
            sub.close()

    run(main())


def test_a_run_time_error_names_the_loaded_texts_line() -> None:
    controller = RecordingController()
    # Numbered by the student; the controller reports the step number, not the line.
    program = "10 MOV P1\n20 MOV P2\n30 ' check the part\n40 ERROR 9100\n50 END\n"

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()
            await service.load_project(ANN, project(program, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: service.state.alarm is not None)
            alarm = service.state.alarm
            assert alarm is not None
            assert (alarm.number, alarm.step, alarm.line) == (9100, 40, 4)
            assert service.state.activity is Activity.ALARM
            sub.close()

    run(main())


def test_a_programs_own_error_is_told_as_its_own() -> None:
    advice = advice_for(9100)
    assert advice.code == "L9100"
    assert "ERROR 9100" in advice.message and "controller refused" not in advice.message
    assert advice_for(9000).code == "H9000"


def test_a_run_stopped_because_its_holders_pages_closed_is_told_once() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            sub = service.subscribe()
            service.connect(ANN)
            await service.load_project(ANN, project(ANNS, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: bool(service.state.running))
            assert service.stopped_when_left("ann") is None  # nothing to tell yet
            await service.disconnect(ANN)  # her last page closed (a reload)
            assert await until(lambda: not service.state.running)
            assert service.lease_holder is None
            when = service.stopped_when_left("ann")
            assert when is not None  # she comes back: told why
            assert service.stopped_when_left("ann") is None  # once
            sub.close()

    run(main())
