"""`RobotService`: the one owner of a robot connection (the thesis's "Execute Node").

Every frontend (web IDE, desktop, ROS, the thesis's string messages) goes through one
service. It runs the sync `melfa.robot.Robot` in one worker thread (`melfa.service.worker`)
and is the only writer to the link. Callers ``await`` typed commands and get the result, or
the failure as the exception: `melfa.robot.ControllerError` (number + message) for a
controller refusal, `melfa.link.LinkError` for the line, the service's own errors
(`LeaseRequired`, `JogBusy`, `Cancelled`, `ServiceClosed`) for its rules.

Order of work: **stop** (never queued: it overtakes everything, see `stop`), then **jog**,
then **user commands**, then **polling** when nothing else waits.

>>> import asyncio
>>> from melfa.service import Actor, Role
>>> async def demo() -> tuple[float, ...] | None:
...     async with RobotService.from_spec("sim") as service:
...         ann = Actor("ann", Role.STUDENT, "s1")
...         await service.servo(ann, True)
...         return await service.read_joints(ann)
>>> asyncio.run(demo())
(0.0, 0.0, 90.0, 0.0, 90.0, 0.0)
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import dataclasses
import datetime as dt
from collections.abc import Callable
from typing import Any

from melfa.lang.plan import UploadPlan
from melfa.link import Link, LinkSettings, parse_robot
from melfa.robot import Robot, RobotSettings
from melfa.robot.opener import open_robot_link
from melfa.robot.profile import profile_settings
from melfa.service.audit import AuditSink, MemoryAuditSink
from melfa.service.bus import EventBus, Subscription
from melfa.service.clock import Clock
from melfa.service.commands import RobotCommands
from melfa.service.config import ServiceConfig, WhenHolderLeaves
from melfa.service.dispatch import Dispatcher, DoneHook, describe_error
from melfa.service.errors import Cancelled, ServiceClosed
from melfa.service.events import (
    SERVICE_ACTOR,
    Actor,
    Event,
    LeaseChanged,
    LinkStatus,
    LinkStatusChanged,
    StateSnapshot,
)
from melfa.service.jogging import JogSession
from melfa.service.lab_network import LabNetwork
from melfa.service.lease import Lease, LeaseChange, LeaseInfo
from melfa.service.lifecycle import Life, Lifecycle
from melfa.service.notes import LinkNotes, alarm_notes, control_note
from melfa.service.policy import Gate, Policy
from melfa.service.polling import JointsRead, StateRead
from melfa.service.posts import (
    BusyChanged,
    JogRefused,
    LinkChanged,
    MotionSent,
    Polled,
    Post,
    Publish,
    ServoTurnedOn,
)
from melfa.service.recording import RunRecorder, Sink
from melfa.service.snapshots import Change, Snapshots
from melfa.service.worker import Worker
from melfa.vocab.commands import Command
from melfa.vocab.jog import JogEnd
from melfa.vocab.lease import LeaseReason

LAST_CONNECTION = "last connection closed"
"""The audit detail of the stop sent when an owner's last connection closes."""
HOUSEKEEPING_S = 0.05
"""How often the loop checks jog heartbeats and lease idle time."""


