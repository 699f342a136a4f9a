"""`RobotPort` on the simulated RV-6S (`melfa.sim.arm.SimulatedArm`).

The only place that converts between program units (radians, `values.Position`) and the
arm's controller units (degrees, `melfa.kin.Pose`), and that turns the arm's `ArmError`s
into `RunError`s with the same numbers.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TypeVar

from melfa.kin import Joints as KJoints
from melfa.kin import Pose
from melfa.protocol.limits import HANDS, span_text
from melfa.sim.arm import SimulatedArm
from melfa.sim.arm_errors import ArmError
from melfa.sim.interp import errors
from melfa.sim.interp.robot import ArcKind
from melfa.sim.interp.values import Joints, Position
from melfa.sim.motion import SPD_DEFAULT

T = TypeVar("T")


def to_pose(p: Position) -> Pose:
    x, y, z, a, b, c = p.to_degrees()
    return Pose(x, y, z, a, b, c, fl1=p.fl1, fl2=p.fl2)


def from_pose(p: Pose) -> Position:
    return Position(
        p.x, p.y, p.z, math.radians(p.a), math.radians(p.b), math.radians(p.c),
        p.l1 or 0.0, p.l2 or 0.0, p.fl1, p.fl2,
    )  # fmt: skip


def to_kjoints(j: Joints) -> KJoints:
    deg = j.to_degrees()
    return KJoints.of((list(deg) + [0.0] * 6)[:6])


def from_kjoints(j: KJoints) -> Joints:
    return Joints(tuple(math.radians(v) for v in j))


def _identity(p: Position) -> bool:
    return not any((p.x, p.y, p.z, p.a, p.b, p.c))


def _call(fn: Callable[[], T]) -> T:
    try:
        return fn()
    except ArmError as exc:
        raise errors.RunError(exc.number, exc.message, level=exc.level) from None
    except ValueError as exc:
        raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, str(exc)) from None


class ArmPort:
    """Adapts a `SimulatedArm` to the interpreter's `RobotPort`."""

    def __init__(self, arm: SimulatedArm) -> None:
        self.arm = arm

    def advance(self, now: float) -> None:
        self.arm.advance(now)

    @property
    def servo_on(self) -> bool:
        return self.arm.servo_on

    def set_servo(self, on: bool, now: float) -> None:
        self.arm.set_servo(on, now)

    def joints(self) -> Joints:
        return from_kjoints(self.arm.joints)

    def position(self) -> Position:
        return from_pose(self.arm.pose)

    def _target(self, target: Position | Joints) -> Pose | KJoints:
        return to_pose(target) if isinstance(target, Position) else to_kjoints(target)

    def move_joint(self, target: Position | Joints, now: float) -> float:
        goal = self._target(target)
        plan = _call(lambda: self.arm.move_joint(goal, now))
        return now + plan.duration

    def move_linear(self, target: Position, now: float) -> float:
        goal = to_pose(target)
        plan = _call(lambda: self.arm.move_linear(goal, now))
        return now + plan.duration

    def move_arc(self, kind: ArcKind, points: tuple[Position, ...], now: float) -> float:
        p1, p2, p3 = (to_pose(p) for p in points)
        arm = self.arm
        moves = {
            ArcKind.MVR: lambda: arm.move_arc(p1, p2, p3, now),
            ArcKind.MVR2: lambda: arm.move_arc_ref(p1, p2, p3, now),
            ArcKind.MVR3: lambda: arm.move_arc_centre(p1, p2, p3, now),
            ArcKind.MVC: lambda: arm.move_circle(p1, p2, p3, now),
        }
        plan = _call(moves[kind])
        return now + plan.duration

    def move_arch(self, target: Position | Joints, now: float) -> float:
        goal = self._target(target)
        plan = _call(lambda: self.arm.move_arch(goal, now))
        return now + plan.duration

    def motion_end(self) -> float | None:
        return self.arm.motion_end()

    def stop(self, now: float) -> None:
        self.arm.stop(now)

    def set_speeds(
        self,
        *,
        ovrd: float | None = None,
        jovrd: float | None = None,
        spd: float | None = None,
        accel: tuple[float, float] | None = None,
    ) -> None:
        _call(lambda: self.arm.set_speeds(ovrd=ovrd, jovrd=jovrd, spd=spd, accel=accel))

    def reset_speeds(self) -> None:
        self.arm.reset_speeds()

    def speeds(self) -> tuple[float, float, float, float]:
        s = self.arm.speeds
        return (s.ovrd, s.jovrd, s.spd, s.op_override)

    def default_speed(self) -> float:
        return SPD_DEFAULT

    def set_hand(self, hand: int, open_: bool, now: float) -> None:
        _call(lambda: self.arm.set_hand(hand, open_, now))

    def hand_open(self, hand: int) -> bool | None:
        if hand not in HANDS:
            raise errors.RunError(
                errors.ARGUMENT_OUT_OF_RANGE, f"hand number {hand} is not {span_text(HANDS)}"
            )
        return self.arm.hand_open(hand)

    def tool(self) -> Position:
        t = self.arm.tool
        return from_pose(t) if t is not None else Position(fl1=0)

    def set_tool(self, tool: Position) -> None:
        self.arm.set_tool(None if _identity(tool) else to_pose(tool))

    def base(self) -> Position:
        b = self.arm.base
        return from_pose(b) if b is not None else Position(fl1=0)

    def set_base(self, base: Position) -> None:
        self.arm.set_base(None if _identity(base) else to_pose(base))

    def to_joints(self, target: Position) -> Joints:
        pose = to_pose(target)
        return from_kjoints(_call(lambda: self.arm.to_joints(pose)))

    def to_position(self, joints: Joints) -> Position:
        return from_pose(self.arm.to_pose(to_kjoints(joints)))

    def set_line(self, line: int | None) -> None:
        self.arm.set_line(line)
