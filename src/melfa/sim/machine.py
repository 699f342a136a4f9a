"""What the controller needs from the simulated arm, in controller units (mm, degrees).

`ControllerArm` is the narrow surface the protocol core uses (JPOSF/PPOSF, servo, OP
override, hand, jog, stop). `make_arm()` builds it on kin's `melfa.sim.arm.SimulatedArm`
when that exists; `InterimArm` is a small stand-in (joint-interpolated moves timed from the
RV-6S joint speeds, kin's FK/IK) so the controller works before and without it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from melfa.kin import (
    HOME,
    JOINT_LIMITS,
    JOINT_MAX_SPEED,
    JointLimitExceeded,
    KinematicsError,
    LimitExceeded,
    Pose,
    fk,
    ik,
)
from melfa.protocol.jog import Jog, JogMode

JOINT_LIMIT_ERROR = 2160  # H2160 [DOC S4]
UNREACHABLE_ERROR = 2600  # [GUESS] L2600 family "Position data exceeds the limit"
JOG_SPEED_AT_100 = 0.10
"""[GUESS] Jog speed at OP override 100 % as a fraction of each joint's maximum speed (the
real one comes from parameters JOGJSP/JOGPSP [DOC S5])."""
JOG_MM_PER_S_AT_100 = 250.0
"""[GUESS] Cartesian jog speed at OP override 100 %."""


class ArmFault(Exception):
    """The arm refused or failed: carries the controller error number (2160 …)."""

    def __init__(self, number: int, message: str) -> None:
        super().__init__(message)
        self.number = number


class ControllerArm(Protocol):
    """The simulated arm as the protocol core sees it. Times are injected seconds."""

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

    def advance(self, now: float) -> None: ...
    def set_servo(self, on: bool, now: float) -> None: ...
    def set_op_override(self, percent: int, now: float) -> None: ...
    def stop(self, now: float) -> None: ...
    def jog(self, jog: Jog, now: float) -> None: ...
    def set_hand(self, hand: int, opened: bool, now: float) -> None: ...
    def hand_open(self, hand: int) -> bool: ...


@dataclass
class _Segment:
    start: tuple[float, ...]
    end: tuple[float, ...]
    t0: float
    t1: float


class InterimArm:
    """A minimal RV-6S: joint-interpolated moves and joint/XYZ jog, no acceleration."""

    def __init__(self, joints: Sequence[float] = HOME) -> None:
        self._joints = tuple(float(j) for j in joints)
        self._segment: _Segment | None = None
        self._jog: tuple[Jog, float] | None = None
        self._servo = False
        self._override = 100
        self._hands = [True] * 8
        self._speed = 0.0
        self._last = 0.0
        self.tool: Pose | None = None
        self.base: Pose | None = None

    # reads
    @property
    def joints(self) -> tuple[float, ...]:
        return self._joints

    @property
    def pose(self) -> Pose:
        return fk(self._joints, self.tool, self.base)

    @property
    def tcp_speed(self) -> float:
        return self._speed

    @property
    def is_moving(self) -> bool:
        return self._segment is not None or self._jog is not None

    @property
    def servo(self) -> bool:
        return self._servo

    @property
    def op_override(self) -> int:
        return self._override

    @property
    def joint_limits(self) -> Sequence[tuple[float, float]]:
        return JOINT_LIMITS

    @property
    def tool_values(self) -> Sequence[float]:
        t = self.tool
        return (0.0,) * 6 if t is None else (t.x, t.y, t.z, t.a, t.b, t.c)

    # commands
    def set_servo(self, on: bool, now: float) -> None:
        if not on:
            self.stop(now)
        self._servo = on

    def set_op_override(self, percent: int, now: float) -> None:
        self.advance(now)
        self._override = percent

    def set_hand(self, hand: int, opened: bool, now: float) -> None:
        self._hands[hand - 1] = opened

    def hand_open(self, hand: int) -> bool:
        return self._hands[hand - 1]

    def move_joint(self, target: Sequence[float], now: float, speed_percent: float = 100) -> float:
        """Start a joint move; returns its end time. Raises `ArmFault` (2160) off limits."""
        target = tuple(float(v) for v in target)
        for index, (value, (lo, hi)) in enumerate(zip(target, JOINT_LIMITS, strict=True)):
            if not lo <= value <= hi:
                raise ArmFault(
                    JOINT_LIMIT_ERROR, str(JointLimitExceeded(index + 1, value, (lo, hi)))
                )
        self.advance(now)
        scale = max(self._override * speed_percent / 10000.0, 0.01)
        duration = max(
            abs(b - a) / (v * scale)
            for a, b, v in zip(self._joints, target, JOINT_MAX_SPEED, strict=True)
        )
        self._segment = _Segment(self._joints, target, now, now + duration)
        return now + duration

    def move_pose(self, target: Pose, now: float, speed_percent: float = 100) -> float:
        try:
            joints = ik(target, self._joints, self.tool, self.base)
        except LimitExceeded as exc:
            raise ArmFault(JOINT_LIMIT_ERROR, str(exc)) from None
        except KinematicsError as exc:
            raise ArmFault(UNREACHABLE_ERROR, str(exc)) from None
        return self.move_joint(joints, now, speed_percent)

    def stop(self, now: float) -> None:
        self.advance(now)
        self._segment = None
        self._jog = None
        self._speed = 0.0

    def jog(self, jog: Jog, now: float) -> None:
        self.advance(now)
        self._segment = None
        self._jog = (jog, now)

    def advance(self, now: float) -> None:
        before, since = self.pose, self._last
        self._last = max(now, self._last)
        if self._segment is not None:
            seg = self._segment
            if now >= seg.t1:
                self._joints = seg.end
                self._segment = None
            elif now > seg.t0:
                f = (now - seg.t0) / (seg.t1 - seg.t0)
                self._joints = tuple(
                    a + (b - a) * f for a, b in zip(seg.start, seg.end, strict=True)
                )
        if self._jog is not None:
            self._advance_jog(now)
        after = self.pose
        moved = math.dist(before.xyz, after.xyz)
        self._speed = moved / (now - since) if self.is_moving and now > since else 0.0

    def _advance_jog(self, now: float) -> None:
        assert self._jog is not None
        jog, since = self._jog
        dt = now - since
        if dt <= 0:
            return
        self._jog = (jog, now)
        scale = self._override / 100.0
        if jog.mode is JogMode.JOINT:
            joints = list(self._joints)
            for axis in range(6):
                sign = (1 if jog.positive >> axis & 1 else 0) - (
                    1 if jog.negative >> axis & 1 else 0
                )
                joints[axis] += sign * JOINT_MAX_SPEED[axis] * JOG_SPEED_AT_100 * scale * dt
                lo, hi = JOINT_LIMITS[axis]
                if not lo <= joints[axis] <= hi:
                    joints[axis] = min(max(joints[axis], lo), hi)
                    self._joints = tuple(joints)
                    self._jog = None
                    raise ArmFault(JOINT_LIMIT_ERROR, f"jog reached the J{axis + 1} limit")
            self._joints = tuple(joints)
            return
        pose = self.pose
        values = [pose.x, pose.y, pose.z, pose.a, pose.b, pose.c]
        for axis in range(6):
            sign = _direction(jog, axis)
            step = JOG_MM_PER_S_AT_100 * scale * dt * (1 if axis < 3 else 0.2)
            values[axis] += sign * step
        x, y, z, a, b, c = values
        target = Pose(x, y, z, a, b, c, fl1=pose.fl1, fl2=pose.fl2)
        try:
            self._joints = tuple(ik(target, self._joints, self.tool, self.base))
        except KinematicsError as exc:
            self._jog = None
            raise ArmFault(JOINT_LIMIT_ERROR, str(exc)) from None


def _direction(jog: Jog, axis: int) -> int:
    return (jog.positive >> axis & 1) - (jog.negative >> axis & 1)


def make_arm() -> InterimArm:
    """The arm a new controller drives."""
    return InterimArm()
