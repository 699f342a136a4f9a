"""What a student can ask of the robot, each one call through the service's one way in
(`melfa.service.dispatch.Dispatcher`): loads, runs, moves, the servo, the hands, the
override, jogs, reads. `RobotService` is made of this and its own rooms (lifecycle, lease,
stop, state).
"""

from __future__ import annotations

import dataclasses
import datetime as dt
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from melfa.lang.plan import UploadPlan
from melfa.protocol import JOINT_NAMES, POSE_NAMES
from melfa.protocol.limits import HANDS, OVERRIDE_PERCENT, span_text
from melfa.robot import JogMethod, Robot, RobotSettings, UploadReport
from melfa.service.config import ServiceConfig
from melfa.service.dispatch import Dispatcher, Done, Precondition, Work
from melfa.service.errors import InvalidArgument, Refused
from melfa.service.events import Actor, JogFrame
from melfa.service.jogging import JogSession
from melfa.service.servo import ServoPolicy
from melfa.service.slot import LoadOrigin, Slot, after_load, refusal_to_run
from melfa.service.snapshots import Snapshots
from melfa.service.statements import move_statements
from melfa.vocab.activity import Motion, MotionKind
from melfa.vocab.commands import Command

T = TypeVar("T")


class RobotCommands:
    """The robot's commands, for `RobotService` (which supplies the parts below)."""

    config: ServiceConfig
    robot_settings: RobotSettings
    _dispatch: Dispatcher
    _jog: JogSession
    _snapshots: Snapshots

    # ================================================================== commands

    def decide(self, actor: Actor, command: Command, decision: Callable[[], T]) -> T:
        """A request of ``actor``'s decided at once, never queued (take control, a queue
        request): a refusal is audited as a command's is (`Dispatcher.decide`)."""
        return self._dispatch.decide(actor, command, decision)

    async def _move(
        self,
        actor: Actor,
        command: Command,
        detail: str,
        work: Work,
        motion: Motion,
        servo: ServoPolicy | None,
        precondition: Precondition | None = None,
    ) -> Any:
        """A command that moves the arm: the jog's override given back first, then the
        servo rule (`melfa.service.servo`), then ``work``; the activity follows ``motion``
        from asked to sent (`Dispatcher.telling_sent`) to moving and arrived."""
        policy = servo if servo is not None else self.config.motion_servo
        work = self._dispatch.telling_sent(motion, work)
        work = self._dispatch.servo_first(actor, command, policy, self._jog.restoring(work))

        previous = self._snapshots.motion
        self._snapshots.motion = motion
        try:
            if command is not Command.RUN:  # "Moving to P1" from the click on
                self._snapshots.update()
            return await self._dispatch.command(
                actor, command, detail, work, precondition=precondition
            )
        except BaseException:
            # Refused, or failed: the arm did not go (a STOP has cleared it already).
            if self._snapshots.motion is motion:
                self._snapshots.motion = previous
                self._snapshots.update()
            raise

    def _loaded(
        self,
        actor: Actor,
        command: Command,
        plan: UploadPlan | None,
        origin: LoadOrigin | None,
        made: Callable[[Slot | None], None] | None = None,
    ) -> Done:
        """What a load or a delete tells the slot when it ends (`melfa.service.slot`), and
        ``made``, when given."""

        def done(ok: bool) -> None:
            at = dt.datetime.now(dt.UTC)
            before = self._snapshots.latest.slot
            clears = self.robot_settings.clear_with_eclr
            slot = after_load(before, actor.user, command, plan, ok, at, origin, clears=clears)
            self._snapshots.update(lambda s: dataclasses.replace(s, slot=slot))
            if made is not None:
                made(slot)

        return done

    async def load_project(
        self, actor: Actor, plan: UploadPlan, origin: LoadOrigin | None = None
    ) -> UploadReport:
        """The plan's program and points (`melfa.lang.plan.plan_upload`) into the
        controller's program in one LOAD…SAVE session; `UploadProgress` events while it
        goes. Polling pauses meanwhile. The state's ``slot`` then names ``actor`` and the
        ``origin`` (the workspace)."""
        done = self._loaded(actor, Command.LOAD_PROJECT, plan, origin)
        return await self._dispatch.upload(
            actor, Command.LOAD_PROJECT, lambda r, p: r.load_project(plan, p), plan, done
        )

    async def upload_program(
        self, actor: Actor, plan: UploadPlan, origin: LoadOrigin | None = None
    ) -> UploadReport:
        """Replace the program (steps and positions) with the plan's."""
        done = self._loaded(actor, Command.UPLOAD_PROGRAM, plan, origin)
        return await self._dispatch.upload(
            actor, Command.UPLOAD_PROGRAM, lambda r, p: r.upload_program(plan, p), plan, done
        )

    async def upload_points(
        self, actor: Actor, plan: UploadPlan, made: Callable[[Slot | None], None] | None = None
    ) -> UploadReport:
        """Add or replace the plan's positions, keeping the steps. ``made`` is told what the
        slot then holds (the program with the positions it kept and these: a pair of its
        own, `Slot.fingerprint`), as the state is; None: not known."""
        done = self._loaded(actor, Command.UPLOAD_POINTS, plan, None, made)
        return await self._dispatch.upload(
            actor, Command.UPLOAD_POINTS, lambda r, p: r.upload_points(plan, p), plan, done
        )

    async def run(
        self, actor: Actor, *, servo: ServoPolicy | None = None, expect: str | None = None
    ) -> None:
        """Start the program (``RUN<program>;1``). ``servo``: what to do when the servo is
        off (`melfa.service.servo`; default `ServiceConfig.motion_servo`). ``expect``: the
        fingerprint of the program the caller means to run (the state's ``slot``); refused
        when the slot holds another (`melfa.service.slot.refusal_to_run`)."""

        def slot_check() -> Refused | None:
            return refusal_to_run(self._snapshots.latest.slot, expect)

        motion = Motion(MotionKind.RUN)
        await self._move(actor, Command.RUN, "", lambda r: r.run(), motion, servo, slot_check)

    async def delete(self, actor: Actor) -> None:
        """Delete the program and its points."""
        done = self._loaded(actor, Command.DELETE, None, None)
        await self._dispatch.command(actor, Command.DELETE, "", lambda r: r.delete(), done=done)

    async def exec(
        self, actor: Actor, statement: str, *, servo: ServoPolicy = ServoPolicy.LEAVE
    ) -> None:
        """Execute one MELFA BASIC statement now (``EXEC``). A statement may not move, so
        the servo is left alone unless ``servo`` says otherwise."""
        statement = statement.strip()
        if not statement:
            raise InvalidArgument("nothing to execute: the statement is empty", "statement")
        motion = Motion(MotionKind.EXEC, statement)
        await self._move(actor, Command.EXEC, statement, lambda r: r.exec(statement), motion, servo)

    async def hand(self, actor: Actor, open_: bool, number: int = 1) -> None:
        """Open or close hand ``number`` (1–8)."""
        if number not in HANDS:
            raise InvalidArgument(f"hand {number} is outside {span_text(HANDS)}", "number")
        detail = f"{'open' if open_ else 'close'} {number}"
        await self._dispatch.command(actor, Command.HAND, detail, lambda r: r.hand(open_, number))
        hands = list(self._snapshots.latest.hands or (None,) * len(HANDS))
        hands[number - 1] = open_
        self._snapshots.update(lambda s: dataclasses.replace(s, hands=tuple(hands)))

    async def hand_toggle(self, actor: Actor, number: int = 1) -> bool:
        """Open a closed hand, close an open one; returns True if it is now open. An
        unknown hand is taken as open (the thesis's rule), so the first toggle closes."""
        hands = self._snapshots.latest.hands
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
        statements = move_statements(target, linear=linear, joints=joints, flags=flags)

        def move(robot: Robot) -> None:
            for statement in statements:
                robot.exec(statement)

        shown = label or (target.strip() if isinstance(target, str) else "the given position")
        motion = Motion(MotionKind.MOVE_TO, shown)
        await self._move(actor, Command.MOVE_TO, "; ".join(statements), move, motion, servo)

    async def servo(self, actor: Actor, on: bool) -> None:
        """Servo on (needs rights) or off."""
        await self._dispatch.command(
            actor, Command.SERVO, "on" if on else "off", lambda r: r.servo(on)
        )

    async def override(self, actor: Actor, percent: int) -> int:
        """Set the OP override (1–100 %); cancels a pending restore after a jog."""
        if percent not in OVERRIDE_PERCENT:
            raise InvalidArgument(
                f"override {percent} % is outside {span_text(OVERRIDE_PERCENT)}", "percent"
            )
        result: int = await self._dispatch.command(
            actor,
            Command.OVERRIDE,
            f"{percent}%",
            lambda robot: self._jog.set_override(robot, percent),
        )
        return result

    async def reset_alarm(self, actor: Actor) -> None:
        """``RSTALRM``."""
        await self._dispatch.command(actor, Command.RESET_ALARM, "", lambda r: r.reset_alarm())

    async def reset_program(self, actor: Actor) -> None:
        """``RSTPRG``: back to the first line after a stop."""
        await self._dispatch.command(actor, Command.RESET_PROGRAM, "", lambda r: r.reset_program())

    async def read_joints(self, actor: Actor) -> tuple[float, ...]:
        """One JPOSF now (queued with user commands; no lease needed)."""
        result: tuple[float, ...] = await self._dispatch.read(
            Command.READ_JOINTS, lambda r: r.joints().values(*JOINT_NAMES)
        )
        return result

    async def read_pose(self, actor: Actor) -> tuple[float, ...]:
        """One PPOSF now: X, Y, Z, A, B, C."""
        result: tuple[float, ...] = await self._dispatch.read(
            Command.READ_POSE, lambda r: r.pose().values(*POSE_NAMES)
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
        policy = servo if servo is not None else self.config.motion_servo
        return await self._jog.start(actor, frame, axis, direction, policy)

    def jog_heartbeat(self, actor: Actor) -> bool:
        """The key is still held. Returns False when ``actor`` has no jog running (ended
        by release, stop, heartbeat loss, takeover or an error): the client should stop
        sending heartbeats."""
        return self._jog.heartbeat(actor)

    async def jog_release(self, actor: Actor) -> None:
        """The key was let go: stop now (JOG with empty masks) rather than waiting for
        the controller's watchdog."""
        await self._jog.release(actor)

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
        await self._jog.step(
            actor,
            frame,
            axis,
            direction,
            waits=self.config.step_waits_for_motion if wait is None else wait,
            servo=servo if servo is not None else self.config.motion_servo,
            step_mm=step_mm,
        )


__all__ = ["RobotCommands"]
