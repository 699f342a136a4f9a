"""The queue run against a real service on the virtual controller (`QueueKeeper`), on the
test's `FakeClock`: only the queue gives the lease, a claim loads and runs the queued
text, a turn ends on time with a STOP, attended mode holds a run for *Arm ready*, STOP
works for everyone, the stored queue comes back."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest

from melfa.service import Refused, RobotService
from melfa.service.errors import Cancelled, LeaseRequired
from melfa.service.queue import QueueSettings, Step
from melfa.service.queue_keeper import QueueChanged, QueueKeeper
from melfa.vocab.queue import QueueStep, RunDropped
from melfa.vocab.refusals import Refusal
from tests.plans import project
from tests.service.helpers import (
    ANN,
    BOB,
    IRIS,
    RecordingController,
    clock,
    make_service,
    run,
    until,
)

POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
LONG = "SERVO ON\nMOV P1\nDLY 100\nEND\n"
SHORT = "SERVO ON\nMOV P1\nEND\n"
SETTINGS = QueueSettings(claim_s=10, turn_s=30, warn_s=5, grace_s=20, overhead_s=5)


class Memory:
    """Storage in a dict (the store's `QueueDocs` has its own test through the web)."""

    def __init__(self) -> None:
        self.docs: dict[str, Any] = {}

    def load(self, target: str) -> dict[str, Any] | None:
        return self.docs.get(target)

    def save(self, target: str, doc: dict[str, Any]) -> None:
        self.docs[target] = doc


def keeper_for(service: RobotService, storage: Memory | None = None) -> tuple[QueueKeeper, list]:  # type: ignore[type-arg]
    audited: list[Step] = []
    keeper = QueueKeeper(
        "lab",
        service,
        SETTINGS,
        clock=clock(),
        storage=storage,
        audit=lambda target, step: audited.append(step),
    )
    return keeper, audited


def join(keeper: QueueKeeper, actor: Any, program: str = SHORT) -> None:
    plan = project(program, POINTS)
    keeper.service.policy.gate_passed(plan, cycle_s=4.0)
    keeper.join(actor, plan, program, POINTS)


def test_only_simulated_text_enters_and_only_the_queue_gives_the_lease() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller, require_simulation=True)
        async with service:
            keeper, audited = keeper_for(service)
            await keeper.start()
            for actor in (ANN, BOB):
                service.connect(actor)
            plan = project(SHORT, POINTS)
            with pytest.raises(Refused) as refused:
                keeper.join(ANN, plan, SHORT, POINTS)
            assert refused.value.reason is Refusal.SIMULATION_REQUIRED
            assert not keeper.queue.active
            join(keeper, ANN)
            join(keeper, BOB)
            changed = project("SERVO ON\nMOV P1\nMOV P1\nEND\n", POINTS)
            with pytest.raises(Refused):  # an update must pass again
                keeper.join(ANN, changed, "x", POINTS)
            assert keeper.queue.entries[0].program == SHORT
            # While the queue is active nobody takes the free arm, from any door of the service
            with pytest.raises(LeaseRequired) as taken:
                service.acquire_lease(BOB)
            assert taken.value.reason is Refusal.QUEUE_ACTIVE
            with pytest.raises(Refused) as moved:
                await service.servo(BOB, True)
            assert moved.value.reason is Refusal.QUEUE_ACTIVE
            assert service.lease_holder is None
            assert keeper.queue.entries[0].offered_until is not None
            keeper.claim(ANN)  # the head claims: the lease is hers, her text loads and runs
            assert service.lease_holder is not None and service.lease_holder.user == "ann"
            assert await until(lambda: any(";RUN" in c for c in controller.commands()), 20)
            with pytest.raises(Refused):
                await service.servo(BOB, True)
            await service.stop(BOB)  # STOP always works for everyone
            kinds = [s.kind for s in audited]
            assert kinds[:4] == [
                QueueStep.JOINED,
                QueueStep.OFFERED,
                QueueStep.JOINED,
                QueueStep.CLAIMED,
            ]
            await keeper.close()

    run(main())


def test_a_turn_ends_on_time_stops_the_program_and_hands_over() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            keeper, audited = keeper_for(service)
            await keeper.start()
            events = service.subscribe(QueueChanged)
            for actor in (ANN, BOB):
                service.connect(actor)
            join(keeper, ANN, LONG)
            join(keeper, BOB)
            started = clock().now()
            keeper.claim(ANN)
            assert await until(lambda: bool(service.state.program_running), 20)
            assert await until(lambda: keeper.queue.turn is None, 40)
            ended = clock().now() - started
            assert 30.0 <= ended <= 30.0 + 1.0  # on time: the keeper's tick is 0.5 s
            kinds = [s.kind for s in audited]
            assert QueueStep.WARNED in kinds and QueueStep.STOPPED in kinds
            assert await until(lambda: any(c.endswith(";STOP") for c in controller.commands()))
            assert service.lease_holder is None  # the lease went back with the turn
            assert keeper.queue.entries[0].user == "bob"
            assert keeper.queue.entries[0].offered_until is not None
            seen: list[QueueChanged] = []
            while (event := events.get_nowait()) is not None:
                assert isinstance(event, QueueChanged)
                seen.append(event)
            assert seen and seen[-1].view.entries[0].user == "bob"
            await keeper.close()

    run(main())


