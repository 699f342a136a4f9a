"""The one way in for every command: admitted (the service open, its policy, audited as
accepted), queued to the worker, awaited, and its outcome audited and published only once
the controller answered (datasette's "events after success").

`Dispatcher.admit` is the one place every command passes before it is queued, whoever
calls (REST, the WebSocket, rosbridge, the thesis's messages, the ROS node, the desktop
client): it asks `melfa.service.policy.Policy` (check-before-upload, the instructor's
gate, the lease). How a command ended is told to its ``done`` (a load's: what the slot now
holds, `melfa.service.slot`) and to the ``done_hooks`` (the run recorder).
`Dispatcher.decide` is the same for what is decided at once and never queued (take
control, join the queue); both audit a refusal in one place (`Dispatcher.refused`).
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import itertools
from collections.abc import Callable
from typing import Any, TypeVar

from melfa.lang.plan import UploadPlan
from melfa.protocol.advice import advice_for
from melfa.protocol.error_table import error_code
from melfa.robot import ControllerError, Robot, UploadReport
from melfa.service.audit import AuditSink
from melfa.service.bus import EventBus
from melfa.service.errors import JogBusy, Refused, ServiceError
from melfa.service.events import Actor, AuditEvent, CommandResult, RobotNote, UploadProgress
from melfa.service.lease import LeaseChange
from melfa.service.lifecycle import Life
from melfa.service.policy import Policy
from melfa.service.posts import MotionSent, Post, Publish, ServoTurnedOn
from melfa.service.servo import ServoPolicy, ensure_servo
from melfa.service.worker import Job, Priority, Worker
from melfa.vocab.activity import Motion
from melfa.vocab.commands import Command
from melfa.vocab.lease import LeaseReason

T = TypeVar("T")
Work = Callable[[Robot], Any]
DoneHook = Callable[[Actor, Command, UploadPlan | None, bool], None]
"""``(actor, command, plan, ok)`` after a command's answer (or failure)."""
Precondition = Callable[[], Refused | None]
"""A command's own check before the policy's (a run's expected slot): a refusal or None."""
Done = Callable[[bool], None]
"""Told how an admitted command ended (True: the controller answered ok)."""


def describe_error(exc: BaseException) -> str:
    """One line for an audit entry or a result event; a policy refusal is the student's
    words and the fix, as every door sends them."""
    if isinstance(exc, Refused | JogBusy):  # already in the student's words
        return str(exc)
    text = str(exc) or type(exc).__name__
    return f"{type(exc).__name__}: {text}"


def outcome_words(exc: BaseException) -> str:
    """How a command failed, as the audit log keeps it for people to read: a controller's
    refusal by its code and its advice (``L2000: The servo is off…``), the student's own
    words; anything else as `describe_error`."""
    if isinstance(exc, ControllerError):
        return f"{error_code(exc.number)}: {advice_for(exc.number).message}"
    return describe_error(exc)


