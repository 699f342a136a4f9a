"""`QueueKeeper`: the queue of one shared robot (`melfa.service.queue.TurnQueue`) run
against its service, on the service's event loop.

It is the queue's only door to the robot: it gives the lease to the student whose turn
began and takes it back at the end (`RobotService.grant_lease` / `revoke_lease`), while
the queue is active the lease refuses a free take at every door
(`melfa.service.lease.Lease.queued`), it says no to new work after a turn's time is up and
holds runs for the supervisor in attended mode (`melfa.service.policy.Turns`), STOPs a
program still running when a turn ends (`TurnEnd.STOP`), loads and runs the queued text
on a claim. Every transition is audited (``audit``), stored whole (``storage``: a restart
keeps the queue) and published as a `QueueChanged` event that every client gets.

Time is the injected `Clock`'s (the wall clock in a server, so stored deadlines keep their
meaning across a restart; a test's `FakeClock` elsewhere); the keeper's task wakes at the
queue's next deadline, at least every `TICK_S`, and at once when something is asked.
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

from melfa.lang.plan import UploadPlan, plan_upload
from melfa.service.clock import Clock
from melfa.service.errors import Cancelled, Refused
from melfa.service.events import Actor, Event, LeaseChanged, Role
from melfa.service.queue import Entry, QueueError, QueueSettings, Step, TurnQueue
from melfa.service.service import RobotService
from melfa.service.servo import ServoPolicy
from melfa.vocab.commands import Command
from melfa.vocab.queue import EntryState, QueueStep, RunDropped, TurnEnd
from melfa.vocab.refusals import Refusal

TICK_S = 0.5
"""While the queue is active: how often presence, the lease and a finishing program are
looked at, at the least."""
QUEUE_ACTOR = Actor("melfa-queue", Role.INSTRUCTOR, "queue")
"""The queue acting on its own (a STOP at a turn's end)."""
_log = logging.getLogger("melfa.service.queue")


class QueueStorage(Protocol):
    def load(self, target: str) -> dict[str, Any] | None: ...

    def save(self, target: str, doc: dict[str, Any]) -> object: ...


# ---------------------------------------------------------------------- what clients see


@dataclass(frozen=True)
class EntryView:
    user: str
    position: int
    state: EntryState
    estimate: dt.datetime
    """When their turn should start (pre-flight cycle times and the turn length)."""
    cycle_s: float | None
    stale: bool
    away: bool
    missed: int
    offer_ends: dt.datetime | None
    gate: Refusal | None
    """What the instructor's gate would say to the queued text now (None: it would load)."""


@dataclass(frozen=True)
class TurnView:
    user: str
    started: dt.datetime
    ends: dt.datetime
    warned: bool
    ending: bool
    away: bool
    held: bool
    """An instructor holds the arm; the turn's time left is kept."""
    left_s: float
    ready: bool
    run_waiting: bool
    """Attended mode: a run waits for *Arm ready*."""


@dataclass(frozen=True)
class QueueView:
    target: str
    now: dt.datetime
    active: bool
    paused: bool
    attended: bool
    turn: TurnView | None
    entries: tuple[EntryView, ...]
    claim_s: float
    turn_s: float
    at_turn_end: TurnEnd


@dataclass(frozen=True, kw_only=True)
class QueueChanged(Event):
    """The queue of a shared robot changed: what happened (``steps``) and all of it now."""

    NAME: ClassVar[str] = "queue"
    target: str
    steps: tuple[Step, ...]
    view: QueueView


def _time(t: float) -> dt.datetime:
    return dt.datetime.fromtimestamp(t, dt.UTC)


# ---------------------------------------------------------------------- the keeper


class QueueKeeper:
    """The queue of ``target`` (its `RobotService`), see the module doc."""

    def __init__(
        self,
        target: str,
        service: RobotService,
        settings: QueueSettings | None = None,
        *,
        clock: Clock,
        storage: QueueStorage | None = None,
        audit: Callable[[str, Step], None] | None = None,
        present: Callable[[str], bool] | None = None,
    ) -> None:
        """``present(user)``: the user has a connection open (the web counts every socket
        of theirs, lab or private simulator); by default their connections to ``service``."""
        self.target = target
        self.service = service
        self.settings = settings or QueueSettings()
        self.clock = clock
        self.queue = TurnQueue(self.settings)
        self._storage = storage
        self._audit = audit
        self._present = present or (lambda user: service.connections(user) > 0)
        self._wake = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._lease_task: asyncio.Task[None] | None = None
        self._waiting: tuple[str, asyncio.Future[None]] | None = None
        self._work: set[asyncio.Task[Any]] = set()

    # ------------------------------------------------------------------ life

    async def start(self) -> QueueKeeper:
        """Read the stored queue, take the lease's door, start the clock's task."""
        steps: list[Step] = []
        if self._storage is not None:
            doc = await asyncio.to_thread(self._storage.load, self.target)
            if doc is not None:
                self.queue = TurnQueue.from_doc(doc, self.settings)
                if self.queue.active or self.queue.paused:
                    steps.append(Step(QueueStep.RESTORED))
        self.service.policy.turns = self
        self._apply(steps)
        self._task = asyncio.create_task(self._drive(), name=f"melfa-queue-{self.target}")
        self._lease_task = asyncio.create_task(self._watch_lease(), name="melfa-queue-lease")
        return self

    async def close(self) -> None:
        for task in (self._task, self._lease_task, *self._work):
            if task is not None:
                task.cancel()
                with contextlib.suppress(BaseException):
                    await task
        self._drop_waiting(RunDropped.CLOSING)
        if self.service.policy.turns is self:
            self.service.policy.turns = None
        self.service.policy.lease.queued = False

    # ------------------------------------------------------------------ what clients see

    def view(self) -> QueueView:
        now = self.clock.now()
        queue = self.queue
        starts = queue.estimates(now)
        entries = tuple(
            EntryView(
                user=e.user,
                position=i + 1,
                state=e.state,
                estimate=_time(starts[i]),
                cycle_s=e.cycle_s,
                stale=e.stale,
                away=e.away_since is not None,
                missed=e.missed,
                offer_ends=None if e.offered_until is None else _time(e.offered_until),
                gate=e.gate,
            )
            for i, e in enumerate(queue.entries)
        )
        turn = queue.turn
        turn_view = None
        if turn is not None:
            left = turn.left_s if turn.left_s is not None else max(0.0, turn.ends - now)
            turn_view = TurnView(
                user=turn.user,
                started=_time(turn.started),
                ends=_time(turn.ends if turn.left_s is None else now + turn.left_s),
                warned=turn.warned,
                ending=turn.ending,
                away=turn.away_since is not None,
                held=turn.left_s is not None,
                left_s=left,
                ready=turn.ready,
                run_waiting=self._waiting is not None,
            )
        s = self.settings
        return QueueView(
            self.target,
            _time(now),
            queue.active,
            queue.paused,
            queue.attended,
            turn_view,
            entries,
            s.claim_s,
            s.turn_s,
            s.at_turn_end,
        )

    # ------------------------------------------------------------------ students

    def join(
        self,
        actor: Actor,
        plan: UploadPlan,
        program: str,
        points: str,
        workspace_id: int | None = None,
    ) -> None:
        """Enter the queue (or replace the queued text) from where the policy lets one
        drive (`Policy.from_where`) with a text it lets in (`Policy.may_queue`: checked, and
        pre-flight passed when the gate is on); a refusal is audited (`RobotService.decide`),
        the join itself is the queue's step."""

        def join() -> None:
            if actor.role is Role.OBSERVER:
                raise Refused(Refusal.OBSERVER, user=actor.user)
            policy = self.service.policy
            policy.from_where(actor)
            policy.may_queue(plan)
            entry = Entry(
                user=actor.user,
                role=actor.role.value,
                program=program,
                points=points,
                program_digest=plan.program_digest,
                points_digest=plan.points_digest,
                cycle_s=policy.cycle_time(plan),
                joined=self.clock.now(),
                workspace_id=workspace_id,
            )
            self._do(lambda q: q.join(entry))

        self.service.decide(actor, Command.JOIN_QUEUE, join)

    def leave(self, actor: Actor) -> None:
        """Leave the queue; a refusal is audited as a join's is."""
        self._decide(actor, Command.LEAVE_QUEUE, lambda q: q.leave(actor.user))

    def claim(self, actor: Actor, *, start: bool = True) -> None:
        """The offered student takes the arm: the lease is theirs; with ``start`` their
        queued text is loaded and run (in attended mode the run waits for *Arm ready*). A
        refusal (not offered to them, outside the lab's networks) is audited."""

        def claim(queue: TurnQueue) -> list[Step]:
            self.service.policy.from_where(actor)  # the lab's networks, before the lease moves
            return queue.claim(actor.user, self.clock.now())

        self._decide(actor, Command.CLAIM_TURN, claim)
        turn = self.queue.turn
        if start and turn is not None and turn.entry is not None:
            self._spawn(self._load_and_run(actor, turn.entry))

    def finish(self, actor: Actor) -> None:
        """The student at the arm gives it back before the end of the turn; a refusal is
        audited."""
        self._decide(actor, Command.GIVE_BACK, lambda q: q.finish(actor.user))

    def workspace_saved(self, workspace_id: int, program: str, points: str) -> None:
        self._do(lambda q: q.workspace_saved(workspace_id, program, points))

    def gate_changed(self) -> None:
        """What the instructor's gate says may have changed (the lab's cell was edited, a
        pre-flight passed): the queued texts are asked again at once, and a student whose
        text would now be refused is told before their turn comes (every transition asks
        too, so a gate switched on the desk is seen within `TICK_S`)."""
        self._wake.set()

    # ------------------------------------------------------------------ the instructor

    def pause(self, by: Actor) -> None:
        self._do(lambda q: q.pause(by.user), by)

    def resume(self, by: Actor) -> None:
        if self.service.policy.lease.holds(by):
            self.service.release_lease(by)
        self._do(lambda q: q.resume(by.user, self.clock.now()), by)

    def move(self, user: str, position: int, by: Actor) -> None:
        self._do(lambda q: q.move(user, position, by.user), by)

    def skip(self, user: str, by: Actor) -> None:
        self._do(lambda q: q.skip(user, by.user, self.clock.now()), by)

    def extend(self, seconds: float, by: Actor) -> None:
        self._do(lambda q: q.extend(seconds, by.user), by)

    def take(self, by: Actor) -> None:
        """Take the arm at once: the queue pauses, a turn keeps its time left."""
        self._do(lambda q: q.take(by.user, self.clock.now()), by)
        self.service.take_over(by)

    def set_attended(self, on: bool, by: Actor) -> None:
        self._do(lambda q: q.set_attended(on, by.user), by)
        if not on:
            self._release_waiting()

    def arm_ready(self, by: Actor) -> None:
        """The supervisor looked at the cell: the waiting run goes (or the next one will)."""
        turn = self.queue.turn
        if turn is None:
            return
        if not self._release_waiting():
            turn.ready = True
        self._apply([Step(QueueStep.ARM_READY, turn.user, by.user)])

    # ------------------------------------------------------------------ the policy's hooks

    def refusal(self, actor: Actor, command: Command) -> Refused | None:
        turn = self.queue.turn
        if turn is not None and turn.ending and turn.user == actor.user and command.moves:
            return Refused(Refusal.TURN_OVER)
        return None

    def attend(self, actor: Actor, command: Command) -> asyncio.Future[None] | None:
        turn = self.queue.turn
        if not self.queue.attended or command is not Command.RUN or turn is None:
            return None
        if turn.user != actor.user:
            return None
        if turn.ready:
            turn.ready = False
            return None
        self._drop_waiting(RunDropped.REPLACED)
        future: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self._waiting = (actor.user, future)
        self._apply([Step(QueueStep.RUN_WAITING, actor.user)])
        return future

    def stopped(self) -> None:
        if self._drop_waiting(RunDropped.STOPPED):
            self._apply([])

    # ------------------------------------------------------------------ inside

    def _decide(
        self, actor: Actor, command: Command, change: Callable[[TurnQueue], list[Step]]
    ) -> None:
        """A student's own queue request: its refusal audited in its own words
        (`RobotService.decide`), the change itself the queue's step."""
        self.service.decide(actor, command, lambda: self._do(change, actor))

    def _do(self, change: Callable[[TurnQueue], list[Step]], by: Actor | None = None) -> None:
        try:
            steps = change(self.queue)
        except QueueError as exc:
            raise Refused(exc.reason, user=exc.user or (by.user if by else "")) from None
        self._apply(steps, by)

    def _apply(self, steps: list[Step], by: Actor | None = None, *, quiet: bool = False) -> None:
        """The effects of ``steps`` on the robot and whatever else is then due (an end
        makes an offer), each audited; then the store and the message to every client
        (``quiet``: only when something happened)."""
        done: list[Step] = []
        pending = list(steps)
        for _ in range(8):
            for step in pending:
                self._effect(step, by)
                if self._audit is not None:
                    with contextlib.suppress(Exception):
                        self._audit(self.target, step)
            done += pending
            pending = self._reconcile()
            pending += self.queue.tick(self.clock.now(), self._present, self._running())
            pending += self.queue.gate_checked(self._gate)
            if not pending:
                break
        self.service.policy.lease.queued = self.queue.active
        if quiet and not done:
            return
        if self._storage is not None:
            try:
                self._storage.save(self.target, self.queue.to_doc())
            except Exception:
                _log.exception("the queue of %s could not be stored", self.target)
        self.service.publish(QueueChanged(target=self.target, steps=tuple(done), view=self.view()))
        self._wake.set()

    def _reconcile(self) -> list[Step]:
        """The queue against the lease: someone who held the arm when the queue began gets
        a turn; a student at the arm who gave the lease back (or let it expire) while
        connected has finished."""
        queue = self.queue
        lease = self.service.policy.lease
        holder = lease.holder
        now = self.clock.now()
        if queue.active and queue.turn is None and not queue.paused and holder is not None:
            if holder.role is not Role.OBSERVER:
                queue.adopt(holder.user, holder.role.value, now)
            return []
        turn = queue.turn
        if (
            turn is not None
            and turn.left_s is None
            and holder is None
            and turn.away_since is None
            and self._present(turn.user)
        ):
            return queue.finish(turn.user)
        return []

    def _effect(self, step: Step, by: Actor | None) -> None:
        kind = step.kind
        user = step.user
        if kind is QueueStep.CLAIMED and user is not None:
            self.service.grant_lease(by if by is not None else self._actor(user))
        elif kind in (QueueStep.BACK, QueueStep.RESUMED):
            turn = self.queue.turn
            if turn is not None and turn.left_s is None and (user is None or user == turn.user):
                self.service.grant_lease(self._actor(turn.user, turn.role))
        elif user is not None and kind in _TURN_ENDS and not self.queue.at_arm(user):
            if self._waiting is not None and self._waiting[0] == user:
                self._drop_waiting(RunDropped.TURN_ENDED)
            if step.stop:
                self._spawn(self.service.stop(QUEUE_ACTOR))
            self.service.revoke_lease(self._actor(user))

    def _gate(self, entry: Entry) -> Refusal | None:
        return self.service.policy.queued_refusal(entry.program_digest, entry.points_digest)

    def _actor(self, user: str, role: str | None = None) -> Actor:
        return Actor(user, Role(role) if role else Role.STUDENT, "queue")

    def _running(self) -> bool:
        state = self.service.state
        return bool(state.program_running or state.running)

    def _release_waiting(self) -> bool:
        if self._waiting is None:
            return False
        _, future = self._waiting
        self._waiting = None
        if not future.done():
            future.set_result(None)
        return True

    def _drop_waiting(self, why: RunDropped) -> bool:
        if self._waiting is None:
            return False
        _, future = self._waiting
        self._waiting = None
        if not future.done():
            future.set_exception(Cancelled(why.words))
        return True

    def _spawn(self, work: Any) -> None:
        task = asyncio.ensure_future(work)
        self._work.add(task)
        task.add_done_callback(self._work.discard)
        task.add_done_callback(_quiet)

    async def _load_and_run(self, actor: Actor, entry: Entry) -> None:
        """The claimed turn's text onto the arm: load, then run (each audited and
        reported by the service like any command of the student's)."""
        plan = await asyncio.to_thread(plan_upload, entry.program, entry.points)
        await self.service.load_project(actor, plan)
        await self.service.run(actor, servo=ServoPolicy.TURN_ON)

    async def _drive(self) -> None:
        """Tick at the next deadline, at least every `TICK_S` while active, and at once
        when woken."""
        while True:
            self._apply([], quiet=True)
            self._wake.clear()
            now = self.clock.now()
            deadline = self.queue.next_deadline()
            waits: set[asyncio.Future[Any]] = {asyncio.ensure_future(self._wake.wait())}
            if self.queue.active:
                delay = TICK_S if deadline is None else min(TICK_S, max(0.0, deadline - now))
                waits.add(asyncio.ensure_future(self.clock.sleep(delay)))
            try:
                await asyncio.wait(waits, return_when=asyncio.FIRST_COMPLETED)
            finally:
                for waiting in waits:
                    waiting.cancel()

    async def _watch_lease(self) -> None:
        """A change of the lease (given back, expired, its holder gone) wakes the keeper."""
        sub = self.service.subscribe(LeaseChanged)
        try:
            async for _ in sub:
                self._wake.set()
        finally:
            sub.close()


_TURN_ENDS = frozenset(
    {QueueStep.ENDED, QueueStep.STOPPED, QueueStep.FINISHED, QueueStep.GONE, QueueStep.SKIPPED}
)


def _quiet(task: asyncio.Task[Any]) -> None:
    """A claim's load or run that failed was reported by the service already."""
    if not task.cancelled():
        task.exception()


__all__ = [
    "QUEUE_ACTOR",
    "TICK_S",
    "EntryView",
    "QueueChanged",
    "QueueKeeper",
    "QueueStorage",
    "QueueView",
    "TurnView",
]
