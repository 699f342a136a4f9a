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
import itertools
import re
import time
from collections.abc import Callable, Sequence
from typing import Any

from melfa.lang.plan import UploadPlan
from melfa.link import Link, LinkSettings, parse_robot
from melfa.protocol import JOINT_NAMES, POSE_NAMES
from melfa.protocol.error_table import BUSY
from melfa.robot import ControllerError, JogMethod, Robot, RobotSettings, UploadReport
from melfa.robot.opener import open_robot_link
from melfa.robot.profile import profile_settings
from melfa.service.activity import Activity, Facts, Motion, MotionKind, activity_of
from melfa.service.audit import AuditSink, MemoryAuditSink
from melfa.service.bus import EventBus, Subscription
from melfa.service.config import ServiceConfig, WhenHolderLeaves
from melfa.service.errors import (
    Cancelled,
    JogBusy,
    Refused,
    ServiceClosed,
    ServiceError,
)
from melfa.service.events import (
    SERVICE_ACTOR,
    Actor,
    AuditEvent,
    CommandResult,
    Event,
    JogChanged,
    JogFrame,
    LeaseChanged,
    LinkStatus,
    LinkStatusChanged,
    StateSnapshot,
    UploadProgress,
)
from melfa.service.jog import JogKeeper, JogRequest
from melfa.service.lease import Lease, LeaseChange, LeaseInfo
from melfa.service.policy import Gate, Policy
from melfa.service.servo import ServoPolicy, ensure_servo
from melfa.service.worker import Job, Priority, Worker
from melfa.vocab.commands import Command

LAST_CONNECTION = "last connection closed"
"""The audit detail of the stop sent when an owner's last connection closes."""
HOUSEKEEPING_S = 0.05
"""How often the loop checks jog heartbeats and lease idle time."""

_POINT_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,7}")
MOVE_POSE_VARIABLE = "PMSVC"
MOVE_JOINT_VARIABLE = "JMSVC"
"""Variables `move_to` assigns for an explicit target (≤ 8 characters, L4300)."""


def describe_error(exc: BaseException) -> str:
    """One line for an audit entry or a result event; a policy refusal is the student's
    words and the fix, as every door sends them."""
    if isinstance(exc, Refused | JogBusy):  # already in the student's words
        return str(exc)
    text = str(exc) or type(exc).__name__
    return f"{type(exc).__name__}: {text}"


