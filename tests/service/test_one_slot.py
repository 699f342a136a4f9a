"""What the controller's slot holds is one record (`melfa.service.slot.Slot`, the state's
``slot``): the instructor's gate decides a load or a run on it, the run recorder says what a
recorded run had loaded, and every client is shown it, so the three never disagree, at the
edges too: a program and its points loaded separately (the thesis's LOAD PROGRAM, then LOAD
POINTS) are the pair they make for all three; points loaded onto a slot whose program is not
known leave it not known for all three; a program loaded with points holds them; points onto
points are added to them, as the controller does; a program loaded without clearing the old
one is not known."""

from __future__ import annotations

import pytest

from melfa.robot import RobotSettings
from melfa.service import RobotService, ServiceConfig, ServoPolicy
from melfa.service.errors import Refused
from melfa.service.recording import Recording
from melfa.sim import VirtualController
from melfa.vocab.link import LinkStatus
from melfa.vocab.refusals import Refusal
from tests.plans import points_plan, program_plan, project
from tests.service.helpers import ANN, BOB, Links, clock, make_service, run, until

PROGRAM = "SERVO ON\nMOV P1\nMOV P2\nEND\n"
POINTS = "P1=(300,100,500,180,0,180)(7,0)\nP2=(300,-100,400,180,0,180)(7,0)\n"
OTHER_POINTS = "P1=(320,100,500,180,0,180)(7,0)\nP2=(320,-100,400,180,0,180)(7,0)\n"


async def _recorded_run(service: RobotService, done: list[Recording]) -> Recording:
    """ann runs what the slot holds; the recording once the program ended."""
    before = len(done)
    await service.run(ANN, servo=ServoPolicy.TURN_ON)
    assert await until(lambda: len(done) > before, timeout=30)
    return done[-1]


def test_a_program_then_its_points_are_the_pair_they_make_for_every_part() -> None:
    pair = project(PROGRAM, POINTS)
    done: list[Recording] = []

    async def main() -> None:
        service, _ = make_service(VirtualController(), require_simulation=True)
        service.record_runs(done.append)
        async with service:
            service.policy.gate_passed(pair)
            await service.upload_program(ANN, program_plan(PROGRAM))
            await service.upload_points(ANN, points_plan(POINTS))
            slot = service.state.slot
            assert slot is not None
            # The client is shown the pair's fingerprint: the IDE's own text matches it,
            # and a run naming it goes (the gate lets it through: the pair passed).
            assert slot.fingerprint == pair.fingerprint
            await service.run(ANN, servo=ServoPolicy.TURN_ON, expect=pair.fingerprint)
            assert await until(lambda: bool(done), timeout=30)
            rec = done[-1]
            assert rec.loaded == slot and rec.fingerprint == pair.fingerprint
            assert rec.loaded is not None and rec.loaded.program == PROGRAM

            # Other points onto the same program: a pair that did not pass; refused by the
            # gate (nothing sent), and the slot still the passed pair.
            with pytest.raises(Refused) as refused:
                await service.upload_points(ANN, points_plan(OTHER_POINTS))
            assert refused.value.reason is Refusal.SIMULATION_REQUIRED
            assert service.state.slot == slot

    run(main())


def _loaded_before_the_service() -> VirtualController:
    """A controller holding a program this service never loaded (a restart, RT ToolBox)."""
    controller = VirtualController()

    async def load() -> None:
        service, _ = make_service(controller)
        async with service:
            await service.load_project(BOB, project(PROGRAM, POINTS))

    run(load())
    return controller


def test_points_onto_a_slot_not_known_leave_it_not_known_for_every_part() -> None:
    controller = _loaded_before_the_service()
    done: list[Recording] = []

    async def main() -> None:
        service, _ = make_service(controller)  # the gate off
        service.record_runs(done.append)
        async with service:
            assert service.state.slot is None
            await service.upload_points(ANN, points_plan(OTHER_POINTS))
            assert service.state.slot is None  # its program is still not known
            with pytest.raises(Refused) as unknown:
                await service.run(ANN, expect=points_plan(OTHER_POINTS).fingerprint)
            assert unknown.value.reason is Refusal.SLOT_UNKNOWN
            rec = await _recorded_run(service, done)
            # The recording says what the state said: not known (not "no program").
            assert (rec.fingerprint, rec.loaded) == (None, None)
            assert rec.frames and all(f.line is None for f in rec.frames)

    run(main())


