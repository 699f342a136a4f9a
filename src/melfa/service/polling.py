"""What the worker reads when nothing else waits, and what each read says: the poll plan
and its typed results.

A cycle is JPOSF every time, PPOSF while the tool offset is unknown (moving) or every
`ServiceConfig.pose_every` cycles (at rest), STATE every `state_every`, HNDSTS every
`hand_every`. Each read gives one frozen result that knows which snapshot fields it sets
(`apply`); the service never splats a dict into its snapshot.

`Poller` keeps what one connection's reads teach (the last joints, the tool offset learned
at rest, the controller's alarm texts) and is reset on every reconnect.
"""

from __future__ import annotations

import contextlib
import dataclasses
import enum
from dataclasses import dataclass

from melfa.kin import Pose, fk, pose_inv, pose_mul
from melfa.protocol import RemoteProtocolError, State, error_text
from melfa.protocol.answers import JOINT_NAMES, POSE_NAMES, RunStatus, StopStatus
from melfa.robot import ControllerError, Robot, RobotError
from melfa.service.config import ServiceConfig
from melfa.service.events import Alarm, StateSnapshot


class PollCommand(enum.StrEnum):
    """The requests polling sends."""

    JOINTS = "JPOSF"
    POSE = "PPOSF"
    STATE = "STATE"
    HANDS = "HNDSTS"


@dataclass(frozen=True)
class JointsRead:
    """A JPOSF: the joints, and the pose computed from them once the tool offset is known."""

    joints: tuple[float, ...]
    moving: bool
    override: int | None = None
    speed: float | None = None
    pose: tuple[float, ...] | None = None
    """Computed (forward kinematics with the learned tool offset); None: keep the last."""

    def apply(self, s: StateSnapshot) -> StateSnapshot:
        s = dataclasses.replace(s, joints=self.joints, moving=self.moving)
        if self.override is not None:
            s = dataclasses.replace(s, override=self.override)
        if self.speed is not None:
            s = dataclasses.replace(s, speed=self.speed)
        if self.pose is not None:
            s = dataclasses.replace(s, pose=self.pose, pose_measured=False)
        return s


@dataclass(frozen=True)
class PoseRead:
    """A PPOSF: the measured pose and its flags."""

    pose: tuple[float, ...]
    flags: tuple[int, int] | None = None

    def apply(self, s: StateSnapshot) -> StateSnapshot:
        s = dataclasses.replace(s, pose=self.pose, pose_measured=True)
        if self.flags is not None:
            s = dataclasses.replace(s, flags=self.flags)
        return s


@dataclass(frozen=True)
class StateRead:
    """A STATE (and the alarm's text when one is active)."""

    program: str
    line: int | None
    override: int | None
    servo: bool
    running: bool
    program_running: bool
    """RUN without PROGRAM SELECT: an EXEC move sets RUN with PROGRAM SELECT still on."""
    paused: bool
    alarm: Alarm | None

    def apply(self, s: StateSnapshot) -> StateSnapshot:
        return dataclasses.replace(
            s,
            program=self.program,
            line=self.line,
            override=self.override,
            servo=self.servo,
            running=self.running,
            program_running=self.program_running,
            paused=self.paused,
            alarm=self.alarm,
        )


@dataclass(frozen=True)
class HandsRead:
    """An HNDSTS: hands 1…8, True open, False closed, None unknown."""

    hands: tuple[bool | None, ...]

    def apply(self, s: StateSnapshot) -> StateSnapshot:
        return dataclasses.replace(s, hands=self.hands)


@dataclass(frozen=True)
class PositionUnknownRead:
    """A position read showing ``****``: the controller does not know where the arm is
    (origin or encoder data lost) [TRACE K9b-C4]. The state says so: no joints, no pose."""

    def apply(self, s: StateSnapshot) -> StateSnapshot:
        return dataclasses.replace(s, joints=None, pose=None, moving=None)


PollResult = JointsRead | PoseRead | StateRead | HandsRead | PositionUnknownRead