class RobotService(RobotCommands):
    """The asyncio face of one robot connection. Create it, ``await start()`` (or use
    ``async with``), call commands with an `Actor`, ``subscribe()`` to state and events,
    ``await close()``."""

    def __init__(
        self,
        link_factory: Callable[[], Link],
        *,
        config: ServiceConfig | None = None,
        robot_settings: RobotSettings | None = None,
        audit: AuditSink | None = None,
        clock: Clock | Callable[[], float] | None = None,
        gated: bool = True,
    ) -> None:
        """``gated``: the policy has the instructor's gate (`melfa.service.policy.Gate`,
        on when `ServiceConfig.require_simulation`) and the lab's networks
        (`ServiceConfig.lab_networks`); a private simulator has neither."""
        self.config = config or ServiceConfig()
        self.robot_settings = robot_settings or RobotSettings()
        if not isinstance(clock, Clock):
            clock = Clock() if clock is None else Clock(now=clock)
        self.clock = clock
        self._link_factory = link_factory
        self._life = Life()
        self._bus = EventBus(on_change=self._listeners_changed)
        self._interest_until = float("-inf")
        self._lease = Lease(
            idle_timeout=self.config.lease_idle_timeout_s,
            auto=self.config.auto_lease,
            clock=self.clock.now,
        )
        self.policy = Policy(
            self._lease,
            Gate(self.config.require_simulation) if gated else None,
            LabNetwork(self.config.lab_networks) if gated else None,
            slot=lambda: self._snapshots.latest.slot,
        )
        """Whether a command may be queued: every command passes `Policy.admit`."""
        self._dispatch = Dispatcher(
            life=self._life,
            policy=self.policy,
            bus=self._bus,
            audit=audit if audit is not None else MemoryAuditSink(),
            post=self._post,
            lease_changed=self._lease_changed,
            jogging=lambda: self._jog.active,
        )
        self._snapshots = Snapshots(self._bus, self._lease, lambda: self._jog.label())
        self._link_notes = LinkNotes()
        self._jog = JogSession(
            config=self.config,
            clock=self.clock,
            life=self._life,
            lease=self._lease,
            bus=self._bus,
            dispatch=self._dispatch,
            snapshots=self._snapshots,
            post=self._post,
        )
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop_pool = concurrent.futures.ThreadPoolExecutor(1, "melfa-stop")
        self._housekeeping: asyncio.Task[None] | None = None
        self._closed_event: asyncio.Event | None = None
        self._stopped_when_left: dict[str, dt.datetime] = {}
        """Users whose run or move was stopped because their last connection closed, and
        when: told once when they come back (`stopped_when_left`)."""
        self.recorder: RunRecorder | None = None
        """Records every run (`record_runs`; the lab robot's, not a private simulator's)."""
        self._recorder_hook: DoneHook | None = None

    def record_runs(self, sink: Sink, **options: Any) -> RunRecorder:
        """Record every run of this robot from its state stream, each finished recording
        handed to ``sink`` (`melfa.service.recording`)."""
        recorder = RunRecorder(
            self.clock, sink, slot=lambda: self._snapshots.latest.slot, **options
        )
        self.recorder = recorder

        def done(actor: Actor, command: Command, plan: UploadPlan | None, ok: bool) -> None:
            recorder.command_done(actor, command, plan, ok)
            if recorder.active:
                self._listeners_changed()  # poll at the listening rate while it runs

        self._dispatch.done_hooks.append(done)
        self._recorder_hook = done
        return recorder

    def stop_recording(self) -> None:
        """End a run under way (its recording goes to the sink) and record no more."""
        recorder, self.recorder = self.recorder, None
        if recorder is not None:
            recorder.close()
        if self._recorder_hook is not None:
            self._dispatch.done_hooks.remove(self._recorder_hook)
            self._recorder_hook = None

    @classmethod
    def from_spec(
        cls,
        spec: str = "sim",
        link_settings: LinkSettings | None = None,
        *,
        trace: bool | None = None,
        trace_sink: Callable[[str], None] | None = None,
        **options: Any,
    ) -> RobotService:
        """A service for a ``--robot`` spec (``sim``, a serial device, ``tcp://host:port``,
        a pyserial URL); the link is reopened from the same spec after a drop. ``sim``
        keeps one virtual controller across reconnects. A real robot gets the settings
        `melfa doctor` found for it (the robot profile); ``trace_sink`` records its bytes."""
        settings = link_settings or LinkSettings()
        if parse_robot(spec).is_sim:
            from melfa.sim import VirtualController, open_sim_link

            controller = VirtualController()
            return cls(lambda: open_sim_link(settings, controller=controller), **options)
        options.setdefault("robot_settings", profile_settings(spec))
        if trace_sink is not None:
            trace = True
        return cls(
            lambda: open_robot_link(spec, settings, trace=trace, trace_sink=trace_sink),
            **options,
        )

    @property
    def audit(self) -> AuditSink:
        """Where audit entries go (the web gives the store's)."""
        return self._dispatch.audit_sink

    @audit.setter
    def audit(self, sink: AuditSink) -> None:
        self._dispatch.audit_sink = sink

    # ================================================================== lifecycle

    async def start(self) -> RobotService:
        """Start the worker; returns once the first connection attempt has finished (the
        service keeps reconnecting in the background if it failed)."""
        self._life.move(Lifecycle.RUNNING)
        self._loop = asyncio.get_running_loop()
        self._closed_event = asyncio.Event()
        worker = Worker(
            self._open_robot,
            self.config,
            self._post,
            listeners=self._state_listeners,
            jog_view=self._jog.keeper.view,
            clock=self.clock,
        )
        self._dispatch.worker = worker
        worker.start()
        await asyncio.get_running_loop().run_in_executor(None, worker.wait_first_attempt)
        await asyncio.sleep(0)  # let the worker's status callbacks land
        self._housekeeping = asyncio.create_task(self._housekeep(), name="melfa-housekeeping")
        return self

    async def __aenter__(self) -> RobotService:
        return await self.start()

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    async def close(self) -> None:
        """Stop polling, fail queued commands, release the lease, close the link. Safe to
        call twice; afterwards every command raises `ServiceClosed`."""
        if self._life.state in (Lifecycle.CLOSING, Lifecycle.CLOSED):
            if self._closed_event is not None:
                await self._closed_event.wait()
            return
        if self._life.state is Lifecycle.NEW:
            self._life.move(Lifecycle.CLOSED)
            self._stop_pool.shutdown(wait=False)
            return
        self._life.move(Lifecycle.CLOSING)
        worker = self._dispatch.require_worker()
        if self._housekeeping is not None:
            self._housekeeping.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._housekeeping
        self._jog.end(JogEnd.SERVICE_CLOSING, SERVICE_ACTOR)
        if self.recorder is not None:
            self.recorder.close()
        worker.shutdown(ServiceClosed("the robot service closed before this command was sent"))
        self._lease_changed(self._lease.clear(LeaseReason.SERVICE_CLOSED))
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(None, worker.join, self.config.close_timeout_s)
        self._stop_pool.shutdown(wait=False)
        for _ in range(3):
            await asyncio.sleep(0)  # deliver the worker's last posts (link closed)
        self._life.move(Lifecycle.CLOSED)
        self._bus.close()
        assert self._closed_event is not None
        self._closed_event.set()

    @property
    def worker(self) -> Worker | None:
        """The thread on the link (None before `start`): tests pull its plug."""
        return self._dispatch.worker

    @property
    def closed(self) -> bool:
        return self._life.state is Lifecycle.CLOSED

    # ================================================================== state & events

    @property
    def state(self) -> StateSnapshot:
        """The latest snapshot (no round trip)."""
        return self._snapshots.latest

    @property
    def link_status(self) -> LinkStatus:
        return self._snapshots.latest.link

    def subscribe(self, *kinds: type[Event], maxlen: int | None = None) -> Subscription:
        """Events of the given types (all when none given) as an async iterator. A
        subscriber that wants `StateSnapshot`s makes the service poll as fast as the line
        allows; it always gets the newest snapshot, never a backlog."""
        self._life.check_open()
        sub = self._bus.subscribe(kinds or None, maxlen or self.config.subscriber_maxlen)
        if sub.wants_state:
            sub._put(self._snapshots.latest)
        return sub

    def want_state(self) -> StateSnapshot:
        """Note that a reader without a subscription (a REST client polling the state)
        wants fresh state: polling runs at the listening rate for
        `ServiceConfig.state_interest_s` from now. Returns the latest snapshot."""
        was_idle = self._state_listeners() == 0
        self._interest_until = self.clock.now() + self.config.state_interest_s
        if was_idle:
            self._listeners_changed()
        return self._snapshots.latest

    def _state_listeners(self) -> int:
        """Subscribers wanting snapshots, plus one while a REST reader showed interest."""
        interest = self.clock.now() < self._interest_until
        # A holder gone while the arm moves: poll to see the motion end, then free the lease.
        recording = self.recorder is not None and self.recorder.active
        return self._bus.state_listeners + interest + self._lease.orphaned + recording

    def publish(self, event: Event) -> None:
        """Put an event on the bus (adapters such as `ThesisMessages` use this)."""
        self._bus.publish(event)

    @property
    def subscribers(self) -> int:
        return self._bus.subscribers

    # ================================================================== lease

    @property
    def lease_holder(self) -> Actor | None:
        self._lease_changed(self._lease.expire())
        return self._lease.holder

    def lease_info(self) -> LeaseInfo:
        """Holder, since when, their connection state and the idle time left."""
        self._lease_changed(self._lease.expire())
        return self._lease.info()

    def acquire_lease(self, actor: Actor) -> None:
        """Take the free operator lease (`LeaseRequired` naming the holder if taken, or
        for observers; `Refused` from outside the lab's networks; each refusal audited).
        Every session of the holder's user shares it."""

        def take() -> None:
            self.policy.from_where(actor)
            self._lease_changed(self._lease.acquire(actor))

        self.decide(actor, Command.TAKE_CONTROL, take)  # a refusal is audited

    def release_lease(self, actor: Actor) -> None:
        """Give the lease back (no effect if ``actor``'s user does not hold it); ends
        their jog."""
        if self._jog.keeper.owned_by_user(actor.user):
            self._jog.end(JogEnd.LEASE_RELEASED, actor, send_stop=True)
        self._lease_changed(self._lease.release(actor))

    def take_over(self, actor: Actor) -> None:
        """An instructor takes the lease from whoever holds it (even while the arm moves
        for them); their jog ends."""
        self._life.check_open()
        change = self._lease.take_over(actor)
        if change is not None and self._jog.active:
            self._jog.end(JogEnd.TAKEN_OVER, actor, by=actor.user, send_stop=True)
        self._lease_changed(change)

    def grant_lease(self, actor: Actor) -> None:
        """The queue gives the lease to ``actor`` for their turn (from whoever held it:
        their jog ends)."""
        self._life.check_open()
        change = self._lease.grant(actor)
        if change is not None and self._jog.active:
            self._jog.end(JogEnd.LEASE_ENDED, actor, send_stop=True)
        self._lease_changed(change)

    def revoke_lease(self, actor: Actor) -> None:
        """The queue takes the lease back from ``actor`` at the end of their turn (a jog
        of theirs ends with it)."""
        self._lease_changed(self._lease.revoke(actor))

    def connections(self, user: str) -> int:
        """Open connections (sockets) of ``user`` to this robot."""
        return self._lease.connections(user)

    def connect(self, actor: Actor) -> None:
        """One connection of ``actor`` opened (an IDE tab, the desktop client, rosbridge):
        pair it with `disconnect`. A lease holder that comes back is connected again."""
        self._lease_changed(self._lease.connected(actor))

    async def disconnect(self, actor: Actor) -> bool:
        """One connection of ``actor`` closed. When it was their user's last one, their jog
        stops at once, and if they hold the lease a move or program is stopped or, with
        `WhenHolderLeaves.FINISH`, finishes while they keep the lease ("disconnected,
        robot moving"); the lease ends when the arm is still. Returns whether it was the
        user's last connection."""
        last = self._lease.connections(actor.user) <= 1
        if not last:
            self._lease.disconnected(actor, moving=False)
            return False
        # Everything up to the first await happens at once, so a cancelled caller (a
        # socket handler torn down) cannot leave the lease or the jog behind.
        jogging = self._jog.keeper.owned_by_user(actor.user)
        if jogging:
            self._jog.end(JogEnd.CLIENT_DISCONNECTED, actor, send_stop=True)
        holds = self._lease.holds(actor) and self._life.running
        finish = self.config.when_holder_leaves is WhenHolderLeaves.FINISH
        if finish:
            # Whether the arm still moves is confirmed by the next STATE poll (polling
            # runs while the lease is orphaned); without polling, the last snapshot decides.
            moving = holds and (self.config.polling or self._maybe_moving())
        else:
            moving = holds and (jogging or self._maybe_moving())
        command_id = None
        if moving and not finish:
            # STOP: queued commands fail and the stop is on its way before the lease ends,
            # so nobody else's command can slip in ahead of it.
            command_id = self._stop_begin(actor, LAST_CONNECTION)
            self._stopped_when_left[actor.user] = dt.datetime.now(dt.UTC)
            moving = False
        _, change = self._lease.disconnected(actor, moving=moving)
        self._lease_changed(change)
        if self._lease.orphaned:
            self._listeners_changed()
        if command_id is not None:
            stopping = asyncio.ensure_future(self._stop_wait(actor, LAST_CONNECTION, command_id))
            with contextlib.suppress(Exception):
                await asyncio.shield(stopping)
        return True

    def stopped_when_left(self, user: str) -> dt.datetime | None:
        """When ``user``'s run or move was stopped because their last connection closed
        (None: it was not); told once, so a client that comes back says why."""
        return self._stopped_when_left.pop(user, None)

    def _maybe_moving(self) -> bool:
        """The last snapshot shows motion or a run, a moving command is on the wire or
        queued, or one finished since the last poll (which has not seen its motion yet)."""
        worker = self._dispatch.worker
        busy = worker is not None and (
            (worker.current is not None and worker.current.moves)
            or any(job.moves for job in worker.queued())
        )
        snapshot = self._snapshots.latest
        return bool(snapshot.moving or snapshot.running or busy or self._dispatch.moved)

    # ================================================================== stop

    async def stop(self, actor: Actor) -> None:
        """Stop everything now. Allowed to everyone, lease or not.

        Stop never queues: queued commands are failed with `Cancelled`, a jog ends, and
        ``<robot>;0;STOP`` goes out from its own thread through the client's cross-thread
        stop, right behind whatever request is on the wire (at most one reply time). An
        upload in progress closes its edit with NEW, so nothing is half saved.
        """
        await self._stop_wait(actor, "", self._stop_begin(actor, ""))

    def _stop_begin(self, actor: Actor, detail: str) -> int:
        """The part of a stop that needs no wait: audit, fail queued work, end a jog."""
        if self._life.state not in (Lifecycle.RUNNING, Lifecycle.CLOSING):
            raise ServiceClosed("the robot service is closed")
        worker = self._dispatch.require_worker()
        command_id = self._dispatch.next_id()
        self._dispatch.audit(actor, command_id, Command.STOP, detail, "accepted")
        worker.cancel_queued(lambda job: True, Cancelled(f"cancelled: {actor.user} pressed stop"))
        self.policy.stopped()  # a run waiting for the supervisor is dropped too
        self._jog.end(JogEnd.STOPPED, actor, by=actor.user)
        self._dispatch.moved = False
        self._snapshots.motion_ended()
        return command_id

    async def _stop_wait(self, actor: Actor, detail: str, command_id: int) -> None:
        """``STOP`` from the stop thread, right behind whatever is on the wire."""
        worker = self._dispatch.require_worker()
        loop = asyncio.get_running_loop()
        try:
            await loop.run_in_executor(self._stop_pool, worker.stop_now)
        except BaseException as exc:
            self._dispatch.finish(actor, command_id, Command.STOP, detail, exc)
            raise
        self._dispatch.finish(actor, command_id, Command.STOP, detail, None)

    # ================================================================== internals

    def _open_robot(self) -> Robot:
        return Robot(self._link_factory(), self.robot_settings)

    async def _housekeep(self) -> None:
        while True:
            await self.clock.sleep(HOUSEKEEPING_S)
            self._jog.check_heartbeat()
            self._lease_changed(self._lease.expire())

    def _lease_changed(self, change: LeaseChange | None) -> None:
        if change is None:
            return
        if self._jog.active and change.holder is None:
            self._jog.end(
                JogEnd.LEASE_ENDED, change.actor, detail=change.reason.words(), send_stop=True
            )
        self._dispatch.note(control_note(change))
        info = self._lease.info()
        self._bus.publish(
            LeaseChanged(
                actor=change.actor,
                holder=change.holder,
                previous=change.previous,
                reason=change.reason,
                since=info.since,
                holder_state=info.state.value if info.state is not None else None,
                command=change.command,
            )
        )
        self._update()

    def _update(self, change: Change | None = None) -> None:
        self._snapshots.update(change)

    def _listeners_changed(self) -> None:
        if self._dispatch.worker is not None:
            self._dispatch.worker.wake()

    # ---------------------------------------------------------------- worker posts

    def _post(self, post: Post) -> None:
        """From the worker thread: handled on the loop (`_on_post`)."""
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        with contextlib.suppress(RuntimeError):
            loop.call_soon_threadsafe(self._on_post, post)

    def _on_post(self, post: Post) -> None:
        match post:
            case Polled(result):
                if isinstance(result, JointsRead):
                    self._dispatch.moved = False
                alarm = self._snapshots.latest.alarm
                self._snapshots.update(result.apply, state_read=isinstance(result, StateRead))
                snapshot = self._snapshots.latest
                for note in alarm_notes(alarm, snapshot.alarm, self._lease.holder):
                    self._dispatch.note(note)
                if self.recorder is not None:
                    self.recorder.polled(result, snapshot)
                # Motion keeps the holder's lease; a STATE read showing a still, idle arm
                # ends an orphaned one.
                if snapshot.moving or snapshot.running or self._jog.active:
                    self._lease_changed(self._lease.motion(True))
                elif isinstance(result, StateRead):
                    self._lease_changed(self._lease.motion(False))
            case BusyChanged(busy):
                self._update(lambda s: dataclasses.replace(s, busy=busy))
            case LinkChanged(status, detail):
                if status is not LinkStatus.CONNECTED and self._jog.active:
                    self._jog.end(JogEnd.LINK_DOWN, SERVICE_ACTOR, detail=status.value)
                self._bus.publish(LinkStatusChanged(status=status, detail=detail))
                noted = self._link_notes.changed(status)
                if noted is not None:
                    self._dispatch.note(noted)
                if self.recorder is not None:
                    self.recorder.link_changed(status)
                if status is LinkStatus.CONNECTED:
                    self._update(lambda s: dataclasses.replace(s, link=status))
                else:  # nothing is known while the link is down: no stale "running, moving"
                    self._update(
                        lambda s: dataclasses.replace(
                            s, link=status, running=None, moving=None, program_running=None
                        )
                    )
            case Publish(event):
                self._bus.publish(event)
            case ServoTurnedOn(actor, command):
                detail = f"on, before {command.label}"
                self._dispatch.audit(actor, self._dispatch.next_id(), Command.SERVO, detail, "ok")
                self._update(lambda s: dataclasses.replace(s, servo=True))
            case JogRefused(error):
                self._jog.refused(error)
            case MotionSent(motion):
                self._snapshots.motion_sent(motion)


__all__ = ["RobotService", "describe_error"]