def test_attended_mode_holds_each_run_for_arm_ready() -> None:
    controller = RecordingController()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            keeper, audited = keeper_for(service)
            await keeper.start()
            service.connect(ANN)
            keeper.set_attended(True, IRIS)
            join(keeper, ANN)
            keeper.claim(ANN)
            assert await until(
                lambda: keeper.view().turn is not None and keeper.view().turn.run_waiting, 20
            )  # type: ignore[union-attr]
            await clock().sleep(5)
            assert not any(";RUN" in c for c in controller.commands())
            keeper.arm_ready(IRIS)
            assert await until(lambda: any(";RUN" in c for c in controller.commands()), 20)
            kinds = [s.kind for s in audited]
            assert QueueStep.RUN_WAITING in kinds and QueueStep.ARM_READY in kinds
            # A second run waits again; STOP drops it
            runs = sum(";RUN" in c for c in controller.commands())
            waiting = asyncio.ensure_future(service.run(ANN))
            assert await until(lambda: keeper.view().turn.run_waiting, 5)  # type: ignore[union-attr]
            await service.stop(ANN)
            with pytest.raises(Cancelled) as dropped:
                await waiting
            assert str(dropped.value) == RunDropped.STOPPED.words  # the student's words
            assert sum(";RUN" in c for c in controller.commands()) == runs
            await keeper.close()

    run(main())


def test_a_restart_keeps_the_queue() -> None:
    controller = RecordingController()
    storage = Memory()

    async def main() -> None:
        service, _ = make_service(controller)
        async with service:
            keeper, _ = keeper_for(service, storage)
            await keeper.start()
            for actor in (ANN, BOB):
                service.connect(actor)
            join(keeper, ANN)
            join(keeper, BOB)
            keeper.move("bob", 1, IRIS)
            await keeper.close()
        service, _ = make_service(controller)
        async with service:
            keeper, audited = keeper_for(service, storage)
            await keeper.start()
            assert [e.user for e in keeper.queue.entries] == ["bob", "ann"]
            assert audited[0].kind is QueueStep.RESTORED
            with pytest.raises(LeaseRequired):
                service.acquire_lease(ANN)
            await keeper.close()

    run(main())


def test_a_queued_student_is_told_at_once_when_the_cell_cancels_their_pass() -> None:
    """An instructor edits the lab's cell: each queued text that passed only in the old one
    is marked at once (``gate``: cell-changed; a step to its student), not refused only at
    the claim; a new pass in the cell as it is clears it. The mark is stored: a restart
    neither loses nor repeats it."""
    controller = RecordingController()
    storage = Memory()
    cell = ["a"]

    async def main() -> None:
        service, _ = make_service(controller, require_simulation=True)
        assert service.policy.gate is not None
        service.policy.gate.cell = lambda: cell[0]
        async with service:
            keeper, audited = keeper_for(service, storage)
            await keeper.start()
            for actor in (ANN, BOB):
                service.connect(actor)
            texts = {"ann": SHORT, "bob": LONG}
            for actor in (ANN, BOB):
                plan = project(texts[actor.user], POINTS)
                service.policy.gate_passed(plan, 4.0, cell[0])
                keeper.join(actor, plan, texts[actor.user], POINTS)
            assert [e.gate for e in keeper.view().entries] == [None, None]

            cell[0] = "b"  # the instructor edited the cell
            keeper.gate_changed()
            assert await until(lambda: keeper.view().entries[1].gate is not None, 2)
            assert [e.gate for e in keeper.view().entries] == [Refusal.CELL_CHANGED] * 2
            again = [s.user for s in audited if s.kind is QueueStep.PREFLIGHT_AGAIN]
            assert again == ["ann", "bob"]
            assert storage.docs["lab"]["entries"][1]["gate"] == "cell-changed"

            service.policy.gate_passed(project(LONG, POINTS), 4.2, "b")  # bob passes again
            keeper.gate_changed()
            assert await until(lambda: keeper.view().entries[1].gate is None, 2)
            assert keeper.view().entries[0].gate is Refusal.CELL_CHANGED
            assert [s.user for s in audited if s.kind is QueueStep.PREFLIGHT_OK] == ["bob"]
            await keeper.close()
        service, _ = make_service(controller, require_simulation=True)
        assert service.policy.gate is not None
        service.policy.gate.cell = lambda: cell[0]
        service.policy.gate.passed(project(LONG, POINTS), 4.2, "b")  # what the store kept
        service.policy.gate.passed(project(SHORT, POINTS), 4.0, "a")
        async with service:
            keeper, audited = keeper_for(service, storage)
            await keeper.start()
            assert [e.gate for e in keeper.view().entries] == [Refusal.CELL_CHANGED, None]
            assert audited[0].kind is QueueStep.RESTORED
            told = {QueueStep.PREFLIGHT_AGAIN, QueueStep.PREFLIGHT_OK}
            assert not [s for s in audited if s.kind in told]  # nothing told twice
            await keeper.close()

    run(main())