class Poller:
    """The poll plan and the memory of one connection's reads (worker thread only)."""

    def __init__(self, config: ServiceConfig) -> None:
        self.config = config
        self._cycle: list[PollCommand] = []
        self._cycle_no = 0
        self.program_running = False
        self.tool_offset: Pose | None = None
        self._joints: tuple[float, ...] | None = None
        self._measured_joints: tuple[float, ...] | None = None
        self._joints_still = False
        self._error_texts: dict[int, str] = {}

    def reconnected(self) -> None:
        """A new connection: what the last one taught about the tool may be stale."""
        self.tool_offset = None
        self._measured_joints = None

    # ------------------------------------------------------------------ the plan

    def peek(self) -> PollCommand:
        """The next read of the cycle (planning a new cycle when one ended)."""
        if not self._cycle:
            self._cycle = self._plan()
        return self._cycle[0]

    def take(self) -> PollCommand:
        command = self.peek()
        self._cycle.pop(0)
        return command

    def _plan(self) -> list[PollCommand]:
        n = self._cycle_no
        self._cycle_no += 1
        plan = [PollCommand.JOINTS]
        moving = not self._joints_still
        # One kind of pose per phase, never alternating: while moving, computed from every
        # JPOSF once the tool offset is known (else measured by PPOSF every cycle); at
        # rest, measured every `pose_every` cycles.
        if (moving and self.tool_offset is None) or (
            not moving and n % self.config.pose_every == 0
        ):
            plan.append(PollCommand.POSE)
        if n % self.config.state_every == 0:
            plan.append(PollCommand.STATE)
        if n % self.config.hand_every == 0:
            plan.append(PollCommand.HANDS)
        return plan

    # ------------------------------------------------------------------ the reads

    def read(self, robot: Robot, command: PollCommand) -> PollResult:
        """Send one poll request and read its answer (the robot's errors propagate)."""
        match command:
            case PollCommand.JOINTS:
                return self._joints_read(robot)
            case PollCommand.POSE:
                return self._pose_read(robot)
            case PollCommand.STATE:
                return self._state_read(robot, robot.state())
            case PollCommand.HANDS:
                return HandsRead(robot.hand_status().hands)

    def _joints_read(self, robot: Robot) -> JointsRead:
        position = robot.joints()
        joints = position.values(*JOINT_NAMES)
        moving = bool(position.speed) or (self._joints is not None and joints != self._joints)
        self._joints = joints
        self._joints_still = not moving
        pose = None
        # At rest where the last PPOSF was read, that measured pose stands: the one
        # computed from 2-decimal joints can differ from it by ~0.5 mm, and alternating
        # the two would make a still arm's pose flicker.
        if self.tool_offset is not None and joints != self._measured_joints:
            with contextlib.suppress(Exception):
                p = pose_mul(fk(joints), self.tool_offset)
                pose = (p.x, p.y, p.z, p.a, p.b, p.c)
        return JointsRead(joints, moving, position.override, position.speed, pose)

    def _pose_read(self, robot: Robot) -> PoseRead:
        position = robot.pose()
        values = position.values(*POSE_NAMES)
        flags = None
        if position.fl1 is not None and position.fl2 is not None:
            flags = (position.fl1, position.fl2)
        if not position.speed:
            # Measured at rest with the joints last read: while they still read the same,
            # this pose stands (the first PPOSF after a move often comes before a JPOSF
            # has seen the arm still; without this the next JPOSF replaced it with the
            # pose computed from 2-decimal joints, ~0.07 mm away, on a still arm).
            self._measured_joints = self._joints
        # Learn the offset only from joints read at rest: joints read mid-move and a pose
        # read after the stop would teach a wrong offset.
        if not position.speed and self._joints is not None and self._joints_still:
            with contextlib.suppress(Exception):
                x, y, z, a, b, c = values
                measured = Pose(x, y, z, a, b, c, position.fl1 or 7, position.fl2 or 0)
                self.tool_offset = pose_mul(pose_inv(fk(self._joints)), measured)
        return PoseRead(values, flags)

    def _state_read(self, robot: Robot, state: State) -> StateRead:
        run = state.status.run
        running = RunStatus.RUNNING in run
        self.program_running = running
        number = state.status.error
        alarm = None
        if number:
            text = self._error_texts.get(number)
            if text is None:
                try:
                    text = robot.error_text(number)
                except (ControllerError, RemoteProtocolError, RobotError):
                    text = error_text(number)
                self._error_texts[number] = text
            alarm = Alarm(number, text)
        stop = state.status.stop
        selected = StopStatus.PROGRAM_SELECT in stop
        return StateRead(
            program=state.program,
            line=state.line,
            override=state.override,
            servo=RunStatus.SERVO_ON in run,
            running=running,
            program_running=running and not selected,
            paused=not running and StopStatus.STOP in stop and not selected,
            alarm=alarm,
        )


__all__ = [
    "HandsRead",
    "JointsRead",
    "PollCommand",
    "PollResult",
    "Poller",
    "PoseRead",
    "StateRead",
]