def test_with_the_gate_on_points_onto_a_slot_not_known_and_its_run_are_refused() -> None:
    controller = _loaded_before_the_service()

    async def main() -> None:
        service, _ = make_service(controller, require_simulation=True)
        async with service:
            service.policy.gate_passed(project(PROGRAM, POINTS))  # even its very pair
            with pytest.raises(Refused) as points:
                await service.upload_points(ANN, points_plan(POINTS))
            assert points.value.reason is Refusal.SIMULATION_REQUIRED
            with pytest.raises(Refused) as ran:
                await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert ran.value.reason is Refusal.SIMULATION_REQUIRED
            assert service.state.slot is None

    run(main())


def test_a_program_loaded_with_points_holds_them_for_every_part() -> None:
    pair = project(PROGRAM, POINTS)
    done: list[Recording] = []

    async def main() -> None:
        service, _ = make_service(VirtualController(), require_simulation=True)
        service.record_runs(done.append)
        async with service:
            service.policy.gate_passed(pair)
            await service.upload_program(ANN, pair)  # one edit: ECLR, the steps, the points
            slot = service.state.slot
            assert slot is not None and slot.fingerprint == pair.fingerprint
            rec = await _recorded_run(service, done)
            assert rec.fingerprint == slot.fingerprint

    run(main())


def test_a_failed_load_leaves_the_slot_not_known_and_the_gate_refuses_a_run() -> None:
    pair = project(PROGRAM, POINTS)

    async def main() -> None:
        service, links = make_service(VirtualController(), require_simulation=True)
        async with service:
            service.policy.gate_passed(pair)
            await service.load_project(ANN, pair)
            assert service.state.slot is not None
            links.opened[-1].close()  # the cable is pulled: the next load fails on the way
            with pytest.raises(Exception):  # noqa: B017 - whichever way the link failed
                await service.load_project(ANN, pair)
            assert service.state.slot is None
            assert await until(lambda: service.state.link is LinkStatus.CONNECTED)
            with pytest.raises(Refused) as ran:
                await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert ran.value.reason is Refusal.SIMULATION_REQUIRED

    run(main())


BRANCHING = "SERVO ON\nIF M_IN(8) = 1 THEN *FAR\nMOV P1\nEND\n*FAR\nMOV P2\nEND\n"
"""Pre-flight (input 8 off) moves to P1 only: a pass with P1 alone says nothing of P2."""
P1_ONLY = "P1=(320,100,500,180,0,180)(7,0)\n"


def test_points_onto_points_are_added_to_them_as_the_controller_does() -> None:
    first, p1_only = project(BRANCHING, POINTS), project(BRANCHING, P1_ONLY)
    both_again = project(BRANCHING, OTHER_POINTS)

    async def main() -> None:
        service, _ = make_service(VirtualController(), require_simulation=True)
        async with service:
            for plan in (first, p1_only, both_again):
                service.policy.gate_passed(plan)
            await service.load_project(ANN, first)
            # P1 alone, sent without clearing: the controller keeps the first load's P2.
            await service.upload_points(ANN, points_plan(P1_ONLY))
            slot = service.state.slot
            assert slot is not None and slot.fingerprint != p1_only.fingerprint
            assert slot.point_lines == (*p1_only.point_texts, first.point_texts[1])
            # Their run was never simulated with these positions together: refused.
            with pytest.raises(Refused) as ran:
                await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert ran.value.reason is Refusal.SIMULATION_REQUIRED
            # Points naming every position replace them all: the pair that passed.
            await service.upload_points(ANN, points_plan(OTHER_POINTS))
            slot = service.state.slot
            assert slot is not None and slot.fingerprint == both_again.fingerprint
            await service.run(ANN, servo=ServoPolicy.TURN_ON, expect=both_again.fingerprint)

    run(main())


def test_a_program_loaded_without_clearing_the_old_one_is_not_known() -> None:
    alone = program_plan("SERVO ON\nMOV P1\nEND\n")

    async def main() -> None:
        links = Links(VirtualController(), clock())
        config = ServiceConfig(require_simulation=True)
        settings = RobotSettings(clear_with_eclr=False)  # steps it does not overwrite stay
        service = RobotService(links, config=config, robot_settings=settings, clock=clock())
        async with service:
            service.policy.gate_passed(project(PROGRAM, POINTS))
            service.policy.gate_passed(alone)
            await service.load_project(ANN, project(PROGRAM, POINTS))
            await service.upload_program(ANN, alone)
            assert service.state.slot is None
            with pytest.raises(Refused) as ran:
                await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert ran.value.reason is Refusal.SIMULATION_REQUIRED

    run(main())
