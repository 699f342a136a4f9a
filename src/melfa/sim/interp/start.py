"""How a simulated run starts: the servo, the arm's pose, lines scripted for ``INPUT #``.

A real program often begins where the last one left the arm, with the servo already on;
started from the simulator's defaults (servo off, the home joints) such a program stops at
its first motion for a reason that is the simulator's, not the program's. `melfa sim --run`
and `melfa debug` take these from the command line (`--servo-on`, `--joints`, `--feed`).
"""

from __future__ import annotations

from dataclasses import dataclass

from melfa.kin.model import HOME
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.io import parse_feed, parse_joints


@dataclass(frozen=True, slots=True)
class RunStart:
    """The servo, the start joints (degrees; None: home) and the ``INPUT #`` feed."""

    servo_on: bool = False
    joints: tuple[float, ...] | None = None
    feed: tuple[tuple[int, str], ...] = ()

    @classmethod
    def parse(cls, servo_on: bool, joints: str | None, feed: list[str] | None) -> RunStart:
        """From the command line's texts; ValueError names the option that is wrong."""
        try:
            start = parse_joints(joints) if joints is not None else None
        except ValueError as exc:
            raise ValueError(f"--joints {exc}") from None
        lines = []
        for text in feed or []:
            try:
                lines.append(parse_feed(text))
            except ValueError as exc:
                raise ValueError(f"--feed {exc}") from None
        return cls(servo_on, start, tuple(lines))

    def arm(self) -> SimulatedArm:
        """A simulated RV-6S as this start asks."""
        return SimulatedArm(self.joints or HOME, servo_on=self.servo_on)

    def apply(self, interp: Interpreter) -> None:
        """Queue the scripted lines for the program's ``INPUT #n``."""
        for channel, line in self.feed:
            interp.feed_line(channel, line)
