"""The simulated arm as the protocol core sees it, in controller units (mm, degrees).

`ControllerArm` is the narrow surface `VirtualController` uses (JPOSF/PPOSF, servo, OP
override, hands, jog, stop); `SimArm` implements it on kin's `melfa.sim.arm.SimulatedArm`,
the arm the interpreter (RUN, EXEC) moves too, turning its typed `ArmError`s into
`ArmFault`s that carry the controller's error number.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

from melfa.kin import JOINT_LIMITS, Pose
from melfa.protocol.jog import JOG_WATCHDOG_S, Jog
from melfa.sim.arm import SimulatedArm, directions_from_masks
from melfa.sim.arm_errors import ArmError
from melfa.sim.motion import Speeds
from melfa.sim.trajectory import TrajectoryRecorder


class ArmFault(Exception):
    """The arm refused or failed: carries the controller error number (2160 …)."""

    def __init__(self, number: int, message: str) -> None:
        super().__init__(message)
        self.number = number


class ControllerArm(Protocol):
    """What the protocol core reads and commands. Times are injected seconds."""

    @property
    def joints(self) -> tuple[float, ...]: ...
    @property
    def pose(self) -> Pose: ...
    @property
    def tcp_speed(self) -> float: ...
    @property
    def is_moving(self) -> bool: ...
    @property
    def servo(self) -> bool: ...
    @property
    def op_override(self) -> int: ...
    @property
    def joint_limits(self) -> Sequence[tuple[float, float]]: ...
    @property
    def tool_values(self) -> Sequence[float]: ...

    def advance(self, now: float) -> None:
        """Raise `ArmFault` when a motion ran into a limit (the arm stopped there)."""

    def set_servo(self, on: bool, now: float) -> None: ...
    def set_op_override(self, percent: int, now: float) -> None: ...
    def stop(self, now: float) -> None: ...
    def jog(self, jog: Jog, now: float) -> None:
        """Start or renew a jog; `ArmFault` (2000 servo off, 2030 refused) if it cannot."""

    def set_hand(self, hand: int, opened: bool, now: float) -> None: ...
    def hand_open(self, hand: int) -> bool: ...
    def hold_program_speeds(self) -> object:
        """Put a paused program's speed settings (SPD, OVRD…) aside and use the defaults."""

    def restore_program_speeds(self, held: object) -> None:
        """Give a resumed program back the settings `hold_program_speeds` put aside."""


HAND_CLOSED_BEFORE_USE = True
"""[GUESS] HNDSTS of a hand never commanded since power-on: closed (the S1 example shows
hand 1 closed). The arm itself says "unknown"."""


class SimArm:
    """`ControllerArm` on a `SimulatedArm` (shared with the interpreter through `arm`)."""

    def __init__(self, arm: SimulatedArm | None = None) -> None:
        self.arm = arm if arm is not None else SimulatedArm()
        self._speed = 0.0
        self._last = self.arm.time

    @property
    def joints(self) -> tuple[float, ...]:
        return tuple(self.arm.joints)

    @property
    def pose(self) -> Pose:
        return self.arm.pose

    @property
    def tcp_speed(self) -> float:
        """TCP speed (mm/s) over the last advance, as JPOSF/PPOSF's end-speed field."""
        return self._speed

    @property
    def is_moving(self) -> bool:
        return self.arm.is_moving()

    @property
    def servo(self) -> bool:
        return self.arm.servo_on

    @property
    def op_override(self) -> int:
        return round(self.arm.op_override)

    @property
    def joint_limits(self) -> Sequence[tuple[float, float]]:
        return JOINT_LIMITS

    @property
    def tool_values(self) -> Sequence[float]:
        tool = self.arm.tool
        return (0.0,) * 6 if tool is None else (tool.x, tool.y, tool.z, tool.a, tool.b, tool.c)

    def advance(self, now: float) -> None:
        before, since = self.arm.pose, self.arm.time
        was_moving = self.arm.is_moving()
        self.arm.advance(now)
        if was_moving and now > since:
            self._speed = math.dist(before.xyz, self.arm.pose.xyz) / (now - since)
        if not self.arm.is_moving():
            self._speed = 0.0
        fault = self.arm.fault
        if fault is not None:
            self.arm.clear_fault()
            raise ArmFault(fault.number, fault.message)

    def set_servo(self, on: bool, now: float) -> None:
        self.arm.set_servo(on, now)

    def set_op_override(self, percent: int, now: float) -> None:
        self.arm.advance(now)
        self.arm.set_op_override(percent)

    def stop(self, now: float) -> None:
        self.arm.stop(now)

    def jog(self, jog: Jog, now: float) -> None:
        try:
            self.arm.jog(
                jog.mode,
                directions_from_masks(jog.negative, jog.positive),
                now,
                inch=jog.inch,
            )
        except ArmError as exc:
            raise ArmFault(exc.number, exc.message) from None

    def set_hand(self, hand: int, opened: bool, now: float) -> None:
        self.arm.set_hand(hand, opened, now)

    def hand_open(self, hand: int) -> bool:
        state = self.arm.hand_open(hand)
        return not HAND_CLOSED_BEFORE_USE if state is None else state

    def hold_program_speeds(self) -> object:
        held = self.arm.speeds
        self.arm.reset_speeds()
        return held

    def restore_program_speeds(self, held: object) -> None:
        if isinstance(held, Speeds):
            self.arm.set_speeds(
                ovrd=held.ovrd, jovrd=held.jovrd, spd=held.spd, accel=(held.accel, held.decel)
            )


CONTROLLER_SAMPLES = 1200
"""Trajectory samples a controller's arm keeps (a minute at 20 polls a second): nothing
reads a longer history of it, and a private simulator runs for hours (20,000 grew each
running one by ~28 kB/s for 15 minutes). The debugger and pre-flight keep their own."""
CONTROLLER_EVENTS = 200
"""Moves and hand events a controller's arm keeps (each move holds its plan)."""


def make_arm(jog_watchdog_s: float = JOG_WATCHDOG_S) -> SimArm:
    """The arm a new controller drives: the RV-6S at its home pose, servo off, stopping a
    jog after the controller's watchdog (`SimConfig.jog_watchdog_s`)."""
    recorder = TrajectoryRecorder(CONTROLLER_SAMPLES, CONTROLLER_EVENTS)
    return SimArm(SimulatedArm(jog_watchdog_s=jog_watchdog_s, recorder=recorder))
