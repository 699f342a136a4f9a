"""Every run on a shared robot is recorded from the service's state stream: who ran it, the
fingerprint and step map of what was loaded, a frame per poll timed on the service's
clock (the test's `FakeClock`), the student's running line, and how it ended."""

from __future__ import annotations

import datetime as dt

from melfa.service import ServoPolicy
from melfa.service.recording import Recording
from melfa.sim import VirtualController
from melfa.vocab.runs import RunOutcome
from tests.plans import project
from tests.service.helpers import ANN, BOB, clock, make_service, run, until

PROGRAM = """' two moves and a pause, unnumbered: the student's lines are not the steps
MOV P1
DLY 0.5
MOV P2
END
"""
POINTS = """P1=(300,100,500,180,0,180)(7,0)
P2=(300,-100,400,180,0,180)(7,0)
"""
WALL = dt.datetime(2026, 11, 26, 10, tzinfo=dt.UTC)


def _record(program: str = PROGRAM, *, stop_after: float | None = None) -> list[Recording]:
    done: list[Recording] = []

    async def main() -> None:
        service, _ = make_service(VirtualController())
        service.record_runs(done.append, wall=lambda: WALL)
        async with service:
            await service.load_project(BOB, project(program, POINTS))  # bob loads, ann runs
            service.release_lease(BOB)
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert service.recorder is not None and service.recorder.active
            if stop_after is not None:
                await clock().sleep(stop_after)
                await service.stop(ANN)
            assert await until(lambda: bool(done), timeout=60)

    run(main())
    return done


def test_a_run_is_recorded_with_its_lines_fingerprint_and_end() -> None:
    (rec,) = _record()
    plan = project(PROGRAM, POINTS)
    assert rec.user == "ann"
    assert rec.started_at == WALL
    assert rec.loaded is not None and rec.loaded.user == "bob"
    assert rec.fingerprint == plan.fingerprint
    assert rec.outcome is RunOutcome.FINISHED
    assert rec.cycle_time is not None and rec.cycle_time > 0.5  # at least the DLY
    times = [f.t for f in rec.frames]
    assert times == sorted(times) and times[-1] <= rec.duration
    assert len(rec.frames) > 10
    # The running line is the student's (2, 3, 4), never the controller's step (10, 20…).
    lines = {f.line for f in rec.frames if f.line is not None}
    assert lines <= {2, 3, 4, 5} and {2, 4} & lines, lines
    # (Step 0: the controller's line once the program ended.)
    assert {f.step for f in rec.frames if f.step is not None} <= {0, 20, 30, 40, 50}
    # It moved: the pose went from P1 towards P2 (Y from +100 towards -100).
    ys = [f.pose[1] for f in rec.frames if f.pose is not None]
    assert max(ys) > 90 and min(ys) < -90
    assert rec.frames[-1].running is False


def test_a_stopped_run_says_so() -> None:
    (rec,) = _record(stop_after=0.3)
    assert rec.outcome is RunOutcome.STOPPED
    assert rec.cycle_time is None
    assert rec.duration >= 0.3


def test_nothing_is_recorded_without_a_run_and_a_delete_forgets_what_was_loaded() -> None:
    done: list[Recording] = []

    async def main() -> None:
        service, _ = make_service(VirtualController())
        recorder = service.record_runs(done.append)
        async with service:
            await service.load_project(ANN, project(PROGRAM, POINTS))
            slot = service.state.slot  # what a recording of a run would say was loaded
            assert slot is not None
            assert slot.step_lines == {10: 1, 20: 2, 30: 3, 40: 4, 50: 5}
            await clock().sleep(1.0)
            await service.delete(ANN)
            assert service.state.slot is None and not recorder.active

    run(main())
    assert done == []


def test_a_run_that_never_ends_is_cut_at_the_recorders_limit() -> None:
    done: list[Recording] = []
    looping = "*LOOP\nMOV P1\nMOV P2\nGOTO *LOOP\n"

    async def main() -> None:
        service, _ = make_service(VirtualController())
        service.record_runs(done.append, max_s=2.0)
        async with service:
            await service.load_project(ANN, project(looping, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            assert await until(lambda: bool(done), timeout=10)
            assert service.state.program_running  # the program goes on: only the record stops
            await service.stop(ANN)

    run(main())
    (rec,) = done
    assert rec.outcome is RunOutcome.TOO_LONG and rec.cycle_time is None
    assert 2.0 < rec.duration < 3.0
    assert {f.line for f in rec.frames if f.line} <= {2, 3, 4}


def test_a_lost_link_ends_the_recording() -> None:
    done: list[Recording] = []

    async def main() -> None:
        service, links = make_service(VirtualController())
        service.record_runs(done.append)
        async with service:
            await service.load_project(ANN, project(PROGRAM, POINTS))
            await service.run(ANN, servo=ServoPolicy.TURN_ON)
            await clock().sleep(0.2)
            links.opened[-1].close()  # the cable is pulled mid-run
            assert await until(lambda: bool(done), timeout=10)

    run(main())
    assert done[0].outcome is RunOutcome.LINK_LOST