class Dispatcher:
    """Admits, queues, audits and reports commands (event loop only)."""

    def __init__(
        self,
        *,
        life: Life,
        policy: Policy,
        bus: EventBus,
        audit: AuditSink,
        post: Callable[[Post], None],
        lease_changed: Callable[[LeaseChange | None], None],
        jogging: Callable[[], bool],
    ) -> None:
        self._life = life
        self._policy = policy
        self._lease = policy.lease
        self._bus = bus
        self.audit_sink = audit
        self._post = post
        self._lease_changed = lease_changed
        self._jogging = jogging
        self._ids = itertools.count(1)
        self.worker: Worker | None = None
        """Set when the service starts."""
        self.moved = False
        """A moving command finished and no poll has looked at the arm since."""
        self.done_hooks: list[DoneHook] = []
        """Told how every admitted command ended (the run recorder: a run began)."""

    def next_id(self) -> int:
        return next(self._ids)

    def require_worker(self) -> Worker:
        if self.worker is None:
            raise ServiceError("the service has not been started (await service.start())")
        return self.worker

    # ------------------------------------------------------------------ the way in

    def admit(
        self,
        actor: Actor,
        command: Command,
        detail: str,
        command_id: int | None = None,
        plan: UploadPlan | None = None,
        precondition: Precondition | None = None,
    ) -> tuple[int, bool]:
        """Every command passes here before it is queued: refused (audited) when the
        service is not open, its ``precondition`` or the policy says no; else audited as
        accepted. Returns the command's id and whether it took a free lease."""
        self._life.check_open()
        command_id = command_id if command_id is not None else self.next_id()
        refused = precondition() if precondition is not None else None
        if refused is not None:
            self.refused(actor, command_id, command, detail, refused)
            raise refused
        taken = self._check_policy(actor, command_id, command, detail, plan)
        self.audit(actor, command_id, command, detail, "accepted")
        return command_id, taken

    def decide(self, actor: Actor, command: Command, decision: Callable[[], T]) -> T:
        """A request decided at once, never queued to the worker (take control, a queue
        request): ``decision``'s `Refused` is audited as a command's refusal is, then raised.
        An accepted one is audited by what it changed (the control note, the queue's step)."""
        self._life.check_open()
        try:
            return decision()
        except Refused as exc:
            self.refused(actor, self.next_id(), command, "", exc)
            raise

    def _check_policy(
        self,
        actor: Actor,
        command_id: int,
        command: Command,
        detail: str,
        plan: UploadPlan | None,
    ) -> bool:
        """The policy's one check (`Policy.admit`); a refusal is audited and raised. True
        when this command took a free lease."""
        try:
            change = self._policy.admit(actor, command, plan)
        except ServiceError as exc:
            self.refused(actor, command_id, command, detail, exc)
            raise
        if change is not None and change.holder is not None:
            change = dataclasses.replace(
                change, reason=LeaseReason.TAKEN_BY_COMMAND, command=command
            )
        self._lease_changed(change)
        return change is not None and change.holder is not None and self._lease.holds(actor)

    def give_back(self, actor: Actor, taken: bool) -> None:
        """A command that took a free lease failed: the lease goes back (never silently
        kept by a failure), unless the arm is jogging for them."""
        if taken and self._lease.holds(actor) and not self._jogging():
            self._lease_changed(self._lease.release(actor, LeaseReason.COMMAND_FAILED))

    async def command(
        self,
        actor: Actor,
        command: Command,
        detail: str,
        work: Work,
        *,
        priority: Priority = Priority.USER,
        busy: str | None = None,
        command_id: int | None = None,
        plan: UploadPlan | None = None,
        precondition: Precondition | None = None,
        done: Done | None = None,
    ) -> Any:
        """Admit, queue, await the controller's answer; audit and publish the outcome
        (``done`` is told it first, then the ``done_hooks``)."""
        command_id, taken = self.admit(actor, command, detail, command_id, plan, precondition)
        waiting = self._policy.attend(actor, command)
        if waiting is not None:  # attended mode: the supervisor's Arm ready first
            try:
                await waiting
            except BaseException as exc:
                self.finish(actor, command_id, command, detail, exc)
                self.give_back(actor, taken)
                raise
        job = Job(command, priority, work, moves=command.moves, busy=busy)
        future = self.require_worker().submit(job)
        try:
            result = await asyncio.wrap_future(future)
        except BaseException as exc:
            if done is not None:
                done(False)
            self._done(actor, command, plan, ok=False)
            self.finish(actor, command_id, command, detail, exc)
            self.give_back(actor, taken)
            raise
        if done is not None:
            done(True)
        self._done(actor, command, plan, ok=True)
        self.finish(actor, command_id, command, detail, None)
        if command.moves:
            self.moved = True  # until a poll has seen whether it moves
        return result

    def _done(self, actor: Actor, command: Command, plan: UploadPlan | None, ok: bool) -> None:
        for hook in self.done_hooks:
            hook(actor, command, plan, ok)

    async def upload(
        self,
        actor: Actor,
        command: Command,
        run: Callable[[Robot, Callable[[int, int], None]], UploadReport],
        plan: UploadPlan,
        done: Done | None = None,
    ) -> UploadReport:
        """A command that sends ``plan``'s program or points, with `UploadProgress` as it
        goes; ``done`` as in `command`."""
        command_id = self.next_id()

        def progress(sent: int, total: int) -> None:
            self._post(
                Publish(
                    UploadProgress(
                        actor=actor,
                        command_id=command_id,
                        command=command,
                        sent=sent,
                        total=total,
                    )
                )
            )

        result: UploadReport = await self.command(
            actor,
            command,
            "",
            lambda robot: run(robot, progress),
            busy="upload",
            command_id=command_id,
            plan=plan,
            done=done,
        )
        return result

    async def read(self, command: Command, work: Work) -> Any:
        """A read: no lease, no audit (it changes nothing)."""
        self._life.check_open()
        job = Job(command, Priority.USER, work, moves=False)
        return await asyncio.wrap_future(self.require_worker().submit(job))

    def servo_first(self, actor: Actor, command: Command, policy: ServoPolicy, work: Work) -> Work:
        """Before a move: the servo rule of `melfa.service.servo` (audited when it acts)."""

        def first(robot: Robot) -> Any:
            if ensure_servo(robot, policy, command.value):
                self._post(ServoTurnedOn(actor, command))
            return work(robot)

        return first

    def telling_sent(self, motion: Motion, work: Work) -> Work:
        """``work``, then the news that the controller took ``motion`` (`MotionSent`)."""

        def sent(robot: Robot) -> Any:
            result = work(robot)
            self._post(MotionSent(motion))
            return result

        return sent

    # ------------------------------------------------------------------ the record

    def audit(
        self,
        actor: Actor,
        command_id: int,
        command: Command,
        detail: str,
        result: str,
        moves: bool | None = None,
    ) -> None:
        entry = AuditEvent(
            actor=actor,
            command_id=command_id,
            command=command,
            detail=detail,
            result=result,
            moves=command.moves if moves is None else moves,
        )
        with contextlib.suppress(Exception):
            self.audit_sink.write(entry)
        self._bus.publish(entry)

    def refused(
        self, actor: Actor, command_id: int, command: Command, detail: str, exc: ServiceError
    ) -> None:
        """The one record of a refusal: ``refused:`` and the student's words and fix
        (`melfa.vocab.refusals`, as every door sends them)."""
        self.audit(actor, command_id, command, detail, f"refused: {exc}")

    def note(self, note: RobotNote) -> None:
        """What happened to the robot that no command asked for (`melfa.service.notes`)."""
        with contextlib.suppress(Exception):
            self.audit_sink.note(note)

    def finish(
        self,
        actor: Actor,
        command_id: int,
        command: Command,
        detail: str,
        error: BaseException | None,
    ) -> None:
        """Outcome: audit entry and result event, only now that the reply is in."""
        if error is None:
            self.audit(actor, command_id, command, detail, "ok")
            self._bus.publish(
                CommandResult(actor=actor, command_id=command_id, command=command, ok=True)
            )
            return
        text = describe_error(error)
        self.audit(actor, command_id, command, detail, f"failed: {outcome_words(error)}")
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


__all__ = ["Dispatcher", "Done", "DoneHook", "Precondition", "Work", "describe_error"]
