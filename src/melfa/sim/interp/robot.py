"""What the interpreter needs from the robot: the `RobotPort` protocol.

The interpreter works in program units (radians, `values.Position`/`values.Joints`); the
port converts to the arm's controller units (mm, degrees) and back, maps the arm's typed
errors to `RunError`s with controller numbers, and tells when a motion ends, so a program
can block on it and the fast runner can jump the clock to it. `ArmPort` (in `armport.py`)
implements it on `melfa.sim.arm.SimulatedArm`.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from typing import Protocol

from melfa.protocol.limits import PROGRAM_OVERRIDE_TEXT, is_program_override
from melfa.sim.interp import errors
from melfa.sim.interp.values import Joints, Position, Value, type_name


class ArcKind(enum.Enum):
    """The circular moves: arc through 3 points, arc not through a reference, by centre,
    full circle [S1 MVR/MVR2/MVR3/MVC]."""

    MVR = "MVR"
    MVR2 = "MVR2"
    MVR3 = "MVR3"
    MVC = "MVC"


class RobotPort(Protocol):
    """The simulated arm as a program drives it. Times are seconds of the injected clock."""

    def advance(self, now: float) -> None:
        """Move the arm's state up to `now`."""

    @property
    def servo_on(self) -> bool: ...

    def set_servo(self, on: bool, now: float) -> None: ...

    def joints(self) -> Joints:
        """Current joint angles (radians)."""

    def position(self) -> Position:
        """Current TCP pose under the active TOOL and BASE (A/B/C in radians)."""

    def move_joint(self, target: Position | Joints, now: float) -> float:
        """Start a joint-interpolated move; returns its end time. Raises `RunError`."""

    def move_linear(self, target: Position, now: float) -> float:
        """Start a linear move (orientation interpolated); returns its end time."""

    def move_arc(self, kind: ArcKind, points: tuple[Position, ...], now: float) -> float:
        """Start a circular move through/around `points` (the arm first moves linearly to
        the start point when it is elsewhere [S1 MVR]); returns its end time."""

    def move_arch(self, target: Position | Joints, now: float) -> float:
        """Start an arch move (MVA: lift, traverse, lower); returns its end time."""

    def motion_end(self) -> float | None:
        """When the current motion ends, or None when the arm is still."""

    def stop(self, now: float) -> None:
        """Decelerate and stop (STOP, SKIP); `motion_end` becomes the stop time."""

    def set_speeds(
        self,
        *,
        ovrd: float | None = None,
        jovrd: float | None = None,
        spd: float | None = None,
        accel: tuple[float, float] | None = None,
    ) -> None:
        """Program speed settings (OVRD %, JOVRD %, SPD mm/s, ACCEL %,%)."""

    def reset_speeds(self) -> None:
        """Back to the defaults (END, RSTPRG) [S1 END]."""

    def speeds(self) -> tuple[float, float, float, float]:
        """(OVRD %, JOVRD %, SPD mm/s, OP override %)."""

    def default_speed(self) -> float:
        """SPD after reset (M_NSPD)."""

    def set_hand(self, hand: int, open_: bool, now: float) -> None: ...

    def hand_open(self, hand: int) -> bool | None:
        """True open, False closed, None never commanded."""

    def tool(self) -> Position: ...

    def set_tool(self, tool: Position) -> None: ...

    def base(self) -> Position: ...

    def set_base(self, base: Position) -> None: ...

    def to_joints(self, target: Position) -> Joints:
        """IK of a pose (under TOOL/BASE) near the current joints; raises `RunError`."""

    def to_position(self, joints: Joints) -> Position:
        """FK of joints, under TOOL/BASE."""

    def set_line(self, line: int | None) -> None:
        """Tell the trajectory recorder which program line is executing."""


def set_speed(robot: RobotPort, what: str, value: Value) -> None:
    """OVRD/JOVRD (0 < % <= 100) and SPD (> 0 mm/s), from a statement or a system variable."""
    if not isinstance(value, int | float):
        raise errors.RunError(errors.TYPE_COMBINATION, f"{what} needs a number")
    v = float(value)
    if what in ("OVRD", "JOVRD"):
        if not is_program_override(v):  # OVRD 0 or >100 is an error [S1 OVRD]
            raise errors.RunError(
                errors.ARGUMENT_OUT_OF_RANGE, f"{what} must be {PROGRAM_OVERRIDE_TEXT}, got {value}"
            )
        if what == "OVRD":
            robot.set_speeds(ovrd=v)
        else:
            robot.set_speeds(jovrd=v)
    elif what == "SPD":
        if v <= 0:
            raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"SPD must be > 0, got {value}")
        robot.set_speeds(spd=v)


def robot_function(
    robot: RobotPort, name: str, args: list[Callable[[], Value]]
) -> Callable[[], Value] | None:
    """Functions that need the arm's kinematics: PTOJ, JTOP, POSCQ (None for others)."""
    if name not in ("PTOJ", "JTOP", "POSCQ") or len(args) != 1:
        return None
    arg = args[0]
    if name == "PTOJ":

        def ptoj() -> Value:
            p = arg()
            if not isinstance(p, Position):
                raise errors.RunError(errors.TYPE_COMBINATION, "PTOJ needs a position")
            return robot.to_joints(p)

        return ptoj
    if name == "JTOP":

        def jtop() -> Value:
            j = arg()
            if not isinstance(j, Joints):
                raise errors.RunError(errors.TYPE_COMBINATION, "JTOP needs a joint position")
            return robot.to_position(j)

        return jtop

    def poscq() -> Value:
        p = arg()
        if isinstance(p, Joints):
            p = robot.to_position(p)
        if not isinstance(p, Position):
            raise errors.RunError(
                errors.TYPE_COMBINATION, f"POSCQ needs a position, not a {type_name(p)}"
            )
        try:
            robot.to_joints(p)
        except errors.RunError:
            return 0
        return 1

    return poscq
