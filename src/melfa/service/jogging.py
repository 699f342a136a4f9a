"""The jog session: hold-to-move (start, heartbeat, release), step jogs, the OP override's
jog ceiling and its ramp, and every way a jog ends (`melfa.vocab.jog.JogEnd`).

The dead-man itself is `melfa.service.jog.JogKeeper`: a heartbeat allows one JOG renewal,
no heartbeat no JOG. Here the keeper meets the worker: the first JOG caps the override at
`ServiceConfig.jog_override_ceiling` (given back before the next user move), an override
asked for during a jog climbs there by `jog_override_step` per renewal, and an ended jog
cancels its queued renewals and, when asked to, sends the empty JOG that stops the arm.
Methods marked *worker* run in the worker thread; the rest on the event loop.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
from collections.abc import Callable
from typing import Any

from melfa.protocol.error_table import BUSY
from melfa.robot import ControllerError, JogMethod, Robot
from melfa.service.bus import EventBus
from melfa.service.clock import Clock
from melfa.service.config import ServiceConfig
from melfa.service.dispatch import Dispatcher, Work
from melfa.service.errors import Cancelled, JogBusy, ServiceClosed
from melfa.service.events import SERVICE_ACTOR, Actor, JogChanged, JogFrame
from melfa.service.jog import JogKeeper, JogRequest
from melfa.service.lease import Lease
from melfa.service.lifecycle import Life
from melfa.service.posts import JogRefused, Post
from melfa.service.servo import ServoPolicy
from melfa.service.snapshots import Snapshots
from melfa.service.worker import Job, Priority
from melfa.vocab.activity import Motion, MotionKind
from melfa.vocab.commands import Command
from melfa.vocab.jog import JogEnd


class JogSession:
    """Who jogs, the override they jog at, and how their jog ends."""

    def __init__(
        self,
        *,
        config: ServiceConfig,
        clock: Clock,
        life: Life,
        lease: Lease,
        bus: EventBus,
        dispatch: Dispatcher,
        snapshots: Snapshots,
        post: Callable[[Post], None],
    ) -> None:
        self.config = config
        self._clock = clock
        self._life = life
        self._lease = lease
        self._bus = bus
        self._dispatch = dispatch
        self._snapshots = snapshots
        self._post = post
        self.keeper = JogKeeper()
        self._step_busy = False
        self._restore_override: int | None = None
        """The operator's OP override while the jog ceiling holds it lower (worker only)."""
        self._jog_override: int | None = None
        self._override_target: int | None = None
        """An override asked for during a jog, reached by `_ramp_override` (worker only)."""

    @property
    def active(self) -> bool:
        return self.keeper.active

    def label(self) -> str | None:
        """What is being jogged (``joint J1+``), None when nothing is."""
        request = self.keeper.request
        return request.label if request is not None else None

    # ------------------------------------------------------------------ hold-to-move

    async def start(
        self,
        actor: Actor,
        frame: JogFrame | str,
        axis: int | str,
        direction: int | str,
        servo: ServoPolicy,
    ) -> JogMethod:
        """Begin hold-to-move (see `RobotService.jog_start`)."""
        self._life.check_open()
        request = JogRequest.make(frame, axis, direction)
        first = self._dispatch.servo_first(actor, Command.JOG, servo, self._renew)
        command_id, _ = self._dispatch.admit(actor, Command.JOG, request.label)
        self.keeper.begin(actor, request, command_id, self._clock.now())
        self.keeper.tick_queued = True
        self._changed(actor, request, active=True)
        future = self._dispatch.require_worker().submit(Job(Command.JOG, Priority.JOG, first))
        try:
            method = await asyncio.wrap_future(future)
        except BaseException as exc:
            if self.keeper.owned_by(actor):
                self.end(JogEnd.REFUSED, actor, detail=str(exc))
            self._dispatch.finish(actor, command_id, Command.JOG, request.label, exc)
            raise
        self.keeper.started(self._clock.now())
        self._dispatch.finish(actor, command_id, Command.JOG, request.label, None)
        return method if method is not None else JogMethod.JOG

    def heartbeat(self, actor: Actor) -> bool:
        """The key is still held; False when ``actor`` has no jog running."""
        if not self._life.running:
            return False
        if not self._lease.holds(actor):
            if self.keeper.owned_by(actor):
                self.end(JogEnd.LEASE_LOST, actor, send_stop=True)
            return False
        self._lease.touch(actor)  # keeps an idle-timeout lease alive
        ours, queue = self.keeper.heartbeat(actor, self._clock.now())
        if queue:
            job = Job(Command.JOG, Priority.JOG, self._renew)
            future = self._dispatch.require_worker().submit(job)
            future.add_done_callback(self._renewal_done)
        return ours

    async def release(self, actor: Actor) -> None:
        """The key was let go: stop now (JOG with empty masks)."""
        if not self.keeper.owned_by(actor):
            return
        self.end(JogEnd.RELEASED, actor)
        job = Job(Command.JOG_STOP, Priority.JOG, self._jog_stop)
        future = self._dispatch.require_worker().submit(job)
        with contextlib.suppress(Cancelled, ServiceClosed):
            await asyncio.wrap_future(future)

    def check_heartbeat(self) -> None:
        """Housekeeping: end a jog whose heartbeats stopped."""
        keeper = self.keeper
        if (
            keeper.active
            and not keeper.starting
            and self._clock.now() - keeper.last_heartbeat > self.config.jog_heartbeat_timeout_s
        ):
            self.end(JogEnd.HEARTBEAT_LOST, SERVICE_ACTOR, send_stop=True)

    def refused(self, error: BaseException) -> None:
        """A renewal failed (posted by the worker): the jog ends with the refusal."""
        actor = self.keeper.actor
        if actor is None:
            return
        command_id = self.keeper.command_id
        label = self.label() or ""
        self.end(JogEnd.REFUSED, actor, detail=str(error))
        self._dispatch.finish(actor, command_id, Command.JOG, label, error)

    def end(
        self,
        why: JogEnd,
        actor: Actor | None,
        *,
        by: str | None = None,
        detail: str = "",
        send_stop: bool = False,
    ) -> None:
        """End the jog (if any) for ``why``: audited, queued renewals dropped, an empty
        JOG sent when ``send_stop``, a `JogChanged` published."""
        owner, request = self.keeper.end()
        if request is None:
            return
        self._override_target = None
        self._dispatch.audit(
            owner or actor or SERVICE_ACTOR,
            self.keeper.command_id,
            Command.JOG_END,
            request.label,
            why.value if by is None else f"{why.value} by {by}",
        )
        worker = self._dispatch.worker
        if worker is not None:
            worker.cancel_queued(
                lambda job: job.command is Command.JOG, Cancelled(f"the jog ended: {why.words(by)}")
            )
            if send_stop and self._life.running:
                worker.submit(Job(Command.JOG_STOP, Priority.JOG, self._jog_stop))
        self._changed(actor, request, active=False, end=why, by=by, detail=detail)

    def _changed(
        self,
        actor: Actor | None,
        request: JogRequest,
        *,
        active: bool,
        end: JogEnd | None = None,
        by: str | None = None,
        detail: str = "",
    ) -> None:
        """Publish a `JogChanged` for ``request`` and a new snapshot."""
        self._bus.publish(
            JogChanged(
                actor=actor,
                active=active,
                frame=request.frame,
                axis=request.axis,
                direction=request.direction,
                end=end,
                by=by,
                detail=detail,
            )
        )
        self._snapshots.update()

    # ------------------------------------------------------------------ step jog

    async def step(
        self,
        actor: Actor,
        frame: JogFrame | str,
        axis: int | str,
        direction: int | str,
        *,
        waits: bool,
        servo: ServoPolicy,
        step_mm: float | None,
    ) -> None:
        """One increment (see `RobotService.jog_step`); `JogBusy` while one is under way."""
        self._life.check_open()
        request = JogRequest.make(frame, axis, direction)
        if self._step_busy:
            raise JogBusy("the previous step is still queued; press again when it has finished")
        worker = self._dispatch.require_worker()

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
                worker.poll_while_moving(robot)

        self._step_busy = True
        # Told when the controller took the step, so the activity can see it arrive
        # (without, "Moving to X+" stayed after the arm had stopped).
        motion = Motion(MotionKind.STEP, request.label)
        self._snapshots.motion = motion
        sent = self._dispatch.telling_sent(motion, step)
        try:
            await self._dispatch.command(
                actor,
                Command.JOG_STEP,
                request.label,
                self._dispatch.servo_first(actor, Command.JOG_STEP, servo, sent),
                priority=Priority.JOG,
            )
        finally:
            self._step_busy = False

    # ------------------------------------------------------------------ the override

    def restoring(self, work: Work) -> Work:
        """Before a user move: give back the OP override the jog ceiling lowered."""

        def first(robot: Robot) -> Any:
            value = self._restore_override
            if value is not None and not self.keeper.active:
                robot.override(value)
                self._restore_override = None
            return work(robot)

        return first

    def set_override(self, robot: Robot, percent: int) -> int:
        """Worker: the operator sets the override; during a jog it is remembered for
        afterwards and climbed to under the ceiling."""
        if self.keeper.active:
            self._restore_override = percent
            self._override_target = min(percent, self.config.jog_override_ceiling)
            return self._ramp_override(robot)
        self._restore_override = None
        self._override_target = None
        return robot.override(percent)

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

    # ------------------------------------------------------------------ worker

    def _renew(self, robot: Robot) -> JogMethod | None:
        """Worker: one JOG renewal if a fresh heartbeat allows it, else nothing."""
        request = self.keeper.take_renewal()
        if request is None:
            return None
        self._apply_ceiling(robot)
        self._ramp_override(robot)
        started = self._clock.now()
        method = robot.jog(request.mode, request.axis, request.direction)
        self._dispatch.require_worker().measure("JOG", self._clock.now() - started)
        self.keeper.last_sent = started
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
            self._post(JogRefused(exc))


__all__ = ["JogSession"]