class RobotService:
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
        clock: Callable[[], float] = time.monotonic,
        gated: bool = True,
    ) -> None:
        """``gated``: the policy has the instructor's gate (`melfa.service.policy.Gate`,
        on when `ServiceConfig.require_simulation`); a private simulator has none."""
        self.config = config or ServiceConfig()
        self.robot_settings = robot_settings or RobotSettings()
        self.audit: AuditSink = audit if audit is not None else MemoryAuditSink()
        self._link_factory = link_factory
        self._clock = clock
        self._bus = EventBus(on_change=self._listeners_changed)
        self._interest_until = float("-inf")
        self._lease = Lease(
            idle_timeout=self.config.lease_idle_timeout_s,
            auto=self.config.auto_lease,
            clock=clock,
        )
        self.policy = Policy(self._lease, Gate(self.config.require_simulation) if gated else None)
        """Whether a command may be queued: every command passes `Policy.admit`."""
        self._jog = JogKeeper()
        self._step_busy = False
        self._motion: Motion | None = None
        """The motion the service last started (names the activity while it moves)."""
        self._restore_override: int | None = None
        """The operator's OP override while the jog ceiling holds it lower (worker only)."""
        self._jog_override: int | None = None
        self._override_target: int | None = None
        self._moved = False
        """A moving command finished and no poll has looked at the arm since."""
        """An override asked for during a jog, reached by `_ramp_override` (worker only)."""
        self._ids = itertools.count(1)
        self._seq = itertools.count(1)
        self._snapshot = StateSnapshot()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._worker: Worker | None = None
        self._stop_pool = concurrent.futures.ThreadPoolExecutor(1, "melfa-stop")
        self._housekeeping: asyncio.Task[None] | None = None
        self._state = "new"  # new → running → closing → closed
        self._closed_event: asyncio.Event | None = None

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

    # ================================================================== lifecycle

    async def start(self) -> RobotService:
        """Start the worker; returns once the first connection attempt has finished (the
        service keeps reconnecting in the background if it failed)."""
        if self._state != "new":
            raise ServiceError("the service was already started")
        self._loop = asyncio.get_running_loop()
        self._closed_event = asyncio.Event()
        self._worker = Worker(
            self._open_robot,
            self.config,
            self._post,
            listeners=self._state_listeners,
            jog_view=self._jog.view,
            clock=self._clock,
        )
        self._state = "running"
        self._worker.start()
        await self._loop.run_in_executor(None, self._worker.wait_first_attempt)
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
        if self._state in ("closing", "closed"):
            if self._closed_event is not None:
                await self._closed_event.wait()
            return
        if self._state == "new":
            self._state = "closed"
            self._stop_pool.shutdown(wait=False)
            return
        self._state = "closing"
        worker = self._require_worker()
        if self._housekeeping is not None:
            self._housekeeping.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._housekeeping
        self._end_jog("service closing", SERVICE_ACTOR)
        worker.shutdown(ServiceClosed("the robot service closed before this command was sent"))
        self._lease_changed(self._lease.clear("service closed"))
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(None, worker.join, self.config.close_timeout_s)
        self._stop_pool.shutdown(wait=False)
        for _ in range(3):
            await asyncio.sleep(0)  # deliver the worker's last posts (link closed)
        self._state = "closed"
        self._bus.close()
        assert self._closed_event is not None
        self._closed_event.set()

    @property
    def closed(self) -> bool:
        return self._state == "closed"

    # ================================================================== state & events

    @property
    def state(self) -> StateSnapshot:
        """The latest snapshot (no round trip)."""
        return self._snapshot

    @property
    def link_status(self) -> LinkStatus:
        return self._snapshot.link

    def subscribe(self, *kinds: type[Event], maxlen: int | None = None) -> Subscription:
        """Events of the given types (all when none given) as an async iterator. A
        subscriber that wants `StateSnapshot`s makes the service poll as fast as the line
        allows; it always gets the newest snapshot, never a backlog."""
        self._check_open()
        sub = self._bus.subscribe(kinds or None, maxlen or self.config.subscriber_maxlen)
        if sub.wants_state:
            sub._put(self._snapshot)
        return sub

    def want_state(self) -> StateSnapshot:
        """Note that a reader without a subscription (a REST client polling the state)
        wants fresh state: polling runs at the listening rate for
        `ServiceConfig.state_interest_s` from now. Returns the latest snapshot."""
        was_idle = self._state_listeners() == 0
        self._interest_until = self._clock() + self.config.state_interest_s
        if was_idle:
            self._listeners_changed()
        return self._snapshot

    def _state_listeners(self) -> int:
        """Subscribers wanting snapshots, plus one while a REST reader showed interest."""
        interest = self._clock() < self._interest_until
        # A holder gone while the arm moves: poll to see the motion end, then free the lease.
        return self._bus.state_listeners + interest + self._lease.orphaned

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
        """Take the free operator lease (`LeaseRequired` naming the holder if taken,
        `NotAllowed` for observers). Every session of the holder's user shares it."""
        self._check_open()
        self._lease_changed(self._lease.acquire(actor))

    def release_lease(self, actor: Actor) -> None:
        """Give the lease back (no effect if ``actor``'s user does not hold it); ends
        their jog."""
        if self._jog.owned_by_user(actor.user):
            self._end_jog("lease released", actor, send_stop=True)
        self._lease_changed(self._lease.release(actor))

    def take_over(self, actor: Actor) -> None:
        """An instructor takes the lease from whoever holds it (even while the arm moves
        for them); their jog ends."""
        self._check_open()
        change = self._lease.take_over(actor)
        if change is not None and self._jog.active:
            self._end_jog(f"taken over by {actor.user}", actor, send_stop=True)
        self._lease_changed(change)

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
        jogging = self._jog.owned_by_user(actor.user)
        if jogging:
            self._end_jog("client disconnected", actor, send_stop=True)
        holds = self._lease.holds(actor) and self._state == "running"
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

    def _maybe_moving(self) -> bool:
        """The last snapshot shows motion or a run, a moving command is on the wire or
        queued, or one finished since the last poll (which has not seen its motion yet)."""
        worker = self._worker
        busy = worker is not None and (
            (worker.current is not None and worker.current.moves)
            or any(job.moves for job in worker.queued())
        )
        return bool(self._snapshot.moving or self._snapshot.running or busy or self._moved)

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
        if self._state not in ("running", "closing"):
            raise ServiceClosed("the robot service is closed")
        worker = self._require_worker()
        command_id = next(self._ids)
        self._audit(actor, command_id, "stop", detail, "accepted")
        worker.cancel_queued(lambda job: True, Cancelled(f"cancelled: {actor.user} pressed stop"))
        self._end_jog(f"stopped by {actor.user}", actor)
        self._moved = False
        return command_id

    async def _stop_wait(self, actor: Actor, detail: str, command_id: int) -> None:
        """``STOP`` from the stop thread, right behind whatever is on the wire."""
        worker = self._require_worker()
        loop = asyncio.get_running_loop()
        try:
            await loop.run_in_executor(self._stop_pool, worker.stop_now)
        except BaseException as exc:
            self._finish(actor, command_id, "stop", detail, True, exc)
            raise
        self._finish(actor, command_id, "stop", detail, True, None)

    # ================================================================== commands

    async def load_project(self, actor: Actor, plan: UploadPlan) -> UploadReport:
        """The plan's program and points (`melfa.lang.plan.plan_upload`) into the
        controller's program in one LOAD…SAVE session; `UploadProgress` events while it
        goes. Polling pauses meanwhile."""
        return await self._upload(actor, "load_project", lambda r, p: r.load_project(plan, p), plan)

    async def upload_program(self, actor: Actor, plan: UploadPlan) -> UploadReport:
        """Replace the program (steps and positions) with the plan's."""
        return await self._upload(
            actor, "upload_program", lambda r, p: r.upload_program(plan, p), plan
        )

    async def upload_points(self, actor: Actor, plan: UploadPlan) -> UploadReport:
        """Add or replace the plan's positions, keeping the steps."""
        return await self._upload(
            actor, "upload_points", lambda r, p: r.upload_points(plan, p), plan
        )

    async def run(self, actor: Actor, *, servo: ServoPolicy | None = None) -> None:
        """Start the program (``RUN<program>;1``). ``servo``: what to do when the servo is
        off (`melfa.service.servo`; default `ServiceConfig.motion_servo`)."""
        policy = self._motion_servo(servo)
        self._motion = Motion(MotionKind.RUN)
        await self._command(actor, "run", "", lambda r: r.run(), restore=True, servo=policy)

    async def delete(self, actor: Actor) -> None:
        """Delete the program and its points."""
        await self._command(actor, "delete", "", lambda r: r.delete(), moves=False)

    async def exec(
        self, actor: Actor, statement: str, *, servo: ServoPolicy = ServoPolicy.LEAVE
    ) -> None:
        """Execute one MELFA BASIC statement now (``EXEC``). A statement may not move, so
        the servo is left alone unless ``servo`` says otherwise."""
        statement = statement.strip()
        if not statement:
            raise ValueError("nothing to execute: the statement is empty")
        self._motion = Motion(MotionKind.EXEC, statement)
        await self._command(
            actor, "exec", statement, lambda r: r.exec(statement), restore=True, servo=servo
        )

    async def hand(self, actor: Actor, open_: bool, number: int = 1) -> None:
        """Open or close hand ``number`` (1–8)."""
        if not 1 <= number <= 8:
            raise ValueError(f"hand {number} is outside 1–8")
        detail = f"{'open' if open_ else 'close'} {number}"
        await self._command(actor, "hand", detail, lambda r: r.hand(open_, number))
        hands = list(self._snapshot.hands or (None,) * 8)
        hands[number - 1] = open_
        self._update(hands=tuple(hands))

    async def hand_toggle(self, actor: Actor, number: int = 1) -> bool:
        """Open a closed hand, close an open one; returns True if it is now open. An
        unknown hand is taken as open (the thesis's rule), so the first toggle closes."""
        hands = self._snapshot.hands
        known = hands[number - 1] if 0 < number <= len(hands) else None
        open_now = known if known is not None else True
        await self.hand(actor, not open_now, number)
        return not open_now

    async def move_to(
        self,
        actor: Actor,
        target: str | Sequence[float],
        *,
        linear: bool = False,
        joints: bool = False,
        flags: tuple[int, int] = (7, 0),
        servo: ServoPolicy | None = None,
        label: str = "",
    ) -> None:
        """Move to a point name (``MOV P1``) or explicit values: six joint angles with
        ``joints=True`` or X, Y, Z, A, B, C; ``linear`` uses MVS. ``servo`` as in `run`;
        ``label`` names the target in the activity (``P1``) when values are sent."""
        verb = "MVS" if linear else "MOV"
        if isinstance(target, str):
            name = target.strip()
            if not _POINT_NAME.fullmatch(name):
                raise ValueError(
                    f"{target!r} is not a point name (letter, then ≤ 7 letters/digits)"
                )
            statements = [f"{verb} {name}"]
        else:
            values = [float(v) for v in target]
            if len(values) != 6:
                raise ValueError(f"a target needs 6 values, got {len(values)}")
            text = ",".join(f"{v:.3f}" for v in values)
            if joints:
                statements = [f"{MOVE_JOINT_VARIABLE}=({text})", f"{verb} {MOVE_JOINT_VARIABLE}"]
            else:
                assign = f"{MOVE_POSE_VARIABLE}=({text})({flags[0]},{flags[1]})"
                statements = [assign, f"{verb} {MOVE_POSE_VARIABLE}"]

        def move(robot: Robot) -> None:
            for statement in statements:
                robot.exec(statement)

        shown = label or (target.strip() if isinstance(target, str) else "the given position")
        self._motion = Motion(MotionKind.MOVE_TO, shown)

        await self._command(
            actor,
            "move_to",
            "; ".join(statements),
            move,
            restore=True,
            servo=self._motion_servo(servo),
        )

    async def servo(self, actor: Actor, on: bool) -> None:
        """Servo on (needs rights) or off."""
        await self._command(actor, "servo", "on" if on else "off", lambda r: r.servo(on))

    async def override(self, actor: Actor, percent: int) -> int:
        """Set the OP override (1–100 %); cancels a pending restore after a jog."""
        if not 1 <= percent <= 100:
            raise ValueError(f"override {percent} % is outside 1–100")

        def set_override(robot: Robot) -> int:
            if self._jog.active:
                # During a jog: remember it for afterwards, and climb under the ceiling.
                self._restore_override = percent
                self._override_target = min(percent, self.config.jog_override_ceiling)
                return self._ramp_override(robot)
            self._restore_override = None
            self._override_target = None
            return robot.override(percent)

        result: int = await self._command(actor, "override", f"{percent}%", set_override)
        return result

    async def reset_alarm(self, actor: Actor) -> None:
        """``RSTALRM``."""
        await self._command(actor, "reset_alarm", "", lambda r: r.reset_alarm(), moves=False)

    async def reset_program(self, actor: Actor) -> None:
        """``RSTPRG``: back to the first line after a stop."""
        await self._command(actor, "reset_program", "", lambda r: r.reset_program(), moves=False)

    async def read_joints(self, actor: Actor) -> tuple[float, ...]:
        """One JPOSF now (queued with user commands; no lease needed)."""
        result: tuple[float, ...] = await self._read(
            "read_joints", lambda r: r.joints().values(*JOINT_NAMES)
        )
        return result

    async def read_pose(self, actor: Actor) -> tuple[float, ...]:
        """One PPOSF now: X, Y, Z, A, B, C."""
        result: tuple[float, ...] = await self._read(
            "read_pose", lambda r: r.pose().values(*POSE_NAMES)
        )
        return result

    # ================================================================== jog

    async def jog_start(
        self,
        actor: Actor,
        frame: JogFrame | str,
        axis: int | str,
        direction: int | str,
        *,
        servo: ServoPolicy | None = None,
    ) -> JogMethod:
        """Begin hold-to-move: sends the first JOG (after capping the OP override at
        `ServiceConfig.jog_override_ceiling`) and returns the method the controller took
        (JOG, or step moves when it refuses JOG). Keep calling `jog_heartbeat` every
        ≤ 100 ms while the key is held; call `jog_release` when it is let go. ``servo`` as
        in `run`."""
        self._check_open()
        request = JogRequest.make(frame, axis, direction)
        command_id = next(self._ids)
        first = self._servo_first(actor, "jog", self._motion_servo(servo), self._renew_jog)
        self._check_lease(actor, command_id, "jog", request.label)
        self._audit(actor, command_id, "jog", request.label, "accepted")
        self._jog.begin(actor, request, command_id, self._clock())
        self._jog.tick_queued = True
        self._bus.publish(
            JogChanged(
                actor=actor,
                active=True,
                frame=request.frame,
                axis=request.axis,
                direction=request.direction,
            )
        )
        self._update()
        future = self._require_worker().submit(Job("jog", Priority.JOG, first))
        try:
            method = await asyncio.wrap_future(future)
        except BaseException as exc:
            if self._jog.owned_by(actor):
                self._end_jog(f"jog refused: {exc}", actor)
            self._finish(actor, command_id, "jog", request.label, True, exc)
            raise
        self._jog.started(self._clock())
        self._finish(actor, command_id, "jog", request.label, True, None)
        return method if method is not None else JogMethod.JOG

    def jog_heartbeat(self, actor: Actor) -> bool:
        """The key is still held. Returns False when ``actor`` has no jog running (ended
        by release, stop, heartbeat loss, takeover or an error): the client should stop
        sending heartbeats."""
        if self._state != "running":
            return False
        if not self._lease.holds(actor):
            if self._jog.owned_by(actor):
                self._end_jog("lease lost", actor, send_stop=True)
            return False
        self._lease.touch(actor)  # keeps an idle-timeout lease alive
        ours, queue = self._jog.heartbeat(actor, self._clock())
        if queue:
            future = self._require_worker().submit(Job("jog", Priority.JOG, self._renew_jog))
            future.add_done_callback(self._renewal_done)
        return ours

    async def jog_release(self, actor: Actor) -> None:
        """The key was let go: stop now (JOG with empty masks) rather than waiting for
        the controller's watchdog."""
        if not self._jog.owned_by(actor):
            return
        self._end_jog("released", actor)
        future = self._require_worker().submit(Job("jog_stop", Priority.JOG, self._jog_stop))
        with contextlib.suppress(Cancelled, ServiceClosed):
            await asyncio.wrap_future(future)

    async def jog_step(
        self,
        actor: Actor,
        frame: JogFrame | str,
        axis: int | str,
        direction: int | str,
        *,
        wait: bool | None = None,
        servo: ServoPolicy | None = None,
        step_mm: float | None = None,
    ) -> None:
        """One increment per press (``step_mm``, else ``RobotSettings.jog_step_mm`` /
        ``jog_step_deg``).
        Refused with `JogBusy` while the previous step is queued or still moving: never a
        backlog. With ``wait`` the worker also waits until the step has finished moving."""
        self._check_open()
        request = JogRequest.make(frame, axis, direction)
        waits = self.config.step_waits_for_motion if wait is None else wait
        if self._step_busy:
            raise JogBusy("the previous step is still queued; press again when it has finished")

        def step(robot: Robot) -> None:
            self._apply_ceiling(robot)
            try:
                for statement in robot.step_statements(
                    request.mode, request.axis, request.direction, step_mm
                ):
                    robot.exec(statement)
            except ControllerError as exc:
                if exc.number == BUSY:
                    raise JogBusy(
                        "the arm is still moving (a program is running, or the last jog step "
                        "has not ended): wait until it stops, or press STOP, then jog again"
                    ) from exc
                raise
            if waits:
                self._require_worker().poll_while_moving(robot)

        self._step_busy = True
        self._motion = Motion(MotionKind.STEP, request.label)
        try:
            await self._command(
                actor,
                "jog_step",
                request.label,
                step,
                priority=Priority.JOG,
                servo=self._motion_servo(servo),
            )
        finally:
            self._step_busy = False

    # ================================================================== internals

    def _open_robot(self) -> Robot:
        return Robot(self._link_factory(), self.robot_settings)

    def _require_worker(self) -> Worker:
        if self._worker is None:
            raise ServiceError("the service has not been started (await service.start())")
        return self._worker

    def _check_open(self) -> None:
        if self._state == "new":
            raise ServiceError("the service has not been started (await service.start())")
        if self._state != "running":
            raise ServiceClosed("the robot service is closed")

    def _check_lease(
        self,
        actor: Actor,
        command_id: int,
        command: str,
        detail: str,
        plan: UploadPlan | None = None,
    ) -> bool:
        """The policy's one check before anything is queued (`melfa.service.policy`: check-
        before-upload, the instructor's gate, the lease); a refusal is audited and raised.
        True when this command took a free lease."""
        try:
            change = self.policy.admit(actor, Command(command), plan)
        except ServiceError as exc:
            self._audit(actor, command_id, command, detail, f"refused: {exc}")
            raise
        if change is not None and change.holder is not None:
            change = dataclasses.replace(change, reason=f"taken by {command}")
        self._lease_changed(change)
        return change is not None and change.holder is not None and self._lease.holds(actor)

    def _give_back(self, actor: Actor, taken: bool) -> None:
        """A command that took a free lease failed: the lease goes back (never silently
        kept by a failure), unless the arm is jogging for them."""
        if taken and self._lease.holds(actor) and not self._jog.active:
            self._lease_changed(self._lease.release(actor, f"{actor.user}'s command failed"))

    async def _command(
        self,
        actor: Actor,
        command: str,
        detail: str,
        fn: Callable[[Robot], Any],
        *,
        moves: bool = True,
        priority: Priority = Priority.USER,
        restore: bool = False,
        busy: str | None = None,
        command_id: int | None = None,
        servo: ServoPolicy | None = None,
        plan: UploadPlan | None = None,
    ) -> Any:
        self._check_open()
        command_id = command_id if command_id is not None else next(self._ids)
        taken = self._check_lease(actor, command_id, command, detail, plan)
        self._audit(actor, command_id, command, detail, "accepted", moves)
        work = self._restoring(fn) if restore else fn
        if servo is not None:
            work = self._servo_first(actor, command, servo, work)
        job = Job(command, priority, work, moves=moves, busy=busy)
        future = self._require_worker().submit(job)
        try:
            result = await asyncio.wrap_future(future)
        except BaseException as exc:
            self.policy.done(Command(command), plan, ok=False)
            self._finish(actor, command_id, command, detail, moves, exc)
            self._give_back(actor, taken)
            raise
        self.policy.done(Command(command), plan, ok=True)
        self._finish(actor, command_id, command, detail, moves, None)
        if moves:
            self._moved = True  # until a poll has seen whether it moves
        return result

    async def _upload(
        self,
        actor: Actor,
        command: str,
        run: Callable[[Robot, Callable[[int, int], None]], UploadReport],
        plan: UploadPlan,
    ) -> UploadReport:
        command_id = next(self._ids)

        def progress(sent: int, total: int) -> None:
            self._post(
                "event",
                UploadProgress(
                    actor=actor, command_id=command_id, command=command, sent=sent, total=total
                ),
            )

        result: UploadReport = await self._command(
            actor,
            command,
            "",
            lambda robot: run(robot, progress),
            moves=False,
            busy="upload",
            command_id=command_id,
            plan=plan,
        )
        return result

    async def _read(self, name: str, fn: Callable[[Robot], Any]) -> Any:
        self._check_open()
        job = Job(name, Priority.USER, fn, moves=False)
        return await asyncio.wrap_future(self._require_worker().submit(job))

    def _motion_servo(self, servo: ServoPolicy | None) -> ServoPolicy:
        return servo if servo is not None else self.config.motion_servo

    def _servo_first(
        self,
        actor: Actor,
        command: str,
        policy: ServoPolicy,
        fn: Callable[[Robot], Any],
    ) -> Callable[[Robot], Any]:
        """Before a move: the servo rule of `melfa.service.servo` (audited when it acts)."""

        def work(robot: Robot) -> Any:
            if ensure_servo(robot, policy, command):
                self._post("servo_on", actor, command)
            return fn(robot)

        return work

    def _restoring(self, fn: Callable[[Robot], Any]) -> Callable[[Robot], Any]:
        """Before a user move: give back the OP override the jog ceiling lowered."""

        def work(robot: Robot) -> Any:
            value = self._restore_override
            if value is not None and not self._jog.active:
                robot.override(value)
                self._restore_override = None
            return fn(robot)

        return work

    def _apply_ceiling(self, robot: Robot) -> None:
        """Worker: cap the OP override at the jog ceiling (once until restored)."""
        if self._restore_override is not None:
            return
        ceiling = self.config.jog_override_ceiling
        # STATE's override field, not `OVRD`: only STATE's answer is on record [TRACE K9b].
        current = robot.state().override or 100
        self._jog_override = current
        if current > ceiling:
            robot.override(ceiling)
            self._restore_override = current
            self._jog_override = ceiling

    def _ramp_override(self, robot: Robot) -> int:
        """Worker, during a jog: one step towards the override asked for (down at once,
        up by `ServiceConfig.jog_override_step`); returns the override now set."""
        target = self._override_target
        current = self._jog_override
        if current is None:
            current = robot.state().override or self.config.jog_override_ceiling
        if target is None:
            return current
        new = target if target <= current else min(target, current + self.config.jog_override_step)
        if new != current:
            robot.override(new)
        self._jog_override = new
        if new == target:
            self._override_target = None
        return new

    def _renew_jog(self, robot: Robot) -> JogMethod | None:
        """Worker: one JOG renewal if a fresh heartbeat allows it, else nothing."""
        request = self._jog.take_renewal()
        if request is None:
            return None
        self._apply_ceiling(robot)
        self._ramp_override(robot)
        started = self._clock()
        method = robot.jog(request.mode, request.axis, request.direction)
        assert self._worker is not None
        self._worker.measure("JOG", self._clock() - started)
        self._jog.last_sent = started
        return method

    def _jog_stop(self, robot: Robot) -> None:
        """Worker: end a JOG at once (empty masks); a step jog ends by itself. A refusal
        here (servo already off, alarm) means the arm is not jogging: nothing to report."""
        with contextlib.suppress(ControllerError):
            robot.jog_stop()

    def _renewal_done(self, future: concurrent.futures.Future[Any]) -> None:
        if future.cancelled():
            return
        exc = future.exception()
        if exc is not None and not isinstance(exc, Cancelled | ServiceClosed):
            self._post("jog_failed", exc)

    def _end_jog(self, reason: str, actor: Actor | None, *, send_stop: bool = False) -> None:
        owner, request = self._jog.end()
        if request is None:
            return
        self._override_target = None
        self._audit(
            owner or actor or SERVICE_ACTOR, self._jog.command_id, "jog_end", request.label, reason
        )
        if self._worker is not None:
            self._worker.cancel_queued(lambda job: job.name == "jog", Cancelled(reason))
            if send_stop and self._state == "running":
                self._worker.submit(Job("jog_stop", Priority.JOG, self._jog_stop))
        self._bus.publish(
            JogChanged(
                actor=actor,
                active=False,
                frame=request.frame,
                axis=request.axis,
                direction=request.direction,
                reason=reason,
            )
        )
        self._update()

    async def _housekeep(self) -> None:
        while True:
            await asyncio.sleep(HOUSEKEEPING_S)
            if (
                self._jog.active
                and not self._jog.starting
                and self._clock() - self._jog.last_heartbeat > self.config.jog_heartbeat_timeout_s
            ):
                self._end_jog("heartbeat lost", SERVICE_ACTOR, send_stop=True)
            self._lease_changed(self._lease.expire())

    def _lease_changed(self, change: LeaseChange | None) -> None:
        if change is None:
            return
        if self._jog.active and change.holder is None:
            self._end_jog(f"lease ended: {change.reason}", change.actor, send_stop=True)
        info = self._lease.info()
        self._bus.publish(
            LeaseChanged(
                actor=change.actor,
                holder=change.holder,
                previous=change.previous,
                reason=change.reason,
                since=info.since,
                holder_state=info.state.value if info.state is not None else None,
            )
        )
        self._update()

    def _motion_seen(self, update: dict[str, Any]) -> None:
        """A poll arrived: motion keeps the holder's lease; a STATE read showing a still,
        idle arm ends an orphaned one."""
        snapshot = self._snapshot
        if snapshot.moving or snapshot.running or self._jog.active:
            self._lease_changed(self._lease.motion(True))
        elif "running" in update:
            self._lease_changed(self._lease.motion(False))

    def _audit(
        self,
        actor: Actor,
        command_id: int,
        command: str,
        detail: str,
        result: str,
        moves: bool = True,
    ) -> None:
        entry = AuditEvent(
            actor=actor,
            command_id=command_id,
            command=command,
            detail=detail,
            result=result,
            moves=moves,
        )
        with contextlib.suppress(Exception):
            self.audit.write(entry)
        self._bus.publish(entry)

    def _finish(
        self,
        actor: Actor,
        command_id: int,
        command: str,
        detail: str,
        moves: bool,
        error: BaseException | None,
    ) -> None:
        """Outcome: audit entry and result event, only now that the reply is in."""
        if error is None:
            self._audit(actor, command_id, command, detail, "ok", moves)
            self._bus.publish(
                CommandResult(actor=actor, command_id=command_id, command=command, ok=True)
            )
            return
        text = describe_error(error)
        self._audit(actor, command_id, command, detail, f"failed: {text}", moves)
        self._bus.publish(
            CommandResult(
                actor=actor,
                command_id=command_id,
                command=command,
                ok=False,
                error=text,
                error_number=getattr(error, "number", None),
            )
        )

    # ---------------------------------------------------------------- worker posts

    def _post(self, kind: str, *args: Any) -> None:
        """From the worker thread: run on the loop."""
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        with contextlib.suppress(RuntimeError):
            loop.call_soon_threadsafe(self._on_worker, kind, args)

    def _on_worker(self, kind: str, args: tuple[Any, ...]) -> None:
        if kind == "poll":
            if "moving" in args[0]:
                self._moved = False
            self._update(**args[0])
            self._motion_seen(args[0])
        elif kind == "busy":
            self._update(busy=args[0])
        elif kind == "status":
            status, detail = args
            if status is not LinkStatus.CONNECTED and self._jog.active:
                self._end_jog(f"link {status.value}", SERVICE_ACTOR)
            self._bus.publish(LinkStatusChanged(status=status, detail=detail))
            self._update(link=status)
        elif kind == "event":
            self._bus.publish(args[0])
        elif kind == "servo_on":
            actor, command = args
            self._audit(actor, next(self._ids), "servo", f"on, before {command}", "ok", False)
            self._update(servo=True)
        elif kind == "jog_failed":
            exc = args[0]
            actor = self._jog.actor
            if actor is not None:
                command_id = self._jog.command_id
                label = self._jog.request.label if self._jog.request else ""
                self._end_jog(f"jog refused: {exc}", actor)
                self._finish(actor, command_id, "jog", label, True, exc)

    def _update(self, **changes: Any) -> None:
        info = self._lease.info()
        snapshot = dataclasses.replace(
            self._snapshot,
            **changes,
            seq=next(self._seq),
            at=type(self._snapshot.at).now(self._snapshot.at.tzinfo),
            jogging=self._jog.active,
            lease_holder=info.holder.user if info.holder is not None else None,
            lease_since=info.since,
            lease_state=info.state.value if info.state is not None else None,
        )
        facts = Facts(
            connected=snapshot.link is LinkStatus.CONNECTED,
            busy=snapshot.busy,
            alarm=snapshot.alarm is not None,
            jogging=snapshot.jogging,
            running=snapshot.running,
            program_running=snapshot.program_running,
            paused=snapshot.paused,
            moving=snapshot.moving,
            line=snapshot.line,
        )
        activity, detail = activity_of(facts, self._motion)
        if activity is Activity.JOGGING and self._jog.request is not None:
            detail = self._jog.request.label
        self._snapshot = dataclasses.replace(snapshot, activity=activity, activity_detail=detail)
        self._bus.publish(self._snapshot)

    def _listeners_changed(self) -> None:
        if self._worker is not None:
            self._worker.wake()


__all__ = ["RobotService", "describe_error"]
