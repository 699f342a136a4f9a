"""How a simulated run starts: the servo, the arm's pose, lines scripted for ``INPUT #``.

A real program often begins where the last one left the arm, with the servo already on;
started from the simulator's defaults (servo off, the home joints) such a program stops at
its first motion for a reason that is the simulator's, not the program's. `melfa sim --run`
and `melfa debug` take these from the command line (`--servo-on`, `--joints` or `--pose`,
`--feed`), the IDE's simulator from its start options (`melfa.web.debug_models.StartIn`).

A start pose in XYZ is solved to joints by `melfa.kin.ik` under its own flags; one the
RV-6S cannot take (out of reach, only with other flags, beyond a joint limit) is refused
with the reason `melfa check` gives for such a point. Start joints are held to the joint
ranges the same way.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from melfa.kin.errors import KinematicsError
from melfa.kin.model import HOME
from melfa.kin.pose import DEFAULT_FL1, DEFAULT_FL2, Pose
from melfa.kin.reach import unreachable_points
from melfa.kin.solver import ik
from melfa.lang.points import PointDef
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.io import parse_feed, parse_joints, parse_pose

START = "the start position"
"""How a start position is named in a refusal ("the start position is out of …")."""


def joints_of_pose(
    values: Sequence[float], fl1: int | None = None, fl2: int | None = None
) -> tuple[float, ...]:
    """The joints (degrees) that put the flange at ``values`` (X, Y, Z mm; A, B, C degrees)
    with the structure flags (the controller's defaults when None); ValueError saying why
    the RV-6S cannot stand there.

    >>> [round(j) for j in joints_of_pose((400, 0, 645, 180, 0, 180))]
    [0, 0, 90, 0, 90, 0]
    """
    f1 = DEFAULT_FL1 if fl1 is None else fl1
    f2 = DEFAULT_FL2 if fl2 is None else fl2
    x, y, z, a, b, c = (float(v) for v in values)
    try:
        return tuple(ik(Pose(x, y, z, a, b, c, f1, f2), use_fl2=fl2 is not None))
    except KinematicsError as exc:
        found = unreachable_points([PointDef.pos(START, (x, y, z, a, b, c), f1, f2)])
        raise ValueError(f"{START} {found[0][1] if found else exc}") from None


def checked_joints(joints: Sequence[float]) -> tuple[float, ...]:
    """``joints`` if the RV-6S can stand there; ValueError with the joint and its range.

    >>> checked_joints((0, 140, 90, 0, 90, 0))
    Traceback (most recent call last):
    ...
    ValueError: the start position has J2 = 140°, beyond its limit -92…135°
    """
    values = tuple(float(j) for j in joints)
    found = unreachable_points([PointDef.jnt(START, values)])
    if found:
        raise ValueError(f"{START} {found[0][1]}")
    return values


@dataclass(frozen=True, slots=True)
class RunStart:
    """The servo (None: as the arm it starts like), the start joints (degrees; None: where
    that arm stands, else home), the OP override (%; None: as that arm's) and the
    ``INPUT #`` feed."""

    servo_on: bool | None = False
    joints: tuple[float, ...] | None = None
    feed: tuple[tuple[int, str], ...] = ()
    override: int | None = None

    @classmethod
    def parse(
        cls,
        servo_on: bool,
        joints: str | None,
        feed: list[str] | None,
        pose: str | None = None,
    ) -> RunStart:
        """From the command line's texts; ValueError names the option that is wrong."""
        if joints is not None and pose is not None:
            raise ValueError("--joints and --pose both say where the arm starts: give one")
        start: tuple[float, ...] | None = None
        if joints is not None:
            try:
                given = parse_joints(joints)
            except ValueError as exc:
                raise ValueError(f"--joints {exc}") from None
            try:
                start = checked_joints(given)
            except ValueError as exc:
                raise ValueError(f"--joints {joints}: {exc}") from None
        if pose is not None:
            try:
                values, fl1, fl2 = parse_pose(pose)
            except ValueError as exc:
                raise ValueError(f"--pose {exc}") from None
            try:
                start = joints_of_pose(values, fl1, fl2)
            except ValueError as exc:
                raise ValueError(f"--pose {pose}: {exc}") from None
        lines = []
        for text in feed or []:
            try:
                lines.append(parse_feed(text))
            except ValueError as exc:
                raise ValueError(f"--feed {exc}") from None
        return cls(servo_on, start, tuple(lines))

    def arm(self, like: SimulatedArm | None = None) -> SimulatedArm:
        """A simulated RV-6S as this start asks; what it does not say is as in ``like`` (a
        student's simulator: its joints, servo, hands and override), else the defaults."""
        joints = self.joints or (tuple(like.joints) if like is not None else HOME)
        servo = self.servo_on
        if servo is None:
            servo = like.servo_on if like is not None else False
        arm = SimulatedArm(joints, servo_on=servo)
        if like is not None:
            for number, state in enumerate(like.hands, start=1):
                if state is not None:
                    arm.set_hand(number, like.hand_open(number) is True, 0.0)
            arm.set_op_override(like.op_override)
        if self.override is not None:
            arm.set_op_override(self.override)
        return arm

    def apply(self, interp: Interpreter) -> None:
        """Queue the scripted lines for the program's ``INPUT #n``."""
        for channel, line in self.feed:
            interp.feed_line(channel, line)
